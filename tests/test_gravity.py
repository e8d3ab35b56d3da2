"""Gravity (body acceleration, LS-DYNA *LOAD_BODY; docs/theory.md, "Gravity") through the whole
stack: /control gravity_x, _y, _z, the force m g on every node's translations.

1. Free fall of an unsupported plate: u(t) = g t^2 / 2 (Newton), which central differences
   started with the half step v(dt/2) = v(0) + (dt/2) g reproduce exactly for a constant
   acceleration; kinetic energy = work of gravity, no strain.
2. A cantilever strip sagging under its own weight, brought to rest by mass damping: tip
   deflection w = q L^4 / (8 E I), q = rho t b g, I = b t^3 / 12 (Timoshenko & Gere, Mechanics of
   Materials, table of cantilever deflections; Euler-Bernoulli beam).
"""

from __future__ import annotations

import numpy as np
import pytest

import models as M
from paradyn.deck import Control

STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)


def test_free_fall_is_g_t_squared_over_two(tmp_path):
    """Every node of a free plate moves u = g t^2 / 2 (relative 1e-6: a start without the half
    step would be off by dt / t = 1e-3), the plate stays unstrained (internal energy below 1e-12
    of the kinetic) and the kinetic energy balances the work of gravity exactly as central
    differences define them: after N steps W = m g^2 (N dt)^2 / 2 and
    KE = m v(N - 1/2) v(N + 1/2) / 2 = m g^2 dt^2 (N^2 - 1/4) / 2, so W - KE = m g^2 dt^2 / 8."""
    g = np.array([1.0, -2.0, -9.81])
    mesh = M.strip(0.1, 0.05, 4, 2)
    end = 1.0e-3
    control = Control(end_time=end, output_interval=end / 4, history_interval=end / 20,
                      gravity_x=g[0], gravity_y=g[1], gravity_z=g[2])
    run = M.run(M.shell_model(mesh, 0.002, STEEL, control), tmp_path)
    res = run.results
    t = res.frame_times
    u = np.asarray(res.displacement)
    expected = 0.5 * t[:, None, None] ** 2 * g[None, None, :]
    np.testing.assert_allclose(u, np.broadcast_to(expected, u.shape), rtol=1e-6, atol=1e-18)
    h = res.history
    assert np.all(h["internal_energy"] + h["hourglass_energy"] <= 1e-12 * h["kinetic_energy"].max())
    mass = STEEL.density * 0.1 * 0.05 * 0.002
    np.testing.assert_allclose(h["external_work"], 0.5 * mass * (g @ g) * h["time"] ** 2, rtol=1e-9)
    lag = h["external_work"] - h["kinetic_energy"]
    np.testing.assert_allclose(lag[h["time"] > 0], mass * (g @ g) * run.dt**2 / 8.0, rtol=1e-6)


def test_cantilever_sags_under_its_own_weight(tmp_path):
    """Static tip deflection of a cantilever strip under its own weight by dynamic relaxation.

    Reference: w = q L^4 / (8 E I), q = rho t b g, I = b t^3 / 12 (Timoshenko & Gere, Mechanics
    of Materials; any strength-of-materials table of cantilever deflections): 5.78 mm for L = 1 m,
    b = 0.1 m, t = 0.01 m, steel, g = 9.81. Strip of 20 x 2 elements clamped at x = 0; gravity
    from t = 0, alpha = 2 omega_1 (critical for the first mode, every higher mode decays at the
    same rate alpha / 2 = omega_1), two periods T1: the transient is down to 13.6 exp(-4 pi) = 5e-5.
    nu = 0.3: the narrow strip bends as a beam (E, not the 9 % stiffer E / (1 - nu^2)), so the
    tolerance is 2 %. The stored energy is half the work of the weights in the sag (Clapeyron).
    """
    beam = M.cantilever(STEEL)
    g = 9.81
    f1 = beam.first_frequency
    period = 1.0 / f1
    control = Control(end_time=2.0 * period, output_interval=period, history_interval=period / 50,
                      mass_damping=2.0 * (2.0 * np.pi * f1), gravity_z=-g)
    run = M.run(beam.model(control), tmp_path)
    h = run.results.history
    w_tip = -h["tracked_displacement"][:, :, 2] @ beam.tip_weights
    q = STEEL.density * beam.thickness * beam.width * g
    reference = q * beam.length**4 / (8.0 * beam.bending_stiffness)

    assert abs(w_tip[-1] - w_tip[int(0.8 * (len(w_tip) - 1))]) < 1e-3 * w_tip[-1]
    assert w_tip[-1] == pytest.approx(reference, rel=0.02)
    uz = np.asarray(run.results.displacement[-1])[:, 2]
    weights = STEEL.density * beam.thickness * M.nodal_areas(beam.mesh) * g
    stored = h["internal_energy"][-1] + h["hourglass_energy"][-1]
    assert stored == pytest.approx(0.5 * float(weights @ -uz), rel=0.01)
