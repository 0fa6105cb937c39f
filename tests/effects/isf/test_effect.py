"""`isf`: ISF shaders run with their inputs bound to hands, gestures and depth; a broken shader is
one clear error naming its file and line, and the other layers keep rendering."""
import numpy as np
import pytest

from effects.depth_view import DepthView
from effects.isf import Isf, IsfError, IsfShader
from host.cli import main
from tests.host.render.stage import frames_with_hand, gesture_at, lit, requires_gl, run_show

SIZE = (320, 240)
HAND = (-300.0, 200.0, 2000.0)

GOOD_HEADER = """/*{
    "ISFVSN": "2",
    "INPUTS": [
        {"NAME": "where", "TYPE": "point2D", "DEFAULT": [0, 0]},
        {"NAME": "age", "TYPE": "float", "DEFAULT": 10000.0}
    ]
}*/
"""


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def isf(**options):
    return Isf(Isf.Options(**options))


@requires_gl
def test_a_shader_that_does_not_compile_names_file_and_line_and_the_others_keep_rendering(tmp_path, capsys):
    broken = write(tmp_path, "broken.fs", GOOD_HEADER + "void main() {\n    vec4 c = vec4(1.0)\n    gl_FragColor = c;\n}\n")
    error_line = GOOD_HEADER.count("\n") + 3  # the statement after the missing semicolon
    frames = frames_with_hand([HAND] * 3)
    image, show, _ = run_show([DepthView(DepthView.Options()), isf(file=str(broken))], frames, tmp_path, SIZE)
    err = capsys.readouterr().err
    assert err.count(f"{broken}:{error_line}:") == 1, err
    assert "syntax error" in err and "disabled" in err
    assert [s.enabled for s in show.effects] == [True, False]
    assert image[120, 160].max() > 100  # the depth view's performer box is still drawn


def test_a_header_that_is_not_json_names_file_and_line(tmp_path):
    path = write(tmp_path, "bad.fs", '/*{\n  "INPUTS": [\n    {"NAME": "x" "TYPE": "float"}\n  ]\n}*/\nvoid main() {}\n')
    with pytest.raises(IsfError, match=rf"{path}:3: the ISF header is not valid JSON"):
        IsfShader(path)


def test_bindings_are_checked_with_the_profile(tmp_path, capsys):
    path = write(tmp_path, "ok.fs", GOOD_HEADER + "void main() { gl_FragColor = vec4(1.0); }\n")
    profile = write(tmp_path, "show.toml", """
backend = "truth"
[source]
name = "clip"
path = "clip.npz"
[[effects]]
name = "isf"
file = "ok.fs"
bind = { nowhere = "hand.right", where = "depth" }
""")
    assert main(["check", str(profile)]) == 2
    err = capsys.readouterr().err
    assert f"effects[0]: {path}: has no input 'nowhere'" in err
    with pytest.raises(ValueError, match=r"input 'where' \(point2D\) cannot be bound to 'depth'"):
        Isf.Options(file=str(path), bind={"where": "depth"})


def test_exactly_one_of_shader_or_file():
    with pytest.raises(ValueError, match="exactly one"):
        Isf.Options()
    with pytest.raises(ValueError, match="no shipped ISF shader"):
        Isf.Options(shader="nope")


@requires_gl
@pytest.mark.parametrize("scale", [1.0, 0.5])
def test_hand_glow_shines_where_the_hand_is(tmp_path, scale):
    frames = frames_with_hand([HAND] * 3)
    effect = isf(shader="hand-glow", bind={"handA": "hand.right"}, scale=scale)
    image, _, stage = run_show([effect], frames, tmp_path, SIZE)
    hand = stage.to_stage(HAND, frames[-1].depth)
    assert lit(image, hand, 2).max() > 200
    far = (SIZE[0] - 20, SIZE[1] - 20)
    assert lit(image, far, 2).max() < 60


