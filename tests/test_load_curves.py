"""Load curves (LS-DYNA *DEFINE_CURVE; docs/theory.md, "Load curves"): the engine's kernel against
linear interpolation by hand, and the scene tables [[curve]], [[pressure]] and [[prescribe]] as
they reach the deck (a load without a curve gets one constant curve; curve relations refused by
both validators are in tests/test_schema_damage.py).

Reference: piecewise-linear interpolation y = y_i + (y_(i+1) - y_i) (t - t_i) / (t_(i+1) - t_i)
between the points around t, the first value held before the first time and the last value held
after the last time (the engine's documented choice).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn import _kernels, deck, scene

# two curves: a trapezoid (ramp up, hold, ramp down to 0) and a single point
FIRST = np.array([1, 5], dtype=np.int32)        # 1-based, as the engine holds them
TIME = np.array([0.0, 1.0, 3.0, 4.0, 2.0])
VALUE = np.array([0.0, 2.0, 2.0, 0.0, -7.5])


def _engine(curve: int, t: np.ndarray) -> np.ndarray:
    return _kernels.load_curve_values(FIRST, TIME, VALUE, curve, np.asarray(t, dtype=np.float64))


def test_curve_is_linear_between_points_and_held_outside() -> None:
    t = np.array([-1.0, 0.0, 0.25, 0.5, 1.0, 2.0, 3.0, 3.5, 3.9, 4.0, 10.0])
    expected = np.interp(t, TIME[:4], VALUE[:4])   # numpy holds the end values too
    np.testing.assert_allclose(_engine(1, t), expected, rtol=0, atol=1e-15)
    assert _engine(1, np.array([0.3]))[0] == pytest.approx(0.6, rel=1e-15)


def test_single_point_curve_is_a_constant() -> None:
    np.testing.assert_array_equal(_engine(2, np.array([-5.0, 2.0, 9.0])), [-7.5, -7.5, -7.5])


def test_many_points_match_interpolation() -> None:
    """Bisection over 200 points gives numpy's interpolation at random times."""
    rng = np.random.default_rng(13)
    time = np.cumsum(rng.uniform(0.01, 1.0, 200))
    value = rng.normal(size=200)
    t = rng.uniform(time[0] - 1.0, time[-1] + 1.0, 500)
    y = _kernels.load_curve_values(np.array([1], dtype=np.int32), time, value, 1, t)
    np.testing.assert_allclose(y, np.interp(t, time, value), rtol=1e-12, atol=1e-12)


SCENE = """
title = "curves"
[run]
end_time = 1e-4
output_interval = 1e-4
gravity = [0.0, 0.0, -9.81]
[[material]]
name = "steel"
model = "elastic"
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3
[[part]]
name = "plate"
material = "steel"
thickness = 0.001
[part.geometry]
kind = "plate"
size = [0.1, 0.05]
elements = [4, 2]
[[curve]]
name = "ramp"
time = [0.0, 1e-4]
value = [0.0, 1.0]
[[curve]]
name = "pulse"
time = [0.0, 1e-5, 2e-5]
value = [0.0, 1.0, 0.0]
[[pressure]]
part = "plate"
value = 1e5
curve = "pulse"
[[pressure]]
part = "plate"
value = -2e3
[[prescribe]]
part = "plate"
box = [[-1e-6, -1e-6, -1e-6], [1e-6, 1.0, 1e-6]]
dof = "uy"
value = 0.5
"""


def _scene(tmp_path: Path, text: str = SCENE) -> scene.Scene:
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return scene.load_scene(path)


def test_scene_curves_reach_the_deck(tmp_path: Path) -> None:
    """Scene curves in order, then one constant curve for the loads that name none."""
    model = scene.build_model(_scene(tmp_path))
    np.testing.assert_array_equal(model.curve_first_point, [0, 2, 5])
    np.testing.assert_array_equal(model.curve_time, [0.0, 1e-4, 0.0, 1e-5, 2e-5, 0.0])
    np.testing.assert_array_equal(model.curve_value, [0.0, 1.0, 0.0, 1.0, 0.0, 1.0])
    np.testing.assert_array_equal(model.pressure_curve, [1, 2])
    np.testing.assert_array_equal(model.pressure_value, [1e5, -2e3])
    np.testing.assert_array_equal(model.prescribed_node, [0, 5, 10])   # the x = 0 edge, 5 nodes a row
    np.testing.assert_array_equal(model.prescribed_dof, [2, 2, 2])
    np.testing.assert_array_equal(model.prescribed_curve, [2, 2, 2])
    assert model.gravity == (0.0, 0.0, -9.81)
    written = deck.read_deck(deck.write_deck(model, tmp_path / "deck.h5"))
    np.testing.assert_array_equal(written.curve_first_point, model.curve_first_point)
    np.testing.assert_array_equal(written.prescribed_value, model.prescribed_value)
    assert written.control.gravity_z == -9.81


