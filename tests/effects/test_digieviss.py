"""DigiEVISS: grab spheres by gesture, carry, release, link on touch, generate Forensic Lucid."""
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from host import (DepthFrame, Frame, Gesture, GestureState, GestureType, Hand, HandState,
                  Intrinsics, Side, Stage, User, user_colour)
from host.assemble import make_backend, make_effects
from host.loop import Show
from host.profile import load
from effects.digieviss import DigiEVISS
from effects.digieviss import lucid
from effects.digieviss.scene import HandKey, Scene, Sphere
from tests.host.render.stage import K as STAGE_K
from tests.host.render.stage import depth_image, lit, requires_gl, run_show

K = Intrinsics(100, 100, 8, 6)
RIGHT, LEFT = 1, 2

LISTING_5_1 = """es
where
    observation o0 = ("A printed" => "very well", 1, 0, 0.85, 1234);
    observation o1 = ("B printed" => "well", 1, 0, 0.65, 2341);
    observation o2 = ("C printed" => "not very well", 1, 0, 0.35, 3412);
    observation o3 = ("D printed" => "not well", 1, 0, 0.15, 4123);
    observation sequence os1 = {o0, o3};
    observation sequence os2 = {o1, o2};
    evidential statement es1 = {os1, os2};
end
"""


def frames(steps):
    """Scripted hand positions and clicks at 30 Hz as the frames a backend would report."""
    for i, (hands, clicks) in enumerate(steps, start=1):
        t = i / 30
        depth = DepthFrame(np.zeros((12, 16), np.uint16), K, i, t)
        hand_objs = tuple(Hand(h, HandState.TRACKING, p, Side.RIGHT if h == RIGHT else Side.LEFT)
                          for h, p in hands.items())
        gestures = tuple(Gesture(GestureType.PUSH, GestureState.COMPLETE, hands[h], h, timestamp=t) for h in clicks)
        yield Frame(i, depth.capture_time, depth, hand_objs, gestures, "script")


def glide(hand, start, end, frames, other=None):
    """`hand` moves in a straight line; `other` (id -> position) stays put."""
    return [({hand: tuple(np.add(start, np.multiply(np.subtract(end, start), (k + 1) / frames))), **(other or {})}, ())
            for k in range(frames)]


def click(hands, hand):
    return [(hands, (hand,))]


def play(steps, tmp_path, make=frames, **options):
    """Every frame in order, as the show loop delivers them when it keeps up: gestures, then the frame."""
    row = {"row_center": (0.0, 300.0, 2000.0), "spacing_mm": 400.0}  # o0..o3 at x = -600, -200, 200, 600
    effect = DigiEVISS(DigiEVISS.Options(program=str(tmp_path / "out.ipl"), **{"log": False, **row, **options}))
    effect.setup(Stage((64, 48), 30.0, "script"))
    for frame in make(steps):
        for gesture in frame.gestures:
            effect.on_gesture(gesture)
        effect.on_frame(frame)
    effect.close()
    return effect


def listing_5_1_script(row_y=300.0, z=2000.0):
    """Right hand carries o3 next to o0; then both hands pick up o1 and o2 and bring them together."""
    o0, o1, o2, o3 = [(x, row_y, z) for x in (-600.0, -200.0, 200.0, 600.0)]
    above, drop = (-450.0, row_y + 350, z), (-450.0, row_y - 180, z)  # drop: touches o0, not o1
    steps = glide(RIGHT, (0, 0, z), o3, 10)
    steps += click({RIGHT: o3}, RIGHT)
    steps += glide(RIGHT, o3, (600.0, row_y + 350, z), 10) + glide(RIGHT, (600.0, row_y + 350, z), above, 30)
    steps += glide(RIGHT, above, drop, 20)
    steps += click({RIGHT: drop}, RIGHT)  # let go
    steps += glide(RIGHT, drop, (0.0, 0.0, z), 10)
    steps += glide(LEFT, (0, 0, z), o1, 10, {RIGHT: (0.0, 0.0, z)})
    steps += glide(RIGHT, (0, 0, z), o2, 10, {LEFT: o1})
    steps += click({LEFT: o1, RIGHT: o2}, LEFT) + click({LEFT: o1, RIGHT: o2}, RIGHT)
    steps += [({LEFT: (-200.0 + 8 * k, row_y, z), RIGHT: (200.0 - 8 * k, row_y, z)}, ()) for k in range(1, 20)]
    return steps


def test_the_thesis_scene_generates_listing_5_1(tmp_path):
    effect = play(listing_5_1_script(), tmp_path)
    assert (tmp_path / "out.ipl").read_text() == LISTING_5_1
    assert effect.scene.links() == [("o0", "o3"), ("o1", "o2")]


