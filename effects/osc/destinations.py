"""Where OSC goes: `host:port` destinations that can never block or stop the show.

A name is resolved once, on a thread of its own (DNS can take seconds to fail); until it is
resolved the destination is skipped. Each destination has a connected, non-blocking UDP socket,
so sending never waits and the kernel reports a port nobody listens on (ECONNREFUSED). Any
error is counted and reported once, naming the destination; the show goes on.
"""
from __future__ import annotations

import ipaddress
import socket
import sys
import threading
from collections import Counter
from dataclasses import dataclass
from typing import Callable

Warn = Callable[[str], None]


def warn_stderr(text: str) -> None:
    print(f"issv: osc: {text}", file=sys.stderr, flush=True)


@dataclass(frozen=True)
class Address:
    """A parsed `host:port` (IPv6 literals in brackets: `[::1]:9000`)."""

    host: str
    port: int

    @classmethod
    def parse(cls, text: str) -> "Address":
        host, sep, port = text.strip().rpartition(":")
        if not sep or not host or not port.isdigit():
            raise ValueError("expected HOST:PORT such as 127.0.0.1:9000")
        if not 0 < int(port) < 65536:
            raise ValueError(f"port must be 1..65535, not {port}")
        return cls(host[1:-1] if host.startswith("[") and host.endswith("]") else host, int(port))

    def __str__(self) -> str:
        return f"[{self.host}]:{self.port}" if ":" in self.host else f"{self.host}:{self.port}"

    @property
    def literal(self) -> bool:
        try:
            ipaddress.ip_address(self.host)
        except ValueError:
            return False
        return True


class Destination:
    """One receiver. `send` is safe to call from the show loop at any time, in any state."""

    def __init__(self, address: Address, warn: Warn = warn_stderr) -> None:
        self.address = address
        self.warn = warn
        self.sent = 0
        self.errors: Counter[str] = Counter()
        self.resolved = threading.Event()
        self._sock: socket.socket | None = None
        self._sockaddr: tuple | None = None
        self._connected = False
        self._warned = False
        self._closed = False

    def start(self) -> None:
        """Resolve now for an IP literal, else on a daemon thread (a slow DNS never stalls setup)."""
        if self.address.literal:
            self._resolve()
        else:
            threading.Thread(target=self._resolve, name=f"issv-osc-resolve {self.address}", daemon=True).start()

    def _resolve(self) -> None:
        try:
            family, kind, proto, _, sockaddr = socket.getaddrinfo(
                self.address.host, self.address.port, type=socket.SOCK_DGRAM)[0]
            sock = socket.socket(family, kind, proto)
            sock.setblocking(False)
        except OSError as error:
            self.errors["resolve"] += 1
            self._report(f"cannot resolve {self.address.host!r} ({error}); nothing is sent there, "
                         f"the show goes on")
        else:
            if self._closed:  # the show ended while the name was resolving
                sock.close()
                return
            self._sockaddr, self._sock = sockaddr, sock
            self._connect()
        finally:
            self.resolved.set()

    def _connect(self) -> bool:
        """Connecting a UDP socket sends nothing; it fixes the peer so the kernel reports refusals."""
        try:
            self._sock.connect(self._sockaddr)
        except OSError as error:
            self._failed("connect", error)
            return False
        self._connected = True
        return True

    def send(self, data: bytes) -> bool:
        """Send one datagram without waiting; False (counted, reported once) when it did not go."""
        sock = self._sock
        if sock is None or (not self._connected and not self._connect()):
            return False
        try:
            sock.send(data)
        except BlockingIOError as error:  # the socket buffer is full: drop rather than wait
            self._failed("busy", error)
            return False
        except OSError as error:
            self._failed(type(error).__name__, error)
            return False
        self.sent += 1
        return True

    def _failed(self, kind: str, error: OSError) -> None:
        self.errors[kind] += 1
        if isinstance(error, ConnectionRefusedError):
            self._report("nothing is listening there (the port refuses datagrams); still sending, "
                         "a receiver started later will get the rest")
        elif isinstance(error, BlockingIOError):
            self._report("the send buffer is full; datagrams are dropped rather than waited for")
        else:
            self._report(f"cannot send ({error}); still trying, the show goes on")

    def _report(self, text: str) -> None:
        if not self._warned:
            self._warned = True
            self.warn(f"destination {self.address}: {text}")

    def close(self) -> None:
        self._closed = True
        if self._sock is not None:
            self._sock.close()
            self._sock = None
