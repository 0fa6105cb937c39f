"""osc-in over real UDP from real processes: issv's own OSCeleton output, `issv osc-replay`, Pd."""
import shutil
import socket
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest

from backends.engine.recognizer import GestureRecognizer
from host import HandState, Side, frames_of
from tests.backends.oscin.helpers import ROOT, backend, body_at, collect, env, hands_at, replay, write_session
from tests.effects.osc.helpers import Receiver, hand_at

SHOW = """
from tests.effects.osc.helpers import Script, make_osc, run_show
run_show([make_osc(destinations=["127.0.0.1:{port}"], scheme="osceleton")], realtime=True, script=Script(n=30))
"""


def _states(frames, user):
    """The user's states frame by frame, runs collapsed: [new, tracking, lost]."""
    out = []
    for f in frames:
        for u in f.users:
            if u.id == user and (not out or out[-1] != u.state.value):
                out.append(u.state.value)
    return out


def test_the_osc_effects_osceleton_output_comes_back_as_a_user_in_mm():
    """A real show (scripted performer -> truth -> osc effect, OSCeleton preset) in another
    process; osc-in rebuilds user 1 with both hands where the performer had them."""
    with backend() as b:
        sender = subprocess.Popen([sys.executable, "-c", SHOW.format(port=b.port)], env=env(), cwd=ROOT)
        frames = collect(b)
    assert sender.wait(30) == 0
    assert _states(frames, 1) == ["new", "tracking", "lost"]  # lost by the timeout: the show just ended
    truth = {side: [hand_at(side, i) for i in range(30)] for side in (Side.LEFT, Side.RIGHT)}
    seen = 0
    for f in frames:
        assert [(h.id, h.side) for h in f.hands] in ([], [(11, Side.LEFT), (12, Side.RIGHT)])
        for h in f.hands:
            nearest = min(truth[h.side], key=lambda p: sum((a - b) ** 2 for a, b in zip(p, h.position)))
            assert h.position == pytest.approx(nearest, abs=0.01)  # float32 on the wire: well under a mm
            assert h.user_id == 1 and h.extended is True  # no torso sent: every hand counts as out
            seen += 1
    assert seen >= 2 * 20  # a loaded machine may fold two bridge frames into one of ours
    assert frames[0].depth.width == 640 and not frames[0].depth.data.any()  # geometry for effects, no readings
    assert frames[-1].users[0].state is HandState.LOST and frames[-1].hands[0].state is HandState.LOST


def test_two_users_one_stops_and_is_lost_after_the_timeout(tmp_path):
    """Users 1 and 2 swipe right together; user 2's messages then stop (no /lost_user): it is LOST
    after lost_timeout_s while user 1 goes on, and user 1 leaves with /lost_user."""
    frames = [hands_at(1, i, -600) + (hands_at(2, i, 600) if i < 36 else []) for i in range(60)] + [[]]
    bodies = [{**body_at(1, -600), **(body_at(2, 600) if i < 36 else {})} for i in range(60)] + [{}]
    session = write_session(tmp_path / "duet.txt", frames, bodies=bodies)
    session.write_text("".join(line + ";" for line in session.read_text().split(";")
                               if "/lost_user 2" not in line and line.strip()))
    with backend(lost_timeout_s=0.4) as b:
        sender = replay(session, b.port)
        got = collect(b)
    assert sender.wait(30) == 0
    assert _states(got, 1) == ["new", "tracking", "lost"] and _states(got, 2) == ["new", "tracking", "lost"]
    start = got[0].time  # untagged: the clock runs from the first message's arrival
    lost_2 = next(f.time - start for f in got for u in f.users if u.id == 2 and u.state is HandState.LOST)
    lost_1 = next(f.time - start for f in got for u in f.users if u.id == 1 and u.state is HandState.LOST)
    assert 36 / 30 + 0.3 < lost_2 < 36 / 30 + 1.5  # its last message, then the 0.4 s timeout
    assert lost_1 > lost_2 + 0.2
    assert any(u.id == 1 and u.state is HandState.TRACKING for f in got if f.time - start > lost_2 for u in f.users)
    swipes = sorted((g.user_id, g.hand_id, g.side) for f in got for g in f.gestures
                    if g.name == "swipe_right" and g.state.value == "complete")
    assert swipes == [(1, 12, Side.RIGHT), (2, 22, Side.RIGHT)]