@requires_gl
def test_depth_contours_draw_only_where_there_is_depth(tmp_path):
    image, _, _ = run_show([isf(shader="depth-contours", bind={"depthImage": "depth"}, values={"body": 0.5})],
                           frames_with_hand([HAND] * 3), tmp_path, SIZE)
    box = image[40:220, 120:200]  # the performer box (depth pixels 60..100 x 20..110, doubled)
    assert box.min() > 40  # the body fill over the whole (flat) box
    assert image[:, :110].max() == 0 and image[:, 210:].max() == 0


@requires_gl
def test_a_gesture_binding_fires_where_the_gesture_happened(tmp_path):
    shader = write(tmp_path, "g.fs", GOOD_HEADER + """
void main() {
    float near = step(distance(isf_FragNormCoord * RENDERSIZE, where), 6.0);
    gl_FragColor = vec4(near * step(age, 5.0), 0.0, 0.0, 1.0);
}
""")
    effect = isf(file=str(shader), bind={"where": "gesture", "age": "gesture.wave.age"}, scale=1.0)
    quiet = run_show([effect], frames_with_hand([HAND] * 4), tmp_path, SIZE)[0]
    assert quiet.max() == 0  # no wave yet: nothing
    swipe = {2: [gesture_at("swipe_left", HAND)]}
    assert run_show([isf(file=str(shader), bind={"where": "gesture", "age": "gesture.wave.age"})],
                    frames_with_hand([HAND] * 4, swipe), tmp_path, SIZE)[0].max() == 0
    waved = {2: [gesture_at("wave", HAND)]}
    effect = isf(file=str(shader), bind={"where": "gesture", "age": "gesture.wave.age"}, scale=1.0)
    image, _, stage = run_show([effect], frames_with_hand([HAND] * 4, waved), tmp_path, SIZE)
    x, y = stage.to_stage(HAND, frames_with_hand([HAND])[0].depth)
    # ISF's point2D is in pixels from the bottom-left: the red dot is at the hand, image row y.
    assert lit(image, (x, y), 2)[2] == 255
    assert image[:, :, 2].sum() / 255 < 200  # a small dot, nothing else


INVERT = """/*{"INPUTS": [{"NAME": "inputImage", "TYPE": "image"}]}*/
void main() { vec4 c = IMG_THIS_PIXEL(inputImage); gl_FragColor = vec4(1.0 - c.rgb, 1.0); }
"""
GREEN = "/*{}*/\nvoid main() { gl_FragColor = vec4(0.0, 1.0, 0.0, 1.0); }\n"
MIX = """/*{"INPUTS": [{"NAME": "startImage", "TYPE": "image"}, {"NAME": "endImage", "TYPE": "image"},
                {"NAME": "progress", "TYPE": "float", "DEFAULT": 0.0}]}*/
void main() { gl_FragColor = mix(IMG_THIS_PIXEL(startImage), IMG_THIS_PIXEL(endImage), progress); }
"""


@requires_gl
def test_a_filter_applies_to_everything_composited_below_it(tmp_path):
    frames = frames_with_hand([HAND] * 3)
    plain = run_show([DepthView(DepthView.Options())], frames, tmp_path, SIZE)[0]
    inverted = run_show([DepthView(DepthView.Options()), isf(file=str(write(tmp_path, "inv.fs", INVERT)))],
                        frames_with_hand([HAND] * 3), tmp_path, SIZE)[0]
    assert plain[5, 5].max() == 0 and inverted[5, 5].min() == 255  # the empty stage, inverted
    assert abs(int(inverted[120, 160, 0]) - (255 - int(plain[120, 160, 0]))) <= 2  # the performer box too


INVERT_BY_PIXEL = INVERT.replace("IMG_THIS_PIXEL(inputImage)", "IMG_PIXEL(inputImage, gl_FragCoord.xy)")


@requires_gl
def test_a_filter_at_a_lower_scale_reads_the_show_below_at_its_own_size(tmp_path):
    """IMG_PIXEL(inputImage, gl_FragCoord.xy) at scale 0.5 still sees the whole stage, not a corner."""
    frames = frames_with_hand([HAND] * 3)
    plain = run_show([DepthView(DepthView.Options())], frames, tmp_path, SIZE)[0]
    half = run_show([DepthView(DepthView.Options()), isf(file=str(write(tmp_path, "inv.fs", INVERT_BY_PIXEL)), scale=0.5)],
                    frames_with_hand([HAND] * 3), tmp_path, SIZE)[0]
    inverted = 255 - plain.astype(int)
    assert half[5, 5].min() == 255
    assert abs(int(half[120, 160, 0]) - inverted[120, 160, 0]) <= 8  # the performer box where it was
    assert np.abs(half.astype(int) - inverted).mean() < 6  # softer edges only


