"""Beams of keyword decks as trusses (docs/keyword.md, "Beams as trusses"): *ELEMENT_BEAM on a
*SECTION_BEAM ELFORM 3 part with its materials, other formulations refused; and the public
pendulum deck of ../shared/realdecks (pydyna_pendulum) run with everything it declares acting."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn._schema import ENUMS
from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import load_keyword
from paradyn.running import launch
from test_keyword import HEAD, MESH

ROOT = Path(__file__).resolve().parents[1]
PENDULUM = ROOT.parent / "shared" / "realdecks" / "pydyna_pendulum" / "pendulum.k"
TRUSS = ENUMS["element_kind"]["truss"]

# two wires from the plate's far corners up to node 21 (held), N3 an orientation node (unused)
BEAMS = """*SECTION_BEAM
         5         3       1.0         1         0       0.0       0.0         0
      1e-4
*PART
wires
         5         5         {mid}
*NODE
      21             1.0            0.25             1.0
      22             5.0             5.0             5.0
*ELEMENT_BEAM
     901       5      11      21      22
     902       5      16      21      22
"""
PLASTIC = """*MAT_PLASTIC_KINEMATIC
         7    7800.0     2e+11       0.3     2.5e8     2.0e9       0.0
*MAT_PIECEWISE_LINEAR_PLASTICITY
         8    7800.0     2e+11       0.3     2.5e8     1.0e9
