"""The pipe whip as an LS-DYNA keyword deck (issue 18, docs/keyword.md): cases/pipe_whip_keyword/pipe_whip.k,
written from cases/pipe_whip/scene.toml by make_deck.py, reads into the scene's model (every array
equal, the deck's ids kept) and runs to the scene's answer, through ``paradyn.run`` and ``paradyn-run``.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import _schema, cli, scene
from paradyn.keyword.scene import load_keyword

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "pipe_whip_keyword"
KEYWORD_DECK = CASE / "pipe_whip.k"
SCENE = ROOT / "cases" / "pipe_whip" / "scene.toml"
SHORT = 3e-4   # s: the upper pipe reaches the lower one after 0.05 ms, so contact is active


def _scene_model() -> paradyn.deck.Model:
    return scene.build_model(scene.load_scene(SCENE))


def test_committed_deck_is_what_make_deck_writes(tmp_path: Path) -> None:
    """The committed deck is the generator's output for the current scene (rerun make_deck.py if not)."""
    from importlib import util
    spec = util.spec_from_file_location("make_deck", CASE / "make_deck.py")
    module = util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--out", str(tmp_path / "deck.k")]) == 0
    assert (tmp_path / "deck.k").read_text() == KEYWORD_DECK.read_text()


def test_keyword_deck_reads_into_the_scene_model() -> None:
    """Every deck dataset of the keyword deck's model equals the scene's, bit for bit, and the
    /control values and names are the same; the ids are the deck's, not row numbers."""
    read, expected = load_keyword(KEYWORD_DECK), _scene_model()
    model = read.model
    ids = {"node_ids", "element_ids", "part_ids"}
    for spec in _schema.DATASETS:
        if spec.python in ids:
            continue
        mine, theirs = getattr(model, spec.python), getattr(expected, spec.python)
        assert (mine is None) == (theirs is None), spec.path
        if mine is not None:
            np.testing.assert_array_equal(mine, theirs, err_msg=spec.path)
    assert model.control == expected.control
    assert (model.part_names, model.tracked_names, model.title) == (expected.part_names, expected.tracked_names,
                                                                    expected.title)
    assert model.material_names == ["steel"]
    assert model.part_ids.tolist() == [1, 2]
    assert model.node_ids[0] == 100001 and model.element_ids[-1] == 200512
    assert len(set(model.node_ids.tolist())) == model.n_nodes
    assert [c.parts for c in read.scene.contacts] == [("lower_pipe", "upper_pipe")]
    assert read.scene.contacts[0].symmetric and read.scene.contacts[0].penalty_scale == pytest.approx(0.1)


def test_keyword_deck_runs_to_the_scene_answer(tmp_path: Path) -> None:
    """0.3 ms of both, on one rank: the histories (energies, tracked displacements and velocities)
    are the same to round-off (the models are the same, so they are in fact bitwise equal)."""
    runs = {}
    for label, source in (("scene", SCENE), ("keyword", KEYWORD_DECK)):
        model = paradyn.read_keyword(source, quiet=True) if label == "keyword" else _scene_model()
        model.control = dataclasses.replace(model.control, end_time=SHORT, output_interval=SHORT)
        runs[label] = paradyn.run(model, tmp_path / label, ranks=1, threads=2, post=False)
    mine, theirs = runs["keyword"].history, runs["scene"].history
    assert mine["time"].size > 20
    assert np.max(theirs["contact_energy"]) > 0.0, "the short run must reach contact"
    for key in ("kinetic_energy", "internal_energy", "contact_energy", "tracked_displacement", "tracked_velocity"):
        scale = max(float(np.max(np.abs(theirs[key]))), 1e-30)
        assert np.max(np.abs(mine[key] - theirs[key])) <= 1e-12 * scale, key


def test_paradyn_run_reads_a_keyword_deck_and_writes_its_ids(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    """``paradyn-run model.k``: the units line and no other warning, the deck's ids in deck.h5 and
    in the VTK cell and point data, the summary naming the keyword file."""
    short = tmp_path / "short.k"
    text = KEYWORD_DECK.read_text().replace("*CONTROL_TERMINATION\n    0.0025", "*CONTROL_TERMINATION\n    0.0001")
    text = text.replace("*DATABASE_BINARY_D3PLOT\n     5e-05", "*DATABASE_BINARY_D3PLOT\n     1e-04")
    short.write_text(text)
    status = cli.main([str(short), "-o", str(tmp_path / "out"), "-n", "1", "-t", "2", "-q", "--vtk-series"])
    err = capsys.readouterr().err
    assert status == 0, err
    warnings = [line for line in err.splitlines() if line.startswith("paradyn: warning:")]
    assert len(warnings) == 1 and "units SI" in warnings[0] and "*CONTROL_UNITS" in warnings[0]
    written = paradyn.deck.read_deck(tmp_path / "out" / "deck.h5")
    assert written.node_ids[0] == 100001 and written.part_ids.tolist() == [1, 2]
    import pyvista
    grid = pyvista.read(tmp_path / "out" / "vtk" / "upper_pipe_00001.vtu")
    assert grid.cell_data["file_element_id"].min() == 200001 and set(grid.cell_data["file_part_id"]) == {2}
    assert grid.point_data["file_node_id"].min() == 200001
    from paradyn.results.vtkhdf_export import read_step
    whole = read_step(tmp_path / "out" / "results.vtkhdf", 1)
    assert sorted(set(whole.cell_data["file_part_id"])) == [1, 2]
    np.testing.assert_array_equal(whole.cell_data["file_element_id"], written.element_ids)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["scene"].endswith("short.k")
