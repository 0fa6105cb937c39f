"""Builds the docs that are generated, never hand-written:

- docs/profile-reference.md: every profile key, from the profile schema (host.profile) and the
  Options schema of every installed backend, source and effect (so it cannot drift from the code);
- docs/images/*.png: the tutorial's pictures, rendered headless by real `issv run ... --snapshot`
  runs of the tutorial's profiles (docs/tutorial/*.toml), with the tutorial's own effect package
  (docs/tutorial/issv-hand-glow) made visible to issv the way pip would.

    python docs/build.py               # everything
    python docs/build.py --reference   # only the reference (no rendering)
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))

from host.plugins import KINDS, default_registry  # noqa: E402  (after the path is set)
from host.profile import EffectRef, Output, ProfileModel  # noqa: E402

# The host's own keys have no descriptions in their schema; these are theirs.
CORE = {
    "name": "the show's name (shown nowhere yet; for you)",
    "description": "what the show is, for the next person who opens the file",
    "source": 'where depth comes from: a name (`source = "synthetic"`) or a table with `name` and its options',
    "backend": "what finds hands and gestures: a name or a table with `name` and its options; `learned = "
               "[\"file\", {file = \"...\", threshold = 0.3, loop = 0}]` adds learned gestures, each optionally "
               "with its own threshold and loop check (docs/learned-gestures.md)",
    "effects": "the effect stack, composited in this order: `[[effects]]` tables with `name` and options",
    "output": "where the show goes (`[output]`)",
    "blend": "how this effect's layer is combined with the layers under it",
    "opacity": "the layer's opacity",
    "enabled": "false: the effect is skipped (quicker than deleting it)",
    "size": "output size in pixels [width, height] (`--size WxH` overrides)",
    "fps": "output (render) rate cap in frames per second",
    "mode": "`--headless` overrides",
    "monitor": "which monitor a fullscreen show uses (0: the first)",
    "hud": "show the status overlay (backend, sFPS / rFPS, latency, last gestures)",
    "video": "also write the show to this video file (`--out` overrides)",
    "snapshot": "save the last rendered frame as a PNG (`--snapshot` overrides)",
    "keystone": "projection mapping: where the output's four corners land, [[x, y], ...] in 0..1",
    "calibration": "camera-to-stage homography (3x3) so effects land on the performer's hands",
}
TUTORIAL_SHOTS = {  # image -> (profile, source seconds to play before the snapshot)
    "first-show.png": ("first-show.toml", 6.0),
    "hand-glow.png": ("hand-glow.toml", 6.0),
}


# -- the reference ------------------------------------------------------------------------------
def type_of(schema: dict) -> str:
    if "$ref" in schema:
        return f"table ({schema['$ref'].split('/')[-1]})"
    if "enum" in schema:
        return " | ".join(json.dumps(v) for v in schema["enum"])
    if "const" in schema:
        return json.dumps(schema["const"])
    if "anyOf" in schema:
        kinds = [s for s in schema["anyOf"] if s.get("type") != "null"]
        text = " or ".join(type_of(s) for s in kinds)
        return text + (" (optional)" if len(kinds) < len(schema["anyOf"]) else "")
    kind = schema.get("type", "any")
    if kind == "array":
        if "prefixItems" in schema:
            return "[" + ", ".join(type_of(s) for s in schema["prefixItems"]) + "]"
        return f"list of {type_of(schema.get('items', {}))}"
    if kind == "object" and "additionalProperties" in schema:
        return f"table of {type_of(schema['additionalProperties'])}"
    return {"number": "number", "integer": "integer", "string": "string", "boolean": "true/false",
            "object": "table"}.get(kind, kind)


BOUNDS = (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<"),
          ("minItems", "items >="), ("maxItems", "items <="), ("minLength", "length >="))


def limits(schema: dict) -> str:
    """The bounds of a key and of each of its alternatives (anyOf)."""
    return ", ".join(f"{sign} {part[key]:g}" for part in (schema, *schema.get("anyOf", []))
                     for key, sign in BOUNDS if isinstance(part.get(key), (int, float)))


def cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def table(schema: dict, core: bool = False, nested: bool = True) -> list[str]:
    """One markdown table of a model's keys; nested models get their own tables below it."""
    defs = schema.get("$defs", {})
    props = schema.get("properties", {})
    if not props:
        return ["No options."]
    required = set(schema.get("required", []))
    lines = ["| key | type | default | what it does |", "|---|---|---|---|"]
    for key, prop in props.items():
        default = "required" if key in required else (
            "see description" if "default" not in prop
            else "its own defaults" if isinstance(prop["default"], dict) else f"`{json.dumps(prop['default'])}`")
        what = prop.get("description") or (CORE.get(key, "") if core else "")
        bounds = limits(prop)
        lines.append(f"| `{key}` | {cell(type_of(prop))} | {cell(default)} | "
                     f"{cell(what + (f' ({bounds})' if bounds else ''))} |")
    for name, sub in defs.items() if nested else ():
        lines += ["", f"`{name}`:", ""] + table(sub)
    return lines


