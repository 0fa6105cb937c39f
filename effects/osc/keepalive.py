"""Synapse's keep-alive: a client asks for a joint's positions with `/<joint>_trackjointpos i`
(1 body, 2 world, 3 screen) on UDP port 12346, and Synapse sends that joint in that space for
KEEPALIVE_S after the last request (its JointHitDetector: KEEPALIVE_TIME 3.1 s).

The socket is read on the show loop, once per frame, as Synapse reads it once per update: no
thread, never waiting (a non-blocking socket drained of what has arrived).
"""
from __future__ import annotations

import socket
import time

from pythonosc.osc_bundle import OscBundle
from pythonosc.osc_message import OscMessage

from effects.osc.destinations import Address, Warn

KEEPALIVE_S = 3.1
MODES = {1: "body", 2: "world", 3: "screen"}
SUFFIX = "_trackjointpos"


class KeepAlive:
    """Which (joint, space) pairs a client has asked for lately. Without a socket (`listen` None,
    or the port is taken) nobody can ask, so everything counts as asked for."""

    def __init__(self, listen: Address | None, warn: Warn, prefix: str = "") -> None:
        self.prefix, self.warn = prefix, warn
        self.until: dict[tuple[str, str], float] = {}  # (joint, space) -> monotonic deadline
        self.ignored = 0
        self.sock: socket.socket | None = None
        if listen is None:
            return
        try:
            family = socket.AF_INET6 if ":" in listen.host else socket.AF_INET
            sock = socket.socket(family, socket.SOCK_DGRAM)
            sock.bind((listen.host, listen.port))
            sock.setblocking(False)
        except OSError as error:
            warn(f"synapse: cannot take keep-alive messages on {listen} ({error}); every joint's positions "
                 f"are sent in every space instead (set keepalive = \"off\" to say so, or another port)")
            return
        self.sock = sock

    @property
    def port(self) -> int | None:
        return None if self.sock is None else self.sock.getsockname()[1]

    def poll(self, now: float | None = None) -> None:
        """Take every request that has arrived (Synapse's UDPMessenger::Poll)."""
        if self.sock is None:
            return
        now = time.monotonic() if now is None else now
        while True:
            try:
                data = self.sock.recv(65536)
            except OSError:  # nothing more waiting (BlockingIOError) or the socket failed
                return
            try:
                messages = _messages(data)
            except Exception:  # python-osc raises several kinds on bytes that are not OSC
                self._ignore("a datagram that is not OSC")
                continue
            for address, args in messages:
                self._request(address, args, now)

    def _request(self, address: str, args: list, now: float) -> None:
        if self.prefix and address.startswith(self.prefix + "/"):
            address = address[len(self.prefix):]
        if not address.endswith(SUFFIX):
            return  # Synapse's other controls (_requiredlength, /depth_mode ...): not ours to act on
        if len(args) != 1 or isinstance(args[0], bool) or not isinstance(args[0], int) or args[0] not in MODES:
            self._ignore(f"{address} with {args!r} (expected one int: 1 body, 2 world, 3 screen)")
            return
        self.until[(address[1:-len(SUFFIX)], MODES[args[0]])] = now + KEEPALIVE_S

    def _ignore(self, what: str) -> None:
        if not self.ignored:
            self.warn(f"synapse: ignored {what}")
        self.ignored += 1

    def wanted(self, joint: str, space: str, now: float) -> bool:
        return self.sock is None or self.until.get((joint, space), 0.0) > now

    def close(self) -> None:
        if self.sock is not None:
            self.sock.close()
            self.sock = None


def _messages(data: bytes) -> list[tuple[str, list]]:
    return _flat(OscBundle(data) if OscBundle.dgram_is_bundle(data) else OscMessage(data))


def _flat(content: OscBundle | OscMessage) -> list[tuple[str, list]]:
    if isinstance(content, OscBundle):
        return [m for part in content for m in _flat(part)]
    return [(content.address, list(content.params))]
