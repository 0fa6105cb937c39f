"""The classifier of a set of learned gestures, trained once and kept (host/learned/cache.py)."""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest

from host.learned import cache
from host.learned.classifier import Classifier, describe_all
from host.learned.examples import read_take
from host.learned.learner import learn
from host.learned.recognizer import LearnedRecognizer
from tests.host.learned.performer import Performer, circle, punch


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> list[Path]:
    """circle and punch, taught by one performer (three repetitions each)."""
    folder = tmp_path_factory.mktemp("taught")
    out = []
    for name, motion in (("circle", circle), ("punch", punch)):
        take = folder / f"{name}.csv"
        Performer(seed=1).write(take, motion, 3)
        out.append(folder / f"{name}.gesture.json")
        learn(name, [read_take(str(take), True)]).save(out[-1])
    return out


@pytest.fixture
def trainings(tmp_path, monkeypatch) -> list[int]:
    """An empty cache folder, nothing trained in this process yet; the trainings (gestures trained
    on) as they happen."""
    monkeypatch.setenv("ISSV_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(cache, "TRAINED", {})
    done: list[int] = []
    train = Classifier.train
    monkeypatch.setattr(Classifier, "train", staticmethod(
        lambda taught, unlike=None: done.append(len(taught)) or train(taught, unlike)))
    return done


def loaded(files: list[Path]) -> Classifier:
    return LearnedRecognizer.from_files(files).matcher.classifier


def a_new_process() -> None:
    cache.TRAINED.clear()


def entries(tmp_path: Path) -> list[Path]:
    return sorted((tmp_path / "cache" / "learned").glob("*"))


DESCRIPTORS = describe_all(np.cumsum(np.random.default_rng(0).normal(0.0, 0.05, (200, 6)), axis=0))


def test_a_set_loaded_again_gets_its_classifier_bit_for_bit_without_training(files, trainings, tmp_path):
    first = loaded(files)
    assert trainings == [2] and len(entries(tmp_path)) == 1
    assert loaded(files) is first  # in this process: every recogniser and user shares one
    a_new_process()
    again = loaded(files)
    assert trainings == [2]  # read from the disk cache
    assert again is not first
    assert np.array_equal(again.probabilities(DESCRIPTORS), first.probabilities(DESCRIPTORS))


def _edited(files: list[Path], folder: Path, edit) -> list[Path]:
    out = []
    for i, path in enumerate(files):
        doc = json.loads(path.read_text())
        if i == 0:
            edit(doc)
        out.append(folder / path.name)
        out[-1].write_text(json.dumps(doc))
    return out


def _nudge_one_repetition(doc: dict) -> None:
    doc["repetitions"][1]["postures"][5][0] += 0.01


def _threshold(doc: dict) -> None:
    doc["threshold"] *= 1.5


def _counter_example(doc: dict) -> None:
    doc["unlike"] = [{**doc["repetitions"][0], "source": "not-this.csv"}]


@pytest.mark.parametrize("change, trained_again", [
    (lambda files, folder: _edited(files, folder, _nudge_one_repetition), True),
    (lambda files, folder: files[::-1], True),  # the classes are in load order
    (lambda files, folder: _edited(files, folder, _counter_example), True),  # `issv learn --unlike`
    (lambda files, folder: _edited(files, folder, _threshold), False),  # the classifier does not use it
    (lambda files, folder: _edited(files, folder, lambda doc: None), False),  # the same contents elsewhere
], ids=["one-repetition-altered", "another-order", "counter-example-added", "threshold-edited", "copied"])
def test_only_what_training_depends_on_makes_another_entry(files, trainings, tmp_path, change, trained_again):
    loaded(files)
    a_new_process()
    loaded(change(files, tmp_path))
    assert trainings == [2, 2] if trained_again else [2]
    assert len(entries(tmp_path)) == (2 if trained_again else 1)


class _Touch:
    """Unpickled, it would make a file: what a pickled cache entry could do."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self):
        return Path.touch, (self.path,)


def _pickled(entry: Path) -> None:
    np.savez(entry, key=np.array(entry.stem), mean=np.array([_Touch(entry.parent / "ran")], dtype=object))


def _rekeyed(entry: Path) -> None:
    with np.load(entry) as arrays:
        kept = dict(arrays)
    np.savez(entry, **{**kept, "key": np.array("another set")})


@pytest.mark.parametrize("spoil", [
    lambda entry: entry.write_bytes(entry.read_bytes()[:300]),
    lambda entry: entry.write_bytes(b"not an npz"),
    lambda entry: np.savez(entry, key=np.array(entry.stem), mean=np.zeros(3), scale=np.ones(3),
                           weights=np.zeros((6, 3)), bias=np.zeros(3)),
    _rekeyed,
    _pickled,
], ids=["truncated", "not-npz", "other-shapes", "another-key", "pickled"])
def test_a_spoilt_entry_is_trained_over(files, trainings, tmp_path, spoil):
    first = loaded(files)
    [entry] = entries(tmp_path)
    spoil(entry)
    a_new_process()
    again = loaded(files)
    assert trainings == [2, 2]
    assert not (entry.parent / "ran").exists()  # nothing in an entry is run
    assert np.array_equal(again.probabilities(DESCRIPTORS), first.probabilities(DESCRIPTORS))
    a_new_process()
    loaded(files)  # written over: sound again
    assert trainings == [2, 2]


def test_a_cache_that_cannot_be_written_is_no_cache(files, trainings, tmp_path, monkeypatch):
    (tmp_path / "a-file").write_text("")
    monkeypatch.setenv("ISSV_CACHE_DIR", str(tmp_path / "a-file"))
    first = loaded(files)
    a_new_process()
    again = loaded(files)
    assert trainings == [2, 2]
    assert np.array_equal(again.probabilities(DESCRIPTORS), first.probabilities(DESCRIPTORS))


def test_the_entries_kept_are_those_of_the_sets_used_last_however_long_ago_they_were_trained(
        files, trainings, tmp_path, monkeypatch):
    monkeypatch.setattr(cache, "KEEP", 2)
    loaded(files)  # trained first, then used again after another set was trained
    [entry_used_long] = entries(tmp_path)
    loaded(files[::-1])
    for entry in entries(tmp_path):  # written a minute apart, the set used long ago first
        stamp = entry.stat().st_mtime - (120 if entry == entry_used_long else 60)
        os.utime(entry, (stamp, stamp))
    a_new_process()
    loaded(files)  # read from disk: now the most recently used
    loaded(files[:1])  # a third set: one entry goes
    assert trainings == [2, 2, 1]
    assert entry_used_long in entries(tmp_path) and len(entries(tmp_path)) == 2
