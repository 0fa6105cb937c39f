"""The stage's promises, by pixels: the keystone puts the corners where the profile says (both
ways: in the effects' own matrix and as a warp pass), blend modes and opacity composite in
profile order, and an effect that fails to render is disabled while the others go on."""
import numpy as np
import pytest

from effects.gl import Sprites, StageQuad
from host import Effect
from host.render.calibration import apply, keystone_matrix
from tests.host.render.stage import frames_with_hand, requires_gl, run_show

SIZE = (320, 240)
KEYSTONE = [(0.1, 0.05), (0.93, 0.12), (0.97, 0.9), (0.04, 0.97)]
# One marker per stage corner, 4 px in, each in its own colour (RGB).
MARKERS = {(4.0, 4.0): (1, 0, 0), (SIZE[0] - 4.0, 4.0): (0, 1, 0),
           (SIZE[0] - 4.0, SIZE[1] - 4.0): (0, 0, 1), (4.0, SIZE[1] - 4.0): (1, 1, 0)}


class Markers(Effect):
    """Test effect: hard dots at the stage's corners."""

    name = "markers"
    renders = True

    def setup(self, stage):
        super().setup(stage)
        self.sprites = Sprites(stage.ctx, softness=0.0)

    def render(self, target):
        centers = np.array(list(MARKERS))
        self.sprites.draw(target, centers, np.full(4, 3.5), np.c_[np.array(list(MARKERS.values())), np.ones(4)])


class AwareMarkers(Markers):
    keystone_aware = True


class Fill(Effect):
    """Test effect: the whole stage in one premultiplied colour (rgb * a, a)."""

    name = "fill"
    renders = True
    keystone_aware = True
    FRAGMENT = "#version 330\nuniform vec4 c;\nin vec2 uv;\nout vec4 color;\nvoid main() { color = c; }\n"

    def __init__(self, rgb, alpha=1.0):
        super().__init__()
        self.rgba = (*(v * alpha for v in rgb), alpha)

    def setup(self, stage):
        super().setup(stage)
        self.quad = StageQuad(stage.ctx, self.FRAGMENT)
        self.quad.prog["c"].value = self.rgba

    def render(self, target):
        self.quad.draw(target)


class Broken(Fill):
    def render(self, target):
        raise RuntimeError("shader melted")


def centroid(image, rgb):
    """Centroid (x, y) of the pixels of one marker colour (image is BGR)."""
    want = np.array(rgb[::-1]) * 255
    hit = np.all(np.abs(image.astype(int) - want) < 90, axis=2)
    ys, xs = np.nonzero(hit)
    assert len(xs) > 5, f"marker {rgb} not found"
    return xs.mean() + 0.5, ys.mean() + 0.5  # pixel centres


def test_keystone_matrix_maps_the_corners_exactly():
    k = keystone_matrix(KEYSTONE, SIZE)
    corners = apply(k, [(0, 0), (SIZE[0], 0), SIZE, (0, SIZE[1])])
    assert np.allclose(corners, np.array(KEYSTONE) * SIZE, atol=1e-6)


@requires_gl
@pytest.mark.parametrize("effect", [AwareMarkers, Markers], ids=["in-matrix", "warp-pass"])
def test_keystone_puts_the_corners_where_the_profile_says(tmp_path, effect):
    image, _, _ = run_show([effect()], frames_with_hand([(0, 0, 2000)] * 2), tmp_path, SIZE, keystone=KEYSTONE)
    k = keystone_matrix(KEYSTONE, SIZE)
    for point, rgb in MARKERS.items():
        want = apply(k, [point])[0]
        got = centroid(image, rgb)
        assert np.hypot(*(np.array(got) - want)) <= 1.0, f"{rgb}: at {got}, expected {want}"


@requires_gl
@pytest.mark.parametrize("blend, expect", [
    ("normal", lambda d, s, o: s * o + d * (1 - o)),
    ("add", lambda d, s, o: np.minimum(d + s * o, 1)),
    ("screen", lambda d, s, o: s * o + d - s * o * d),
    ("multiply", lambda d, s, o: s * o * d + d * (1 - o)),
])
@pytest.mark.parametrize("opacity", [1.0, 0.5])
def test_blend_modes_and_opacity_composite_in_profile_order(tmp_path, blend, expect, opacity):
    below, above = np.array([0.2, 0.6, 0.4]), np.array([0.5, 0.5, 0.9])
    effects = [Fill(below), (Fill(above), blend, opacity)]
    image, _, _ = run_show(effects, frames_with_hand([(0, 0, 2000)] * 2), tmp_path, SIZE)
    got = image[SIZE[1] // 2, SIZE[0] // 2][::-1] / 255.0
    assert np.allclose(got, expect(below, above, opacity), atol=2.5 / 255), (blend, opacity, got)


@requires_gl
def test_a_failing_effect_is_disabled_once_and_the_others_keep_rendering(tmp_path, capsys):
    effects = [Fill((0.0, 0.0, 1.0)), Broken((1.0, 0.0, 0.0)), (Fill((0.0, 1.0, 0.0)), "add", 1.0)]
    image, show, _ = run_show(effects, frames_with_hand([(0, 0, 2000)] * 5), tmp_path, SIZE)
    err = capsys.readouterr().err
    assert err.count("shader melted") == 1 and "'fill' (effects[1])" in err and "render" in err
    assert [s.enabled for s in show.effects] == [True, False, True]
    assert tuple(image[10, 10]) == (255, 255, 0)  # BGR: blue + green, no red