def first_line(cls: type) -> str:
    doc = (cls.__doc__ or "").strip() or (sys.modules[cls.__module__].__doc__ or "").strip()
    return " ".join(doc.split("\n\n")[0].split())


def reference() -> str:
    registry = default_registry()
    out = ["# Profile reference", "",
           "Generated by `python docs/build.py` from the profile schema and the installed plugins' options:",
           "do not edit by hand. A profile is a TOML file (see the tutorial); `issv check PROFILE` names",
           "every mistake as `FILE: key.path: expected ..., got ...`. Relative paths are relative to the",
           "profile file.", "", "## Top level", ""]
    out += table(ProfileModel.model_json_schema(), core=True, nested=False)
    out += ["", "## Every `[[effects]]` entry", "",
            "Besides `name` and the effect's own options below:", ""]
    effect_keys = EffectRef.model_json_schema()
    effect_keys["properties"] = {k: v for k, v in effect_keys["properties"].items() if k != "name"}
    out += table(effect_keys, core=True)
    out += ["", "## `[output]`", ""] + table(Output.model_json_schema(), core=True)
    titles = {"sources": "Sources (`source`)", "backends": "Backends (`backend`)", "effects": "Effects (`[[effects]]`)"}
    for kind in KINDS:
        out += ["", f"## {titles[kind]}", ""]
        for entry in registry.all(kind):
            reason = entry.availability()
            out += [f"### `{entry.name}`", "", first_line(entry.cls), "",
                    f"From plugin `{entry.plugin}`." + (f" Not available here: {reason}" if reason else ""), ""]
            try:
                out += table(entry.cls.Options.model_json_schema())
            except Exception as error:  # a plugin's schema that cannot be generated is documented as such
                out.append(f"(its options schema could not be generated: {type(error).__name__}: {error})")
            out.append("")
    return "\n".join(out).rstrip() + "\n"


# -- the tutorial's images ----------------------------------------------------------------------
def plugin_path(package: Path, entry: str, module: str) -> Path:
    """A folder that makes `package` an installed issv plugin for a child process: the package
    itself plus a .dist-info with its entry point, which is what pip would write."""
    folder = Path(tempfile.mkdtemp(prefix="issv-docs-"))
    info = folder / f"{package.name.replace('-', '_')}-0.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {package.name}\nVersion: 0.0\n")
    (info / "entry_points.txt").write_text(f"[issv]\n{entry} = {module}\n")
    return folder


def images(out_dir: Path) -> list[Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    glow = DOCS / "tutorial" / "issv-hand-glow"
    extra = plugin_path(glow, "hand-glow", "issv_hand_glow")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(extra), str(glow), str(ROOT)])}
    made = []
    for image, (profile, seconds) in TUTORIAL_SHOTS.items():
        target = out_dir / image
        cmd = [sys.executable, "-m", "host", "run", str(DOCS / "tutorial" / profile), "--headless",
               "--seconds", str(seconds), "--snapshot", str(target), "--no-reload"]
        run = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=ROOT)
        if run.returncode != 0:
            raise SystemExit(f"docs: {' '.join(cmd[2:])} failed:\n{run.stderr.strip()}")
        made.append(target)
    return made


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reference", action="store_true", help="only write the profile reference")
    args = parser.parse_args(argv)
    (DOCS / "profile-reference.md").write_text(reference(), encoding="utf-8")
    print(f"wrote {DOCS / 'profile-reference.md'}")
    if not args.reference:
        for path in images(DOCS / "images"):
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
