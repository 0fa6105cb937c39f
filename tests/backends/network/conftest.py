"""Real processes on real sockets: `issv serve` in a subprocess, free ports, clip profiles.

The served clip is made here: the synthetic performer's wave, rendered once per session and
written as a depth clip with its hand truth (no recording from outside the repo is needed)."""
from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from tests.backends.engine.performer import WAVE_THEN_REST, frames, write_clip

ROOT = Path(__file__).resolve().parents[3]
START_S = 30  # an `issv serve` that has not said "publishing" by then has failed


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


@pytest.fixture(scope="session")
def performer_clip(tmp_path_factory) -> Path:
    """A 320x240 depth clip of the synthetic performer waving, with both hands' truth."""
    path = tmp_path_factory.mktemp("performer") / "wave.npz"
    return write_clip(path, frames(WAVE_THEN_REST, width=320, height=240, background="none"))


def clip_profile(tmp: Path, clip: Path, loop: bool = True, backend: str = "truth") -> Path:
    path = tmp / "serve.toml"
    path.write_text(f'[source]\nname = "clip"\npath = "{clip}"\nloop = {str(loop).lower()}\n'
                    f'[backend]\nname = "{backend}"\n')
    return path


def stop(proc: subprocess.Popen, grace: float = 10.0) -> None:
    """SIGINT (to its process group if it leads one: roscore's children go with it), SIGKILL if it
    lingers; already gone is fine. What is left of its group afterwards is killed."""
    try:
        group = proc.poll() is None and os.getpgid(proc.pid) == proc.pid
    except ProcessLookupError:  # it ended (and was reaped) between the poll and the lookup
        group = False
    for sig in (signal.SIGINT, signal.SIGKILL):
        try:
            os.killpg(proc.pid, sig) if group else proc.send_signal(sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(timeout=grace)
            break
        except subprocess.TimeoutExpired:
            continue
    if group:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _read_lines(fd: int, pending: bytearray, wait: float) -> list[str] | None:
    """Whole lines that arrived on `fd` within `wait` seconds ([] if none yet); None at its end.
    Raw reads after select, so a partial line or a pipe held open by a grandchild never blocks."""
    ready, _, _ = select.select([fd], [], [], wait)
    if not ready:
        return []
    chunk = os.read(fd, 65536)
    if not chunk:
        return None
    pending += chunk
    *whole, rest = pending.split(b"\n")
    pending[:] = rest
    return [line.decode(errors="replace") + "\n" for line in whole]


def wait_for_line(proc: subprocess.Popen, marker: str, what: str, timeout: float = START_S,
                  stream=None) -> list[str]:
    """The lines `proc` writes to `stream` (default its stderr) up to the first one holding `marker`.

    A helper process that exits first, or says nothing of the kind within `timeout` seconds, is
    stopped and fails the test at once with everything it wrote: no test waits without a bound."""
    fd = (stream if stream is not None else proc.stderr).fileno()
    lines: list[str] = []
    pending = bytearray()
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        got = _read_lines(fd, pending, 0.2)
        if got is None:  # its end: it exited (or closed the stream)
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                pass
            break
        lines += got
        if any(marker in line for line in got):
            return lines
    running = proc.poll() is None
    stop(proc)
    why = f"said nothing with {marker!r} in {timeout:.0f} s" if running else f"exited with status {proc.returncode}"
    end = time.monotonic() + 2.0  # what it wrote while stopping, without waiting on a pipe left open
    while time.monotonic() < end and (got := _read_lines(fd, pending, 0.2)):
        lines += got
    pytest.fail(f"{what} did not start ({why}):\n{''.join(lines)}{pending.decode(errors='replace')}", pytrace=False)


class HelperDied(Exception):
    """A helper process the test relies on (an `issv serve`) failed while the test ran."""


def _raise_helper_died(signum, frame) -> None:
    raise HelperDied(Serve.last_failure)


class Serve:
    """`issv serve` in a subprocess; waits until it says it is publishing (fails the test if it cannot).

    Its stderr is drained on a thread. If it then fails (exits non-zero without being stopped), the
    test's main thread is interrupted with HelperDied carrying that stderr, even while it blocks in
    a subscriber waiting for frames that will never come."""

    last_failure = ""

    def __init__(self, *args: str, prefix: tuple[str, ...] = (), env: dict | None = None) -> None:
        cmd = [*prefix, sys.executable, "-m", "host", "serve", *args]
        self.what = f"issv serve {' '.join(args)}"
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                                     env={**os.environ, **(env or {})})
        self.lines = wait_for_line(self.proc, "publishing", self.what)
        self.stopping = False
        signal.signal(signal.SIGUSR1, _raise_helper_died)
        self._main = threading.main_thread().ident
        self._drain = threading.Thread(target=self._watch, daemon=True)
        self._drain.start()

    def _watch(self) -> None:
        for line in self.proc.stderr:
            self.lines.append(line)
        status = self.proc.wait()
        if status != 0 and not self.stopping:
            Serve.last_failure = f"{self.what} failed (status {status}):\n{''.join(self.lines)}"
            signal.pthread_kill(self._main, signal.SIGUSR1)

    def kill(self) -> None:
        """End it the hard way (no goodbye), on purpose."""
        self.stopping = True
        self.proc.send_signal(signal.SIGKILL)
        self.proc.wait()

    def stop(self) -> str:
        self.stopping = True
        stop(self.proc)
        self._drain.join(timeout=10)
        return "".join(self.lines)


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
