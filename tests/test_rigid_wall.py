"""Planar rigid walls (LS-DYNA's *RIGIDWALL_PLANAR and _MOVING) through the whole stack: a scene
with ``[[rigid_wall]]`` tables, the engine, the results file (docs/theory.md, "Rigid walls").

A steel plate 0.1 m x 0.1 m, 2 mm thick, 4 x 4 elements, every node tracked, one history record
per step. The wall pushes a node behind it back with the penalty force -k d n, k = s m / dt^2
(s = /rigid_walls/penalty_scale, default 0.1; m the node's lumped mass; d < 0 its signed distance
to the plane). A plate that hits the wall flat stays flat and rigid: every node is then the same
mass on a spring, the linear oscillator x'' = -(s / dt^2) x, whose central-difference solution
has the frequency omega_h = 2 asin(sqrt(s) / 2) / dt (Belytschko, Liu and Moran, Nonlinear Finite
Elements for Continua and Structures, 2000, section 6.3: the central difference method on the
linear oscillator) and leaves the wall with the speed it came in (the spring is elastic).

The wall's force is an external force: its work, counted by the trapezoidal rule with the other
external forces, holds minus the energy stored in the penalty springs while a node is behind the
wall, and the work a moving wall does on the model; so KE + IE + hourglass energy - external work
stays at its initial value through the impact.
"""

from __future__ import annotations

import shutil
from collections.abc import Sequence
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from models import interrupted_copy
from paradyn import deck, scene
from paradyn.mesh import geometry
from paradyn.running import launch

STEEL_DENSITY = 7850.0
THICKNESS = 0.002
SIZE = 0.1
ELEMENTS = 4
PLATE_MASS = STEEL_DENSITY * THICKNESS * SIZE * SIZE
DEFAULT_SCALE = 0.1


def _vector(v: Sequence[float] | float) -> str:
    if isinstance(v, (int, float)):
        return repr(float(v))
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def _scene(folder: Path, *, origin: Sequence[float], velocity: Sequence[float], end_time: float,
           walls: Sequence[dict[str, Sequence[float] | float]] = (), u_axis: Sequence[float] = (1.0, 0.0, 0.0),
           v_axis: Sequence[float] = (0.0, 1.0, 0.0), load: float = 0.0, extra: str = "") -> tuple[Path, np.ndarray]:
    """The plate scene with the given walls (keys point, normal, velocity); every node is tracked,
    in mesh order. ``load`` (N) pushes the first corner along the plate's normal, to bend it;
    ``extra`` is TOML text appended at the end (an [effects] table).
    Returns the scene file and the plate's node coordinates."""
    mesh = geometry.plate((SIZE, SIZE), (ELEMENTS, ELEMENTS), origin, u_axis, v_axis)
    lines = [
        'title = "rigid wall"',
        "[run]", f"end_time = {end_time!r}", f"output_interval = {end_time / 4!r}", "history_interval = 1e-9",
        "[[material]]", 'name = "steel"', 'model = "elastic"', f"density = {STEEL_DENSITY!r}",
        "youngs_modulus = 200e9", "poisson_ratio = 0.3",
        "[[part]]", 'name = "plate"', 'material = "steel"', f"thickness = {THICKNESS!r}",
        f"initial_velocity = {_vector(velocity)}",
        "[part.geometry]", 'kind = "plate"', f"size = [{SIZE!r}, {SIZE!r}]", f"elements = [{ELEMENTS}, {ELEMENTS}]",
        f"origin = {_vector(origin)}", f"u_axis = {_vector(u_axis)}", f"v_axis = {_vector(v_axis)}",
    ]
    for wall in walls:
        lines += ["[[rigid_wall]]", *(f"{key} = {_vector(value)}" for key, value in wall.items())]
    if load:
        lines += ["[[load]]", 'part = "plate"', f"point = {_vector(mesh.coordinates[0])}", 'dof = "uz"',
                  f"value = {load!r}", "ramp_time = 0.0"]
    for k, point in enumerate(mesh.coordinates):
        lines += ["[[track]]", f'name = "node{k}"', 'part = "plate"', f"point = {_vector(point)}"]
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "scene.toml"
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    return path, mesh.coordinates


def _run(path: Path, ranks: int = 1, threads: int = 1) -> paradyn.Results:
    return paradyn.run(path, path.parent / f"out_{ranks}x{threads}", ranks=ranks, threads=threads, post=False)


