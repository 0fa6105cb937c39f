"""`issv serve PROFILE`: run a profile's source and backend and publish its frames for `network`.

A command of the network backend's plugin (registered through `register_commands`). The sensor
side is the host's own frame loop (host.app.SensorShow): the same pacing, limits, metrics and
rules for a backend that raises as `issv run`; every frame the backend makes is published as it
is made. Light to import: every `issv` call imports it; the transports load in `main`.
"""
from __future__ import annotations

import argparse
import ipaddress
import json
import sys
from pathlib import Path
from urllib.parse import urlsplit

from host import PluginUnavailable
from host.errors import UserError

NAME = "serve"
HELP = "publish a profile's backend frames on the network (subscribe with backend = \"network\")"
DEFAULT_BIND = "tcp://127.0.0.1:5555"


def crop(text: str) -> tuple[int, int, int, int]:
    try:
        x, y, w, h = (int(v) for v in text.split(","))
        if x >= 0 and y >= 0 and w > 0 and h > 0:
            return (x, y, w, h)
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"expected X,Y,WIDTH,HEIGHT in pixels such as 80,60,480,360, got {text!r}")


def add_arguments(p: argparse.ArgumentParser) -> None:
    from backends.network.wire import CODECS, DEFAULT_CODEC  # numpy and zstandard: loaded anyway by the backend
    from host.app import add_limit_arguments
    p.add_argument("profile", help="a profile TOML file; its source and backend are served")
    p.add_argument("--bind", metavar="ADDR",
                   help=f"where to publish (default {DEFAULT_BIND}: this machine only; tcp://0.0.0.0:5555 "
                        "for every interface). Depth uses the next port. With --transport ros: the ROS master URI")
    p.add_argument("--transport", choices=("zmq", "ros"), default="zmq", help="ZeroMQ (default) or ROS 1 topics")
    p.add_argument("--namespace", default="/openiss", help="ROS topic namespace (default /openiss)")
    p.add_argument("--no-depth", action="store_true", help="send hands and gestures only")
    p.add_argument("--no-labels", action="store_true",
                   help="send depth without the user label image that goes with it when the backend knows it")
    p.add_argument("--codec", choices=sorted(CODECS),
                   help=f"lossless depth compression (default: raw when bound to this machine only, where "
                        f"compressing costs time and saves nothing; {DEFAULT_CODEC} otherwise)")
    p.add_argument("--downscale", type=int, default=1, metavar="N", help="keep every Nth depth pixel and row")
    p.add_argument("--crop", type=crop, metavar="X,Y,W,H", help="send only this part of the depth image")
    p.add_argument("--depth-fps", type=float, metavar="F", help="send at most F depth images per second")
    add_limit_arguments(p)
    p.add_argument("--fast", action="store_true", help="do not pace recorded sources")
    p.add_argument("--stats-json", metavar="FILE", help="write what was published (and the show's metrics) as JSON at exit")


def published(publisher) -> str:
    s = publisher.stats()
    return (f"[bold]serve[/] {s['bind']}  subscribers {s['subscribers']}  sent {s['sent']}  "
            f"depth skipped {s['depth_skipped']}  compression {s['compression'] or '-'}x")


def loopback(addr: str) -> bool:
    """Whether tcp://HOST:PORT names this machine only (a host name may be another machine)."""
    host = urlsplit(addr).hostname or ""
    try:
        return host == "localhost" or ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def codec_for(codec: str | None, bind: str, transport: str = "zmq") -> str:
    """--codec if given; else raw on loopback (copying an image is ~0.1 ms, compressing it several
    ms that every frame would wait for, to save bandwidth loopback does not lack); else the default."""
    from backends.network.publisher import endpoints
    from backends.network.wire import DEFAULT_CODEC
    if codec is not None:
        return codec
    if transport == "zmq" and loopback(endpoints(bind)[0]):
        return "raw"
    return DEFAULT_CODEC


def how_to_serve(connect: str, namespace: str | None = None) -> str:
    """Where and how to start the `issv serve` a subscriber to `connect` (a ROS master URI with
    `namespace`) would hear: what a technician is told while the show waits for a publisher."""
    if namespace is not None:
        return f"on the camera machine: issv serve PROFILE --transport ros --bind {connect} --namespace {namespace}"
    if loopback(connect):
        return f"on this machine: issv serve PROFILE --bind {connect}"
    addr = urlsplit(connect)
    return f"on {addr.hostname}: issv serve PROFILE --bind tcp://0.0.0.0:{addr.port}"


def make_publisher(args: argparse.Namespace, backend: str):
    from backends.network.publisher import DepthOptions
    codec = codec_for(args.codec, args.bind or DEFAULT_BIND, args.transport)
    depth = DepthOptions(not args.no_depth, codec, max(1, args.downscale), args.crop, args.depth_fps,
                         labels=not args.no_labels)
    if args.transport == "ros":
        from backends.network.ros import RosPublisher
        try:
            return RosPublisher(args.bind, args.namespace, depth, backend)
        except PluginUnavailable as error:
            raise UserError(f"issv serve --transport ros: {error}") from None
    from backends.network.publisher import Publisher
    return Publisher(args.bind or DEFAULT_BIND, depth, backend)


def main(args: argparse.Namespace) -> int:
    from host.app import SensorShow

    show = SensorShow(args.profile, fast=args.fast)
    if show.backend.name == "network":
        raise UserError(f"issv serve: {args.profile} uses backend 'network'; serve a profile whose backend "
                        "computes frames (e.g. profiles/demo.toml)")
    publisher = make_publisher(args, show.backend.name)
    where = publisher.stats()["bind"]
    print(f"issv serve: publishing backend {show.backend.name!r} at {where}; Ctrl-C stops", file=sys.stderr, flush=True)
    try:
        show.run(publisher.publish, observe_end=publisher.publish_end, closed=publisher.close,
                 frames=args.frames, seconds=args.seconds, status=lambda: published(publisher))
    finally:
        stats = publisher.stats()
        print(f"issv serve: sent {stats['sent']}, depth skipped {stats['depth_skipped']}, "
              f"compression {stats['compression'] or '-'}x", file=sys.stderr, flush=True)
        if args.stats_json:  # and the show's own metrics (issv run's --metrics-json document)
            shown = {"metrics": show.metrics.to_json()} if show.metrics is not None else {}
            Path(args.stats_json).write_text(json.dumps({**stats, **shown}, indent=2) + "\n")
    return 0
