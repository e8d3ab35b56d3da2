"""Triangles in the engine (issue 33, item 2): the C0 triangle (shell_c0_triangle) on meshes of
triangles and of triangles mixed with quadrilaterals in one part, against the same Kirchhoff
references as the quadrilaterals (tests/test_verification.py), on 1 and 2 ranks, and in contact.

A triangle is a row of the deck's connectivity whose third node is repeated as the fourth.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
from paradyn import deck
from paradyn.running import launch
from test_verification import PLATE_ALPHA, PLATE_LAMBDA, STEEL, _settled

ROOT = Path(__file__).resolve().parents[1]


def split(mesh: M.geometry.Mesh, which: np.ndarray | None = None) -> M.geometry.Mesh:
    """``mesh`` with its quadrilaterals ``which`` (all by default) each cut into two triangles in
    place (the element order kept), along the diagonal that points at the mesh's centre: the
    "union jack" pattern, symmetric about the centre of a rectangular plate."""
    quads = mesh.quads
    which = np.ones(len(quads), dtype=bool) if which is None else which
    xy = mesh.coordinates[:, :2]
    centre = 0.5 * (xy.min(axis=0) + xy.max(axis=0))
    rows = []
    for cut, q in zip(which, quads, strict=True):
        if not cut:
            rows.append(q)
            continue
        c = xy[q].mean(axis=0) - centre
        a, b, cc, d = q
        if c[0] * c[1] > 0:    # diagonal a-c
            rows += [[a, b, cc, cc], [a, cc, d, d]]
        else:                  # diagonal b-d
            rows += [[a, b, d, d], [b, cc, d, d]]
    return M.geometry.Mesh(mesh.coordinates, np.array(rows, dtype=np.int64))


def _relaxed_plate(tmp_path: Path, mesh: M.geometry.Mesh, support: str) -> tuple[float, float]:
    """The set-up of test_verification._relaxed_plate on any mesh of the 1 m plate (t = 0.01 m, steel,
    P = 100 N at the centre, dynamic relaxation): the final centre deflection and its reference."""
    a, t, load = 1.0, 0.01, 100.0
    D = STEEL.young * t**3 / (12.0 * (1.0 - STEEL.poisson**2))
    omega1 = PLATE_LAMBDA[support] / a**2 * np.sqrt(D / (STEEL.density * t))
    period = 2.0 * np.pi / omega1
    control = deck.Control(end_time=7.0 * period, output_interval=period, history_interval=period / 20,
                           mass_damping=2.0 * omega1)
    c = mesh.coordinates
    edge = np.flatnonzero((np.abs(c[:, 0]) < 1e-12) | (np.abs(c[:, 0] - a) < 1e-12)
                          | (np.abs(c[:, 1]) < 1e-12) | (np.abs(c[:, 1] - a) < 1e-12))
    flags = (1, 1, 1, 0, 0, 0) if support == "simple" else M.ALL_DOFS
    centre = M.geometry.nearest_node(c, (0.5 * a, 0.5 * a, 0.0))
    model = M.shell_model(mesh, t, STEEL, control, fixed={int(k): flags for k in edge},
                          loads=[M.Load(np.array([centre]), 3, np.array([-load]), 2.0 * period)], tracked=[centre])
    run = M.run(model, tmp_path)
    w = -run.results.history["tracked_displacement"][:, 0, 2]
    assert _settled(w) < 1e-3
    h = run.results.history
    stored = h["internal_energy"][-1] + h["hourglass_energy"][-1]
    assert stored == pytest.approx(0.5 * load * w[-1], rel=0.01)    # Clapeyron: the forces are conjugate
    return float(w[-1]), PLATE_ALPHA[support] * load * a**2 / D


@pytest.mark.parametrize("support", ["simple", "clamped"])
def test_triangle_plate_converges_to_the_kirchhoff_deflection(tmp_path: Path, support: str) -> None:
    """Reference: w = alpha P a^2 / D, alpha = 0.01160 simply supported, 0.00560 clamped, nu = 0.3
    (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells), the quadrilaterals' reference of
    test_verification.test_plate_central_deflection; 24 x 24 squares cut into 1152 triangles (union
    jack), tolerance 3 %: 0.9930 / 0.9845 of the reference (8 x 8: 0.931 / 0.730; 16 x 16: 0.982 /
    0.958; the triangle converges from the stiff side). The stored energy equals P w / 2 within 1 %
    (the forces are the conjugates of the strains)."""
    w, reference = _relaxed_plate(tmp_path, split(M.strip(1.0, 1.0, 24, 24)), support)
    assert w == pytest.approx(reference, rel=0.03)


@pytest.mark.parametrize("support", ["simple", "clamped"])
def test_mixed_plate_converges_to_the_kirchhoff_deflection(tmp_path: Path, support: str) -> None:
    """Reference: as test_triangle_plate_converges_to_the_kirchhoff_deflection, on a mixed mesh of one
    part: the squares of the left half cut into triangles, the right half quadrilaterals (each row of
    elements alternates triangles and quads: many groups of each shape). 16 x 16, tolerance 3 %."""
    mesh = M.strip(1.0, 1.0, 16, 16)
    left = mesh.coordinates[mesh.quads].mean(axis=1)[:, 0] < 0.5
    w, reference = _relaxed_plate(tmp_path, split(mesh, left), support)
    assert w == pytest.approx(reference, rel=0.03)


def _impact(lower_triangles: bool, upper_mixed: bool) -> deck.Model:
    """test_parallel._plastic_impact with triangles: two 6 x 6 J2 steel plates 2 mm thick, the upper
    one thrown obliquely at the lower one with friction; the lower plate all triangles (contact on
    triangle segments) and the upper one mixed (every other element cut into two triangles)."""
    plate, t, gap = 0.1, 0.002, 1.0e-5
    z = 0.5 * (t + gap)
    lower = M.flat_plate((plate, plate), (6, 6), origin=(-0.5 * plate, -0.5 * plate, -z))
    upper = M.flat_plate((plate, plate), (6, 6), origin=(-0.5 * plate + plate / 24, -0.5 * plate, z))
    if lower_triangles:
        lower = split(lower)
    if upper_mixed:
        upper = split(upper, np.arange(upper.n_elements) % 2 == 0)
    control = deck.Control(end_time=20.0e-6, output_interval=4.0e-6)
    model = M.contact_model([M.Body(lower, t), M.Body(upper, t, (4.0, 2.0, -20.0))],
                            M.Material(young=200.0e9, poisson=0.3, density=7850.0), control,
                            static_friction=0.3).model
    model.material_model = np.array([deck.J2_PLASTICITY])
    model.yield_stress, model.tangent_modulus, model.hardening_mixing = [20.0e6], [1.0e9], [1.0]
    model.normalise()
    return model


FIELDS = ("displacement", "velocity", "element_membrane_stress", "element_von_mises", "element_plastic_strain")


def _engine(model: deck.Model, folder: Path, name: str, ranks: int) -> dict[str, np.ndarray]:
    deck_path = deck.write_deck(model, folder / f"deck_{name}.h5")
    results = folder / f"results_{name}_{ranks}.h5"
    launch.run_engine(deck_path, results, ranks, 1, log_path=folder / f"engine_{name}_{ranks}.log")
    with h5py.File(results, "r") as f:
        data = {k: f["/frames"][k][()] for k in FIELDS}
        data["contact_energy"] = f["/history/contact_energy"][()]
    return data


@pytest.mark.mpi
@pytest.mark.parametrize("partition", ["blocks", "rcb"])
def test_mixed_mesh_is_bitwise_the_same_on_one_and_two_ranks(tmp_path: Path, partition: str) -> None:
    """Reference: docs/theory.md (parallel design), as tests/test_parallel.py: every node sums its
    corners in ascending global element order whatever rank owns them, and a group holds one part
    and one shape. The oblique plastic impact with friction of test_parallel, the lower plate all
    triangles and the upper one mixed, on 1 and 2 ranks: displacements, velocities, element stresses,
    plastic strains and contact energy bitwise equal."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    model = _impact(lower_triangles=True, upper_mixed=True)
    model.control.partition = partition
    one, two = _engine(model, tmp_path, partition, 1), _engine(model, tmp_path, partition, 2)
    assert np.max(one["element_plastic_strain"][-1]) > 0.0 and np.max(one["contact_energy"]) > 0.0
    for key in (*FIELDS, "contact_energy"):
        assert np.array_equal(one[key], two[key]), key


