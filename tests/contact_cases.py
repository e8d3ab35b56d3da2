"""What the whole-stack contact tests (tests/test_contact_*.py) share: steel, the shells and the
plates, two facing plates symmetric under a half turn, and small measures on their results.

The plates are flat in planes z = const; "clearance" is the distance between the contact
surfaces (the mid-surfaces less half a thickness each, fortran/src/contact/state/contact_interface.f90). The
contact time scale of thin shells, which these helpers measure, is explained in the docstring of
tests/test_contact_impact.py.
"""

from __future__ import annotations

import numpy as np

import models as M
from paradyn.deck import Control
from paradyn.mesh import geometry

STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)
T = 0.002           # shell thickness (m)
PLATE = 0.1         # side of the square plates (m)
N = 6               # elements along a side
H = PLATE / N       # element side (m)
ROTATE_Y = np.array([-1.0, 1.0, -1.0])  # half turn about the y axis: (x, y, z) -> (-x, y, -z)


# ----------------------------------------------------------------------------------------------
# helpers


def _plate_pair(clearance: float, shift: float = 0.0, n: int = N) -> tuple[geometry.Mesh, geometry.Mesh]:
    """Two square plates facing each other across z = 0, ``clearance`` between the contact
    surfaces. Plate A (below, normal +z) spans x in [-L/2 - shift, L/2 - shift]; plate B is A
    turned half a turn about the y axis, node for node (B's node i = R A's node i, R = ROTATE_Y),
    so B spans x in [-L/2 + shift, L/2 + shift] and the two meshes are offset by 2 shift in x.
    R maps every coordinate to its exact negative or itself, so the deck is symmetric in floating
    point too."""
    z = 0.5 * (T + clearance)
    a = M.flat_plate((PLATE, PLATE), (n, n), origin=(-0.5 * PLATE - shift, -0.5 * PLATE, -z))
    b = geometry.Mesh(coordinates=a.coordinates * ROTATE_Y, quads=a.quads.copy())
    return a, b


def _symmetry_error(displacement: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """max |u_B - R u_A| over frames and nodes, relative to max |u|."""
    diff = displacement[:, b] - displacement[:, a] * ROTATE_Y
    return float(np.abs(diff).max() / np.abs(displacement).max())


def _momentum(masses: np.ndarray, velocity: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """sum m v over ``nodes``; velocity (n_records, n_nodes, 3) -> (n_records, 3)."""
    return np.einsum("n,rnc->rc", masses[nodes], velocity[:, nodes])


def _node_pair_oscillator(mass: float, stiffness: float) -> float:
    """omega of two facing nodes of mass m, each pushed by 2 k (slave and master, passes = 2)."""
    return 2.0 * np.sqrt(stiffness / mass)


def _interior_node_mass(h: float) -> float:
    return STEEL.density * T * h * h


def _control(end_time: float, step_fraction: float | None, stable: float, frames: int = 10,
             history_every_step: bool = True) -> Control:
    """``step_fraction`` of the stable step (None: the engine's automatic step)."""
    dt = stable * (step_fraction if step_fraction is not None else 1.0)
    return Control(end_time=end_time, output_interval=end_time / frames,
                   history_interval=dt if history_every_step else end_time / 200,
                   time_step=0.0 if step_fraction is None else dt)
