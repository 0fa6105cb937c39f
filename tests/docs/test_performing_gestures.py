"""docs/performing-gestures.md quotes the recogniser's rules to performers: every rule it names must
exist, and every default its tables give must be the code's."""
import re
from pathlib import Path

from backends.engine.rules import GestureRules

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "performing-gestures.md"
RULE_PREFIXES = ("swipe_", "wave_", "click_", "raise_", "active_", "steady_", "refractory_")


def test_every_rule_the_guide_names_exists():
    named = {n for n in re.findall(r"`([a-z_]+)`", GUIDE.read_text()) if n.startswith(RULE_PREFIXES)}
    assert named, "the guide names no rule"
    assert named <= set(GestureRules.model_fields), sorted(named - set(GestureRules.model_fields))


def test_every_default_in_the_guide_is_the_code_s():
    rows = re.findall(r"^\| `([a-z_]+)` \| ([-0-9.]+) \|", GUIDE.read_text(), re.MULTILINE)
    assert len(rows) >= 20, rows
    defaults = GestureRules()
    for key, value in rows:
        assert float(value) == float(getattr(defaults, key)), f"{key}: the guide says {value}, the code {getattr(defaults, key)}"
