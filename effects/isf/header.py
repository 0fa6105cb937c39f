"""An ISF file's JSON header read as the ISF 2.0 spec means it, whatever version or quirks it has.

Real files put `//` comments before or inside the header, leave trailing commas, write ISF v1
(`PERSISTENT_BUFFERS`, IMPORTED as a list), give WIDTH/HEIGHT as numbers or as expressions
(`"floor($WIDTH/4.0)"`, `"max(8.0,floor($HEIGHT*$buffQuality))"`): all are normalised here into
`Header` (inputs, passes, imported images), so the renderer only knows ISF 2.0.
"""
from __future__ import annotations

import ast
import json
import math
import operator
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from host.errors import UserError

GLSL_TYPES = {"float": "float", "long": "int", "bool": "bool", "event": "bool", "color": "vec4",
              "point2D": "vec2", "image": "sampler2D", "audio": "sampler2D", "audioFFT": "sampler2D"}
IMAGE_TYPES = ("image", "audio", "audioFFT")


class IsfError(UserError):
    """An ISF file that cannot run: the message names the file (and line when there is one)."""


@dataclass
class Input:
    """One entry of INPUTS; `default` is already of the input's type (see `default_value`)."""

    name: str
    type: str
    default: Any
    minimum: Any = None
    maximum: Any = None
    identity: Any = None
    values: list[int] = field(default_factory=list)
    labels: list[str] = field(default_factory=list)

    @property
    def samples(self) -> int:
        """An audio/audioFFT input's MAX: how many samples or bins it wants (0: the host's choice)."""
        return int(self.maximum) if isinstance(self.maximum, (int, float)) and self.maximum >= 2 else 0


@dataclass
class Pass:
    """One entry of PASSES: `target` None draws the output; sizes are expressions or None."""

    target: str | None = None
    persistent: bool = False
    float: bool = False
    width: str | None = None
    height: str | None = None


@dataclass
class Header:
    inputs: list[Input]
    passes: list[Pass]
    imported: dict[str, Path]
    persistent: dict[str, Pass]  # v1 PERSISTENT_BUFFERS that no pass targets still exist
    description: str = ""
    categories: list[str] = field(default_factory=list)
    body_start: int = 0  # offset of the GLSL after the header comment

    @property
    def kind(self) -> str:
        """"transition" (startImage, endImage, progress), "filter" (inputImage) or "generator"."""
        names = {i.name for i in self.inputs}
        if {"startImage", "endImage", "progress"} <= names:
            return "transition"
        return "filter" if "inputImage" in names else "generator"


def parse_header(path: Path, text: str) -> Header:
    start = text.find("/*")
    if start < 0 or text[:start].strip() and not _only_line_comments(text[:start]):
        raise IsfError(f"{path}:1: an ISF shader starts with its JSON header in a /* ... */ comment")
    end = text.find("*/", start)
    brace = text.find("{", start, end if end >= 0 else None)
    if end < 0 or brace < 0:
        raise IsfError(f"{path}:{text.count(chr(10), 0, start) + 1}: the ISF header comment has no "
                       "JSON object or is not closed with */")
    raw = relax_json(text[brace:end])
    try:
        data = json.loads(raw)
    except json.JSONDecodeError as error:
        line = text.count("\n", 0, brace) + error.lineno
        raise IsfError(f"{path}:{line}: the ISF header is not valid JSON: {error.msg}") from None
    if not isinstance(data, dict):
        raise IsfError(f"{path}:1: the ISF header must be a JSON object")
    persistent = _persistent_buffers(data.get("PERSISTENT_BUFFERS"))
    passes = [_pass(path, p, persistent) for p in (data.get("PASSES") or [{}])]
    targeted = {p.target for p in passes}
    return Header(inputs=[_input(path, entry) for entry in _list(data.get("INPUTS"))],
                  passes=passes,
                  imported=_imported(path, data.get("IMPORTED")),
                  persistent={n: p for n, p in persistent.items() if n not in targeted},
                  description=str(data.get("DESCRIPTION", "")),
                  categories=[str(c) for c in _list(data.get("CATEGORIES"))],
                  body_start=end + 2)


def _only_line_comments(prefix: str) -> bool:
    return all(not line.strip() or line.strip().startswith("//") for line in prefix.splitlines())


def relax_json(text: str) -> str:
    """`//` comments and trailing commas removed (outside strings), newlines kept for line numbers."""
    return _outside_strings(_outside_strings(text, _drop_comment), _drop_trailing_comma)


def _outside_strings(text: str, rule) -> str:
    """Applies `rule(text, i) -> (output, next i) | None` at each character outside JSON strings."""
    out, i, n, in_string = [], 0, len(text), False
    while i < n:
        c = text[i]
        if in_string:
            out.append(text[i:i + 2] if c == "\\" else c)
            i += 2 if c == "\\" else 1
            in_string = c != '"'
            continue
        applied = rule(text, i)
        if applied is not None:
            out.append(applied[0])
            i = applied[1]
            continue
        in_string = c == '"'
        out.append(c)
        i += 1
    return "".join(out)


def _drop_comment(text: str, i: int) -> tuple[str, int] | None:
    if not text.startswith("//", i):
        return None
    end = text.find("\n", i)
    return "", len(text) if end < 0 else end


def _drop_trailing_comma(text: str, i: int) -> tuple[str, int] | None:
    if text[i] != ",":
        return None
    rest = text[i + 1:].lstrip()
    return (" ", i + 1) if rest[:1] in ("]", "}") else None


def _list(value: Any) -> list:
    return value if isinstance(value, list) else []


