"""The benches' shared data folder: --data, $ISSV_DATA, and one line for what is skipped without it."""
from __future__ import annotations

import argparse
from pathlib import Path

from bench.common import add_data_argument, data_set, default_data


def parse(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    add_data_argument(parser)
    return parser.parse_args(argv)


def test_the_data_folder_comes_from_the_environment_first(tmp_path, monkeypatch):
    monkeypatch.setenv("ISSV_DATA", str(tmp_path))
    assert default_data() == tmp_path
    assert parse([]).data == tmp_path
    assert parse(["--data", "/elsewhere"]).data == Path("/elsewhere")


def test_a_present_set_is_used_and_a_missing_one_is_one_line(tmp_path, capsys):
    (tmp_path / "utd-mhad-dev").mkdir()
    args = parse(["--data", str(tmp_path)])
    assert data_set(args, "utd-mhad-dev", "the real rows") == tmp_path / "utd-mhad-dev"
    assert capsys.readouterr().err == ""
    assert data_set(args, "msrc12-dev", "the MSRC-12 rows") is None
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "msrc12-dev" in err[0] and "skipping the MSRC-12 rows" in err[0]


def test_no_data_at_all_says_how_to_give_it(monkeypatch, capsys):
    monkeypatch.delenv("ISSV_DATA", raising=False)
    assert data_set(argparse.Namespace(data=None), "utd-mhad-dev", "the real rows") is None
    assert "no --data DIR and no $ISSV_DATA: skipping the real rows" in capsys.readouterr().err
