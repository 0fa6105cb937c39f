"""The HUD panel: a long line (a webcam's input label) is made smaller to fit, never cut."""
import moderngl
import numpy as np

from host.metrics import Metrics
from host.render.hud import Hud
from tests.host.render.stage import requires_gl

LABEL = "webcam file kinect-desk-hand-rgb.mp4 640x480, 27 fps, pose 24 ms"


@requires_gl
def test_a_long_input_label_fits_the_panel():
    ctx = moderngl.create_context(standalone=True, backend="egl")
    try:
        hud = Hud(ctx, (640, 360))
        hud._update(Metrics("mediapipe", 27.0, input=lambda: LABEL), "")
        pw, ph = hud.panel
        img = np.frombuffer(hud.texture.read(), np.uint8).reshape(ph, pw, 4)[::-1]
        row = img[hud.line_h // 4: hud.line_h * 2 + 2]  # the first two lines: backend, input
        text = np.flatnonzero((row[..., 0] > 0).any(axis=0))  # columns with white text
        assert text.size and text[-1] < pw - 3  # the label ends inside the panel
        assert text[-1] > pw // 2  # and is not shrunk away: it spans most of the panel
        hud.release()
    finally:
        ctx.release()