def test_fby_notation(tmp_path):
    play(listing_5_1_script(), tmp_path, notation="fby")
    text = (tmp_path / "out.ipl").read_text()
    assert "observation sequence os1 = o0 fby o3;" in text and "observation sequence os2 = o1 fby o2;" in text


def test_no_grab_outside_the_radius_and_no_program_without_links(tmp_path):
    z = 2000.0
    near_o1 = (-200.0 + 125.0, 300.0, z)  # 125 mm from o1's centre, radius 120
    steps = glide(RIGHT, (0, 0, z), near_o1, 5) + click({RIGHT: near_o1}, RIGHT)
    steps += glide(RIGHT, near_o1, (200.0, 300.0, z), 20)
    effect = play(steps, tmp_path)
    assert not effect.scene.grips and effect.scene.spheres[1].center == (-200.0, 300.0, z)
    assert not (tmp_path / "out.ipl").exists()


A, B, H = HandKey(1, "right"), HandKey(1, "left"), HandKey(2, "right")


def sphere_row(n=3, radius=100.0, spacing=400.0):
    return [Sphere(f"o{i}", f"data{i}", (i * spacing, 0.0, 2000.0), radius) for i in range(n)]


def test_a_grabbed_sphere_follows_the_hand_without_jumping():
    scene = Scene(sphere_row())
    scene.update({A: (30.0, 40.0, 1900.0)}, 0.0)
    scene.grab_or_release(A, (30.0, 40.0, 1900.0), 0.0, grab=True, release=True)
    scene.update({A: (130.0, -60.0, 1800.0)}, 0.1)
    assert scene.spheres[0].center == pytest.approx((100.0, -100.0, 1900.0))


def test_release_by_gesture_then_the_sphere_stays():
    scene = Scene(sphere_row())
    scene.grab_or_release(A, (0.0, 0.0, 2000.0), 0.0, grab=True, release=True)
    scene.update({A: (50.0, 0.0, 2000.0)}, 0.1)
    scene.grab_or_release(A, (50.0, 0.0, 2000.0), 0.2, grab=True, release=True)
    scene.update({A: (200.0, 0.0, 2000.0)}, 0.3)
    assert not scene.grips and scene.spheres[0].center == (50.0, 0.0, 2000.0)


def test_release_when_the_hand_is_out_of_sight_or_held_too_long():
    scene = Scene(sphere_row(), lost_release_s=0.5, hold_timeout_s=2.0)
    scene.grab_or_release(A, (0.0, 0.0, 2000.0), 0.0, grab=True, release=False)
    scene.update({}, 0.4)
    assert A in scene.grips  # a short occlusion does not drop it
    scene.update({}, 0.6)
    assert not scene.grips
    scene.grab_or_release(B, (400.0, 0.0, 2000.0), 1.0, grab=True, release=False)
    scene.update({B: (400.0, 0.0, 2000.0)}, 2.9)
    assert B in scene.grips
    scene.update({B: (400.0, 0.0, 2000.0)}, 3.1)
    assert not scene.grips


def test_a_resting_hand_carries_its_sphere_but_links_nothing():
    scene = Scene(sphere_row())  # o0 at x = 0, o1 at 400, radius 100
    scene.grab_or_release(A, (0.0, 0.0, 2000.0), 0.0, grab=True, release=True)
    assert not scene.update({A: (400.0, 50.0, 2000.0)}, 0.1, resting={A})  # over o1, arm down
    assert scene.spheres[0].center == (400.0, 50.0, 2000.0) and not scene.sequences
    assert scene.update({A: (250.0, 0.0, 2000.0)}, 0.2)  # raised beside o1: presented, linked
    assert scene.sequences == [["o0", "o1"]]


def test_a_one_frame_jump_of_the_hand_links_nothing():
    scene = Scene(sphere_row(), touch_s=0.1)  # o0 at x = 0, o1 at 400, radius 100
    scene.grab_or_release(A, (0.0, 0.0, 2000.0), 0.0, grab=True, release=True)
    assert not scene.update({A: (250.0, 0.0, 2000.0)}, 1 / 30)  # touching o1 for one frame...
    assert not scene.update({A: (0.0, -300.0, 2000.0)}, 2 / 30)  # ...then back where it was
    assert not scene.update({A: (250.0, 0.0, 2000.0)}, 3 / 30)  # touching again: the clock restarts
    assert not scene.update({A: (250.0, 0.0, 2000.0)}, 5 / 30) and not scene.sequences
    assert scene.update({A: (250.0, 0.0, 2000.0)}, 6 / 30)  # 0.1 s of touch
    assert scene.sequences == [["o0", "o1"]]


