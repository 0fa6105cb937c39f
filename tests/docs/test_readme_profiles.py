"""Every profile snippet the README shows is a valid profile: an artist copies them as they are, so a key
renamed in the code (or a value out of range) must fail here, not on stage."""
import re
import tomllib
from pathlib import Path

import pytest

from host import profile as profiles

README = Path(__file__).resolve().parents[2] / "README.md"
STATEMENT = re.compile(r"^[A-Za-z_][\w-]*\s*=")


def toml_blocks() -> list[tuple[int, str]]:
    """(line, text) of each ```toml block of the README, except a plugin's pyproject.toml."""
    text = README.read_text()
    found = [(text[: m.start()].count("\n") + 2, m.group(1))
             for m in re.finditer(r"^```toml\n(.*?)^```", text, re.M | re.S)]
    return [(line, block) for line, block in found if "[project" not in block]


def snippets(block: str) -> list[str]:
    """A block that is one profile (or part of one) whole; a list of alternatives (the same key on
    several lines, as the sources' examples are) one statement at a time, with its continued lines."""
    try:
        tomllib.loads(block)
        return [block]
    except tomllib.TOMLDecodeError:
        pass
    statements: list[str] = []
    for line in block.splitlines():
        if STATEMENT.match(line):
            statements.append(line)
        elif statements and line.startswith(" "):
            statements[-1] += "\n" + line
    return statements


CASES = [pytest.param(snippet, id=f"README.md:{line}#{i}")
         for line, block in toml_blocks() for i, snippet in enumerate(snippets(block))]


def test_the_readme_shows_profiles_of_every_kind():
    shown = "\n".join(c.values[0] for c in CASES)
    assert len(CASES) >= 20
    for table in ("[source.performers]", "[backend]", "[[effects]]", "[output]", "[source]"):
        assert table in shown, table


@pytest.mark.parametrize("snippet", CASES)
def test_each_profile_snippet_of_the_readme_is_valid(snippet, tmp_path):
    source = tomllib.loads(snippet).get("source")
    if isinstance(source, dict) and "name" not in source:  # the synthetic performers' tables alone
        snippet = '[source]\nname = "synthetic"\n' + snippet
    profile = profiles.parse(snippet, "README.md", tmp_path)
    assert profile.backend is not None and profile.warnings == []
