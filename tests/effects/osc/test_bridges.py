"""OSCeleton and Synapse from users with bodies, as their own consumers check them.

OSCeleton's Processing examples accept `/joint` only with the type tags "sifff" and the user
messages with "i" (checkTypetag): liblo's oscdump shows the tags exactly as sent. Synapse's
consumers ask for what they want with keep-alives; the client here behaves as the published
Python Synapse client (Eran Egozy's kinect.py, MIT 21M.385: not on PyPI): it listens on its port
in body mode, the default, and sends `/<joint>_trackjointpos 1` for its joints every 3 s.
"""
import re
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from pythonosc import dispatcher, osc_server, udp_client

from backends.oscin.backend import OscInBackend, OscInOptions
from backends.replay import ReplayBackend
from effects.osc.osceleton import JOINTS, OSCELETON_TEXT, normalised
from effects.osc.synapse import DETECTORS, SYNAPSE_TEXT
from host import HandState, Joint, User, frames_of
from host.recording import Recording
from tests.backends.network.test_users import duet as duet_session
from tests.backends.oscin.helpers import env, replay
from tests.effects.osc.helpers import PureData, Receiver, as_sent, body_at, free_port, make_osc, run_show_with, run_users

def documented(text: str) -> dict[str, str]:
    """The address -> type tags table of a preset's text (what `issv osc-schema NAME` prints)."""
    return {a: t.replace(" ", "") for a, t in re.findall(r"^  (/\S+)\s+((?:[ifs] )*[ifs])\s\s", text, re.M)}


OSCELETON_TAGS = {a.replace("<id>", "2"): t for a, t in documented(OSCELETON_TEXT).items()}


def duet(i: int) -> tuple[User, ...]:
    """User 1 from frame 0 to 19 (LOST at 20), its right hand resting but for frames 5-9; user 2
    from frame 8, calibrating (no joints, a centre of mass) until frame 11, its left elbow unsure."""
    users = []
    if i <= 20:
        state = HandState.NEW if i == 0 else HandState.LOST if i == 20 else HandState.TRACKING
        users.append(User(1, state, body_at(-600, i, raised=5 <= i < 10), (-600.0, 150.0, 2200.0)))
    if i >= 8:
        joints = body_at(600, i) if i >= 12 else {}
        if joints:
            joints["left_elbow"] = Joint(joints["left_elbow"].position, 0.3)
        users.append(User(2, HandState.NEW if i == 8 else HandState.TRACKING, joints, (600.0, 150.0, 2200.0)))
    return tuple(users)


def test_osceleton_users_type_tags_through_oscdump(oscdump, receiver):
    run_users([make_osc(destinations=[oscdump.address, receiver.address], scheme="osceleton")], duet, 30)
    lines = oscdump.stop(until=lambda lines: any(line[1] == "/lost_user" for line in lines))
    assert {line[1] for line in lines} == set(OSCELETON_TAGS)
    assert all(line[2] == OSCELETON_TAGS[line[1]] for line in lines)
    assert receiver.wait_for(lambda r: r.messages("/lost_user"))
    messages = receiver.messages()
    events = [(a, args[0]) for a, _, args in messages if a in ("/new_user", "/new_skel", "/lost_user")]
    # each user once; /new_skel with the first joints (user 2 calibrates first); lost once, when it leaves
    assert events == [("/new_user", 1), ("/new_skel", 1), ("/new_user", 2), ("/new_skel", 2), ("/lost_user", 1)]
    first_joint_2 = next(k for k, m in enumerate(messages) if m[0] == "/joint" and m[2][1] == 2)
    assert messages.index(("/new_skel", "i", [2])) < first_joint_2
    names = [args[0] for a, _, args in messages if a == "/joint" and args[1] == 1]
    every = [name for _, name in JOINTS if name not in ("l_knee", "l_foot", "r_knee", "r_foot")]
    assert " ".join(name for _, name in JOINTS) in " ".join(OSCELETON_TEXT.split())  # documented, in order
    assert names[:len(every)] == every  # OSCeleton's names, in its order
    assert "l_elbow" not in [args[0] for a, _, args in messages if a == "/joint" and args[1] == 2]  # < 0.5
    assert len(names) == len(every) * 20  # every frame of user 1's, resting hand or not
    for _, _, (name, user, x, y, z) in [m for m in messages if m[0] == "/joint"]:
        issv = dict((b, a) for a, b in JOINTS)[name]
        expected = [j.position for u in duet_all() if u.id == user for j in [u.joints.get(issv)] if j]
        assert any((x, y, z) == pytest.approx(normalised(p), rel=1e-6) for p in expected), name
    left, right = (next(args for a, _, args in messages if a == "/joint" and args[:2] == [n, 1])
                   for n in ("l_hand", "r_hand"))
    assert left[2] < right[2]  # the performer's left hand on the smaller x, as OSCeleton mirrors
    com = receiver.messages("/user/2")
    assert com and com[0][2] == pytest.approx([(1280 + 600) / 2560, (1280 - 150) / 2560, 2200 * 7.8125 / 10000])


