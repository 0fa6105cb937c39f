"""The HUD's per-layer GPU time: measured with GL timer queries where the driver reports them,
and said to be unreported where it does not (llvmpipe answers every query with 2^32-1 ns)."""
from effects.depth_view import DepthView
from tests.host.render.stage import frames_with_hand, requires_gl, run_show


@requires_gl
def test_each_layer_is_timed_or_said_to_be_unreported(tmp_path):
    image, show, _ = run_show([DepthView(DepthView.Options())], frames_with_hand([(0.0, 0.0, 2000.0)] * 3),
                              tmp_path, (160, 120), hud=True)
    times = show.renderer.layer_times
    assert times.ms or not times.reported
    if times.reported:
        assert 0 < times.ms["[0]depth-view"] < 1000 and "[0]depth-view" in times.line()
    else:
        assert times.line() == "layer GPU ms: not reported by this driver"
    assert image[:20, :60].max() > 0  # the HUD panel is drawn