def test_osc_in_gestures_equal_the_recogniser_on_the_same_hands(tmp_path):
    """What osc-in finds through UDP is what the recogniser finds on the hands directly, at the
    very same times: the replay stamps the session's own times (`--time-tags`), so a busy machine
    that delays datagrams changes nothing (arrival times are tested with the duet above)."""
    frames = [hands_at(1, i) for i in range(45)]
    body = body_at(1)[1]
    recognizer = GestureRecognizer()
    direct = [g for i, hands in enumerate(frames) for g in recognizer.update(i / 30, hands, body, True)]
    direct += recognizer.finish()
    with backend() as b:
        sender = replay(write_session(tmp_path / "one.txt", frames, bodies=[{1: body}] * 45), b.port, "--time-tags")
        frames = collect(b)
    assert sender.wait(30) == 0
    got = [g for f in frames for g in f.gestures]
    assert direct and [(g.name, g.side) for g in got] == [(g.name, g.side) for g in direct]
    for a, b_ in zip(got, direct):
        assert a.timestamp == pytest.approx(b_.timestamp, abs=1e-6)  # ms deltas written to 7 digits
        assert a.position == pytest.approx(b_.position, abs=0.01)


def test_bad_messages_are_counted_and_reported_once_per_kind():
    warnings = []
    with backend(end_after_idle_s=0.3) as b:
        b.warn = b.receiver.warn = warnings.append
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            bad = [b"not osc at all", b"/joint\0\0,siff\0\0\0head\0\0\0\0\0\0\0\x01",  # arguments cut short
                   b"/elsewhere\0\0,\0\0\0"] * 3
            for data in bad:
                s.sendto(data, ("127.0.0.1", b.port))
        collect(b)
    assert b.receiver.bad == Counter({"datagrams that are not OSC": 6, "unknown OSCeleton address": 3})
    assert len([w for w in warnings if w.startswith("ignoring")]) == 2
    assert warnings[-1] == "9 messages, ignored: 6 datagrams that are not OSC, 3 unknown OSCeleton address" or \
        "ignored: 6 datagrams that are not OSC, 3 unknown OSCeleton address" in warnings[-1]


def test_a_quiet_bridges_frames_are_made_now_not_captured_long_ago():
    """OSCeleton says /new_user, then nothing until the skeleton is calibrated: the frames that keep
    the user (until LOST) carry no message, so their capture time is when they are made; the
    show's capture -> effect latency stays that of the frames, not the silence's length. Their
    source time stays that of the last message: they bring nothing new, and a learned recogniser
    fed the same hands at later times would read a pause the performer never made."""
    from pythonosc.udp_client import SimpleUDPClient
    with backend(end_after_idle_s=1.2, lost_timeout_s=0.8) as b:
        SimpleUDPClient("127.0.0.1", b.port).send_message("/new_user", 1)
        lags, made, times = [], [], set()
        for frame in frames_of(b):
            lags.append(time.time() - frame.capture_time)
            made.append(time.monotonic())
            times.add(frame.time)
    assert made[-1] - made[0] > 0.6 and len(lags) > 10  # the user kept, then LOST, with no message
    assert max(lags) < 0.2, lags
    assert len(times) == 1  # the /new_user's


def test_synapse_is_sent_the_keep_alive_it_needs():
    synapse = Receiver()  # stands where Synapse listens for /<joint>_trackjointpos
    try:
        with backend(scheme="synapse", synapse_port=synapse.port, end_after_idle_s=0.2) as b:
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
                from host.osc import Message, encode
                s.sendto(encode(Message("/righthand_pos_world", (("f", 10.0), ("f", 20.0), ("f", 1500.0))), True),
                         ("127.0.0.1", b.port))
            frames = collect(b)
        assert synapse.wait_for(lambda r: r.messages("/righthand_trackjointpos"))
        assert synapse.messages("/righthand_trackjointpos")[0][1:] == ("i", [2])  # 2: world positions
        assert frames[0].hands[0].position == (10.0, 20.0, 1500.0) and frames[0].hands[0].side is Side.RIGHT
    finally:
        synapse.close()


