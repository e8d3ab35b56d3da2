"""Friction through the whole stack: decks built in Python (``tests/models.py``,
``contact_model``), ``paradyn-engine``, results file, compared with Coulomb's law.

Steel and the shell thickness are in tests/contact_cases.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import models as M
from contact_cases import STEEL, T
from paradyn.deck import Control

# ----------------------------------------------------------------------------------------------
# Friction


def _slider(tmp_path: Path, mu: float, g: float, vx: float, end_time: float) -> tuple[M.Run, np.ndarray]:
    """A 0.05 m plate (5 x 5) resting on a fixed 0.1 m plate (10 x 10), sliding at vx along x,
    pressed down by nodal loads that give it the acceleration g. The slider's edges lie midway
    between base nodes, so no base node meets them (all contact is face on). Returns the run and
    the slider's mass fractions (tracked nodes are the slider's)."""
    base = M.flat_plate((0.1, 0.1), (10, 10), origin=(-0.05, -0.05, 0.0))
    slider = M.flat_plate((0.05, 0.05), (5, 5), origin=(-0.025, -0.025, T))
    control = Control(end_time=end_time, output_interval=end_time / 4, history_interval=end_time / 200)
    bodies = [M.Body(base, T, fixed=True), M.Body(slider, T, (vx, 0.0, 0.0))]
    probe = M.contact_model(bodies, STEEL, control)
    nodes = probe.nodes[1]
    masses = probe.masses()[nodes]
    weights = masses / masses.sum()
    asm = M.contact_model(bodies, STEEL, control, static_friction=mu,
                          loads=[M.Load(nodes, 3, -g * masses)], tracked=nodes)
    return M.run(asm.model, tmp_path), weights


def test_friction_decelerates_the_slider_at_mu_g(tmp_path):
    """Coulomb friction on a sliding plate.

    Reference: Coulomb's law, M dv_x/dt = -mu N and M dv_z/dt = N - M g for the slider (N the
    total normal force, every contact slipping well above the regularisation speed 1e-3 m/s):
    v_x(t) = v0 - mu (g t + v_z(t)). The normal force rings on the penalty springs, but its
    impulse is M (g t + v_z) exactly, so the identity holds at every record, and on average the
    deceleration is mu g.

    Slider 0.05 m, 5 x 5, t = 2 mm, on a fixed 0.1 m plate, v0 = 1 m/s along x, g = 100 m/s^2 as
    nodal loads (mass-weighted, a uniform body force), mu_s = mu_d = 0.3, 1 ms at the automatic
    step. Measured: fitted deceleration 30.00004 m/s^2 (mu g = 30, 1.2e-6); v_x(end) matches the
    identity to 5e-8 of the change. Asserted: deceleration within 1e-3 of mu g (friction in
    one pass only, or without its reaction on the master nodes, would give about mu g / 2);
    the identity within 1e-4 of the change at every record after the first.
    """
    mu, g, v0, end = 0.3, 100.0, 1.0, 1.0e-3
    run, w = _slider(tmp_path, mu, g, v0, end)
    h = run.results.history
    velocity = np.einsum("n,rnc->rc", w, h["tracked_velocity"])
    t = h["time"]
    slope = np.polyfit(t, velocity[:, 0], 1)[0]
    assert -slope == pytest.approx(mu * g, rel=1e-3)
    predicted = v0 - mu * (g * t + velocity[:, 2])
    change = v0 - velocity[-1, 0]
    assert change == pytest.approx(mu * g * end, rel=0.01)
    assert np.abs(velocity[1:, 0] - predicted[1:]).max() <= 1e-4 * change
    assert h["contact_penetration"].max() > 0.0


def test_frictionless_slider_keeps_its_tangential_velocity(tmp_path):
    """The slider above with mu = 0: the contact forces are normal to the base's flat segments
    (the slider's slaves) or to the slider's own segments (the base's slaves), so the slider's
    mean tangential velocity does not change. Reference: no tangential force; the segments of the
    pressed slider tilt slightly, which leaves a second-order x force, measured 3.6e-11 m/s over
    1 ms (it grows as g^2: 3.6e-9 at g = 1000). Asserted: |v_x - v0| <= 1e-9 v0, |v_y| <= 1e-12."""
    v0 = 1.0
    run, w = _slider(tmp_path, 0.0, 100.0, v0, 1.0e-3)
    h = run.results.history
    velocity = np.einsum("n,rnc->rc", w, h["tracked_velocity"])
    assert np.abs(velocity[:, 0] - v0).max() <= 1e-9 * v0
    assert np.abs(velocity[:, 1]).max() <= 1e-12 * v0
    assert h["contact_penetration"].max() > 0.0
