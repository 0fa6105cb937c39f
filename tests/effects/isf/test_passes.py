"""ISF shaders rendered on Mesa's EGL: passes, persistent and FLOAT buffers, size expressions,
vertex shaders, imported images, old GLSL dialects, errors that name FILE:LINE."""
import cv2
import moderngl
import numpy as np
import pytest

from effects.isf import IsfError, IsfShader
from effects.isf.passes import IsfRenderer, Output
from host.render.context import headless_context
from tests.host.render.stage import requires_gl

SIZE = (160, 120)


@pytest.fixture(scope="module")
def ctx():
    if requires_gl.args[0]:
        pytest.skip(requires_gl.kwargs["reason"])
    context = headless_context()
    yield context
    context.release()


def render(ctx, path, frames=1, values=None, images=None, sizes=None):
    """The last of `frames` frames as RGBA floats 0..1, row 0 at the top."""
    shader = IsfShader(path)
    runner = IsfRenderer(ctx, shader)
    texture = ctx.texture(SIZE, 4)
    fbo = ctx.framebuffer([texture])

    def bind():
        fbo.use()
        ctx.enable_only(moderngl.NOTHING)

    try:
        for i in range(frames):
            fbo.clear(0.0, 0.0, 0.0, 0.0)
            runner.draw({**shader.defaults, **(values or {})}, images or {}, Output(bind, SIZE), i / 30, 1 / 30, sizes)
        pixels = np.frombuffer(fbo.read(components=4), np.uint8).reshape(SIZE[1], SIZE[0], 4)
        return pixels[::-1] / 255.0
    finally:
        runner.release()
        fbo.release()
        texture.release()


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


COUNTER = """/*{
    "ISFVSN": "2",
    "PASSES": [{"TARGET": "count", "PERSISTENT": true, "FLOAT": %s}, {}]
}*/
void main() {
    if (PASSINDEX == 0)
        gl_FragColor = vec4(IMG_THIS_PIXEL(count).r + 1.0, 0.0, 0.0, 1.0);
    else
        gl_FragColor = vec4(IMG_THIS_PIXEL(count).r / 10.0, 0.0, 0.0, 1.0);
}
"""


@pytest.mark.parametrize("floating, expected", [("true", 0.4), ("false", 0.1)])
def test_a_persistent_buffer_keeps_its_pixels_across_frames_and_float_keeps_values_above_one(
        ctx, tmp_path, floating, expected):
    image = render(ctx, write(tmp_path, "count.fs", COUNTER % floating), frames=4)
    assert image[..., 0].mean() == pytest.approx(expected, abs=0.01)  # 8-bit buffers stop at 1.0


def test_each_pass_that_branches_on_passindex_is_a_program_of_its_own_with_passindex_constant(ctx, tmp_path):
    path = write(tmp_path, "three.fs", """/*{"PASSES": [{"TARGET": "a"}, {"TARGET": "b"}, {}]}*/
void main() {
    if (PASSINDEX == 0) gl_FragColor = vec4(0.25, 0.0, 0.0, 1.0);
    else if (PASSINDEX == 1) gl_FragColor = IMG_THIS_PIXEL(a) + vec4(0.0, 0.5, 0.0, 0.0);
    else gl_FragColor = IMG_THIS_PIXEL(b) + vec4(0.0, 0.0, float(PASSINDEX) / 4.0, 0.0);
}
""")
    shader = IsfShader(path)
    assert shader.branches_on_pass
    program = shader.program(ctx, 2)
    try:
        assert program.get("PASSINDEX", None) is None  # a constant: the other passes' code is gone
    finally:
        program.release()
    r, g, b, _ = render(ctx, path)[60, 80]
    assert (r, g, b) == pytest.approx((0.25, 0.5, 0.5), abs=0.01)


def test_a_pass_size_expression_sizes_its_buffer(ctx, tmp_path):
    path = write(tmp_path, "size.fs", """/*{
    "INPUTS": [{"NAME": "quality", "TYPE": "float", "DEFAULT": 0.5}],
    "PASSES": [{"TARGET": "small", "WIDTH": "floor($WIDTH/4.0)", "HEIGHT": "max(1.0, $HEIGHT * $quality)"}, {}]
}*/
void main() {
    gl_FragColor = PASSINDEX == 0 ? vec4(RENDERSIZE / 255.0, 0.0, 1.0)
                                  : vec4(IMG_SIZE(small) / 255.0, IMG_THIS_PIXEL(small).r, 1.0);
}
""")
    r, g, b, _ = render(ctx, path)[60, 80] * 255
    assert (round(r), round(g)) == (40, 60)
    assert round(b) == 40  # the first pass saw its own size as RENDERSIZE