def test_links_chain_left_to_right_and_never_branch():
    scene = Scene(sphere_row(4))
    def carry(sphere, to, t):
        start = scene.spheres[sphere].center
        scene.grab_or_release(H, start, t, grab=True, release=True)
        scene.update({H: to}, t + 0.1)
        scene.grab_or_release(H, to, t + 0.2, grab=True, release=True)
    carry(2, (1000.0, 0.0, 2000.0), 0.0)   # o2 touches o3 from its left (o3 at 1200)
    carry(1, (1380.0, 0.0, 2000.0), 1.0)   # o1 to the right of o3: o2 -> o3 -> o1
    assert scene.sequences == [["o2", "o3", "o1"]]
    carry(0, (1100.0, 80.0, 2000.0), 2.0)  # touches o2 and o3 from above: that would branch
    assert scene.sequences == [["o2", "o3", "o1"]]
    carry(0, (960.0, 80.0, 2000.0), 3.0)   # left of o2, the chain's head: it grows
    assert scene.sequences == [["o0", "o2", "o3", "o1"]]


# -- users: both hands reported all the time, resting ones included (the open engine, osc-in) ---

def user_frames(steps):
    """Frames of a backend that reports users: each step is ({(user, side): (hand id, position,
    extended)}, [(user, side) that click]) at 30 Hz."""
    for i, (hands, clicks) in enumerate(steps, start=1):
        t = i / 30
        depth = DepthFrame(np.zeros((12, 16), np.uint16), K, i, t)
        users = tuple(User(u, HandState.TRACKING) for u in sorted({u for u, _ in hands}))
        hand_objs = tuple(Hand(hand_id, HandState.TRACKING, p, side, user, extended=extended)
                          for (user, side), (hand_id, p, extended) in hands.items())
        gestures = tuple(Gesture(GestureType.CLICK, GestureState.COMPLETE, hands[k][1], hands[k][0], k[1],
                                 timestamp=t, user_id=k[0]) for k in clicks)
        yield Frame(i, depth.capture_time, depth, hand_objs, gestures, "script", users=users)


Z = 2000.0
O0, O1, O2, O3 = [(x, 300.0, Z) for x in (-600.0, -200.0, 200.0, 600.0)]  # play()'s row


def move(user, side, hand_id, start, end, count, extended=True, still=None):
    """`count` steps of one hand gliding start -> end; `still` ((user, side) -> (id, position,
    extended)) are reported too, where they are."""
    return [({(user, side): (hand_id, tuple(np.add(start, np.multiply(np.subtract(end, start), (k + 1) / count))),
                             extended), **(still or {})}, []) for k in range(count)]


def test_a_carried_sphere_stays_in_a_hand_that_comes_down_to_rest(tmp_path):
    """Grab o3, let the arm hang at the side and walk (for far longer than lost_release_s, the
    resting hand even under another id), raise it beside o0: linked, and the click lets go."""
    left = {(1, Side.LEFT): (11, (-300.0, -350.0, Z), False)}  # the other hand, resting all along
    rest = (600.0, -350.0, Z)
    beside_o0 = (-480.0, 100.0, Z)  # 233 mm from o0 (touching: <= 240), 344 from o1
    steps = move(1, Side.RIGHT, 12, (400.0, 0.0, Z), O3, 10, still=left)
    steps += [({(1, Side.RIGHT): (12, O3, True), **left}, [(1, Side.RIGHT)])]
    steps += move(1, Side.RIGHT, 12, O3, rest, 10, still=left)
    steps += move(1, Side.RIGHT, 13, rest, (-480.0, -350.0, Z), 60, extended=False, still=left)  # 2 s at rest
    steps += move(1, Side.RIGHT, 14, (-480.0, -350.0, Z), beside_o0, 15, still=left)
    steps += [({(1, Side.RIGHT): (14, beside_o0, True), **left}, [])] * 5  # held there a moment
    steps += [({(1, Side.RIGHT): (14, beside_o0, True), **left}, [(1, Side.RIGHT)])]
    steps += move(1, Side.RIGHT, 14, beside_o0, (0.0, -350.0, Z), 10, extended=False, still=left)
    effect = play(steps, tmp_path, make=user_frames)
    assert effect.scene.links() == [("o0", "o3")]
    assert effect.scene.spheres[3].center == pytest.approx(beside_o0)  # carried all the way, let go there
    assert not effect.scene.grips
    assert (tmp_path / "out.ipl").read_text().count("observation sequence os1 = {o0, o3};") == 1


