"""The scheme is documented once: `issv osc-schema`, the README and both patches agree with it."""
import json
import re
import subprocess
import sys

from effects.osc import OscEffect
from effects.osc.schema import SCHEMA_TEXT
from host.cli import main
from tests.effects.osc.helpers import ROOT
from tests.effects.osc.test_scheme import DOCUMENTED

PD = (ROOT / "patches" / "issv-receiver.pd").read_text()
MAX = json.loads((ROOT / "patches" / "issv-receiver.maxpat").read_text())


def pd_objects() -> list[str]:
    return [m.group(1) for m in re.finditer(r"^#X obj \d+ \d+ (.*?);$", PD, re.M)]


def test_osc_schema_prints_the_scheme(capsys):
    assert main(["osc-schema"]) == 0
    assert capsys.readouterr().out == SCHEMA_TEXT
    assert main(["osc-schema", "synapse"]) == 0
    assert "/<joint>_pos_body      f f f" in capsys.readouterr().out


def test_osc_schema_is_a_real_command():
    out = subprocess.run([sys.executable, "-m", "host", "osc-schema"], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0 and out.stdout == SCHEMA_TEXT


def test_the_readme_quotes_the_scheme_the_presets_and_names_the_patches():
    readme = (ROOT / "README.md").read_text()
    for scheme in ("issv", "osceleton", "synapse", "custom"):
        assert OscEffect.describe(scheme) in readme
    assert "patches/issv-receiver.pd" in readme and "patches/issv-receiver.maxpat" in readme


def test_the_pd_patch_listens_on_9000_and_routes_the_scheme():
    objects = pd_objects()
    assert "netreceive -u -b" in objects and "oscparse" in objects
    assert re.search(r"^#X msg \d+ \d+ listen 9000;$", PD, re.M)
    kinds = [a.split("/")[2] for a in DOCUMENTED]
    assert "route issv" in objects and f"route {' '.join(kinds)}" in objects
    as_pd = {a: t.replace("i", "f") for a, t in DOCUMENTED.items()}  # Pd numbers are floats
    assert "unpack " + " ".join(as_pd["/issv/frame"]) in objects
    assert "unpack " + " ".join(as_pd["/issv/gesture"]) in objects
    assert "unpack " + " ".join(as_pd["/issv/hand"][3:]) in objects  # x y z confidence, after id side state


def test_the_max_patch_is_valid_and_routes_the_scheme():
    boxes = {b["box"]["id"]: b["box"] for b in MAX["patcher"]["boxes"]}
    for line in MAX["patcher"]["lines"]:
        (src, outlet), (dst, inlet) = line["patchline"]["source"], line["patchline"]["destination"]
        assert outlet < boxes[src]["numoutlets"] and inlet < boxes[dst]["numinlets"]
    texts = [b.get("text", "") for b in boxes.values() if b["maxclass"] == "newobj"]
    assert "udpreceive 9000" in texts
    assert f"route {' '.join(DOCUMENTED)}" in texts
    assert "unpack " + " ".join(DOCUMENTED["/issv/frame"]) in texts
    assert "unpack " + " ".join(DOCUMENTED["/issv/gesture"]) in texts