def test_a_companion_vertex_shader_and_old_glsl_run(ctx, tmp_path):
    header = '/*{"INPUTS": [{"NAME": "amount", "TYPE": "float", "DEFAULT": 1.0}]}*/\n'
    write(tmp_path, "flip.vs", "varying vec2 flipped;\nvoid main() {\n    isf_vertShaderInit();\n"
                               "    flipped = vec2(isf_FragNormCoord.x, 1.0 - isf_FragNormCoord.y) * amount;\n}\n")
    path = write(tmp_path, "flip.fs", header + "varying vec2 flipped;\nvoid main() {\n"
                                               "    float input = flipped.y;  // a name GLSL 330 reserves\n"
                                               "    gl_FragColor = vec4(input, 0.0, 0.0, 1.0);\n}\n")
    image = render(ctx, path)
    assert image[0, 80, 0] < 0.02 and image[-1, 80, 0] > 0.98  # flipped: 0 at the top, 1 at the bottom


def test_glsl_130_qualifiers_stay_qualifiers_while_old_names_that_are_now_reserved_are_renamed(ctx, tmp_path):
    write(tmp_path, "q.vs", "flat out float level;\nvoid main() { isf_vertShaderInit(); level = 0.5; }\n")
    path = write(tmp_path, "q.fs", '/*{"INPUTS": []}*/\nflat in float level;\n'
                                   "float smooth(float filter) { float flat = filter; return flat; }\n"
                                   "void main() { gl_FragColor = vec4(smooth(level), 0.0, 0.0, 1.0); }\n")
    assert render(ctx, path)[60, 80, 0] == pytest.approx(0.5, abs=0.01)


def test_an_error_in_the_vertex_shader_names_the_vs_file_and_line(ctx, tmp_path):
    write(tmp_path, "bad.vs", "void main() {\n    isf_vertShaderInit();\n    gl_Position.x += nope;\n}\n")
    path = write(tmp_path, "bad.fs", "/*{}*/\nvoid main() { gl_FragColor = vec4(1.0); }\n")
    with pytest.raises(IsfError, match=r"bad\.vs:3: error: .*nope"):
        IsfShader(path).program(ctx)


def test_lax_int_and_uint_code_compiles_where_the_driver_has_glsl_420(ctx, tmp_path):
    path = write(tmp_path, "uint.fs", "/*{}*/\nfloat half_of(float x) { if (x < 0.0) return 0; return x / 2.0; }\n"
                                      "void main() {\n    uint code = 3;\n    if (code > 2) gl_FragColor = "
                                      "vec4(half_of(1.0), 0.0, 0.0, 1.0);\n}\n")
    assert render(ctx, path)[0, 0, 0] == pytest.approx(0.5, abs=0.01)


def test_an_imported_image_is_read_upright(ctx, tmp_path):
    image = np.zeros((2, 2, 3), np.uint8)
    image[0, 0] = (0, 0, 255)  # BGR: red at the top-left
    cv2.imwrite(str(tmp_path / "corner.png"), image)
    path = write(tmp_path, "imp.fs", '/*{"IMPORTED": {"corner": {"PATH": "corner.png"}}}*/\n'
                                     "void main() { gl_FragColor = IMG_NORM_PIXEL(corner, isf_FragNormCoord); }\n")
    out = render(ctx, path)
    assert out[2, 2, 0] > 0.9 and out[-3, -3, 0] < 0.1


def test_an_image_input_is_sampled_with_img_pixel_in_pixels(ctx, tmp_path):
    texture = ctx.texture((4, 1), 4, np.array([[0, 0, 0, 255], [60, 0, 0, 255], [120, 0, 0, 255], [240, 0, 0, 255]],
                                               np.uint8).tobytes())
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    path = write(tmp_path, "px.fs", '/*{"INPUTS": [{"NAME": "inputImage", "TYPE": "image"}]}*/\n'
                                    "void main() { gl_FragColor = IMG_PIXEL(inputImage, vec2(2.5, 0.5)); }\n")
    assert render(ctx, path, images={"inputImage": texture})[5, 5, 0] == pytest.approx(120 / 255, abs=0.01)
    texture.release()