QLIST_SENDER = """#N canvas 0 50 700 320 12;
#X obj 20 20 r issv-port;
#X msg 20 50 connect 127.0.0.1 \\$1;
#X obj 20 250 netsend -u -b;
#X obj 250 20 r issv-file;
#X msg 250 50 read \\$1 \\, bang;
#X obj 250 80 qlist;
#X obj 20 110 r osceleton;
#X obj 20 140 route /joint /new_user /new_skel /lost_user;
#X obj 20 170 oscformat joint;
#X obj 150 170 oscformat new_user;
#X obj 300 170 oscformat new_skel;
#X obj 450 170 oscformat lost_user;
#X obj 20 200 list prepend send;
#X obj 20 225 list trim;
#X obj 600 140 list;
#X connect 0 0 1 0;
#X connect 1 0 2 0;
#X connect 3 0 4 0;
#X connect 4 0 5 0;
#X connect 6 0 7 0;
#X connect 7 0 14 0;
#X connect 14 0 8 0;
#X connect 7 1 9 0;
#X connect 7 2 10 0;
#X connect 7 3 11 0;
#X connect 8 0 12 0;
#X connect 9 0 12 0;
#X connect 10 0 12 0;
#X connect 11 0 12 0;
#X connect 12 0 13 0;
#X connect 13 0 2 0;
"""


@pytest.mark.skipif(shutil.which("pd") is None, reason="Pure Data is not installed (apt-get install puredata-core)")
def test_pure_data_playing_the_session_with_qlist(tmp_path):
    """Pd reads the session with [qlist] and sends it with [oscformat] and [netsend -u -b], as a Pd
    patch forwarding a tracker would: loose messages, every number a float."""
    frames = [hands_at(1, i) for i in range(40)] + [[]]
    session = write_session(tmp_path / "session.txt", frames)
    patch = tmp_path / "qlist-sender.pd"
    patch.write_text(QLIST_SENDER)
    with backend() as b:
        pd = subprocess.Popen(["pd", "-nogui", "-noaudio", "-stderr", "-open", str(patch),
                               "-send", f"issv-port {b.port}", "-send", f"issv-file symbol {session}"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        try:
            got = collect(b)
        finally:
            pd.kill()
            errors = pd.communicate()[1]
    assert "error" not in errors.lower()
    assert _states(got, 1) == ["new", "tracking", "lost"] and b.receiver.bad == Counter()
    sent = [(h.side, h.position) for hands in frames for h in hands]
    received = [(h.side, h.position) for f in got for h in f.hands if h.in_view]
    for side, position in received:  # Pd's 32-bit floats, written with 7 digits: within 0.01 mm
        assert min(sum((a - b) ** 2 for a, b in zip(position, p)) for s, p in sent if s is side) < 1e-4
    assert len({p for _, p in received}) >= 0.9 * len({p for _, p in sent})  # loose messages regrouped


def test_osc_replay_keeps_the_timing_and_names_bad_lines(tmp_path):
    session = tmp_path / "s.txt"
    session.write_text("0 osceleton /new_user 1;\n400 osceleton /new_skel 1;\n600 osceleton /lost_user 1;\n")
    inbox = Receiver()
    try:
        proc = replay(session, inbox.port, "--speed", "2")
        assert proc.wait(60) == 0  # a loaded machine takes seconds to start a Python process
        assert inbox.wait_for(lambda r: len(r.packets) == 3)
        at = [p.at for p in inbox.packets]
        # at half the recorded gaps (0.4 s, 0.6 s); a busy machine delays an arrival by tens of ms.
        # 0.1 s still tells them from the recorded gaps and from no pacing (0 s)
        assert at[1] - at[0] == pytest.approx(0.2, abs=0.1) and at[2] - at[1] == pytest.approx(0.3, abs=0.1)
        assert [m[:2] for p in inbox.packets for m in p.messages] == [("/new_user", "i"), ("/new_skel", "i"),
                                                                      ("/lost_user", "i")]
    finally:
        inbox.close()
    session.write_text("0 osceleton /new_user 1;\nten osceleton /joint head 1 0.5 0.5 1;\n")
    proc = replay(session, 9)
    assert proc.wait(60) == 1
    assert f"{session}:2: expected '<ms delta>" in proc.stderr.read()


def test_a_port_in_use_is_one_clear_error():
    from host.errors import UserError
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("0.0.0.0", 0))
        port = taken.getsockname()[1]
        with pytest.raises(UserError, match=f"backend 'osc-in': cannot listen on udp 0.0.0.0:{port}"):
            backend(port=port).init()