def test_two_users_carry_their_own_spheres(tmp_path, capsys):
    """User 1's right hand and user 2's right hand each hold a sphere; user 2's release gesture
    lets go only of its own, and user 1 carries o3 on, its left hand resting."""
    one, two = (1, Side.RIGHT), (2, Side.RIGHT)
    resting = {(1, Side.LEFT): (11, (300.0, -350.0, Z), False)}
    steps = [({one: (12, O3, True), two: (22, O0, True), **resting}, [one, two])]  # both grab
    steps += [({one: (12, O3, True), two: (22, (-600.0, 0.0, Z), True), **resting}, [])] * 3
    steps += [({one: (12, (700.0, 300.0, Z), True), two: (22, (-650.0, 0.0, Z), True), **resting}, [two])]
    steps += [({one: (12, (800.0, 200.0, Z), True), two: (22, (-200.0, -300.0, Z), False), **resting}, [])] * 3
    effect = play(steps, tmp_path, make=user_frames, log=True)
    held = {hand: grip.sphere.id for hand, grip in effect.scene.grips.items()}
    assert {str(hand): sphere for hand, sphere in held.items()} == {"user 1 right hand": "o3"}
    assert effect.scene.spheres[3].center == pytest.approx((800.0, 200.0, Z))
    assert effect.scene.spheres[0].center == pytest.approx((-600.0, 0.0, Z))  # where user 2 let go
    log = capsys.readouterr().out
    assert "user 2 right hand grabbed o0" in log and "user 2 right hand released o0 (release gesture)" in log


def test_observations_preloaded_from_a_forensic_lucid_file(tmp_path):
    source = tmp_path / "case.ipl"
    source.write_text(LISTING_5_1)
    found = lucid.read_observations(source)
    assert [o.id for o in found] == ["o0", "o1", "o2", "o3"]
    assert found[2].data == '"C printed" => "not very well", 1, 0, 0.35, 3412'
    assert lucid.program(found, [["o3", "o1"]]).splitlines()[-3:] == [
        "    observation sequence os1 = {o3, o1};", "    evidential statement es1 = os1;", "end"]


def test_bad_options_and_files_say_what_to_fix(tmp_path):
    from host.errors import UserError
    with pytest.raises(ValueError, match="expected one of wave, click"):
        DigiEVISS.Options(grab_gesture="pinch")
    with pytest.raises(ValueError, match="either `spheres` or `observations`"):
        DigiEVISS.Options(observations="x.ipl", spheres=[{"evidence": "a", "value": "b"}])
    empty = tmp_path / "empty.ipl"
    empty.write_text("es where end\n")
    with pytest.raises(UserError, match="no `observation oN"):
        lucid.read_observations(empty)


ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "profiles" / "digieviss.toml"


def test_the_profile_plays_the_synthetic_choreography_into_listing_5_1(tmp_path):
    """The interface of issue 8: `issv run profiles/digieviss.toml --headless` writes digieviss.ipl
    here; since issue 17 the open engine tracks the performer (both hands all the time: o3 is
    carried low at the side past o2 and o1, and linked only when raised beside o0)."""
    run = subprocess.run([sys.executable, "-m", "host", "run", str(PROFILE), "--headless", "--fast"],
                         cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "digieviss.ipl").read_text() == LISTING_5_1
    assert "linked o0 -> o3" in run.stdout and "user 1 right hand released o3 (release gesture)" in run.stdout
    assert "out of sight" not in run.stdout


def test_without_a_renderer_and_with_the_program_path_from_the_profile(tmp_path):
    """No GL at all: the synthetic performer through the profile's backend (openiss), in-process."""
    profile = tmp_path / "show.toml"
    text = PROFILE.read_text().replace('name = "digieviss"\n#', 'name = "digieviss"\nprogram = "out/case.ipl"\n#')
    profile.write_text(text.replace('[[effects]]\nname = "hand-trails"\n', ""))
    (tmp_path / "out").mkdir()
    prof = load(profile)
    effects = make_effects(prof)
    show = Show(make_backend(prof, realtime=False), effects, Stage((64, 48), 1000.0, "openiss"))
    show.run()
    assert show.stage.ctx is None and effects[0].effect.view is None
    assert (tmp_path / "out" / "case.ipl").read_text() == LISTING_5_1


@requires_gl
def test_each_hand_cursor_is_drawn_in_its_users_colour(tmp_path):
    hands = {1: (-300.0, -300.0, 2000.0), 2: (300.0, -300.0, 2000.0)}  # well below the row of spheres
    shown = []
    for i in range(4):
        depth = DepthFrame(depth_image(), STAGE_K, i, i / 30)
        shown.append(Frame(i + 1, depth.capture_time, depth, tuple(
            Hand(10 * u + 2, HandState.TRACKING, p, Side.RIGHT, u, extended=False) for u, p in hands.items()),
            (), "script", users=(User(1, HandState.TRACKING), User(2, HandState.TRACKING))))
    effect = DigiEVISS(DigiEVISS.Options(program=str(tmp_path / "out.ipl"), log=False))
    image, _, stage = run_show([effect], shown, tmp_path)
    for user, position in hands.items():
        b, g, r = lit(image, stage.to_stage(position, shown[-1].depth)).astype(int)
        assert np.abs(np.array([r, g, b]) - np.round(np.multiply(user_colour(user), 255))).max() <= 2