def test_an_image_seen_at_another_size_is_read_in_that_size_pixels(ctx, tmp_path):
    """At `scale` the host gives the full-size show and the size the shader sees it at."""
    row = np.zeros((8, 4), np.uint8)
    row[:, 0], row[:, 3] = np.arange(8) * 30, 255
    texture = ctx.texture((8, 2), 4, np.stack([row, row]).tobytes())
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    path = write(tmp_path, "px.fs", '/*{"INPUTS": [{"NAME": "inputImage", "TYPE": "image"}]}*/\n'
                                    "void main() { gl_FragColor = vec4(IMG_PIXEL(inputImage, vec2(2.9, 0.5)).r,"
                                    " IMG_SIZE(inputImage) / 255.0, 1.0); }\n")
    r, g, b, _ = render(ctx, path, images={"inputImage": texture}, sizes={"inputImage": (4, 1)})[5, 5] * 255
    assert round(r) == 150 and (round(g), round(b)) == (4, 1)  # x 2.9 of 4 is texel 5 of 8
    texture.release()


def test_files_that_declare_what_isf_gives_or_start_with_a_bom_run(ctx, tmp_path):
    redeclared = write(tmp_path, "redeclared.fs", '/*{"INPUTS": [{"NAME": "speed", "TYPE": "float", "DEFAULT": 1.0}]}*/\n'
                                                  "uniform float TIME;\nuniform float speed;\nvarying vec2 vv_FragNormCoord;\n"
                                                  "float t = 0.5 + TIME * speed;  // a global set from uniforms\n"
                                                  "void main(void) { gl_FragColor = vec4(t, vv_FragNormCoord.x, 0.0, 1.0); }\n")
    assert render(ctx, redeclared)[60, 80, 0] == pytest.approx(0.5, abs=0.01)
    bom = tmp_path / "bom.fs"
    bom.write_bytes(b'\xef\xbb\xbf/*{\r\n "INPUTS": []\r\n}*/\r\nvoid main() {\r\n gl_FragColor = vec4(0.25, 0.25, 0.25, 1.0);\r\n}\r\n')
    assert render(ctx, bom)[0, 0, 0] == pytest.approx(0.25, abs=0.01)


def test_an_isf_v1_file_with_persistent_buffers_and_an_imported_list_runs(ctx, tmp_path):
    cv2.imwrite(str(tmp_path / "grey.png"), np.full((4, 4, 3), 128, np.uint8))
    path = write(tmp_path, "v1.fs", """/*{
    "INPUTS": [{"NAME": "decay", "TYPE": "float", "DEFAULT": 0.5,},],
    "IMPORTED": [{"NAME": "grey", "PATH": "grey.png"}],
    "PERSISTENT_BUFFERS": ["trail"],
    "PASSES": [{"TARGET": "trail"}, {}],
}*/
void main() {
    if (PASSINDEX == 0) gl_FragColor = IMG_NORM_PIXEL(trail, vv_FragNormCoord) * decay + IMG_THIS_PIXEL(grey) * 0.5;
    else gl_FragColor = vec4(IMG_THIS_PIXEL(trail).rgb, 1.0);
}
""")
    # trail_n = trail_(n-1) / 2 + 0.25: 0.25, 0.375, 0.4375 after three frames (8-bit steps)
    assert render(ctx, path, frames=3)[60, 80, 0] == pytest.approx(0.4375, abs=0.01)


def test_compatibility_profile_built_ins_of_old_vertex_and_fragment_shaders_run(ctx, tmp_path):
    write(tmp_path, "old.vs", "varying vec2 uv;\nvoid main() {\n    gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;\n"
                              "    uv = gl_MultiTexCoord0.xy;\n}\n")
    path = write(tmp_path, "old.fs", "/*{}*/\nvarying vec2 uv;\nvoid main() {\n"
                                     "    gl_FragColor = vec4(uv.x, gl_TexCoord[0].y, 0.0, 1.0);\n}\n")
    image = render(ctx, path)
    assert image[0, -1, 0] > 0.98 and image[0, -1, 1] > 0.98 and image[-1, 0, :2].max() < 0.02
