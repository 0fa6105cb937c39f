"""Real processes on real sockets: `issv serve` in a subprocess, free ports, clip profiles."""
from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
CLIPS = ROOT.parent / "shared" / "data" / "utd-mhad-dev" / "clips"
CLIP = CLIPS / "a10_s1_t1_draw_circle_ccw.npz"


def free_ports(n: int = 2) -> int:
    """A port P such that P .. P+n-1 are free on loopback now (serve uses P and P+1)."""
    for _ in range(50):
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            base = s.getsockname()[1]
        if base + n >= 65535:
            continue
        try:
            held = []
            for p in range(base, base + n):
                t = socket.socket()
                t.bind(("127.0.0.1", p))
                held.append(t)
            return base
        except OSError:
            continue
        finally:
            for t in held:
                t.close()
    raise RuntimeError("no free pair of ports")


def clip_profile(tmp: Path, clip: Path = CLIP, loop: bool = True, backend: str = "truth") -> Path:
    path = tmp / "serve.toml"
    path.write_text(f'[source]\nname = "clip"\npath = "{clip}"\nloop = {str(loop).lower()}\n'
                    f'[backend]\nname = "{backend}"\n')
    return path


class Serve:
    """`issv serve` in a subprocess; waits until it says it is publishing."""

    def __init__(self, *args: str, prefix: tuple[str, ...] = (), env: dict | None = None) -> None:
        cmd = [*prefix, sys.executable, "-m", "host", "serve", *args]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                                     env={**os.environ, **(env or {})})
        self.lines: list[str] = []
        deadline = time.time() + 30
        while time.time() < deadline:
            ready, _, _ = select.select([self.proc.stderr], [], [], 0.5)
            if ready:
                text = self.proc.stderr.readline()
                self.lines.append(text)
                if "publishing" in text:
                    return
            if self.proc.poll() is not None:
                break
        self.stop()
        raise RuntimeError(f"issv serve did not start: {''.join(self.lines)}{self.proc.stderr.read()}")

    def stop(self) -> str:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        return "".join(self.lines) + (self.proc.stderr.read() or "")


@pytest.fixture
def serve():
    started: list[Serve] = []

    def start(*args: str, **kw) -> Serve:
        s = Serve(*args, **kw)
        started.append(s)
        return s

    yield start
    for s in started:
        s.stop()
