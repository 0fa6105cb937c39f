"""The MCAP recording: readable by standard MCAP tools, readable up to the cut when cut short,
and a clear error with the byte offset when damaged."""
from __future__ import annotations

import json
import os
from dataclasses import replace
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader

from backends.truth import TruthBackend
from host.errors import UserError
from host.recording import Recording, RecordingWriter
from host.recording import codec
from host.recording import writer as writer_module
from sources.recording import RecordingSource, RecordingSourceOptions
from tests.recordings import SYNTH, as_tracked, record, tracked_live, write_profile


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    return record(tmp_path_factory.mktemp("rec"), seconds=3.0)


def write(path: Path, frames) -> Path:
    with RecordingWriter(path, {"test": "yes"}) as writer:
        for frame in frames:
            writer.write_frame(frame)
    return path


def test_standard_mcap_readers_see_the_documented_channels(recording):
    with open(recording, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        assert set(channels) == {codec.DEPTH, codec.LABELS, codec.HANDS, codec.GESTURES, codec.METRICS}
        assert channels[codec.HANDS].message_encoding == "json"
        assert channels[codec.LABELS].message_encoding == codec.LABELS_ENCODING
        assert summary.schemas[channels[codec.GESTURES].schema_id].encoding == "jsonschema"
        counts = {channels_by_id.topic: n for channels_by_id, n in
                  ((summary.channels[cid], n) for cid, n in summary.statistics.channel_message_counts.items())}
        hands = [json.loads(m.data) for _, _, m in reader.iter_messages(topics=[codec.HANDS])]
    live = tracked_live(3.0)
    assert counts[codec.HANDS] == len(live) == len(hands) and counts[codec.DEPTH] == len(live) == counts[codec.LABELS]
    assert counts[codec.GESTURES] == sum(len(f.gestures) for f in live) > 0
    assert [h["seq"] for h in hands] == [f.seq for f in live]
    assert hands[5]["hands"][0]["position"] == list(live[5].hands[0].position)


def test_metrics_and_metadata_are_recorded(recording):
    with Recording(recording) as rec:
        assert rec.complete and rec.truncated_at is None
        assert rec.meta["format"] == codec.FORMAT and rec.meta["backend"] == "truth"
        assert rec.meta["source"] == "synthetic"
        final = rec.metrics()[-1]
    assert final["final"] is True and final["frames"] == len(tracked_live(3.0)) and final["sfps"] > 0


def test_a_recording_is_a_source_with_the_same_depth_and_truth(recording):
    source = RecordingSource(RecordingSourceOptions(path=str(recording)))
    with TruthBackend(source) as backend:
        retracked = []
        while (frame := backend.update()) is not None:
            retracked.append(frame)
    live = tracked_live(3.0)
    assert source.fps == pytest.approx(30.0) and source.intrinsics == live[0].depth.intrinsics
    # re-tracking the recorded depth (and its recorded truth) reproduces the live run
    assert [(f.hands, f.gestures) for f in retracked[:len(live)]] == [(f.hands, f.gestures) for f in live]
    assert np.array_equal(retracked[10].depth.data, live[10].depth.data)


@pytest.fixture
def small_chunks(monkeypatch):
    """Chunks of 16 KB: a few seconds of test depth then spans many of them (a show's chunks end
    at the once-a-second flush; these tests write faster than that)."""
    monkeypatch.setattr(writer_module, "CHUNK_BYTES", 16 * 1024)


def test_a_long_recordings_index_is_kept_packed_and_standard_readers_seek_with_it(tmp_path, small_chunks):
    live = tracked_live(3.0)
    with RecordingWriter(tmp_path / "r.mcap") as writer:
        for frame in live:
            writer.write_frame(frame)
        packed = writer._mcap._Writer__chunk_indices
        assert isinstance(packed, writer_module.PackedChunkIndexes) and len(packed) > 10
        assert len(packed._data) < 120 * len(packed)  # bytes, not ~1 kB of objects per chunk
    with open(tmp_path / "r.mcap", "rb") as f:
        summary = make_reader(f).get_summary()
    indexes = sorted(summary.chunk_indexes, key=lambda c: c.chunk_start_offset)
    assert len(indexes) == len(packed) == summary.statistics.chunk_count
    assert all(a.message_end_time <= b.message_start_time for a, b in zip(indexes, indexes[1:]))
    with Recording(tmp_path / "r.mcap") as rec:
        middle = live[len(live) // 2].timestamp
        assert as_tracked(list(rec.frames(middle - live[0].timestamp))) == as_tracked(live[len(live) // 2:])


def test_a_truncated_file_is_read_up_to_the_cut(tmp_path, small_chunks):
    live = tracked_live(3.0)
    whole = write(tmp_path / "whole.mcap", live)
    data = whole.read_bytes()
    for fraction in (0.3, 0.7, 0.95):
        cut = tmp_path / f"cut{fraction}.mcap"
        cut.write_bytes(data[: int(len(data) * fraction)])
        warnings = []
        with Recording(cut, warn=warnings.append) as rec:
            frames = list(rec.frames())
            assert not rec.complete and rec.truncated_at is not None and rec.truncated_at <= len(data) * fraction
        assert 0 < len(frames) < len(live)
        assert as_tracked(frames) == as_tracked(live[: len(frames)])
        assert len(warnings) == 1 and f"byte {rec.truncated_at}" in warnings[0]


def test_a_recording_killed_mid_show_is_readable(tmp_path):
    prof = write_profile(tmp_path / "p.toml", {"name": "synthetic", **SYNTH})
    out = tmp_path / "crash.mcap"
    proc = subprocess.Popen([sys.executable, "-m", "host", "record", str(prof), "-o", str(out)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 60
        while time.time() < deadline and (not out.exists() or out.stat().st_size < 100_000):
            time.sleep(0.1)
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
    with Recording(out, warn=lambda _: None) as rec:
        frames = list(rec.frames())
        assert not rec.complete
    assert len(frames) > 10
    assert as_tracked(frames) == as_tracked(tracked_live(10.0)[: len(frames)])


def test_corrupt_data_names_the_byte_offset(tmp_path):
    path = write(tmp_path / "ok.mcap", tracked_live(1.0))
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle: middle + 64] = bytes(64)  # zeroes inside a chunk: its CRC no longer matches
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(bytes(data))
    with pytest.raises(UserError, match=r"corrupt recording at byte (\d+)") as caught:
        with Recording(bad) as rec:
            list(rec.frames())
    offset = int(caught.value.args[0].split("at byte ")[1].split()[0])
    assert 8 <= offset <= middle and str(bad) in str(caught.value)


def test_garbage_instead_of_a_record_is_corruption_not_truncation(tmp_path):
    path = write(tmp_path / "ok.mcap", tracked_live(0.5))
    with Recording(path) as rec:
        first_chunk = next(r.offset for r in rec._records(8) if r.opcode == 0x06)
    data = bytearray(path.read_bytes())
    data[first_chunk] = 0x7F  # not an MCAP record type
    path.write_bytes(bytes(data))
    with pytest.raises(UserError, match=f"corrupt recording at byte {first_chunk}: unknown MCAP record type 0x7f"):
        with Recording(path, warn=lambda _: None) as rec:
            list(rec.frames())


def test_not_a_recording(tmp_path):
    other = tmp_path / "clip.npz"
    other.write_bytes(b"PK\x03\x04 not mcap at all")
    with pytest.raises(UserError, match="not an MCAP recording"):
        Recording(other)
    with pytest.raises(UserError, match="no such recording"):
        Recording(tmp_path / "missing.mcap")


def test_users_extended_hands_and_gesture_users_are_recorded(tmp_path):
    """A frame without depth (an OSC tracker's) keeps its time, users and who made a gesture."""
    from host import Gesture, GestureState, GestureType, Hand, HandState, Joint, Side, User
    from host.model import Frame
    user = User(3, HandState.TRACKING, {"torso": Joint((10.0, 20.0, 2000.0), 0.9), "head": Joint((0.0, 600.0, 2000.0))},
                (10.0, -50.0, 2010.0))
    hand = Hand(32, HandState.TRACKING, (300.0, 400.0, 1700.0), Side.RIGHT, 3, 0.8, extended=True)
    gesture = Gesture(GestureType.WAVE, GestureState.COMPLETE, (300.0, 400.0, 1700.0), 32, Side.RIGHT, 0.7, 1.25, 3)
    frames = [Frame(1, 100.0, None, (hand,), (gesture,), "osc-in", users=(user,), time=1.25),
              Frame(2, 100.1, None, (), (), "osc-in", time=1.3)]
    with Recording(write(tmp_path / "users.mcap", frames)) as rec:
        back = list(rec.frames())
    assert back[0].users == (user,) and back[0].hands == (hand,) and back[0].time == 1.25
    assert back[0].gestures[0].user_id == 3 and back[1].users == () and back[1].timestamp == 1.3


def test_the_duet_labels_are_recorded_and_replayed_pixel_for_pixel(tmp_path):
    """`issv record` of the synthetic duet (truth backend: the scene's own labels): each depth
    image's user labels come back from the file, and from the replay backend, as they were made."""
    from backends.replay import ReplayBackend
    out = record(tmp_path, seconds=2.0, name="duet.mcap", scene="duet", seed=1)
    live = tracked_live(2.0, scene="duet", seed=1)
    with Recording(out) as rec:
        back = list(rec.frames())
    assert [f.depth.frame_id for f in back] == [f.depth.frame_id for f in live]
    for mine, theirs in zip(back, live):
        assert np.array_equal(mine.user_labels, theirs.user_labels)
        assert np.array_equal(mine.user_mask, theirs.user_labels > 0)
    assert set(np.unique(back[0].user_labels)) == {0, 1, 2}
    with ReplayBackend.for_recording(out) as replay:
        replayed = list(iter(replay.update, None))
    assert all(np.array_equal(a.user_labels, b.user_labels) for a, b in zip(replayed, live))
    assert len(replayed) == len(live)


def test_a_recording_without_labels_has_no_labels_channel_and_plays_as_before(tmp_path):
    """A backend that knows no user pixels writes what every recording held before labels existed
    (no /user_labels channel at all), and such a file plays with no labels."""
    frames = [replace(f, make_user_labels=None) for f in tracked_live(1.0)]
    path = write(tmp_path / "old.mcap", frames)
    with open(path, "rb") as f:
        topics = {c.topic for c in make_reader(f).get_summary().channels.values()}
    assert codec.LABELS not in topics and codec.DEPTH in topics
    with Recording(path) as rec:
        back = list(rec.frames())
    assert len(back) == len(frames) and all(f.user_labels is None and f.depth is not None for f in back)


def test_damaged_labels_are_named():
    depth = tracked_live(0.1)[0].depth
    good = codec.encode_labels(depth, np.ones(depth.data.shape, np.uint8))
    assert np.array_equal(codec.decode_labels(good)[1], np.ones(depth.data.shape, np.uint8))
    head, _, payload = good.partition(b"\n")
    with pytest.raises(codec.FormatError, match="bytes for"):
        codec.decode_labels(head.replace(b'"width": 160', b'"width": 80') + b"\n" + payload)
    with pytest.raises(codec.FormatError, match="do not decompress"):
        codec.decode_labels(head + b"\n" + payload[:-3])
    with pytest.raises(ValueError, match="user labels of shape"):
        codec.encode_labels(depth, np.ones((2, 2), np.uint8))
