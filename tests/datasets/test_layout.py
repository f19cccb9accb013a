"""The dataset loader: names from disk, splits, and clear errors for malformed trees."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from framefree.datasets import (
    GESTURES,
    MODEL_CONTEXT,
    REPLICA_CONTEXTS,
    LayoutWarning,
    load_dataset,
)
from framefree.errors import DatasetError


def _write(path: Path, rows: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, rows, delimiter=",")


def _rows(n: int = 10) -> np.ndarray:
    t = np.arange(n) * 0.02
    return np.column_stack([t, t, np.zeros(n), np.zeros(n), np.ones(n), np.zeros((n, 3))])


@pytest.fixture
def tiny(tmp_path: Path) -> Path:
    """Two gestures × two contexts × trials 1..3, custom names."""
    for g in ("wave", "clap"):
        for c in ("ref", "noisy"):
            for k in (1, 2, 3):
                _write(tmp_path / g / c / f"rec_{k}.csv", _rows())
    return tmp_path


def test_replica_layout(replica) -> None:
    assert replica.gestures == tuple(sorted(GESTURES))
    assert replica.contexts == REPLICA_CONTEXTS
    assert replica.model_context == MODEL_CONTEXT
    assert len(replica) == 560
    assert len(replica.models()) == 35
    assert len(replica.queries()) == 525
    assert len(replica.queries("train")) == 210
    assert len(replica.queries("test")) == 315
    assert all(t.name[-1] in "12" for t in replica.queries("train"))
    assert {t.context for t in replica.queries()} == set(REPLICA_CONTEXTS) - {MODEL_CONTEXT}
    t = replica.trials[0]
    assert t.path.is_file() and t.path.stem == t.name and len(t.trajectory) > 50
    with pytest.raises(ValueError, match="split"):
        replica.queries("validation")


def test_names_read_from_disk(tiny: Path) -> None:
    ds = load_dataset(tiny, model_context="ref")
    assert ds.gestures == ("clap", "wave")
    assert ds.contexts == ("noisy", "ref")
    assert [t.name for t in ds.select("wave", "ref")] == ["rec_1", "rec_2", "rec_3"]
    assert len(ds.models()) == 6 and len(ds.queries("test")) == 2


def test_hidden_entries_and_streams_skipped(tiny: Path) -> None:
    (tiny / ".DS_Store").write_text("x")
    (tiny / "wave" / "ref" / ".hidden.csv").write_text("junk")
    _write(tiny / "streams" / "s.csv", _rows())
    assert len(load_dataset(tiny, model_context="ref")) == 12


def test_natural_trial_order(tmp_path: Path) -> None:
    for k in (1, 2, 10):
        _write(tmp_path / "g" / "original_1" / f"trial_{k}.csv", _rows())
    ds = load_dataset(tmp_path)
    assert [t.name for t in ds.trials] == ["trial_1", "trial_2", "trial_10"]


def test_xyzw_quaternions(tmp_path: Path) -> None:
    rows = _rows()
    rows[:, 4:] = [0.0, 0.0, np.sqrt(0.5), np.sqrt(0.5)]  # x, y, z, w
    _write(tmp_path / "g" / "original_1" / "trial_1.csv", rows)
    ds = load_dataset(tmp_path, quat_order="xyzw")
    np.testing.assert_allclose(ds.trials[0].trajectory.q[0], [np.sqrt(0.5), 0, 0, np.sqrt(0.5)])


def test_missing_root(tmp_path: Path) -> None:
    with pytest.raises(DatasetError, match="no such dataset folder"):
        load_dataset(tmp_path / "nope")


def test_root_is_a_file(tmp_path: Path) -> None:
    f = tmp_path / "x.csv"
    f.write_text("")
    with pytest.raises(DatasetError, match="not a folder"):
        load_dataset(f)


def test_empty_root(tmp_path: Path) -> None:
    with pytest.raises(DatasetError, match="empty folder"):
        load_dataset(tmp_path)


def test_empty_gesture_folder(tiny: Path) -> None:
    (tiny / "empty").mkdir()
    with pytest.raises(DatasetError, match=r"empty.*expected context folders"):
        load_dataset(tiny, model_context="ref")


def test_empty_context_folder(tiny: Path) -> None:
    (tiny / "wave" / "blank").mkdir()
    with pytest.raises(DatasetError, match=r"blank: empty folder"):
        load_dataset(tiny, model_context="ref")


def test_stray_file_in_root_is_skipped_with_a_warning(tiny: Path) -> None:
    (tiny / "notes.txt").write_text("hello")
    (tiny / "gallery.png").write_bytes(b"\x89PNG\r\n")
    with pytest.warns(LayoutWarning) as record:
        ds = load_dataset(tiny, model_context="ref")
    messages = sorted(str(w.message) for w in record)
    assert messages[0].startswith(f"{tiny / 'gallery.png'}: skipped: not a .csv recording")
    assert messages[1].startswith(f"{tiny / 'notes.txt'}: skipped: not a .csv recording")
    assert len(ds) == 12


def test_stray_file_in_gesture_folder(tiny: Path) -> None:
    _write(tiny / "wave" / "loose.csv", _rows())
    with pytest.raises(DatasetError, match=r"loose.csv: unexpected file"):
        load_dataset(tiny, model_context="ref")


def test_stray_file_in_context_folder_is_skipped_with_a_warning(tiny: Path) -> None:
    (tiny / "wave" / "ref" / "readme.md").write_text("x")
    with pytest.warns(LayoutWarning, match=r"readme.md: skipped.*only .csv trials"):
        ds = load_dataset(tiny, model_context="ref")
    assert [t.name for t in ds.select("wave", "ref")] == ["rec_1", "rec_2", "rec_3"]


def test_a_csv_that_fails_to_parse_stays_an_error(tiny: Path) -> None:
    (tiny / "wave" / "ref" / "rec_4.csv").write_bytes(b"\x89PNG\r\n\x1a\n")
    with pytest.raises(DatasetError, match=r"rec_4.csv: this is a PNG image, not a pose CSV"):
        load_dataset(tiny, model_context="ref")


def test_nested_folder_in_context(tiny: Path) -> None:
    (tiny / "wave" / "ref" / "deeper").mkdir()
    with pytest.raises(DatasetError, match=r"deeper: unexpected folder"):
        load_dataset(tiny, model_context="ref")


def test_missing_model_context(tiny: Path) -> None:
    shutil.rmtree(tiny / "clap" / "ref")
    with pytest.raises(DatasetError, match=r"clap: no model context folder 'ref'"):
        load_dataset(tiny, model_context="ref")
    with pytest.raises(DatasetError, match="original_1"):
        load_dataset(tiny)


def test_bad_csv_names_file_and_row(tiny: Path) -> None:
    bad = tiny / "wave" / "noisy" / "rec_2.csv"
    lines = bad.read_text().splitlines()
    lines[4] = "0.08,1,2,oops,1,0,0,0"
    bad.write_text("\n".join(lines))
    with pytest.raises(DatasetError, match=r"rec_2.csv, row 5: column 4: 'oops' is not a number"):
        load_dataset(tiny, model_context="ref")


def test_csv_with_wrong_column_count(tiny: Path) -> None:
    (tiny / "clap" / "ref" / "rec_1.csv").write_text("0,1,2\n")
    with pytest.raises(DatasetError, match=r"rec_1.csv, row 1: expected 8"):
        load_dataset(tiny, model_context="ref")


def test_a_folder_of_people_gives_every_persons_recordings_to_their_label(tmp_path: Path) -> None:
    """``<person>/<label>/*.csv`` (several people's segmented examples) has a dataset root's
    shape; with no model context in it, ``--models`` and ``enroll`` read it as people."""
    from framefree.datasets import resolve_models
    from framefree.library import read_takes

    for person, labels in (("ann", ("swing", "punch")), ("bob", ("swing", "punch")), ("cy", ("swing",))):
        for label in labels:
            for k in (1, 2):
                _write(tmp_path / "people" / person / label / f"{k}.csv", _rows())
    found = resolve_models(tmp_path / "people")
    assert found.layout == "people"
    assert sorted(found.labels) == ["punch"] * 4 + ["swing"] * 6
    assert "folder of people" in found.description and "from 3 people" in found.description
    takes = read_takes(tmp_path / "people")
    assert list(takes.labels) == found.labels  # the same recordings in the same order
    assert "swing/cy/2" in takes.names and len(takes.without(["swing/cy/2"]).takes) == 9


def test_a_dataset_root_is_not_read_as_people(tiny: Path) -> None:
    """A dataset root keeps its meaning: with its model context, with a context asked for, and
    with one gesture folder of two unknown contexts (which asks for the context)."""
    from framefree.datasets import resolve_models
    from framefree.datasets.layout import people_trials

    assert resolve_models(tiny, model_context="ref").layout == "dataset"
    own = tiny.with_name(tiny.name + "_own")
    for g in ("wave", "clap"):
        shutil.copytree(tiny / g / "ref", own / g / "own")
    assert people_trials(own) is None  # framefree record's own folders
    single = tiny.with_name(tiny.name + "_single")
    shutil.copytree(tiny / "clap", single / "clap")
    with pytest.raises(DatasetError, match="--model-context"):
        resolve_models(single)
    _write(tiny / "wave" / MODEL_CONTEXT / "rec_1.csv", _rows())
    assert people_trials(tiny) is None
