"""`issv osc-replay FILE`: send a recorded OSC session over UDP with its timing.

FILE is Pure Data `qlist` text, as Pd records OSC it receives: one message per line,
`<milliseconds since the previous line> <receiver> <address> <arguments...>;`, e.g.
`33 osceleton /joint head 3 0.52 0.31 1.21;`. Pd keeps no OSC types, so they are restored:
OSCeleton's own addresses get its documented tags (`/joint` s i f f f, user messages i), other
arguments are i when written as integers, f when numbers, s otherwise. Lines of one instant (a
delta of 0 after the first) go out as one bundle, as OSCeleton sent each frame; `--no-bundle`
sends every message on its own, as Pd's qlist does. `--time-tags` stamps each bundle with its
instant in the session as a time of day (seconds after today's midnight UTC: in the past, so
a receiver that schedules bundles runs them at once), not scaled by `--speed`; osc-in, whose
clock is its time tags' time of day, then reads the session's own times exactly
(`session_seconds` of each line) at any speed.
"""
from __future__ import annotations

import argparse
import socket
import sys
import time
from dataclasses import dataclass
from pathlib import Path

HELP = "send a recorded OSC session (Pd qlist text, ms deltas) over UDP with its timing, e.g. to osc-in"
NAME = "osc-replay"
OSCELETON_TYPES = {"/joint": "sifff", "/new_user": "i", "/new_skel": "i", "/lost_user": "i"}


@dataclass(frozen=True)
class Line:
    at_ms: float  # since the start of the session
    address: str
    args: tuple[tuple[str, object], ...]  # (OSC type tag, value)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", type=Path, help="Pd qlist text: '<ms delta> <receiver> <address> <args...>;' per line")
    p.add_argument("--host", default="127.0.0.1", help="where to send (default 127.0.0.1)")
    p.add_argument("--port", type=int, default=7110, help="UDP port (default 7110, OSCeleton's)")
    p.add_argument("--speed", type=float, default=1.0, help="playback speed (2: twice as fast; default 1)")
    p.add_argument("--no-bundle", action="store_true", help="send each message alone instead of one bundle per instant")
    p.add_argument("--time-tags", action="store_true",
                   help="stamp each bundle with its time in the session, as a time of day "
                        "(osc-in then reads the session's own times at any --speed)")


def _typed(address: str, words: list[str]) -> tuple[tuple[str, object], ...]:
    tags = OSCELETON_TYPES.get(address, "")
    if len(tags) != len(words):
        tags = ""
    out = []
    for i, word in enumerate(words):
        tag = tags[i] if tags else _guess(word)
        out.append((tag, int(float(word)) if tag == "i" else float(word) if tag == "f" else word))
    return tuple(out)


def _guess(word: str) -> str:
    try:
        float(word)
    except ValueError:
        return "s"
    return "i" if word.lstrip("-").isdigit() else "f"


def read_qlist(path: Path) -> list[Line]:
    """The session's messages with their times; a UserError names the file and line of a bad one."""
    from host.errors import UserError
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise UserError(f"{path}: cannot read the qlist ({error})") from None
    lines, at, number = [], 0.0, 1
    for chunk in text.split(";"):
        line_no = number + len(chunk) - len(chunk.lstrip("\n"))
        number += chunk.count("\n")
        words = chunk.split()
        if not words:
            continue
        try:
            delta = float(words[0])
        except ValueError:
            raise UserError(f"{path}:{line_no}: expected '<ms delta> <receiver> <address> <args...>;', "
                            f"got {chunk.strip()!r}") from None
        if len(words) < 3 or not words[2].startswith("/") or delta < 0:
            raise UserError(f"{path}:{line_no}: expected '<ms delta> <receiver> /address <args...>;' "
                            f"with a delta >= 0, got {chunk.strip()!r}")
        at += delta
        try:
            lines.append(Line(at, words[2], _typed(words[2], words[3:])))
        except ValueError:
            raise UserError(f"{path}:{line_no}: {words[2]} expects {OSCELETON_TYPES[words[2]]} arguments, "
                            f"got {' '.join(words[3:])!r}") from None
    if not lines:
        raise UserError(f"{path}: no messages (expected Pd qlist lines such as "
                        f"'33 osceleton /joint head 3 0.5 0.3 1.2;')")
    return lines


def instants(lines: list[Line]) -> list[list[Line]]:
    """Consecutive lines with the same time."""
    groups: list[list[Line]] = []
    for line in lines:
        if groups and groups[-1][0].at_ms == line.at_ms:
            groups[-1].append(line)
        else:
            groups.append([line])
    return groups


def session_seconds(line: Line) -> float:
    """A line's time in the session, in seconds to the nanosecond (the deltas' sum without its
    float noise): what its time tag carries, as a time of day."""
    return round(line.at_ms / 1000.0, 9)


def replay(lines: list[Line], host: str, port: int, speed: float = 1.0, bundle: bool = True,
           time_tags: bool = False) -> dict:
    """Send the lines at their times; returns what was sent and how late the latest send was."""
    from backends.oscin.decode import midnight, stamp, time_tag
    from host.osc import Message, encode, encode_bundle
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    start, datagrams, late = time.perf_counter(), 0, 0.0
    origin = midnight(time_tag(time.time()))
    try:
        for group in instants(lines):
            due = start + group[0].at_ms / 1000.0 / speed
            delay = due - time.perf_counter()
            if delay > 0:
                time.sleep(delay)
            late = max(late, time.perf_counter() - due)
            messages = [Message(line.address, line.args) for line in group]
            tag = stamp(origin, session_seconds(group[0])) if time_tags else 1
            payloads = [encode_bundle(messages, False, tag)] if bundle else [encode(m, False) for m in messages]
            for data in payloads:
                sock.sendto(data, (host, port))
                datagrams += 1
    finally:
        sock.close()
    return {"messages": len(lines), "datagrams": datagrams, "seconds": time.perf_counter() - start,
            "max_late_ms": late * 1000.0}


def main(args: argparse.Namespace) -> int:
    from host.errors import UserError
    if args.speed <= 0:
        raise UserError(f"--speed must be > 0, got {args.speed}")
    if args.time_tags and args.no_bundle:
        raise UserError("--time-tags needs bundles (OSC messages alone carry no time tag): drop --no-bundle")
    lines = read_qlist(args.file)
    report = replay(lines, args.host, args.port, args.speed, not args.no_bundle, args.time_tags)
    print(f"osc-replay: {report['messages']} messages in {report['datagrams']} datagrams to "
          f"{args.host}:{args.port} in {report['seconds']:.1f} s (latest send {report['max_late_ms']:.1f} ms late)",
          file=sys.stderr)
    return 0
