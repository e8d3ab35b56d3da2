"""Warnings in Python (issue 34): ``paradyn.run`` issues the check's warnings (a likely unit
mistake) and the engine's through Python's ``warnings`` with ParaDyn's categories, at the caller's
line, every run; keeps them in ``EngineRun.warnings`` and writes them to ``summary.json``; a
``RunProgress`` display shows them instead."""

from __future__ import annotations

import io
import json
import tomllib
import warnings
from pathlib import Path

import pytest
import tomli_w

import paradyn
from paradyn.running.progress import RunProgress

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def _plate_with_mistakes(folder: Path) -> Path:
    """The small plate with a density in g/cm^3 (7.86, not 7860) and a requested step far above the
    stable one (the engine's warning); it still runs, in a few hundred cycles."""
    tables = tomllib.loads(SMALL_PLATE.read_text())
    tables["material"][0]["density"] = 7.86
    tables["run"]["time_step"] = 1e-5
    path = folder / "mistakes.toml"
    path.write_text(tomli_w.dumps(tables))
    return path


def test_unit_mistakes_and_engine_warnings_reach_python(tmp_path: Path) -> None:
    source = _plate_with_mistakes(tmp_path)
    with pytest.warns(paradyn.ParaDynWarning) as caught:
        res = paradyn.run(source, tmp_path / "out", ranks=1, threads=1)
    model = [w for w in caught if w.category is paradyn.ModelWarning]
    engine = [w for w in caught if w.category is paradyn.EngineWarning]
    assert len(model) == 1 and "density 7.86 looks like g/cm^3" in str(model[0].message)
    assert len(engine) == 1 and "the requested time step" in str(engine[0].message)
    assert {Path(w.filename) for w in caught} == {Path(__file__)}   # the caller's line, not paradyn's
    kept = res.engine_run.warnings
    assert len(kept) == 2 and kept[0].startswith("paradyn: warning: material steel: density 7.86")
    assert kept[1].startswith("paradyn-engine: warning: the requested time step")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["warnings"] == kept


def test_warnings_are_said_again_on_every_run_and_follow_the_filters(tmp_path: Path) -> None:
    source = _plate_with_mistakes(tmp_path)
    for _ in range(2):   # Python's default shows a warning once per line; a run says it every time
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("default")
            paradyn.run(source, tmp_path / "out", ranks=1, threads=1, post=False)
        assert [w.category for w in caught] == [paradyn.ModelWarning, paradyn.EngineWarning]
    with warnings.catch_warnings():
        warnings.simplefilter("error", paradyn.ModelWarning)
        with pytest.raises(paradyn.ModelWarning, match="looks like g/cm"):
            paradyn.run(source, tmp_path / "stopped", ranks=1, threads=1)
    assert not (tmp_path / "stopped" / "results.h5").exists()


def test_a_display_shows_them_instead(tmp_path: Path) -> None:
    stream = io.StringIO()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = paradyn.run(_plate_with_mistakes(tmp_path), tmp_path / "out", ranks=1, threads=1, post=False,
                          progress=RunProgress(stream=stream, live=False))
    assert not [w for w in caught if issubclass(w.category, paradyn.ParaDynWarning)]
    text = stream.getvalue()
    assert "warning: material steel: density 7.86" in text and "the requested time step" in text
    assert len(res.engine_run.warnings) == 2


def test_a_clean_model_has_no_warnings(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error", paradyn.ParaDynWarning)
        res = paradyn.run(SMALL_PLATE, tmp_path, ranks=1, threads=1, vtk=False)
    assert res.engine_run.warnings == []
    assert json.loads((tmp_path / "summary.json").read_text())["warnings"] == []


def test_a_keyword_decks_warnings_reach_python(tmp_path: Path) -> None:
    """The keyword reader's warnings (a card left out, the units) come as KeywordWarning, first."""
    from test_keyword import HEAD, MESH

    deck = tmp_path / "model.k"
    deck.write_text(HEAD + MESH + "*CONTROL_ACCURACY\n         1\n*END\n")
    with pytest.warns(paradyn.ParaDynWarning) as caught:
        res = paradyn.run(deck, tmp_path / "out", ranks=1, threads=1, post=False)
    read = [str(w.message) for w in caught if w.category is paradyn.KeywordWarning]
    assert any("*CONTROL_ACCURACY is not supported" in m for m in read) and any("units SI" in m for m in read)
    assert [w.category for w in caught if w.category is paradyn.ModelWarning] == [paradyn.ModelWarning]
    kept = res.engine_run.warnings
    assert kept[:len(read)] == [f"paradyn: warning: {m}" for m in read]
    assert "nothing in this model moves" in kept[len(read)]


def test_post_processing_again_keeps_the_warnings(tmp_path: Path) -> None:
    from paradyn import cli

    with pytest.warns(paradyn.ParaDynWarning):
        res = paradyn.run(_plate_with_mistakes(tmp_path), tmp_path / "out", ranks=1, threads=1, vtk=False)
    assert cli.main([str(tmp_path / "out"), "--post", "--no-vtk"]) == 0
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["warnings"] == res.engine_run.warnings
