"""`issv isf`'s files tried in a child process, so one shader costs at most `--timeout` seconds.

A shader that loops for ever keeps llvmpipe (or a GPU driver) busy inside glFinish, where no
Python signal can reach it, and a driver can also crash on a bad file. The child holds the GL
context and the demo views and renders the files one after the other; when a file does not
answer in time, or the child dies, that file is reported as not ok, the child is replaced and
the batch goes on. The time limit counts from when the file is sent, not the child's start-up.
"""
from __future__ import annotations

import multiprocessing
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

STARTUP_S = 300.0  # a fresh GL context and the demo's depth views, even on a loaded machine


class BoundedTrial:
    """Renders one file at a time in a child process; `run()` never waits longer than `timeout`."""

    def __init__(self, size: tuple[int, int], timeout: float) -> None:
        self.size, self.timeout = size, timeout
        self.process: multiprocessing.process.BaseProcess | None = None
        self.conn: Connection | None = None

    def _start(self) -> None:
        ctx = multiprocessing.get_context("spawn")  # no GL state or threads inherited
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_serve, args=(child, self.size), daemon=True, name="issv-isf-trial")
        self.process.start()
        child.close()
        if not self.conn.poll(STARTUP_S) or self.conn.recv() != "ready":
            raise RuntimeError("issv isf: the renderer process did not start")

    def run(self, path: Path, frames: int, snapshot: Path | None) -> dict[str, Any]:
        if self.process is None or not self.process.is_alive():
            self._start()
        self.conn.send((str(path), frames, str(snapshot) if snapshot else None))
        try:
            if self.conn.poll(self.timeout):
                return self.conn.recv()
            why = f"did not finish {frames} frame(s) within {self.timeout:g} s (--timeout); skipped"
        except EOFError:  # the child died: a driver crash on this file
            why = f"the renderer crashed on this file (exit code {self.process.exitcode}); skipped"
        self._stop()
        return failed(path, why)

    def _stop(self) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.join()
            self.conn.close()
        self.process = self.conn = None

    def close(self) -> None:
        if self.process is not None and self.process.is_alive():
            self.conn.send(None)
            self.process.join(10)
        self._stop()


def failed(path: Path, why: str) -> dict[str, Any]:
    """A result for a file that did not answer; passes and kind still come from its header."""
    from effects.isf.shader import IsfShader

    result: dict[str, Any] = {"file": str(path), "ok": False, "error": f"{path}: {why}", "passes": 0,
                              "kind": "generator", "mean": 0.0, "std": 0.0}
    try:
        shader = IsfShader(path)
        result["passes"], result["kind"] = len(shader.header.passes), shader.kind
    except Exception:  # the header was readable to the child; it is only a courtesy here
        pass
    return result


def _serve(conn: Connection, size: tuple[int, int]) -> None:
    from effects.isf.trial import Trial

    trial = Trial(size)
    try:
        conn.send("ready")
        while (job := conn.recv()) is not None:
            path, frames, snapshot = job
            conn.send(trial.run(Path(path), frames, Path(snapshot) if snapshot else None))
    except (EOFError, KeyboardInterrupt):
        pass
    finally:
        trial.close()
