"""ISF's GLSL, whatever dialect it was written in, as GLSL 330 core (what Mesa and desktop GPUs
accept), with `#line` kept so that the driver's errors name the .fs or .vs file's own lines.

ISF files are mostly GLSL 1.10/1.20 (gl_FragColor, texture2D, varying, attribute); a few use
words GLSL 330 reserves (`input`, `smooth`, `filter`...) as names. The translation is textual
and keeps every line where it was.
"""
from __future__ import annotations

import re
from pathlib import Path

from effects.isf.header import GLSL_TYPES, Header, IsfError

# Names GLSL 330 reserves that older shaders use as variables or functions.
RESERVED = ("input", "output", "smooth", "flat", "noperspective", "filter", "common", "partition", "active",
            "superp", "sample", "patch", "subroutine", "resource", "buffer", "shared", "coherent", "restrict",
            "readonly", "writeonly", "precise", "long", "short", "double", "half", "fixed", "unsigned",
            "union", "enum", "typedef", "template", "this", "packed", "goto", "inline", "noinline",
            "volatile", "public", "static", "extern", "external", "interface", "namespace", "using",
            "sizeof", "cast", "row_major", "asm", "class", "layout", "centroid", "invariant")
# ... but not where they are what GLSL 1.30+ means by them: a qualifier before a declaration
# (`flat out float x;`, `smooth in`, `invariant gl_Position`) or `layout(...)`.
QUALIFIED = (r"(?:in|out|inout|varying|uniform|centroid|flat|smooth|noperspective|invariant|const|highp|mediump|"
             r"lowp|float|int|uint|bool|vec[234]|ivec[234]|uvec[234]|bvec[234]|mat[234](?:x[234])?|gl_\w+)")
_RESERVED = re.compile(r"\b(" + "|".join(RESERVED) + r")\b(?!\s+" + QUALIFIED + r"\b)"
                       r"|\b(layout)\b(?!\s*\()")
COMMON = [(re.compile(r"\btexture2DRect\b"), "texture"), (re.compile(r"\btexture2DProj\b"), "textureProj"),
          (re.compile(r"\btexture2DLod\b"), "textureLod"), (re.compile(r"\btexture2DGrad\b"), "textureGrad"),
          (re.compile(r"\btextureCube\b"), "texture"), (re.compile(r"\btexture2D\b"), "texture"),
          (re.compile(r"\btexture[13]D\b"), "texture"), (re.compile(r"\bshadow2D\b"), "texture"),
          (re.compile(r"\bsampler2DRect\b"), "sampler2D"), (re.compile(r"\bvoid\s+main\s*\("), "void isf_main("),
          (re.compile(r"^[ \t]*#[ \t]*version\b.*$", re.M), "")]
# Compatibility-profile built-ins that core removed, as the full-screen quad gives them.
FRAGMENT_ONLY = [(re.compile(r"\bgl_FragColor\b"), "isf_FragColor"),
                 (re.compile(r"\bgl_TexCoord\s*\[\s*0\s*\]"), "vec4(isf_FragNormCoord, 0.0, 1.0)"),
                 (re.compile(r"\bgl_FragData\s*\[\s*0\s*\]"), "isf_FragColor"), (re.compile(r"\bvarying\b"), "in")]
VERTEX_ONLY = [(re.compile(r"\bvarying\b"), "out"), (re.compile(r"\battribute\b"), "in"),
               (re.compile(r"\bftransform\s*\(\s*\)|\bgl_Vertex\b"), "vec4(issv_position, 0.0, 1.0)"),
               (re.compile(r"\bgl_ModelViewProjectionMatrix\b"), "mat4(1.0)"),
               (re.compile(r"\bgl_MultiTexCoord0\b"), "vec4(issv_position * 0.5 + 0.5, 0.0, 1.0)")]
GIVEN = {"RENDERSIZE", "TIME", "TIMEDELTA", "FRAMEINDEX", "PASSINDEX", "DATE", "isf_FragNormCoord", "vv_FragNormCoord"}
TEXTURE_VARIABLE = re.compile(r"\btexture\b(?!\s*\()")
IMG_SIZED = re.compile(r"\bIMG_(PIXEL|SIZE)\s*\(\s*(\w+)\s*([,)])")

PASSINDEX_UNIFORM = "uniform int PASSINDEX;\n"  # a constant in a program made for one pass
BUILTINS = """uniform vec2 RENDERSIZE;
uniform float TIME;
uniform float TIMEDELTA;
uniform int FRAMEINDEX;
""" + PASSINDEX_UNIFORM + """uniform vec4 DATE;
#define IMG_NORM_PIXEL(img, coord) texture(img, coord)
#define IMG_PIXEL(img, coord) texture(img, (coord) / vec2(textureSize(img, 0)))
#define isf_img_pixel(img, size, coord) texture(img, (coord) / (size))
#define IMG_THIS_NORM_PIXEL(img) texture(img, isf_FragNormCoord)
#define IMG_THIS_PIXEL(img) texture(img, isf_FragNormCoord)
#define IMG_SIZE(img) vec2(textureSize(img, 0))
#define vv_FragNormCoord isf_FragNormCoord
"""
FRAGMENT_HEAD = "in vec2 isf_FragNormCoord;\nout vec4 isf_FragColor;\nuniform bool issv_premultiply;\n"
# The ISF main runs first; the output pass then premultiplies its straight alpha for the stage.
FRAGMENT_TAIL = ("\nvoid main() { isf_main(); if (issv_premultiply) "
                 "isf_FragColor = vec4(isf_FragColor.rgb * isf_FragColor.a, isf_FragColor.a); }\n")
