"""Issue 13: the step is built from the effects a scene declares (schema/effects.toml).

The engine alone decides what a deck declares and writes the effect table (results.h5
/effects, summary.json "effects"); an effect that is not declared has no row. A scene's
[effects] switch takes a declared effect out: the run must then be bitwise the run of the scene
written without it (plasticity off = the same parts elastic, friction off = coefficients 0,
contact off = no pair, point loads off = no loads), and the table says it was off.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn._schema import ENERGY_NAMES
from paradyn.results.names import EffectRow
from paradyn.scene import SceneError

TWO_PLATES = """
title = "two plates"
[run]
end_time = 3e-4
output_interval = 1e-4
history_interval = 1e-5
[[material]]
name = "steel"
model = "{model}"
density = 7860.0
youngs_modulus = 200e9
poisson_ratio = 0.3
{plastic}
[[part]]
name = "lower"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "plate"
size = [0.1, 0.1]
elements = [4, 4]
[[part]]
name = "upper"
material = "steel"
thickness = 0.002
initial_velocity = [3.0, 0.0, -20.0]
[part.geometry]
kind = "plate"
size = [0.06, 0.06]
elements = [3, 3]
origin = [0.02, 0.02, 0.0025]
[[fix]]
part = "lower"
box = [[-1e-6, -1e-6, -1e-6], [1e-6, 0.100001, 1e-6]]
{load}
{contact}
{effects}
"""
J2 = "yield_stress = 50e6\ntangent_modulus = 2e9"
CONTACT = "[[contact]]\nparts = [\"lower\", \"upper\"]\nstatic_friction = 0.3\ndynamic_friction = 0.2"
FRICTIONLESS = "[[contact]]\nparts = [\"lower\", \"upper\"]"
LOAD = "[[load]]\npart = \"lower\"\npoint = [0.1, 0.1, 0.0]\ndof = \"uz\"\nvalue = -50.0\nramp_time = 1e-4"


def _run(tmp_path: Path, name: str, model: str = "elastic", contact: str = CONTACT, effects: str = "",
         loads: bool = True) -> paradyn.Results:
    plastic = J2 if model == "j2_plasticity" else ""
    text = TWO_PLATES.format(model=model, plastic=plastic, contact=contact, load=LOAD if loads else "",
                             effects=f"[effects]\n{effects}" if effects else "")
    folder = tmp_path / name
    folder.mkdir()
    scene_path = folder / "scene.toml"
    scene_path.write_text(text, encoding="utf-8")
    return paradyn.run(scene_path, folder / "out", ranks=1, threads=1, vtk=False, plots=False, progress=False)


def _histories(results: paradyn.Results) -> dict[str, np.ndarray]:
    with h5py.File(results.path, "r") as f:
        return {name: f["history"][name][()] for name in f["history"]}


def _same(a: paradyn.Results, b: paradyn.Results, energies_rtol: float = 0.0) -> None:
    """Bitwise the same histories and last frame; energies (summed per rank, then over the ranks)
    to energies_rtol when the layouts differ."""
    ha, hb = _histories(a), _histories(b)
    assert ha.keys() == hb.keys()
    for name in ha:
        if energies_rtol and (name in ENERGY_NAMES or name.startswith("part_")):
            scale = energies_rtol * np.abs(hb[name]).max()
            np.testing.assert_allclose(ha[name], hb[name], rtol=energies_rtol, atol=scale)
            continue
        assert np.array_equal(ha[name], hb[name]), name
    assert np.array_equal(a.displacement[-1], b.displacement[-1])


def _table(results: paradyn.Results) -> dict[str, EffectRow]:
    return {row.name: row for row in results.effect_table}


@pytest.fixture(scope="module")
def base(tmp_path_factory: pytest.TempPathFactory) -> paradyn.Results:
    return _run(tmp_path_factory.mktemp("effects"), "base", model="j2_plasticity")


def test_the_table_lists_what_the_deck_declares_in_the_order_of_the_step(base: paradyn.Results) -> None:
    table = _table(base)
    assert list(table) == ["point_loads", "time_integration", "fixed_boundaries", "plastic_shells", "hourglass",
                           "contact", "friction"]
    assert base.effects == list(table)   # /run effects: the ones that ran
    cycles = int(base.run["cycles"])
    for row in table.values():
        assert row.state == "on"
        assert row.active_cycles + row.skipped_cycles == cycles, row
    assert table["plastic_shells"].wall_s > 0 and table["contact"].wall_s > 0
    assert table["friction"].timed_with == "contact" and table["friction"].wall_s == 0
    # undeclared effects (gravity, mass damping, elastic shells, ...) have no row at all
    with h5py.File(base.path, "r") as f:
        assert sorted(f["effects"]) == sorted(table)
        assert f["run"].attrs["effects_off"] == ""


def test_plasticity_off_is_the_same_parts_elastic(tmp_path: Path, base: paradyn.Results) -> None:
    off = _run(tmp_path, "plasticity_off", model="j2_plasticity", effects="plasticity = false")
    elastic = _run(tmp_path, "elastic", model="elastic")
    _same(off, elastic)
    table = _table(off)
    assert table["plastic_shells"].state == "off" and table["plastic_shells"].active_cycles == 0
    assert table["elastic_shells"].active_cycles == int(off.run["cycles"])
    assert "plastic_shells" not in off.effects and "elastic_shells" in off.effects
    # the switch did something: the plates yield when plasticity runs
    assert base.plastic_strain[-1].max() > 0
    assert not np.array_equal(_histories(base)["internal_energy"], _histories(elastic)["internal_energy"])


def test_friction_off_is_frictionless_contact(tmp_path: Path) -> None:
    off = _run(tmp_path, "friction_off", effects="friction = false")
    frictionless = _run(tmp_path, "frictionless", contact=FRICTIONLESS)
    _same(off, frictionless)
    assert _table(off)["friction"].state == "off"
    assert "friction" not in _table(frictionless)   # not declared: no row
    with_friction = _run(tmp_path, "friction", effects="friction = true")
    assert not np.array_equal(with_friction.displacement[-1], frictionless.displacement[-1])


def test_contact_off_is_no_pair(tmp_path: Path) -> None:
    off = _run(tmp_path, "contact_off", effects="contact = false")
    without = _run(tmp_path, "no_contact", contact="")
    _same(off, without)
    table = _table(off)
    assert table["contact"].state == "off" and table["friction"].state == "off"
    assert "contact" not in _table(without)


def test_point_loads_off_is_no_load(tmp_path: Path) -> None:
    off = _run(tmp_path, "loads_off", effects="point_loads = false")
    without = _run(tmp_path, "no_loads", loads=False)
    _same(off, without)
    assert _table(off)["point_loads"].state == "off" and "point_loads" not in _table(without)


def test_an_unknown_switch_is_refused(tmp_path: Path) -> None:
    with pytest.raises(SceneError, match=r"unknown key 'plastic' in \[effects\]"):
        _run(tmp_path, "typo", effects="plastic = false")


@pytest.mark.mpi
def test_two_ranks_give_the_same_run_and_table(tmp_path: Path, base: paradyn.Results) -> None:
    """The pipeline keeps results bitwise independent of the layout, and the table's counts."""
    folder = tmp_path / "layout"
    two = paradyn.run(base.deck_path, folder, ranks=2, threads=2, vtk=False, plots=False, progress=False)
    _same(two, base, energies_rtol=1e-12)
    counts = {r.name: (r.state, r.active_cycles, r.skipped_cycles) for r in two.effect_table}
    assert counts == {r.name: (r.state, r.active_cycles, r.skipped_cycles) for r in base.effect_table}


def test_the_contact_row_counts_each_pair(base: paradyn.Results) -> None:
    """The contact row lists its pairs by part name, with the cycles each ran or was idle."""
    row = _table(base)["contact"]
    assert [pair["parts"] for pair in row.pairs] == [["lower", "upper"]]
    pair = row.pairs[0]
    assert pair["active_cycles"] + pair["skipped_cycles"] == int(base.run["cycles"])
    assert pair["active_cycles"] == row.active_cycles   # one pair: the row is the pair