def _persistent_buffers(value: Any) -> dict[str, Pass]:
    """ISF v1: a list of names, or {name: {WIDTH, HEIGHT, FLOAT}}."""
    if isinstance(value, dict):
        return {n: Pass(n, True, bool(v.get("FLOAT")), _size(v.get("WIDTH")), _size(v.get("HEIGHT")))
                for n, v in value.items() if isinstance(v, dict)}
    return {n: Pass(n, True) for n in _list(value) if isinstance(n, str)}


def _size(value: Any) -> str | None:
    return None if value is None else str(value)


def _pass(path: Path, entry: Any, persistent: dict[str, Pass]) -> Pass:
    if not isinstance(entry, dict):
        raise IsfError(f"{path}: PASSES entries are objects, not {entry!r}")
    target = entry.get("TARGET") or None
    v1 = persistent.get(target)
    return Pass(target=target,
                persistent=bool(entry.get("PERSISTENT")) or v1 is not None,
                float=bool(entry.get("FLOAT")) or bool(v1 and v1.float),
                width=_size(entry.get("WIDTH")) or (v1.width if v1 else None),
                height=_size(entry.get("HEIGHT")) or (v1.height if v1 else None))


def _imported(path: Path, value: Any) -> dict[str, Path]:
    entries = value.items() if isinstance(value, dict) else ((e.get("NAME"), e) for e in _list(value)
                                                              if isinstance(e, dict))
    out = {}
    for name, entry in entries:
        file = entry.get("PATH") if isinstance(entry, dict) else None
        if not isinstance(name, str) or not isinstance(file, str):
            raise IsfError(f"{path}: IMPORTED entry {name!r}: expected {{\"PATH\": \"image file\"}}")
        out[name] = path.parent / file
    return out


def _input(path: Path, entry: Any) -> Input:
    name, kind = (entry.get("NAME"), entry.get("TYPE")) if isinstance(entry, dict) else (None, None)
    if not isinstance(name, str) or kind not in GLSL_TYPES:
        raise IsfError(f"{path}: ISF input {entry!r}: expected a NAME and a TYPE among {', '.join(GLSL_TYPES)}")
    values = [int(v) for v in _list(entry.get("VALUES")) if isinstance(v, (int, float))]
    item = Input(name, kind, None, entry.get("MIN"), entry.get("MAX"), entry.get("IDENTITY"), values,
                 [str(label) for label in _list(entry.get("LABELS"))])
    item.default = default_value(item, entry.get("DEFAULT"))
    return item


def default_value(item: Input, given: Any) -> Any:
    """The DEFAULT as its type; without one the IDENTITY, else the middle of MIN..MAX (0..1 when
    not given: a float without a default is a slider, and 0 often hides everything)."""
    as_type = _AS_TYPE.get(item.type)
    if as_type is None:
        return None  # images: bound at render time
    try:
        return as_type(item, given if given is not None else item.identity)
    except (TypeError, ValueError):
        raise IsfError(f"input {item.name!r} ({item.type}): DEFAULT {given!r} is not a {item.type}") from None


def _float(item: Input, value: Any) -> float:
    if value is None:
        lo = item.minimum if isinstance(item.minimum, (int, float)) else 0.0
        hi = item.maximum if isinstance(item.maximum, (int, float)) else 1.0
        value = (lo + hi) / 2
    return float(value)


def _long(item: Input, value: Any) -> int:
    if value is None:
        value = item.values[0] if item.values else item.minimum or 0
    return int(value)


def _color(item: Input, value: Any) -> tuple[float, ...]:
    rgba = [float(v) for v in (value if isinstance(value, list) else [0, 0, 0, 1])][:4]
    return tuple(rgba + [1.0] * (4 - len(rgba)))


def _point(item: Input, value: Any) -> tuple[float, ...]:
    if value is None and isinstance(item.minimum, list) and isinstance(item.maximum, list):
        value = [(a + b) / 2 for a, b in zip(item.minimum, item.maximum)]
    xy = [float(v) for v in (value if isinstance(value, list) else [0, 0])][:2]
    return tuple(xy + [0.0] * (2 - len(xy)))


_AS_TYPE = {"float": _float, "long": _long, "bool": lambda item, value: bool(value),
            "event": lambda item, value: bool(value), "color": _color, "point2D": _point}


_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.Mod: operator.mod, ast.Pow: operator.pow, ast.USub: operator.neg, ast.UAdd: operator.pos}
_FUNCS = {name: getattr(math, name) for name in ("floor", "ceil", "sqrt", "pow", "sin", "cos", "tan", "log",
                                                 "exp", "fabs")} | {"max": max, "min": min, "abs": abs,
                                                                    "round": round}


def evaluate_size(expression: str, variables: dict[str, float]) -> float:
    """A WIDTH/HEIGHT expression: numbers, $WIDTH, $HEIGHT, $input, + - * / % and math functions."""
    source = re.sub(r"\$(\w+)", r"_\1", expression.strip())
    env = {f"_{k}": float(v) for k, v in variables.items()}

    def value(node: ast.AST) -> float:
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.Name) and node.id in env:
            return env[node.id]
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](value(node.left), value(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](value(node.operand))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS:
            return float(_FUNCS[node.func.id](*(value(a) for a in node.args)))
        raise ValueError(ast.dump(node))

    try:
        return value(ast.parse(source, mode="eval").body)
    except (SyntaxError, ValueError, TypeError, ZeroDivisionError) as error:
        raise IsfError(f"size expression {expression!r} cannot be evaluated ({error}); use numbers, "
                       "$WIDTH, $HEIGHT, input names and + - * / floor ceil max min") from None