def _energy_drift(history: dict[str, np.ndarray]) -> np.ndarray:
    """KE + IE + hourglass + contact energy - external work, less its initial value (J)."""
    total = (history["kinetic_energy"] + history["internal_energy"] + history["hourglass_energy"]
             + history["contact_energy"] - history["external_work"])
    return total - total[0]


def _mean_velocity(history: dict[str, np.ndarray], weights: np.ndarray) -> np.ndarray:
    """The plate's momentum over its mass at every record, from the tracked nodes."""
    return np.einsum("rnk,n->rk", history["tracked_velocity"], weights) / weights.sum()


def _lumped_weights() -> np.ndarray:
    """Lumped masses of the 5 x 5 nodes, up to a factor: 1 inside, 1/2 on edges, 1/4 at corners."""
    edge = np.ones(ELEMENTS + 1)
    edge[[0, -1]] = 0.5
    return np.outer(edge, edge).ravel()


# ----------------------------------------------------------------------------------------------
# 1. A plate bouncing off a stationary wall


def test_flat_plate_bounces_off_a_stationary_wall(tmp_path: Path) -> None:
    """A free plate at v0 = (1, 0.5, -5) m/s hits the wall z = 0 flat, 1 mm away.

    References: an elastic impact on a rigid, frictionless wall reverses the normal velocity and
    keeps the tangential one (coefficient of restitution 1; Goldsmith, Impact, 1960, chapter 1).
    Each node is the oscillator of the module docstring, so the deepest penetration is
    v0 / omega = 5 dt / sqrt(0.1) (dt the run's step) up to the sampling of the peak on steps and
    omega_h / omega = 1.004.

    Measured: the plate leaves at vz = +4.9971 m/s (bound: within 2 % of +5), vx and vy unchanged
    to round-off, the deepest point 6.59e-5 m below the wall against 6.66e-5 m (bound 3 %), the
    energy balance closed to 1e-15 J of the 1.96 J of kinetic energy (bound 1 %). A constraint wall
    (LS-DYNA's default) would stop the plate (vz = 0); a stiffness without the mass or the square
    of the step would miss the penetration by orders of magnitude.
    """
    v0 = np.array([1.0, 0.5, -5.0])
    path, _ = _scene(tmp_path, origin=(0.0, 0.0, 0.001), velocity=v0, end_time=4e-4,
                     walls=[{"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 2.0)}])
    results = _run(path)
    h, dt = results.history, float(results.run["dt_s"])
    v = _mean_velocity(h, _lumped_weights())
    assert v[-1, 2] == pytest.approx(-v0[2], rel=0.02)
    np.testing.assert_allclose(v[:, :2], np.broadcast_to(v0[:2], v[:, :2].shape), rtol=1e-12)
    # rigid: every node bounces alike
    np.testing.assert_allclose(h["tracked_velocity"][-1, :, 2], v[-1, 2], rtol=1e-12)
    lowest = 0.001 + h["tracked_displacement"][:, :, 2].min()
    assert -lowest == pytest.approx(-v0[2] * dt / np.sqrt(DEFAULT_SCALE), rel=0.03)
    kinetic = 0.5 * PLATE_MASS * float(v0 @ v0)
    assert h["kinetic_energy"][0] == pytest.approx(kinetic, rel=1e-12)
    assert np.abs(_energy_drift(h)).max() <= 0.01 * kinetic
    # the work of the wall while the plate is in it is the stored spring energy, near all the normal KE
    assert -h["external_work"].min() == pytest.approx(0.5 * PLATE_MASS * v0[2] ** 2, rel=0.05)


# ----------------------------------------------------------------------------------------------
# 2. A moving wall pushing a plate at rest


def test_moving_wall_throws_a_resting_plate_at_twice_its_speed(tmp_path: Path) -> None:
    """A wall with normal (1, 1, 1) (given unnormalised) moves at V = 2 m/s along its normal, plus
    a sliding component (3, -3, 0) m/s in its own plane, towards a plate at rest 0.5 mm away and
    parallel to it.

    Reference: in the wall's frame the plate comes in at -V n and leaves at +V n (elastic impact on
    a rigid wall), so it leaves at 2 V n in the model's frame; the wall is frictionless, so its
    sliding does nothing; the work the wall does is the plate's final kinetic energy 2 M V^2.

    Measured: every node leaves at 3.9961 n m/s (bound: within 1 % of 2 V = 4 m/s, no tangential
    velocity above 1e-9 m/s), the external work 1.2536 J against 2 M V^2 = 1.2560 J (bound 1 %),
    the energy balance closed to round-off (bound 1 % of the final kinetic energy).
    """
    n = np.ones(3) / np.sqrt(3.0)
    speed = 2.0
    u_axis, v_axis = (1.0, -1.0, 0.0), (1.0, 1.0, -2.0)
    path, _ = _scene(tmp_path, origin=0.0005 * n, velocity=(0.0, 0.0, 0.0), end_time=4e-4, u_axis=u_axis,
                     v_axis=v_axis, walls=[{"point": (0.0, 0.0, 0.0), "normal": (1.0, 1.0, 1.0),
                                            "velocity": speed * n + np.array([3.0, -3.0, 0.0])}])
    h = _run(path).history
    final = h["tracked_velocity"][-1]
    np.testing.assert_allclose(final @ n, 2.0 * speed, rtol=0.01)
    assert np.abs(final - np.outer(final @ n, n)).max() <= 1e-9
    kinetic = 2.0 * PLATE_MASS * speed**2
    assert h["external_work"][-1] == pytest.approx(kinetic, rel=0.01)
    assert np.abs(_energy_drift(h)).max() <= 0.01 * kinetic


# ----------------------------------------------------------------------------------------------
# 3. A wall that nothing reaches changes nothing


def test_a_wall_nothing_reaches_changes_no_bit(tmp_path: Path) -> None:
    """A bending plate (a corner load of 50 N) flies at 5 m/s towards a wall 5 mm away and stops
    2 mm short of it at the end time: the whole history and the frames are bitwise those of the
    same scene without the wall (reference: the penalty force is zero in front of the wall)."""
    common = {"origin": (0.0, 0.0, 0.005), "velocity": (0.0, 0.0, -5.0), "end_time": 4e-4, "load": 50.0}
    with_wall, _ = _scene(tmp_path / "wall", walls=[{"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0)}],
                          **common)
    without, _ = _scene(tmp_path / "none", **common)
    a, b = _run(with_wall), _run(without)
    assert np.abs(a.history["tracked_velocity"]).max() > 0.0
    assert a.history["internal_energy"].max() > 0.0
    for name, values in b.history.items():
        if name != "rigid_wall_force":   # one column per wall: none without the wall, zeros with it
            assert np.array_equal(a.history[name], values), name
    assert np.array_equal(a.history["rigid_wall_force"], np.zeros((len(a.history["time"]), 1, 3)))
    assert np.array_equal(a.displacement[...], b.displacement[...])
    # the wall ran every cycle all the same (it is never idle), and only the run with it lists it
    row = {r.name: r for r in a.effect_table}["rigid_wall"]
    assert (row.state, row.active_cycles, row.skipped_cycles) == ("on", int(a.run["cycles"]), 0)
    assert "rigid_wall" not in {r.name for r in b.effect_table}


def test_switching_the_wall_off_gives_the_run_without_it(tmp_path: Path) -> None:
    """[effects] rigid_wall = false (docs/scene.md): the plate flies through the plane z = 0 as
    if the scene had no [[rigid_wall]], bitwise, and the effect table says the wall was off."""
    common = {"origin": (0.0, 0.0, 0.001), "velocity": (0.0, 0.0, -5.0), "end_time": 4e-4}
    off, _ = _scene(tmp_path / "off", walls=[{"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0)}],
                    extra="[effects]\nrigid_wall = false\n", **common)
    without, _ = _scene(tmp_path / "none", **common)
    a, b = _run(off), _run(without)
    assert a.history["tracked_displacement"][-1, :, 2].max() < -0.001   # through the plane
    for name, values in b.history.items():
        assert np.array_equal(a.history[name], values), name
    row = {r.name: r for r in a.effect_table}["rigid_wall"]
    assert (row.state, row.active_cycles) == ("off", 0)


def test_restart_in_the_middle_of_a_bounce_is_bitwise(tmp_path: Path) -> None:
    """A checkpoint at 0.21 ms falls while the plate of test 1 is in the wall (from 0.20 to about
    0.24 ms); the run restarted from it reproduces every frame and history record of the
    uninterrupted run bit for bit (DESIGN.md, restarts): the wall keeps no state of its own, and
    the restored step finds its external forces and their work where the run left them."""
    path, _ = _scene(tmp_path, origin=(0.0, 0.0, 0.001), velocity=(0.0, 0.0, -5.0), end_time=4e-4,
                     walls=[{"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0)}])
    model = scene.build_model(scene.load_scene(path))
    model.control.checkpoint_interval = 2.1e-4
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    launch.run_engine(deck_path, tmp_path / "results.h5")
    with h5py.File(tmp_path / "results.checkpoint.h5", "r") as f:
        assert f.attrs["time"] == pytest.approx(2.1e-4, rel=0.05)
    interrupted_copy(tmp_path / "results.h5", tmp_path / "restarted.h5")
    shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / "restarted.checkpoint.h5")
    launch.run_engine(deck_path, tmp_path / "restarted.h5", restart=True)
    with h5py.File(tmp_path / "results.h5", "r") as a, h5py.File(tmp_path / "restarted.h5", "r") as b:
        assert b.attrs["complete"] == 1
        for group in ("frames", "history"):
            for name in a[group]:
                assert np.array_equal(a[group][name][()], b[group][name][()]), f"{group}/{name}"
        in_wall = a["history"]["tracked_displacement"][:, :, 2].min(axis=1) < -0.001
        times = a["history"]["time"][()]
        assert times[in_wall].min() < 2.1e-4 < times[in_wall].max()


# ----------------------------------------------------------------------------------------------
# 4. Layouts


@pytest.mark.mpi
def test_tilted_plate_bounce_is_bitwise_the_same_on_2_ranks_x_2_threads(tmp_path: Path) -> None:
    """A plate tilted by 2 degrees about y hits the wall z = 0 edge first and bends. Its history
    on 2 ranks x 2 threads equals the 1 x 1 run bitwise (times, tracked nodes, frames), the
    energies and the external work (the wall's work comes from many nodes) to 1e-14 of the
    kinetic energy, as they are summed per rank and then over ranks (tests/test_parallel.py), and the
    energy balance closes to 1 % of the initial kinetic energy on both (docs/theory.md)."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    tilt = np.radians(2.0)
    path, _ = _scene(tmp_path, origin=(0.0, 0.0, 0.0005), velocity=(0.0, 0.0, -5.0), end_time=3e-4,
                     u_axis=(np.cos(tilt), 0.0, np.sin(tilt)),
                     walls=[{"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0)}])
    one, four = _run(path), _run(path, ranks=2, threads=2)
    assert one.history["internal_energy"].max() > 1e-3 * one.history["kinetic_energy"][0]
    for name in ("time", "tracked_displacement", "tracked_velocity"):
        assert np.array_equal(one.history[name], four.history[name]), name
    assert np.array_equal(one.displacement[...], four.displacement[...])
    for name in ("kinetic_energy", "internal_energy", "hourglass_energy", "external_work"):
        np.testing.assert_allclose(four.history[name], one.history[name], rtol=0,
                                   atol=1e-14 * one.history["kinetic_energy"][0], err_msg=name)
    for results in (one, four):
        assert np.abs(_energy_drift(results.history)).max() <= 0.01 * results.history["kinetic_energy"][0]


# ----------------------------------------------------------------------------------------------
# 5. The scene's checks


@pytest.mark.parametrize("wall, words", [
    ({"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 0.0)},
     "/rigid_walls/normal[0] ([[rigid_wall]] #1 'normal') is the zero vector"),
    ({"point": (0.0, 0.0, 0.0), "normal": (0.0, 0.0, 1.0), "penalty_scale": 0.8},
     "'penalty_scale' in [[rigid_wall]] #1"),
    ({"point": (0.0, 0.0, 0.01), "normal": (0.0, 0.0, 1.0)},
     "/rigid_walls/point[0] ([[rigid_wall]] #1 'point') puts node 0 behind"),
])
def test_scene_refuses_a_bad_wall(tmp_path: Path, wall: dict, words: str) -> None:
    """A zero normal, a penalty scale above the stable 0.5, and a model that starts behind its wall
    are refused with a message that names the key and says what to do."""
    path, _ = _scene(tmp_path, origin=(0.0, 0.0, 0.001), velocity=(0.0, 0.0, 0.0), end_time=1e-4, walls=[wall])
    with pytest.raises(scene.SceneError) as refused:
        scene.build_model(scene.load_scene(path))
    assert words in str(refused.value)
