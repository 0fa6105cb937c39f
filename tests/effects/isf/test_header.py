"""ISF headers as real files write them: comments, trailing commas, v1 buffers, size expressions."""
import pytest

from effects.isf import IsfError, IsfShader
from effects.isf.header import evaluate_size, parse_header

BODY = "void main() { gl_FragColor = vec4(1.0); }\n"


def parse(tmp_path, header: str):
    path = tmp_path / "s.fs"
    text = header + BODY
    path.write_text(text)
    return parse_header(path, text)


def test_comments_before_and_inside_the_json_and_trailing_commas_are_read(tmp_path):
    header = parse(tmp_path, '// by someone\n// http://example.com\n/*\n{\n  "DESCRIPTION": "a // b",\n'
                             '  "INPUTS": [\n    {"NAME": "x", "TYPE": "float", "DEFAULT": 0.25,}, // the x\n  ],\n}\n*/\n')
    assert header.description == "a // b"
    assert [(i.name, i.default) for i in header.inputs] == [("x", 0.25)]


def test_a_header_that_is_not_json_names_the_file_line(tmp_path):
    with pytest.raises(IsfError, match=r"s\.fs:4: the ISF header is not valid JSON"):
        parse(tmp_path, '/*{\n  "INPUTS": [\n    {"NAME": "x",\n     "TYPE" "float"}\n  ]\n}*/\n')


def test_isf_v1_persistent_buffers_become_persistent_passes(tmp_path):
    header = parse(tmp_path, '/*{"PERSISTENT_BUFFERS": ["trail", "spare"], '
                             '"PASSES": [{"TARGET": "trail"}, {}]}*/\n')
    assert [(p.target, p.persistent) for p in header.passes] == [("trail", True), (None, False)]
    assert list(header.persistent) == ["spare"]  # not drawn by any pass, still an image to read
    sized = parse(tmp_path, '/*{"PERSISTENT_BUFFERS": {"t": {"WIDTH": 1, "HEIGHT": "$HEIGHT", "FLOAT": true}}, '
                            '"PASSES": [{"TARGET": "t"}, {}]}*/\n')
    assert (sized.passes[0].width, sized.passes[0].height, sized.passes[0].float) == ("1", "$HEIGHT", True)


@pytest.mark.parametrize("expression, expected", [
    ("floor($WIDTH/4.0)", 160.0), ("$HEIGHT / 2.0", 180.0), ("1", 1.0), ("512", 512.0),
    ("max(8.0,floor($HEIGHT*$buffQuality))", 90.0), ("max(floor($WIDTH*0.02),1.0)", 12.0)])
def test_size_expressions(expression, expected):
    assert evaluate_size(expression, {"WIDTH": 641, "HEIGHT": 360, "buffQuality": 0.25}) == expected


def test_a_size_expression_that_cannot_be_evaluated_says_what_is_allowed():
    with pytest.raises(IsfError, match=r"'\$WIDTH \* \$nope'.*\$WIDTH, \$HEIGHT"):
        evaluate_size("$WIDTH * $nope", {"WIDTH": 10, "HEIGHT": 10})
    with pytest.raises(IsfError, match="cannot be evaluated"):
        evaluate_size("__import__('os')", {"WIDTH": 10, "HEIGHT": 10})


def test_defaults_without_a_default(tmp_path):
    header = parse(tmp_path, '/*{"INPUTS": [{"NAME": "f", "TYPE": "float", "MIN": 2, "MAX": 4},'
                             '{"NAME": "g", "TYPE": "float"},'
                             '{"NAME": "mode", "TYPE": "long", "VALUES": [3, 5], "LABELS": ["a", "b"]},'
                             '{"NAME": "c", "TYPE": "color", "DEFAULT": [1, 0, 0]},'
                             '{"NAME": "p", "TYPE": "point2D", "MIN": [0, 0], "MAX": [1, 1]},'
                             '{"NAME": "i", "TYPE": "float", "IDENTITY": 0.7}]}*/\n')
    assert {i.name: i.default for i in header.inputs} == {"f": 3.0, "g": 0.5, "mode": 3, "c": (1.0, 0.0, 0.0, 1.0),
                                                          "p": (0.5, 0.5), "i": 0.7}


@pytest.mark.parametrize("inputs, kind", [
    ('[{"NAME": "startImage", "TYPE": "image"}, {"NAME": "endImage", "TYPE": "image"},'
     '{"NAME": "progress", "TYPE": "float"}]', "transition"),
    ('[{"NAME": "inputImage", "TYPE": "image"}]', "filter"), ("[]", "generator")])
def test_kind(tmp_path, inputs, kind):
    assert parse(tmp_path, f'/*{{"INPUTS": {inputs}}}*/\n').kind == kind


def test_a_missing_imported_image_is_named(tmp_path):
    path = tmp_path / "s.fs"
    path.write_text('/*{"IMPORTED": {"noise": {"PATH": "noise.png"}}}*/\n' + BODY)
    with pytest.raises(IsfError, match=r"IMPORTED image 'noise' not found at .*noise\.png"):
        IsfShader(path)