def duet_all() -> list[User]:
    return [u for i in range(30) for u in duet(i)]


class SynapseClient:
    """A Synapse consumer as the published Python client is: listens on its port, in body mode by
    default, and sends `/<joint>_trackjointpos <mode>` for each of its joints every 3 s."""

    HEARTBEAT_S = 3.0
    MODES = {"_pos_body": 1, "_pos_world": 2, "_pos_screen": 3}

    def __init__(self, keepalive_port: int, joints: list[str], mode: str = "_pos_body") -> None:
        self.joints, self.mode = joints, mode
        self.received: list[tuple[float, str, tuple]] = []
        d = dispatcher.Dispatcher()
        d.set_default_handler(lambda address, *args: self.received.append((time.monotonic(), address, args)))
        self.server = osc_server.ThreadingOSCUDPServer(("127.0.0.1", 0), d)
        self.port = self.server.server_address[1]
        self.client = udp_client.SimpleUDPClient("127.0.0.1", keepalive_port)
        self.sent: dict[str, list[float]] = {j: [] for j in joints}
        self._stop = threading.Event()
        threading.Thread(target=self.server.serve_forever, daemon=True).start()

    def start(self) -> None:
        """Begin the heartbeats (once Synapse runs: before, nothing listens for them)."""
        threading.Thread(target=self._heartbeat, daemon=True).start()

    def _heartbeat(self) -> None:
        while not self._stop.is_set():
            for joint in self.joints:
                self.client.send_message(f"/{joint}_trackjointpos", self.MODES[self.mode])
                self.sent[joint].append(time.monotonic())
            self._stop.wait(self.HEARTBEAT_S)

    def ask_once(self, joint: str, mode: str) -> float:
        self.client.send_message(f"/{joint}_trackjointpos", self.MODES[mode])
        return time.monotonic()

    def of(self, address: str) -> list[tuple[float, tuple]]:
        return [(t, args) for t, a, args in list(self.received) if a == address]

    def close(self) -> None:
        self._stop.set()
        self.server.shutdown()
        self.server.server_close()


def test_a_synapse_client_in_body_mode_gets_positions_relative_to_the_torso():
    port = free_port()
    client = SynapseClient(port, ["righthand", "lefthand", "head", "torso"])
    try:
        effect = make_osc(destinations=[f"127.0.0.1:{client.port}"], scheme="synapse", keepalive=f"127.0.0.1:{port}")
        asked = {}

        def users(i: int) -> tuple[User, ...]:
            if i == 0:
                client.start()
            if i == 3:
                asked["leftelbow"] = client.ask_once("leftelbow", "_pos_world")
            return (User(1, HandState.NEW if i == 0 else HandState.TRACKING, body_at(-100, i, raised=i % 60 < 20)),)

        run_users([effect], users, 150)  # 5 s: two heartbeats, past one keep-alive's 3.1 s
        time.sleep(0.2)
    finally:
        client.close()
    # tracked all along: the right hand coming down does not stop the skeleton
    assert [args for _, args in client.of("/tracking_skeleton")] == [(1,)]
    body = client.of("/righthand_pos_body")
    assert len(body) >= 140
    # kept alive: a lapsed request would leave a gap until the next heartbeat (about 3 s); a loaded
    # machine may stall the show for a fraction of that
    assert max(b - a for (a, _), (b, _) in zip(body, body[1:])) < 1.5
    resting = [args for _, args in body if args[1] < 0]
    raised = [args for _, args in body if args[1] > 0]
    assert resting and raised
    assert resting[0] == pytest.approx((320.0, -200.0, -20.0))  # right_hand - torso, Synapse's _pos_body
    assert client.of("/torso_pos_body")[0][1] == (0.0, 0.0, 0.0)
    assert client.of("/head_pos_body")[0][1] == pytest.approx((-110.0, 700.0, 0.0))  # from the right hip
    assert client.of("/lefthand_pos_body") and not client.of("/leftelbow_pos_body")
    # nothing it did not ask for; one request lasts 3.1 s
    addresses = {a for _, a, _ in client.received}
    assert not {a for a in addresses if a.endswith(("_pos_world", "_pos_screen"))} - {"/leftelbow_pos_world"}
    elbow = client.of("/leftelbow_pos_world")
    assert elbow and elbow[-1][0] - asked["leftelbow"] == pytest.approx(3.1, abs=0.25)
    assert not client.of("/rightknee_pos_body")  # a joint the backend does not report


