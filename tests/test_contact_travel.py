"""The contact travel limit (``[run] contact_travel_limit``, /control contact_travel_limit;
docs/theory.md, Contact): a node of an active contact may move at most a fraction of the thinner
wall per step, so a thin wall hit fast is not crossed in one step.

Two free 6 x 6 plates 0.1 m square, walls t = 0.1 mm, 0.1 mm apart, closing at 2 x 20 m/s. The
automatic step is about 3 us: a node moves 60 um, 0.6 t, a step, and the reach (t + t) / 2 = t is
crossed in two steps, so the plates pass through each other. With the limit 0.1 the step is
0.1 t / (2 x 20 m/s) = 0.25 us while the plates are near (the closing speed bounded by twice the
fastest node's; history dt_element = -2: the contact sets it), and the plates stop on each other.
The deepest penetration is then the penalty's own, that of the node-pair oscillator of
tests/test_contact_impact.py: 2 v / omega, omega = 2 sqrt(k / m), m = rho t h^2, k = 0.1 K A / d,
2.1e-5 m = 0.21 t (measured within 2 %). The limit stops the crossing; the penalty scale sets the
penetration.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import models as M
from contact_cases import STEEL
from paradyn.deck import Control
from paradyn.mesh import geometry

T = 1.0e-4
V = 20.0


def _run(tmp_path: Path, limit: float):
    """The plates with the travel limit ``limit`` and the automatic closing limit off (its own
    tests: tests/test_contact_closing.py)."""
    a = M.flat_plate((0.1, 0.1), (6, 6), origin=(0.0, 0.0, -0.5 * (T + 1.0e-4)))
    b = geometry.Mesh(coordinates=a.coordinates * np.array([1.0, 1.0, -1.0]), quads=a.quads[:, ::-1].copy())
    control = Control(end_time=3.0e-5, output_interval=1.0e-5, history_interval=2.5e-7, contact_travel_limit=limit,
                      contact_closing_limit=0.0)
    asm = M.contact_model([M.Body(a, T, (0, 0, V)), M.Body(b, T, (0, 0, -V))], STEEL, control,
                          tracked=[24, a.n_nodes + 24])
    return M.run(asm.model, tmp_path).results


def test_without_a_limit_the_thin_plates_pass_through(tmp_path: Path) -> None:
    h = _run(tmp_path, 0.0).history
    z = h["tracked_displacement"][:, :, 2]
    assert h["dt"][0] > 10 * (0.1 * T / (2.0 * V))
    assert np.any(z[:, 0] - z[:, 1] > 1.0e-4 + T)     # the lower plate's centre ends above the upper's


def test_the_limit_sets_the_step_and_stops_the_plates(tmp_path: Path) -> None:
    h = _run(tmp_path, 0.1).history
    assert h["dt_element"][0] == -2
    assert h["dt"][0] == pytest.approx(0.1 * T / (2.0 * V), rel=1e-3)
    mesh = M.flat_plate((0.1, 0.1), (6, 6))
    omega = 2.0 * np.sqrt(M.segment_stiffness(mesh, STEEL, 0.1)[0] / (STEEL.density * T * (0.1 / 6) ** 2))
    assert h["contact_penetration"].max() == pytest.approx(2.0 * V / omega, rel=0.05)
    z = h["tracked_displacement"][:, :, 2]
    assert np.all(z[:, 0] - z[:, 1] < 1.0e-4 + T)     # the mid-surfaces never cross
