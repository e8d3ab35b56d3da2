"""Given mass properties of a rigid body (LS-DYNA *PART_INERTIA; docs/theory.md, "Given mass
properties"): the body moves with the mass, centre and inertia tensor given instead of those of
its nodes.

- Free spin: the rigid plate of tests/rigid_cases.py given a full (non-diagonal) inertia tensor,
  principal moments (2, 10, 15) g m^2 about axes turned 30 degrees about z and 20 about x, and a
  centre off its middle, spinning near the intermediate principal axis: the body-axis angular
  velocity follows RK4 on Euler's equations with the given principal moments (Landau & Lifshitz,
  Mechanics, section 37) through the tumble, and the given centre moves at a constant velocity
  (free flight: the momentum M V is constant).
- Keyword: *PART_INERTIA's cards land in /rigid_bodies/given_* in SI, IRCS = 1 turned to global axes.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.keyword.reader import KeywordError
from paradyn.keyword.scene import load_keyword
from paradyn.running import launch
from rigid_cases import SIDES, euler_free_spin, spinning_plate
from test_keyword import HEAD, MESH
from test_keyword_rigid import BLOCK

PRINCIPAL = np.array([0.002, 0.010, 0.015])   # kg m^2


def _turn(axis: int, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    i, j = [k for k in range(3) if k != axis]
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


AXES = _turn(2, np.pi / 6) @ _turn(0, np.pi / 9)    # principal axes (columns) in the world
OMEGA0 = AXES @ np.array([0.01, 50.0, 0.0])         # near the intermediate axis (rad/s)
CENTRE_SHIFT = np.array([0.01, 0.005, 0.002])       # m, the given centre from the plate's middle


@pytest.fixture(scope="module")
def spin(tmp_path_factory: pytest.TempPathFactory) -> tuple[paradyn.deck.Model, Path]:
    model = spinning_plate(0.4, tuple(OMEGA0), velocity=(1.0, 2.0, 3.0))
    a, b = SIDES
    tensor = AXES @ np.diag(PRINCIPAL) @ AXES.T
    model.rigid_body_given_mass = np.array([3.0])
    model.rigid_body_given_centre = np.array([[a / 2, b / 2, 0.0]]) + CENTRE_SHIFT
    model.rigid_body_given_inertia = tensor[[0, 1, 2, 0, 1, 2], [0, 1, 2, 1, 2, 0]][None, :]
    folder = tmp_path_factory.mktemp("given")
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", 1, 1)
    return model, folder / "results.h5"


def _body_frames(results: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Times, rotations R (records, 3, 3) from the plate's axes at t = 0 (the world's), the
    body-axis angular velocity and the tracked origin corner's place."""
    with h5py.File(results) as f:
        t = f["history/time"][:]
        d = f["history/tracked_displacement"][:]
        v = f["history/tracked_velocity"][:]
    a, b = SIDES
    x = np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0]])[None] + d
    e1 = (x[:, 1] - x[:, 0]) / a
    e2 = (x[:, 2] - x[:, 0]) / b
    rotation = np.stack([e1, e2, np.cross(e1, e2)], axis=2)
    world = np.cross(e1, v[:, 1] - v[:, 0]) / a   # omega x e1 a = dv1: the part of omega across e1 ...
    along = np.einsum("ij,ij->i", v[:, 2] - v[:, 0], np.cross(e1, e2)) / b   # ... and e1 . omega
    world += along[:, None] * e1
    return t, rotation, np.einsum("rji,rj->ri", rotation, world), x[:, 0]


def test_free_spin_follows_euler_with_the_given_tensor(spin: tuple[paradyn.deck.Model, Path]) -> None:
    """Principal-axis omega within 1e-5 |omega| of RK4 on Euler's equations with the given moments
    at every record of 0.4 s, through the flip of the intermediate component (the nodes' own
    lumped inertia, about 2e-3, 1.8e-2, 2e-2 kg m^2 about the plate's axes, turns another way
    within the first tenth of a second)."""
    _, results = spin
    t, _, body, _ = _body_frames(results)
    reference = euler_free_spin(PRINCIPAL, AXES.T @ OMEGA0, t)
    principal = body @ AXES
    assert reference[:, 1].min() < -0.99 * 50.0
    # the record at t = 0 averages the initial velocity and the first step's chord: its centripetal
    # term, omega^2 |s| dt / 4, reads as 1e-3 rad/s here; every later record is a mid-step average
    assert np.abs(principal - reference)[1:].max() < 1e-5 * 50.0
    assert np.abs(principal - reference)[0].max() < 1e-4 * 50.0