def test_synapse_keepalive_off_sends_every_joint_in_every_space(receiver):
    users = lambda i: (User(1, HandState.TRACKING, body_at(0, i)),)  # noqa: E731
    run_users([make_osc(destinations=[receiver.address], scheme="synapse", keepalive="off")], users, 5)
    assert receiver.wait_for(lambda r: len(r.messages("/closesthand_pos_screen")) == 5)
    expected = [f"/{name}_pos_{space}" for name, joint, ref in DETECTORS
                if joint in body_at(0, 0) or name == "closesthand"
                for space in ("world", "body", "screen") if space != "body" or ref in body_at(0, 0)]
    bundle = [m[0] for m in receiver.packets[0].messages]
    assert bundle == ["/tracking_skeleton"] + expected  # Synapse's order: detectors, then world, body, screen
    tags = documented(SYNAPSE_TEXT)
    for address, types, _ in receiver.packets[0].messages:
        joint, _, space = address[1:].rpartition("_pos_")
        assert types == tags[f"/<joint>_pos_{space}" if joint else address]
    listed = " ".join(SYNAPSE_TEXT.split("joint  ")[1].split("(Synapse's order")[0].split())
    assert listed == " ".join(name for name, _, _ in DETECTORS)


def _listening(port: int) -> bool:
    """Whether some process holds this UDP port (osc-in has bound it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("0.0.0.0", port))
        except OSError:
            return True
    return False


def test_a_recorded_duet_plays_back_to_osceleton_with_its_users(tmp_path, receiver):
    """`issv record` (osc-in fed a duet by `issv osc-replay`) in processes of their own; the
    recording's users, replayed, make OSCeleton's user messages as the live show would."""
    session, profile, osc_port = duet_session(tmp_path)
    out = tmp_path / "duet.mcap"
    record = subprocess.Popen([sys.executable, "-m", "host", "record", str(profile), "-o", str(out)],
                              env=env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not _listening(osc_port) and record.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    sender = replay(session, osc_port)
    assert sender.wait(60) == 0, sender.stderr.read()
    _, err = record.communicate(timeout=60)
    assert record.returncode == 0, err
    with Recording(out) as rec:
        frames = list(rec.frames())
    assert {tuple(sorted(u.id for u in f.users)) for f in frames} >= {(1,), (1, 2)}
    assert all(u.joints["torso"].position == pytest.approx((900.0, 0.0, 2100.0), abs=0.01)
               for f in frames for u in f.users if u.id == 2 and "torso" in u.joints)
    # paced as a show replays it: unpaced, a busy machine delivered only the newest frame, the last,
    # where both users are already gone (newest wins), and no user message went out at all
    backend = ReplayBackend(None, ReplayBackend.Options(path=str(out), realtime=True))
    run_show_with(backend, [make_osc(destinations=[receiver.address], scheme="osceleton")])
    assert receiver.wait_for(lambda r: len(r.messages("/lost_user")) == 2)
    events = [(a, args[0]) for a, _, args in receiver.messages() if a in ("/new_user", "/new_skel", "/lost_user")]
    # each user's /new_skel after its /new_user (osc-in may cut a frame between OSCeleton's /new_user
    # and the first joints when the machine is busy: a user calibrating for a frame, as live)
    assert sorted(events[:4]) == [("/new_skel", 1), ("/new_skel", 2), ("/new_user", 1), ("/new_user", 2)]
    assert events.index(("/new_user", 1)) < events.index(("/new_skel", 1)) < events.index(("/new_skel", 2))
    assert events.index(("/new_user", 2)) < events.index(("/new_skel", 2))
    assert sorted(events[4:]) == [("/lost_user", 1), ("/lost_user", 2)]
    torso = [args for a, _, args in receiver.messages("/joint") if args[:2] == ["torso", 2]]
    assert torso and torso[0][2:] == pytest.approx(list(normalised((900.0, 0.0, 2100.0))), rel=1e-5)


BRIDGES_PD = Path(__file__).with_name("bridges-echo.pd")


@pytest.fixture
def bridges_pd():
    """Pure Data running bridges-echo.pd, asking the Synapse keep-alive port given by `start(port)`."""
    started = []

    def start(keepalive_port: int | None = None) -> PureData:
        sends = (f"issv-synapse {keepalive_port}",) if keepalive_port else ()
        pd = PureData(Receiver(), BRIDGES_PD, sends)
        started.append(pd)
        return pd

    yield start
    for pd in started:
        pd.close()
        pd.echo.close()


def test_a_pd_patch_for_osceleton_parses_every_message(bridges_pd, receiver):
    pd = bridges_pd()
    run_users([make_osc(destinations=[pd.address, receiver.address], scheme="osceleton")], duet, 30)
    assert receiver.wait_quiet()  # user 1 leaves at frame 20: its /lost_user is not the last message
    sent = [m for m in receiver.messages() if m[0] in ("/joint", "/new_user", "/new_skel", "/lost_user")]
    assert pd.echo.wait_for(lambda r: len(r.messages()) == len(sent) + 1)  # and /echo/ready
    for (address, _, args), (echoed, tags, back) in zip(sent, pd.echo.messages()[1:]):
        assert echoed == "/echo" + address
        assert list(back) == as_sent(args)  # ids come back as Pd floats, positions as sent
    assert "error" not in pd.close()


def test_a_pd_patch_for_synapse_keeps_body_positions_coming(bridges_pd):
    port = free_port()
    pd = bridges_pd(port)
    effect = make_osc(destinations=[pd.address], scheme="synapse", keepalive=f"127.0.0.1:{port}")
    run_users([effect], lambda i: (User(1, HandState.TRACKING, body_at(0, i)),), 180)  # 6 s: past 3.1 s
    assert pd.echo.wait_for(lambda r: len(r.messages("/echo/righthand_pos_body")) >= 100)
    assert pd.echo.messages("/echo/tracking_skeleton") == [("/echo/tracking_skeleton", "f", [1.0])]
    assert {tuple(m[2]) for m in pd.echo.messages("/echo/righthand_pos_body")} == {(320.0, -200.0, -20.0)}
    assert "error" not in pd.close()


def test_issv_run_a_synthetic_handover_to_osceleton_and_synapse(tmp_path, oscdump, receiver):
    """The product path: `issv run --headless` of a profile (synthetic handover scene, truth
    backend) with both presets; oscdump reads OSCeleton's, a socket Synapse's (keepalive off)."""
    profile = tmp_path / "handover.toml"
    profile.write_text(f'[source]\nname = "synthetic"\nscene = "handover"\nwidth = 320\nheight = 240\n'
                       f'[backend]\nname = "truth"\n'
                       f'[[effects]]\nname = "osc"\nscheme = "osceleton"\ndestinations = ["{oscdump.address}"]\n'
                       f'[[effects]]\nname = "osc"\nscheme = "synapse"\nkeepalive = "off"\n'
                       f'destinations = ["{receiver.address}"]\n')
    run = subprocess.run([sys.executable, "-m", "host", "run", str(profile), "--headless", "--fast", "--size",
                          "320x240", "--no-reload", "--seconds", "12"], env=env(), capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    lines = oscdump.stop(until=lambda lines: sum(line[1] == "/lost_user" for line in lines) >= 1)
    assert all(line[2] == OSCELETON_TAGS[line[1]] for line in lines if line[1] in OSCELETON_TAGS)
    events = [(line[1], int(line[3])) for line in lines if line[1] in ("/new_user", "/new_skel", "/lost_user")]
    users = {u for _, u in events}
    assert len(users) == 2 and ("/lost_user", min(users)) in events  # one leaves while the other enters
    for user in users:
        mine = [e for e, u in events if u == user]
        assert mine[:2] == ["/new_user", "/new_skel"] and mine.count("/new_user") == mine.count("/new_skel")
    assert receiver.messages("/tracking_skeleton")[0] == ("/tracking_skeleton", "i", [1])
    assert receiver.messages("/righthand_pos_body") and receiver.messages("/head_pos_body")


def test_the_synapse_preset_feeds_osc_in_which_asks_with_keepalives():
    """issv's own Synapse reader (osc-in, scheme synapse) as the consumer: it asks for world
    positions with `/<joint>_trackjointpos 2` every few seconds and rebuilds the user from them."""
    keepalive = free_port()
    backend = OscInBackend(None, OscInOptions(port=0, scheme="synapse", synapse_port=keepalive, end_after_idle_s=3.0),
                           warn=lambda text: None)
    frames = []

    def collect() -> None:
        with backend as b:
            frames.extend(frames_of(b))

    reader = threading.Thread(target=collect, daemon=True)
    reader.start()
    deadline = time.monotonic() + 10
    while getattr(backend, "port", None) is None and time.monotonic() < deadline:
        time.sleep(0.02)
    effect = make_osc(destinations=[f"127.0.0.1:{backend.port}"], scheme="synapse", keepalive=f"127.0.0.1:{keepalive}")
    run_users([effect], lambda i: (User(1, HandState.TRACKING, body_at(-100, i)),), 60)
    reader.join(timeout=20)
    bodies = [u for f in frames for u in f.users if len(u.joints) >= 8]
    assert len(bodies) >= 30
    for joint in ("right_hand", "left_elbow", "head", "torso"):
        assert bodies[-1].joints[joint].position == pytest.approx(body_at(-100, 0)[joint].position, abs=0.01)