VERTEX_HEAD = """uniform mat3 issv_clip;   // clip space -> clip space: the keystone on the output pass
in vec2 issv_position;    // the full-screen quad's corners, -1..1
out vec2 isf_FragNormCoord;
void isf_vertShaderInit() {
    gl_Position = vec4(issv_position, 0.0, 1.0);
    isf_FragNormCoord = issv_position * 0.5 + 0.5;
}
#define vv_vertShaderInit isf_vertShaderInit
"""
# isf_vertShaderInit() runs first too: a .vs that forgets it still gives isf_FragNormCoord.
VERTEX_TAIL = "\nvoid main() { isf_vertShaderInit(); isf_main(); vec3 p = issv_clip * gl_Position.xyw; gl_Position = vec4(p.xy, 0.0, p.z); }\n"
DEFAULT_VERTEX_BODY = "void isf_main() { isf_vertShaderInit(); }\n"
COMPILER_LINE = re.compile(r"^\s*\d+:(\d+)\(\d+\):\s*(.*)$|^\s*ERROR:\s*\d+:(\d+):\s*(.*)$")


def glsl_name(name: str) -> str:
    """An ISF name as the translated GLSL calls it (reserved words get a prefix)."""
    return f"isf_{name}" if name in RESERVED else name


def declarations(header: Header) -> str:
    """Uniforms for the inputs, imported images and pass buffers, with ISF's per-image helpers."""
    lines, images = [], []
    for item in header.inputs:
        lines.append(f"uniform {GLSL_TYPES[item.type]} {glsl_name(item.name)};")
        if GLSL_TYPES[item.type] == "sampler2D":
            images.append(item.name)
    buffers = [p.target for p in header.passes if p.target] + list(header.persistent) + list(header.imported)
    for name in dict.fromkeys(buffers):
        if name not in images:
            lines.append(f"uniform sampler2D {glsl_name(name)};")
            images.append(name)
    for name in images:  # VVISF's names, which a few shaders read directly
        lines += [f"uniform vec4 _{name}_imgRect;", f"uniform vec2 _{name}_imgSize;", f"uniform bool _{name}_flip;"]
    return "\n".join(lines) + "\n"


def translate(body: str, stage: str, declared: set[str]) -> str:
    """One stage's GLSL in 330 core; lines stay where they were."""
    if "texture2D" in body and TEXTURE_VARIABLE.search(body):
        body = TEXTURE_VARIABLE.sub("isf_texture", body)
    for pattern, repl in COMMON + (FRAGMENT_ONLY if stage == "fragment" else VERTEX_ONLY):
        body = pattern.sub(repl, body)
    body = in_image_pixels(body, declared)
    body = _RESERVED.sub(lambda m: f"isf_{m.group(1) or m.group(2)}", body)
    # A shader that declares what ISF already gives (its inputImage, TIME, isf_FragNormCoord) keeps one.
    redeclared = re.compile(r"^[ \t]*(?:uniform|in|out)\s+(?:(?:high|medium|low)p\s+)?\w+\s+(\w+)\s*;", re.M)
    return redeclared.sub(lambda m: "" if m.group(1) in declared | GIVEN else m.group(0), body)


def in_image_pixels(body: str, declared: set[str]) -> str:
    """IMG_PIXEL and IMG_SIZE of a named image read its `_NAME_imgSize`, as VVISF's do: the host
    then says how big an image is to the shader. At `scale` the show below is a full-size texture
    that the shader sees at its own size, with no extra pass to shrink it."""
    def sized(match: re.Match) -> str:
        kind, name, end = match.groups()
        if f"_{name}_imgSize" not in declared or (kind == "PIXEL") != (end == ","):
            return match.group(0)
        return f"isf_img_pixel({name}, _{name}_imgSize," if kind == "PIXEL" else f"_{name}_imgSize"
    return IMG_SIZED.sub(sized, body)


def fragment_source(path: Path, text: str, header: Header) -> str:
    body = text[header.body_start:]
    first_line = text.count("\n", 0, header.body_start) + 1  # the body starts on the header's last line
    decl = declarations(header)
    body = translate(body, "fragment", _declared(decl))
    if "isf_main(" not in body:
        raise IsfError(f"{path}: the shader has no `void main()`")
    return f"#version 330\n{BUILTINS}{decl}{FRAGMENT_HEAD}#line {first_line}\n{body}{FRAGMENT_TAIL}"


def vertex_source(vs_text: str | None, header: Header) -> str:
    decl = declarations(header)
    body = DEFAULT_VERTEX_BODY if vs_text is None else translate(vs_text, "vertex", _declared(decl))
    return f"#version 330\n{BUILTINS}{decl}{VERTEX_HEAD}#line 1\n{body}{VERTEX_TAIL}"


def _declared(decl: str) -> set[str]:
    return set(re.findall(r"uniform \w+ (\w+);", decl))


def explain(path: Path, log: str) -> str:
    """The driver's log as `FILE:LINE: message` (up to three, the first one first)."""
    found = []
    for raw in log.splitlines():
        m = COMPILER_LINE.match(raw)
        if m:
            line, msg = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
            found.append(f"{path}:{line}: {msg.strip()}")
    if not found:
        detail = " ".join(line.strip() for line in log.splitlines() if line.strip() and "=" * 5 not in line)
        return f"{path}: the shader does not compile or link: {detail[:300]}"
    return "; ".join(found[:3])
