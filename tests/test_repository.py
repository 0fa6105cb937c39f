"""The repository stands on its own: no tracked file cites design notes that are not in it."""
from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUTSIDE_NOTES = re.compile(r"\b(DESIGN|STYLE)\.md\b")
HISTORY = {"docs/architecture.md"}  # its History section says what replaced those notes


def tracked_files() -> list[str]:
    listed = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    if listed.returncode == 0 and listed.stdout:
        return listed.stdout.splitlines()
    return [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.is_file() and ".git" not in p.parts]


def test_no_file_cites_the_design_notes_outside_the_repo():
    citing = []
    for name in tracked_files():
        if name in HISTORY or name == "tests/test_repository.py":
            continue
        try:
            text = (ROOT / name).read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError):
            continue  # binary files; files deleted in the working tree
        citing += [f"{name}:{i}" for i, line in enumerate(text.splitlines(), 1) if OUTSIDE_NOTES.search(line)]
    assert citing == [], f"cite docs/architecture.md or docs/style.md instead: {citing}"


def test_the_architecture_page_covers_what_the_code_relies_on():
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    for section in ("## The pipeline", "## Vocabulary and data model", "## Contracts", "## Interchange formats",
                    "## The frame loop", "## Where each part lives"):
        assert section in text
    for linked in re.findall(r"`((?:host|backends|sources|effects|bench|tests)/[\w/.]*)`", text):
        assert (ROOT / linked).exists(), f"docs/architecture.md names {linked}, which does not exist"