@requires_gl
@pytest.mark.parametrize("progress", [0.0, 1.0])
def test_a_transition_crossfades_the_show_below_with_a_layer_group_drawn_apart(tmp_path, progress):
    green = isf(file=str(write(tmp_path, "green.fs", GREEN)))
    fade = isf(file=str(write(tmp_path, "mix.fs", MIX)), bind={"endImage": "layers.1"}, values={"progress": progress})
    image = run_show([DepthView(DepthView.Options()), green, fade], frames_with_hand([HAND] * 3), tmp_path, SIZE)[0]
    if progress == 0.0:  # the depth view alone: the green layer is not drawn on the stage
        assert image[5, 5].max() == 0 and image[120, 160, 1] == image[120, 160, 0] > 100
    else:
        assert (image[..., 1] == 255).all() and image[..., [0, 2]].max() == 0


def test_bindings_for_transitions_and_filters_are_checked(tmp_path):
    path = write(tmp_path, "mix.fs", MIX)
    Isf.Options(file=str(path), bind={"startImage": "mask", "endImage": "layers.2-4", "progress": "time.8"})
    Isf.Options(file=str(path), bind={"progress": "gesture.wave.toggle"})
    Isf.Options(file=str(path), bind={"progress": "hand.right.x"})
    with pytest.raises(ValueError, match=r"input 'endImage' \(image\) cannot be bound to 'layers'"):
        Isf.Options(file=str(path), bind={"endImage": "layers"})
    with pytest.raises(ValueError, match=r"cannot be bound to 'time.0'"):
        Isf.Options(file=str(path), bind={"progress": "time.0"})


SHOW_VALUE = """/*{"INPUTS": [{"NAME": "v", "TYPE": "float", "MIN": 0.0, "MAX": 1.0, "DEFAULT": 0.0}]}*/
void main() { gl_FragColor = vec4(v, 0.0, 0.0, 1.0); }
"""


@requires_gl
@pytest.mark.parametrize("gesture, lit", [("swipe_left", True), ("wave", False)])
def test_a_toggle_binding_starts_fading_on_its_gesture(tmp_path, gesture, lit):
    shader = write(tmp_path, "v.fs", SHOW_VALUE)
    effect = isf(file=str(shader), bind={"v": "gesture.swipe_left.toggle"})
    image = run_show([effect], frames_with_hand([HAND] * 10, {1: [gesture_at(gesture, HAND)]}), tmp_path, SIZE)[0]
    red = int(image[120, 160, 2])
    assert (5 < red < 250) if lit else red == 0  # fading in over a second (the run lasts ~0.2 s)


@requires_gl
def test_a_float_follows_the_hand_across_the_stage(tmp_path):
    shader = write(tmp_path, "v.fs", SHOW_VALUE)
    frames = frames_with_hand([HAND] * 3)
    image, _, stage = run_show([isf(file=str(shader), bind={"v": "hand.right.x"})], frames, tmp_path, SIZE)
    x = stage.to_stage(HAND, frames[-1].depth)[0] / SIZE[0]
    assert abs(int(image[120, 160, 2]) - x * 255) <= 2


@requires_gl
def test_a_transition_that_reads_its_own_layer_says_so_and_the_show_goes_on(tmp_path, capsys):
    fade = isf(file=str(write(tmp_path, "mix.fs", MIX)), bind={"endImage": "layers.1"}, values={"progress": 1.0})
    image, show, _ = run_show([DepthView(DepthView.Options()), fade], frames_with_hand([HAND] * 3), tmp_path, SIZE)
    err = capsys.readouterr().err
    assert err.count("effects[1]: reads effects[1..1], which must be other effects") == 1
    assert all(slot.enabled for slot in show.effects)
