"""Prescribed nodal velocity with a load curve (LS-DYNA *BOUNDARY_PRESCRIBED_MOTION_NODE, VAD = 0;
docs/theory.md, "Prescribed velocity") through the whole stack: /curves and /prescribed, the
velocity set after each update to value x curve(t + dt / 2), and the reaction's work.

1. The prescribed node's displacement is the integral of the curve: exactly the midpoint rule
   sum dt v(t_k + dt / 2), within dt^2 / 8 |slope jump| of the exact integral at each kink.
2. A strip whose end is suddenly moved at a constant velocity v (one-dimensional elastic waves:
   Graff, Wave Motion in Elastic Solids, sec. 2.1; Kolsky, Stress Waves in Solids, ch. 4): the
   front runs at c = sqrt(E / rho) with free sides and sqrt(E / (rho (1 - nu^2))) with the sides
   held (uy = 0); the far, free end starts at t = L / c and then moves at 2 v; the end is pushed
   with the force rho c v A, so the work grows at rho c v^2 A, and it all goes into the strip.
"""

from __future__ import annotations

import numpy as np
import pytest

import models as M
from paradyn.deck import Control

STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)


def _with_motion(model, nodes, dof: int, value: float, time, curve_values):
    """The model with dof of the nodes following value x the curve (time, curve_values)."""
    model.curve_first_point = np.array([0], dtype=np.int32)
    model.curve_time = np.asarray(time, dtype=np.float64)
    model.curve_value = np.asarray(curve_values, dtype=np.float64)
    model.prescribed_node = np.asarray(nodes, dtype=np.int32)
    model.prescribed_dof = np.full(len(nodes), dof, dtype=np.int32)
    model.prescribed_value = np.full(len(nodes), value)
    model.prescribed_curve = np.zeros(len(nodes), dtype=np.int32)
    return model


def test_displacement_is_the_integral_of_the_curve(tmp_path):
    """Curve: 0 -> 1 over 20 us, held to 50 us, down to -0.5 at 60 us, held; scale 2 m/s along x
    on the x = 0 edge of a free strip. Tracked every step: the edge's displacement equals the
    midpoint-rule integral to 1e-12 and the exact integral within the kink bound; at the end
    2 (0.5 x 20 + 30 + 0.5 x 10 x 0.5 - 20 x 0.5) us = 65 um."""
    time, values, scale = [0.0, 2e-5, 5e-5, 6e-5], [0.0, 1.0, 1.0, -0.5], 2.0
    mesh = M.strip(0.05, 0.01, 10, 2)
    edge = M.nodes_at(mesh, 0, 0.0)
    end = 8e-5
    dt = M.stable_time_step(mesh, STEEL)
    control = Control(end_time=end, output_interval=end, history_interval=0.5 * dt)
    model = _with_motion(M.shell_model(mesh, 0.001, STEEL, control, tracked=edge), edge, 1, scale, time, values)
    run = M.run(model, tmp_path)
    h = run.results.history
    t, ux = h["time"], h["tracked_displacement"][:, :, 0]
    np.testing.assert_array_equal(ux, ux[:, :1] * np.ones((1, len(edge))))
    steps = np.round(t / run.dt).astype(int)
    midpoints = (np.arange(steps[-1]) + 0.5) * run.dt
    midpoint_rule = np.concatenate([[0.0], np.cumsum(run.dt * scale * np.interp(midpoints, time, values))])
    np.testing.assert_allclose(ux[:, 0], midpoint_rule[steps], rtol=1e-12, atol=1e-18)
    exact = np.array([scale * _integral(time, values, s) for s in t])
    jumps = np.abs(np.diff(np.diff(values) / np.diff(time))).sum() + 1.0 / 2e-5   # the start is a kink too
    assert np.max(np.abs(ux[:, 0] - exact)) <= scale * jumps * run.dt**2 / 8.0 * 1.0001
    assert ux[-1, 0] == pytest.approx(6.5e-5, rel=1e-3)


def _integral(time: list[float], values: list[float], t: float) -> float:
    """Integral from 0 to t of the piecewise-linear curve, its end values held."""
    grid = np.union1d(np.asarray(time), [0.0, t])
    grid = grid[(grid >= 0.0) & (grid <= t)]
    return float(np.trapezoid(np.interp(grid, time, values), grid))


@pytest.mark.parametrize("lateral", ["free", "held"])
def test_strip_end_moved_at_constant_velocity(tmp_path, lateral):
    """Strip L = 0.2 m, 2 mm x 1 mm, 100 x 1 elements, steel nu = 0.3; the x = 0 end moves at
    v = 1 m/s along +x from t = 0 (a constant curve). c = 5048 m/s with free sides, 5292 m/s
    with uy = 0 on every node (4.8 % apart). Measured:
    - the far end's displacement from 1.2 to 1.8 L / c is a line of slope 2 v (within 2 %)
      whose start is the arrival L / c_measured: c within 2 %;
    - the work of the prescribed motion grows at rho c v^2 A (within 2 %, from 0.2 to 1.8 L / c);
    - it all goes into the strip: |KE + IE + HG - W| below 0.5 % of W at every record;
    - the moved end is at v t to 1e-12."""
    length, width, thickness, v = 0.2, 0.002, 0.001, 1.0
    mesh = M.strip(length, width, 100, 1)
    moved, far = M.nodes_at(mesh, 0, 0.0), M.nodes_at(mesh, 0, length)
    if lateral == "free":
        fixed, c = {}, STEEL.bar_wave_speed
    else:
        fixed, c = {n: (0, 1, 0, 0, 0, 0) for n in range(mesh.n_nodes)}, STEEL.plate_wave_speed
    t_arrival = length / c
    end = 1.9 * length / STEEL.bar_wave_speed
    dt = M.stable_time_step(mesh, STEEL)
    control = Control(end_time=end, output_interval=end, history_interval=dt)
    model = M.shell_model(mesh, thickness, STEEL, control, fixed=fixed, tracked=np.concatenate([moved, far]))
    run = M.run(_with_motion(model, moved, 1, v, [0.0], [1.0]), tmp_path)
    h = run.results.history
    t = h["time"]
    ux = h["tracked_displacement"][:, :, 0]
    np.testing.assert_allclose(ux[:, : len(moved)], v * t[:, None] * np.ones((1, len(moved))), rtol=1e-12,
                               atol=1e-18)
    window = (t > 1.2 * t_arrival) & (t < 1.8 * t_arrival)
    slope, start = np.polyfit(t[window], ux[window, len(moved):].mean(axis=1), 1)
    assert slope == pytest.approx(2.0 * v, rel=0.02)
    assert length / (-start / slope) == pytest.approx(c, rel=0.02)
    work = h["external_work"]
    early = (t > 0.2 * t_arrival) & (t < 1.8 * t_arrival)
    rate = np.polyfit(t[early], work[early], 1)[0]
    assert rate == pytest.approx(STEEL.density * c * v**2 * width * thickness, rel=0.02)
    assert np.max(np.abs(run.results.total_energy())) < 0.005 * work[-1]
