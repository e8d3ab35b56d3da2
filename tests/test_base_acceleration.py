"""Base acceleration (LS-DYNA *LOAD_BODY_X/Y/Z with a load curve; docs/theory.md, "Base
acceleration") through the whole stack: a scene's ``[[base_acceleration]]`` rows (a row table from
the schema alone, paradyn.scene.row_tables), the deck's /base_accelerations, the engine's member
of the nodal effect family, f_ext += m a(t) on every node's translations at the loads stage,
a(t) = sum over the rows of value x curve(t) x unit(direction).

1. A free plate under a constant base acceleration moves as a rigid body: u(t) = a t^2 / 2, which
   central differences started with the half step reproduce exactly for a constant acceleration,
   and the energy balance they define, W - KE = m |a|^2 dt^2 / 8 (as for gravity,
   tests/test_gravity.py). Two rows add up, each along the unit vector of its direction.
2. With a ramp curve, a(t) = A t / T up to T and A after, the velocity is the integral of a(t):
   A t^2 / (2T), then A (t - T/2). The velocity update is the midpoint rule of that integral, exact
   on the linear pieces; the first half step, dt/2 a(0), lags the integral by A dt^2 / (8T), which
   the whole-step velocity (the mean of the two half steps, as the results report it) makes up
   before T; over the kink at T the midpoint rule leads by at most dt^2/8 x the jump of the slope,
   A dt^2 / (8T). So v - integral lies in [-A dt^2 / (8T), 0] after T and is 0 before.
3. Switched off ([effects] base_acceleration = false) the rows are dropped: the plate stays at rest,
   and the effect table lists the effect as off.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn.scene.row_tables import ROW_TABLES

DENSITY = 7850.0
THICKNESS = 0.002
SIZE = (0.1, 0.05)
MASS = DENSITY * THICKNESS * SIZE[0] * SIZE[1]
CORNER = [0.1, 0.05, 0.0]


def _plate(end_time: float, effects: dict[str, bool] | None = None) -> paradyn.Scene:
    """An unsupported steel plate, 4 x 2 elements, its far corner tracked, a record every step."""
    s = paradyn.Scene("base acceleration", end_time=end_time, output_interval=end_time / 4,
                      history_interval=1e-9, effects=effects)
    s.add_material("steel", model="elastic", density=DENSITY, youngs_modulus=200e9, poisson_ratio=0.3)
    s.add_part("plate", material="steel", thickness=THICKNESS, geometry=paradyn.Plate(size=SIZE, elements=(4, 2)))
    s.add_track("corner", part="plate", point=CORNER)
    return s


def _shaken(end_time: float, effects: dict[str, bool] | None = None) -> tuple[paradyn.Scene, np.ndarray]:
    """The plate under two constant rows, and their sum a = (1, -6, -8) m/s^2."""
    s = _plate(end_time, effects)
    s.add("base_acceleration", direction=[2.0, 0.0, 0.0], value=1.0)
    s.add("base_acceleration", direction=[0.0, 3.0, 4.0], value=-10.0)
    return s, np.array([1.0, -6.0, -8.0])


def _run(s: paradyn.Scene, folder: Path, ranks: int = 1) -> paradyn.Results:
    return paradyn.run(s, folder, ranks=ranks, threads=1, post=False)


def test_the_scene_table_is_its_datasets(tmp_path: Path) -> None:
    """[[base_acceleration]] has the keys of its datasets: direction and value required, curve
    optional (a constant 1); the deck rows are those of the scene and a written scene reads back."""
    keys = {k.name: k for k in ROW_TABLES["base_acceleration"]}
    assert list(keys) == ["direction", "value", "curve"]
    assert [name for name, k in keys.items() if k.required] == ["direction", "value"]
    s, _ = _shaken(1e-4)
    model = s.build()
    np.testing.assert_array_equal(model.base_acceleration_direction, [[2.0, 0.0, 0.0], [0.0, 3.0, 4.0]])
    np.testing.assert_array_equal(model.base_acceleration_value, [1.0, -10.0])
    constant = len(model.curve_first_point) - 1   # the frontend's constant curve, factor 1
    assert model.curve_value[model.curve_first_point[constant]] == 1.0
    np.testing.assert_array_equal(model.base_acceleration_curve, [constant, constant])
    again = paradyn.Scene.from_toml(s.to_toml(tmp_path / "scene.toml")).validate()
    assert again.rows["base_acceleration"][1]["value"] == -10.0


def test_a_constant_base_acceleration_moves_the_plate_as_a_rigid_body(tmp_path: Path) -> None:
    """u = a t^2 / 2 on every node and every frame, W = m |a|^2 t^2 / 2 and W - KE = m |a|^2 dt^2 / 8
    at every record, all to 1e-9 relative, the plate unstrained; on two ranks the same motion."""
    end = 1.0e-3
    s, a = _shaken(end)
    res = _run(s, tmp_path / "one")
    t = res.frame_times
    u = np.asarray(res.displacement)
    expected = np.broadcast_to(0.5 * t[:, None, None] ** 2 * a[None, None, :], u.shape)
    np.testing.assert_allclose(u, expected, rtol=1e-9, atol=1e-9 * 0.5 * end**2 * np.abs(a).max())
    h = res.history
    time = h["time"]
    dt = float(res.run["dt_s"])
    assert np.all(h["dt"] == dt)   # a rigid body: the step never changes
    assert np.all(h["internal_energy"] + h["hourglass_energy"] <= 1e-12 * h["kinetic_energy"].max())
    np.testing.assert_allclose(h["external_work"], 0.5 * MASS * (a @ a) * time**2, rtol=1e-9, atol=0.0)
    lag = h["external_work"] - h["kinetic_energy"]
    np.testing.assert_allclose(lag[time > 0], MASS * (a @ a) * dt**2 / 8.0, rtol=1e-9)
    table = {row.name: row for row in res.effect_table}
    assert table["base_acceleration"].state == "on"
    assert table["base_acceleration"].active_cycles == int(res.run["cycles"])
    two = _run(s, tmp_path / "two", ranks=2)
    np.testing.assert_allclose(np.asarray(two.displacement), expected, rtol=1e-9,
                               atol=1e-9 * 0.5 * end**2 * np.abs(a).max())


def test_the_velocity_is_the_integral_of_a_ramp(tmp_path: Path) -> None:
    """a(t) = A t / T up to T, A after (T inside a step: the kink counts): the corner's velocity is
    the integral of a(t) to the midpoint rule's error, within [-A dt^2 / (8T), 0], and exact before T."""
    end, peak = 8.0e-4, 50.0
    ramp = 0.35 * end
    s = _plate(end)
    s.add_curve("ramp", time=[0.0, ramp], value=[0.0, 1.0])
    s.add("base_acceleration", direction=[0.0, 0.0, 1.0], value=peak, curve="ramp")
    res = _run(s, tmp_path)
    h = res.history
    t = h["time"]
    dt = float(res.run["dt_s"])
    assert np.all(h["dt"] == dt) and abs(ramp / dt % 1.0 - 0.5) > 0.1   # T inside a step, not at its middle
    v = h["tracked_velocity"][:, 0, 2]
    exact = np.where(t <= ramp, peak * t**2 / (2.0 * ramp), peak * (t - ramp / 2.0))
    bound = peak * dt**2 / (8.0 * ramp)
    rounding = 1e-12 * exact.max()
    error = v - exact
    assert error.min() >= -bound * (1.0 + 1e-6) - rounding and error.max() <= rounding, (error.min(), bound)
    assert np.abs(error[t < ramp - dt]).max() <= rounding
    assert np.abs(h["tracked_velocity"][:, 0, :2]).max() <= rounding   # along z alone
    assert v[-1] == pytest.approx(peak * (end - ramp / 2.0), abs=bound * (1.0 + 1e-6))   # 33 mm/s


def test_switched_off_the_plate_stays_at_rest(tmp_path: Path) -> None:
    s, _ = _shaken(2e-4, effects={"base_acceleration": False})
    res = _run(s, tmp_path)
    assert not np.any(np.asarray(res.displacement)) and not np.any(np.asarray(res.velocity))
    assert not np.any(res.history["external_work"]) and not np.any(res.history["kinetic_energy"])
    table = {row.name: row for row in res.effect_table}
    assert table["base_acceleration"].state == "off" and table["base_acceleration"].active_cycles == 0
    assert "base_acceleration" not in res.effects
