"""Bad destinations: one warning naming the destination, the show goes on, nothing blocks."""
import socket
import threading

from effects.osc import destinations
from tests.effects.osc.helpers import Script, free_port, make_osc, run_show

SCRIPT = Script(n=20)


def run_with(bad: str, receiver):
    """A show sending to `bad` and to a healthy receiver; returns the effect and its warnings."""
    warnings: list[str] = []
    effect = make_osc(destinations=[bad, receiver.address], warn=warnings.append)
    show = run_show([effect], realtime=True, script=SCRIPT)
    assert show.metrics.frames == SCRIPT.n and all(slot.enabled for slot in show.effects)
    assert receiver.wait_for(lambda r: r.has_frame(SCRIPT.n))
    assert len(receiver.messages("/issv/gesture")) == 2  # the healthy destination lost nothing
    return effect, warnings


def test_a_name_that_does_not_resolve(receiver):
    effect, warnings = run_with("no-such-host.invalid:9000", receiver)
    effect.destinations[0].resolved.wait(10)
    assert len(warnings) == 1
    assert warnings[0].startswith("destination no-such-host.invalid:9000: cannot resolve")
    assert effect.destinations[0].errors["resolve"] == 1 and effect.destinations[0].sent == 0


def test_a_port_nobody_listens_on(receiver):
    effect, warnings = run_with(f"127.0.0.1:{free_port()}", receiver)
    assert warnings == [f"destination {effect.destinations[0].address}: nothing is listening there (the port "
                        "refuses datagrams); still sending, a receiver started later will get the rest"]
    bad = effect.destinations[0]
    assert bad.errors["ConnectionRefusedError"] >= 1
    assert bad.sent + sum(bad.errors.values()) == len(receiver.packets)  # every datagram went or was counted


def test_a_port_in_use_by_a_tcp_service(receiver):
    with socket.socket() as service:
        service.bind(("127.0.0.1", 0))
        service.listen()
        effect, warnings = run_with(f"127.0.0.1:{service.getsockname()[1]}", receiver)
    assert len(warnings) == 1 and "nothing is listening there" in warnings[0]


def test_a_port_in_use_by_a_program_that_never_reads(receiver):
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as stuck:
        stuck.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1024)
        stuck.bind(("127.0.0.1", 0))
        effect, warnings = run_with(f"127.0.0.1:{stuck.getsockname()[1]}", receiver)
    assert warnings == [] and effect.destinations[0].sent == len(receiver.packets)


def test_an_unreachable_host(receiver):
    # TEST-NET-2 (RFC 5737) is never a real host: depending on the network the datagrams are
    # refused, unroutable, or silently lost. Whichever it is, the show must not notice.
    effect, warnings = run_with("198.51.100.1:9000", receiver)
    assert len(warnings) <= 1 and all(w.startswith("destination 198.51.100.1:9000: ") for w in warnings)


def test_a_name_that_takes_forever_to_resolve_never_holds_the_show(receiver, monkeypatch):
    """A fake slow DNS (no real one can be made to hang on demand here): blocks until released."""
    release = threading.Event()
    real = socket.getaddrinfo

    def slow_getaddrinfo(host, *args, **kwargs):
        if host == "slow.example":
            release.wait(30)
        return real(host, *args, **kwargs)

    monkeypatch.setattr(destinations.socket, "getaddrinfo", slow_getaddrinfo)
    try:
        effect, warnings = run_with("slow.example:9000", receiver)
        assert not effect.destinations[0].resolved.is_set() and effect.destinations[0].sent == 0
    finally:
        release.set()


def test_warnings_go_to_stderr_by_default(receiver, capfd):
    effect = make_osc(destinations=["no-such-host.invalid:9000"])
    run_show([effect], script=Script(n=3))
    effect.destinations[0].resolved.wait(10)
    assert "issv: osc: destination no-such-host.invalid:9000: cannot resolve" in capfd.readouterr().err