"""


def _read(tmp_path: Path, extra: str):
    path = tmp_path / "model.k"
    path.write_text(HEAD + MESH + extra + "*END\n")
    return load_keyword(path)


def test_element_beam_on_an_elform_3_section_is_a_truss_part(tmp_path: Path) -> None:
    """The beams follow the shells as elements N1 N2 N2 N2 of their own part (truss, A from the
    section), their EIDs kept, the orientation node N3 left out of the mesh with a warning."""
    read = _read(tmp_path, BEAMS.format(mid=1))
    model = read.model
    assert model.element_kind.tolist() == [ENUMS["element_kind"]["shell"], TRUSS]
    assert model.cross_section_area[1] == pytest.approx(1e-4)
    assert model.thickness[1] == pytest.approx(np.sqrt(4e-4 / np.pi))
    assert model.element_ids.tolist() == [101, 102, 901, 902]
    rows = {int(n): i for i, n in enumerate(model.node_ids)}
    np.testing.assert_array_equal(model.connectivity[2:], [[rows[11], rows[21], rows[21], rows[21]],
                                                           [rows[16], rows[21], rows[21], rows[21]]])
    assert 22 not in rows
    assert any("1 node(s) of *NODE belong to no shell or beam element" in w for w in read.warnings)
    # a contact over every part (SSID 0) leaves the wires out: they have no surface
    contact = read.model
    assert contact.contact_pairs is None or TRUSS not in contact.element_kind[np.asarray(contact.contact_pairs)]


def test_single_surface_over_every_part_leaves_the_trusses_out(tmp_path: Path) -> None:
    read = _read(tmp_path, BEAMS.format(mid=1) + "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n         0\n\n\n")
    assert read.model.contact_pairs.tolist() == [[0, 0]]


@pytest.mark.parametrize(("mid", "model"), [(7, "j2_plasticity"), (8, "piecewise_linear")])
def test_plastic_materials_on_beams(tmp_path: Path, mid: int, model: str) -> None:
    read = _read(tmp_path, PLASTIC + BEAMS.format(mid=mid))
    material = read.model.part_material[1]
    assert read.model.material_model[material] == ENUMS["material_model"][model]
    assert read.model.yield_stress[material] == pytest.approx(2.5e8)


@pytest.mark.parametrize(("elform", "named"), [(1, "Hughes-Liu"), (6, "discrete beam")])
def test_other_beam_formulations_are_refused(tmp_path: Path, elform: int, named: str) -> None:
    deck = BEAMS.format(mid=1).replace("         5         3       1.0", f"         5         {elform}       1.0")
    with pytest.raises(KeywordError, match=rf"ELFORM = {elform} \({named}.*ELFORM 3"):
        _read(tmp_path, deck)


def test_a_beam_section_without_area_is_refused(tmp_path: Path) -> None:
    with pytest.raises(KeywordError, match=r"A = 0\.0; give the truss's cross-section area"):
        _read(tmp_path, BEAMS.format(mid=1).replace("      1e-4\n", "       0.0\n"))


@pytest.mark.skipif(not PENDULUM.is_file(), reason="../shared/realdecks not present")
def test_pendulum_deck_runs_as_published_and_its_spheres_collide(tmp_path: Path) -> None:
    """pydyna_pendulum (mm, kg, ms): two shell spheres made rigid by *DEFORMABLE_TO_RIGID, hung on
    eight ELFORM 3 wires from four held nodes; sphere 1, raised to the pivots' height, starts down
    at 12 m/s (*INITIAL_VELOCITY by box) under gravity (*LOAD_BODY_Y) and swings into sphere 2
    through the single-surface contact over every part (SSID 0). The first impact falls at
    11.09 ms, just past the published end (11 ms): the test runs to 11.15 ms, when it is over,
    the history every step. Checked: nothing NaN; the energy balance within 1 %; sphere 1's
    centre keeps its distance from its pivot line (105 mm: the wires hold it) until the impact;
    sphere 2 hangs at rest till then; at the impact the x-momentum sphere 2 gains is the impulse
    of the contact between the spheres (the momentum theorem; measured 2.3 %, the rest the pull of
    its wires, whose waves make its momentum ring by 10 % after the impact) and more than half of
    what sphere 1 brought, which sphere 1 loses. The published 11 ms and a run on to 16 ms by
    hand: docs/validation.md."""
    read = load_keyword(PENDULUM, units="mm-kg-ms")
    model = read.model
    assert model.control.end_time == pytest.approx(0.011)
    assert (model.element_kind == TRUSS).sum() == 1
    pairs = model.contact_pairs.tolist()
    assert sorted(pairs) == [[0, 0], [0, 1], [1, 1]]
    model.control.end_time = 0.01115   # the impact is over at 11.14 ms
    model.control.output_interval = 5e-5
    model.control.history_interval = 1e-6   # every step, for the impulse
    folder = tmp_path / "pendulum"
    folder.mkdir()
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", 1, 2)
    body = np.asarray(model.node_rigid_body)
    mass = _node_masses(folder)
    with h5py.File(folder / "results.h5") as f:
        h = {k: f["history"][k][:] for k in ("time", "kinetic_energy", "internal_energy", "hourglass_energy",
                                             "contact_energy", "external_work")}
        force = f["history/contact_force"][:, pairs.index([0, 1]), :]
        velocity = f["frames/velocity"][:]
        displacement = f["frames/displacement"][:]
        times = f["frames/time"][:]
    assert np.all(np.isfinite(velocity)) and np.all(np.isfinite(displacement)) and np.all(np.isfinite(force))
    total = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"] + h["contact_energy"]
    balance = np.abs(total - h["external_work"] - total[0]).max() / max(total.max(), h["external_work"].max())
    assert balance < 0.01
    touching = np.flatnonzero(np.linalg.norm(force, axis=1) > 0.0)
    assert 0.011 < h["time"][touching[0]] < 0.0112
    momentum = np.stack([np.einsum("i,fij->fj", mass[body == b], velocity[:, body == b]) for b in (0, 1)], axis=1)
    before = int(np.argmin(np.abs(times - 0.011)))
    assert np.abs(momentum[before, 1]).max() < 1e-3 * np.abs(momentum[before, 0]).max()   # sphere 2 at rest
    impulse = np.trapezoid(force, h["time"], axis=0)   # on sphere 1: sphere 2 gets minus it
    after = len(times) - 1   # the end, just after the impact
    assert times[after] > h["time"][touching[-1]]
    gained = momentum[after, 1, 0] - momentum[before, 1, 0]
    assert gained == pytest.approx(-impulse[0], rel=0.05)
    assert gained > 0.5 * momentum[before, 0, 0] > 0.0
    assert momentum[after, 0, 0] < momentum[before, 0, 0] - 0.5 * gained
    # sphere 1's centre swings on its circle about the pivot line (x = 5 mm, y = 100 mm) till then
    centre = np.array([(model.coordinates[body == 0] + displacement[k][body == 0]).mean(axis=0)
                       for k in range(before + 1)])
    radius = np.hypot(centre[:, 0] - 0.005, centre[:, 1] - 0.1)
    np.testing.assert_allclose(radius, 0.105, rtol=2e-3)


def _node_masses(folder: Path) -> np.ndarray:
    """The nodes' lumped masses as the engine has them: shells rho t A / 4, trusses rho A L / 2."""
    with h5py.File(folder / "deck.h5") as d:
        x = d["nodes/coordinates"][:]
        conn = d["elements/connectivity"][:]
        part = d["elements/part"][:]
        t = d["parts/thickness"][:]
        kind = d["parts/element_kind"][:]
        area = d["parts/cross_section_area"][:]
        rho = d["materials/density"][:][d["parts/material"][:]]
    c = x[conn]
    truss = kind[part] == TRUSS
    shell = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1) * (rho * t)[part] / 4.0
    bar = np.linalg.norm(c[:, 1] - c[:, 0], axis=1) * (rho * area)[part] / 2.0
    mass = np.zeros(len(x))
    np.add.at(mass, conn[~truss].ravel(), np.repeat(shell[~truss], 4))
    np.add.at(mass, conn[truss, 0], bar[truss])
    np.add.at(mass, conn[truss, 1], bar[truss])
    return mass
