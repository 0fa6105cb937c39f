"""zstd contexts, one per thread: contexts must not be shared between threads, and making one per
message (or per band of an image) costs more than the compression of a small one. Level 1, the
fastest: recordings and the network compress depth on the sensor path."""
from __future__ import annotations

import threading

import zstandard

_local = threading.local()


def compressor() -> zstandard.ZstdCompressor:
    if not hasattr(_local, "compressor"):
        _local.compressor = zstandard.ZstdCompressor(level=1)
    return _local.compressor


def decompressor() -> zstandard.ZstdDecompressor:
    if not hasattr(_local, "decompressor"):
        _local.decompressor = zstandard.ZstdDecompressor()
    return _local.decompressor