def test_the_given_centre_moves_at_a_constant_velocity(spin: tuple[paradyn.deck.Model, Path]) -> None:
    """The given centre, carried with the body, moves at V + omega0 x shift (the plate's rigid
    velocity there) to 1e-11 of the distance travelled (the corners' rounding, 1e-16 m, over the
    0.1 m that gives the axes): free flight at the given mass."""
    model, results = spin
    t, rotation, _, origin = _body_frames(results)
    centre0 = np.asarray(model.rigid_body_given_centre)[0]
    centre = origin + np.einsum("rij,j->ri", rotation, centre0)
    velocity = np.array([1.0, 2.0, 3.0]) + np.cross(OMEGA0, CENTRE_SHIFT)
    expected = centre0 + t[:, None] * velocity
    assert np.abs(centre - expected).max() < 1e-11 * np.linalg.norm(velocity) * t[-1]


def test_part_inertia_cards_give_the_body(tmp_path: Path) -> None:
    """*PART_INERTIA on the rigid block of the keyword tests (mm, t, s: TM in t, lengths in mm):
    TM, the centre of node 22 (NODEID), the tensor turned from the axes of card 5a (IRCS = 1: XL
    along y, XLIP along -x, so local x, y, z are global y, -x, z) and the initial velocity of its
    nodes, V + omega x (x - centre)."""
    inertia = BLOCK.replace("*PART\nblock\n         2         2         2\n",
                            "*PART_INERTIA\nblock\n         2         2         2\n"
                            "       0.0       0.0       0.0       0.5         1        22\n"
                            "     100.0       0.0       0.0     200.0       0.0     300.0\n"
                            "       1.0       0.0       0.0       0.0       0.0       2.0\n"
                            "       0.0       1.0       0.0      -1.0       0.0       0.0         0\n")
    assert inertia != BLOCK
    path = tmp_path / "inertia.k"
    path.write_text(HEAD.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_UNITS\n        mm       sec  mtrc_ton\n")
                    + MESH + inertia + "*END\n")
    model = load_keyword(path).model
    body = int(np.flatnonzero(np.asarray(model.rigid_body_part) >= 0)[0])
    np.testing.assert_allclose(model.rigid_body_given_mass[body], 500.0, rtol=1e-12)
    node = int(np.flatnonzero(np.asarray(model.node_ids) == 22)[0])
    centre = np.asarray(model.coordinates)[node]
    np.testing.assert_allclose(model.rigid_body_given_centre[body], centre, rtol=1e-12)
    np.testing.assert_allclose(model.rigid_body_given_inertia[body], np.array([200, 100, 300, 0, 0, 0]) * 1e3 * 1e-6,
                               rtol=1e-12, atol=1e-15)
    nodes = np.flatnonzero(np.asarray(model.node_rigid_body) == body)
    x = np.asarray(model.coordinates)[nodes]
    expected = np.array([1e-3, 0.0, 0.0]) + np.cross([0.0, 0.0, 2.0], x - centre)
    np.testing.assert_allclose(np.asarray(model.initial_velocity)[nodes], expected, rtol=1e-12, atol=1e-15)


def test_a_tensor_that_is_not_positive_is_refused(tmp_path: Path) -> None:
    inertia = BLOCK.replace("*PART\nblock\n         2         2         2\n",
                            "*PART_INERTIA\nblock\n         2         2         2\n"
                            "       0.5       0.5       1.1       1.0         0\n"
                            "       1.0       2.0       0.0       1.0       0.0       1.0\n"
                            "       0.0       0.0       0.0       0.0       0.0       0.0\n")
    path = tmp_path / "bad.k"
    path.write_text(HEAD + MESH + inertia + "*END\n")
    with pytest.raises(KeywordError, match="not positive definite"):
        load_keyword(path)