def test_contact_on_triangle_segments_stops_the_plate(tmp_path: Path) -> None:
    """Reference: the penalty contact of docs/theory.md on triangle master segments (degenerate quads,
    closest point and normal of segment_projection; tests/test_contact_local_search.py checks the
    projection): the impact of test_parallel on a lower plate of triangles against the same impact on
    quadrilaterals (the same flat surface): the upper plate's nodes stay outside the lower plate's
    contact thickness (no penetration beyond 20 % of it) and its vertical velocity turns over within
    10 % of the quads' run, while the upper plate is mixed in both."""
    quads = _engine(_impact(lower_triangles=False, upper_mixed=True), tmp_path, "quads", 1)
    tris = _engine(_impact(lower_triangles=True, upper_mixed=True), tmp_path, "tris", 1)
    model = _impact(lower_triangles=True, upper_mixed=True)
    upper = np.flatnonzero(np.isin(np.arange(model.coordinates.shape[0]),
                                   np.unique(model.connectivity[model.element_part == 1])))
    z0 = model.coordinates[upper, 2]
    z = z0[None, :] + tris["displacement"][:, upper, 2]
    lower_z = -0.5 * (0.002 + 1.0e-5) + tris["displacement"][:, :upper.min(), 2].min(axis=1)
    assert np.min(z - lower_z[:, None]) > 0.8 * 0.002            # (t_s + t_m) / 2 = t
    assert np.max(tris["contact_energy"]) > 0.0
    vz_tris = tris["velocity"][-1, upper, 2].mean()
    vz_quads = quads["velocity"][-1, upper, 2].mean()
    assert vz_tris > -10.0                                         # thrown at -20 m/s: slowed or reversed
    assert vz_tris == pytest.approx(vz_quads, rel=0.1, abs=0.5)