def test_scene_without_loads_writes_no_curves(tmp_path: Path) -> None:
    text = SCENE.split("[[curve]]")[0]
    model = scene.build_model(_scene(tmp_path, text))
    assert model.n_curves == 0 and model.n_pressures == 0 and model.n_prescribed == 0
    path = deck.write_deck(model, tmp_path / "deck.h5")
    with h5py.File(path, "r") as f:
        assert "curves" not in f and "pressure" not in f and "prescribed" not in f


@pytest.mark.parametrize("change, words", [
    (("time = [0.0, 1e-5, 2e-5]", "time = [0.0, 2e-5, 2e-5]"), "must increase strictly"),
    (("time = [0.0, 1e-5, 2e-5]", "time = [0.0, 1e-5]"), "2 times and 3 values"),
    (('curve = "pulse"', 'curve = "pluse"'), "curve 'pluse', which is not defined"),
    (('dof = "uy"', 'dof = "uw"'), "'dof' = 'uw'"),
    (("box = [[-1e-6, -1e-6, -1e-6], [1e-6, 1.0, 1e-6]]", "box = [[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]"),
     "contains no node"),
    (("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, -9.81]"), "'gravity' in [run] must be a list of 3"),
])
def test_scene_load_mistakes_are_named(tmp_path: Path, change: tuple[str, str], words: str) -> None:
    text = SCENE.replace(*change)
    assert text != SCENE
    with pytest.raises(scene.SceneError) as refused:
        scene.build_model(_scene(tmp_path, text))
    assert words in str(refused.value)


def test_a_dof_prescribed_twice_is_refused(tmp_path: Path) -> None:
    text = SCENE + '[[prescribe]]\npart = "plate"\nbox = [[-1e-6, -1e-6, -1e-6], [1e-6, 1e-6, 1e-6]]\n' \
                   'dof = "uy"\nvalue = 1.0\n'
    with pytest.raises(scene.SceneError, match="already has its uy velocity prescribed"):
        scene.build_model(_scene(tmp_path, text))


@pytest.mark.parametrize("switch", ["gravity", "pressure", "prescribed_velocity"])
def test_a_load_switched_off_is_the_scene_without_it(tmp_path: Path, switch: str) -> None:
    """[effects] <switch> = false runs bitwise as the scene written without that load (issue 13),
    and the effect table says it was declared but off; with it on, the run differs."""
    without = {"gravity": SCENE.replace("gravity = [0.0, 0.0, -9.81]\n", ""),
               "pressure": SCENE.replace('[[pressure]]\npart = "plate"\nvalue = 1e5\ncurve = "pulse"\n', "")
                                .replace('[[pressure]]\npart = "plate"\nvalue = -2e3\n', ""),
               "prescribed_velocity": SCENE[:SCENE.index("[[prescribe]]")]}[switch]
    assert without != SCENE
    runs = {}
    for name, text in [("off", SCENE + f"[effects]\n{switch} = false\n"), ("without", without), ("on", SCENE)]:
        folder = tmp_path / name
        folder.mkdir()
        (folder / "scene.toml").write_text(text)
        runs[name] = paradyn.run(folder / "scene.toml", folder / "out", ranks=1, threads=1, post=False)
    off, on = runs["off"], runs["on"]
    for key in ("displacement", "velocity"):
        assert np.array_equal(np.asarray(getattr(off, key)), np.asarray(getattr(runs["without"], key))), key
    for key, values in off.history.items():
        assert np.array_equal(values, runs["without"].history[key]), key
    assert not np.array_equal(np.asarray(on.displacement[-1]), np.asarray(off.displacement[-1]))
    row = next(r for r in off.effect_table if r.name == switch)
    assert row.state == "off" and row.active_cycles == 0
    assert next(r for r in on.effect_table if r.name == switch).active_cycles == int(on.run["cycles"])
