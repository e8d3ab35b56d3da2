"""A time step that follows the mesh (issue 14, item 3; docs/theory.md, "A time step that follows
the mesh").

References: the element step L / c with L = area / longest side and c = sqrt(E / (rho (1 -
nu^2))) (Hallquist, LS-DYNA Theory Manual, shell time step), computed here with numpy from the
positions in a frame; central differences with a varying step (Belytschko, Liu & Moran,
Nonlinear Finite Elements, sec. 6.2.1); mass scaling as LS-DYNA's negative DT2MS: an element's
density times (target / (safety L / c))^2, the others unchanged. Each test states its tolerance.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
import paradyn
from paradyn import deck, scene
from paradyn.deck import Control
from paradyn.mesh import geometry
from paradyn.running import launch
from paradyn.running.launch import EngineError

SOFT = M.Material(young=1.0e6, poisson=0.3, density=1000.0)   # c = 33 m/s: steps of 0.1 ms
SAFETY = 0.9
THICKNESS = 0.002
END_TIME = 1.2e-3


def _element_steps(coordinates: np.ndarray, quads: np.ndarray, material: M.Material) -> np.ndarray:
    """L / c of every element of a flat mesh: L = area / longest side (no safety factor)."""
    c = coordinates[quads]
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    sides = np.linalg.norm(np.roll(c, -1, axis=1) - c, axis=2)
    return area / sides.max(axis=1) / material.plate_wave_speed


def _crushed_plate(end_time: float = END_TIME, **control: float) -> deck.Model:
    """A 0.1 m square plate of 32 x 32 elements squeezed along x: initial v_x = -100 (x - 0.05)
    m/s, free edges, for a quarter of its first in-plane period (2 x 0.1 m / c = 6 ms): the
    elements shorten along x, so L = their x size falls."""
    mesh = M.flat_plate((0.1, 0.1), (32, 32))
    velocity = np.zeros((mesh.n_nodes, 3))
    velocity[:, 0] = -100.0 * (mesh.coordinates[:, 0] - 0.05)
    settings = dict(end_time=end_time, output_interval=end_time / 8, history_interval=end_time / 8,
                    time_step_safety=SAFETY)
    settings.update(control)
    return M.shell_model(mesh, THICKNESS, SOFT, Control(**settings), velocity=velocity)


@pytest.fixture(scope="module")
def crushed(tmp_path_factory: pytest.TempPathFactory) -> paradyn.Results:
    return M.run(_crushed_plate(), tmp_path_factory.mktemp("crushed")).results


def test_the_step_follows_the_current_element_sizes(crushed: paradyn.Results) -> None:
    """At every frame, the history's dt_stable is safety x min L / c of the positions in that frame
    (to 1e-9: the kernel measures the sides in the element's plane, numpy in space; the plate is
    flat), dt_element is an element with that smallest step, and dt is at most dt_stable and at
    least the time left over one more stable step than fit in it; the step falls as the plate is
    crushed."""
    res = crushed
    quads = np.asarray(res.connectivity)
    h = res.history
    stable = []
    for k, t in enumerate(res.time_values[:-1]):   # the last record's step is one past the end
        record = int(np.flatnonzero(h["time"] == t)[0])
        steps = _element_steps(res.coordinates + res.displacement[k], quads, SOFT)
        stable.append(SAFETY * steps.min())
        assert h["dt_stable"][record] == pytest.approx(stable[-1], rel=1e-9)
        assert steps[int(h["dt_element"][record])] == pytest.approx(steps.min(), rel=1e-9)
        left = END_TIME - t
        assert left / (np.ceil(left / stable[-1]) + 1) < h["dt"][record] <= stable[-1] * (1 + 1e-9)
    assert len(stable) >= 6
    assert stable[-1] < 0.95 * stable[0] and h["dt"][len(stable) - 1] < 0.95 * h["dt"][0]
    assert res.run["dt_first_s"] == h["dt"][0]
    assert res.run["dt_stable_min_s"] < 0.95 * res.run["dt_stable_max_s"]


def test_the_varying_step_keeps_the_energy_balance_and_ends_on_time(crushed: paradyn.Results) -> None:
    """The elastic plate conserves KE + IE (+ hourglass) with the varying step to 0.5 % of the
    initial kinetic energy (no loads, no damping; measured 0.25 % at most, at a record where the
    step changed by 1/14; 0.02 % after it: the kinetic energy m v(n-1/2).v(n+1/2) / 2 that central
    differences conserve for a constant step moves with a change of step), and the last record
    and frame are at end_time exactly."""
    h = crushed.history
    total = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"]
    assert np.abs(total - total[0]).max() < 5e-3 * h["kinetic_energy"][0]
    assert abs(total[-2] - total[0]) < 1e-3 * h["kinetic_energy"][0]
    assert h["internal_energy"].max() > 0.1 * h["kinetic_energy"][0]   # the plate did deform
    assert h["time"][-1] == END_TIME and crushed.time_values[-1] == END_TIME


def _driven_strip(tmp_path: Path) -> Path:
    """The deck of the floor tests: an 8 x 2 strip driven against its fixed left edge."""
    mesh = M.flat_plate((0.1, 0.025), (8, 2))
    velocity = np.zeros((mesh.n_nodes, 3))
    velocity[:, 0] = -50.0 * mesh.coordinates[:, 0]
    control = Control(end_time=1e-2, output_interval=1e-4, time_step_safety=SAFETY, time_step_floor=0.95,
                      checkpoint_interval=1e-3)
    fixed = {int(j): M.ALL_DOFS for j in M.nodes_at(mesh, 0, 0.0)}
    model = M.shell_model(mesh, THICKNESS, SOFT, control, velocity=velocity, fixed=fixed)
    return deck.write_deck(model, tmp_path / "deck.h5")


@pytest.mark.mpi
def test_the_floor_stop_on_two_ranks_names_the_same_element(tmp_path: Path) -> None:
    """The element's rank composes the message and every rank stops with it (no rank waits in a
    collective): the same words on 1 and 2 ranks."""
    path = _driven_strip(tmp_path)
    messages = []
    for ranks in (1, 2):
        with pytest.raises(EngineError) as stop:
            launch.run_engine(path, tmp_path / f"results{ranks}.h5", ranks, 1, runner="mpirun")
        assert stop.value.exit_code == 3
        messages.append(str(stop.value))
    # elements 0 and 8, the column at the fixed edge, mirror each other across the strip's centre
    # line: which of the two has the smaller step is decided by rounding
    named = [e for e in (0, 8) if f"element {e} of part 0" in messages[0]]
    assert messages[0] == messages[1] and len(named) == 1, messages


def test_a_step_below_the_floor_stops_the_run_naming_the_element(tmp_path: Path) -> None:
    """Issue 14, item 3.3: an 8 x 2 strip driven against its fixed left edge (v_x = -50 x m/s,
    0.15 c at the free end: the elements shorten by 1.5 % a step at first, some 10 % in all) brings
    the step below time_step_floor = 0.95 x the first step: the run stops with status 3 naming the
    element, its part, its size (whose step is below the floor) and the step; the results so far
    stay readable (complete = 0, the step falling in the history) and a checkpoint holds the state."""
    path = _driven_strip(tmp_path)
    mesh = M.flat_plate((0.1, 0.025), (8, 2))
    with pytest.raises(EngineError) as stop:
        launch.run_engine(path, tmp_path / "results.h5")
    message = str(stop.value)
    assert stop.value.exit_code == 3, message
    assert "fell below /control time_step_floor" in message and "of part 0" in message
    element = int(message.split(" s: element ")[1].split()[0])
    assert 0 <= element < 16
    size = float(message.split("longest side = ")[1].split()[0])
    with h5py.File(tmp_path / "results.h5") as f:
        assert int(f.attrs["complete"]) == 0
        dt = f["history/dt"][()]
        assert dt.size >= 2 and dt[-1] < 0.95 * dt[0]   # the last record is that of the stop
        assert int(f["history/dt_element"][-1]) == element
    first = SAFETY * _element_steps(mesh.coordinates, mesh.quads, SOFT).min()
    assert SAFETY * size / SOFT.plate_wave_speed < 0.95 * first   # the size named sets the step
    with h5py.File(tmp_path / "results.checkpoint.h5") as f:
        assert f.attrs["dt"] < 0.95 * f.attrs["dt_first"]


def _strip_with_a_sliver() -> tuple[geometry.Mesh, float]:
    """A 4 x 1 strip whose last column is a sliver 2 mm wide (the others 25 mm): the sliver's step
    is 12.5 times smaller. Returns the mesh and the sliver's width."""
    mesh = M.flat_plate((0.077, 0.025), (4, 1))
    x = mesh.coordinates[:, 0]
    mesh.coordinates[:, 0] = np.select([x < 0.01, x < 0.03, x < 0.05, x < 0.07], [0.0, 0.025, 0.05, 0.075], 0.077)
    return mesh, 0.002


def test_mass_scaling_reaches_the_target_step_adding_the_analytic_mass(tmp_path: Path) -> None:
    """Issue 14, item 3.4: with mass_scaling_step = T = safety x 5 mm / c, the sliver alone
    (step safety x 2 mm / c < T) gets its density raised by (T / (safety x 2 mm / c))^2: the first
    step is T (to 1e-12), the added mass (/run, summary.json, per part) is the analytic
    (f - 1) rho t A (to 1e-12), and the free strip, set moving unevenly, keeps its momentum with the
    scaled masses (to 1e-12 of its size)."""
    mesh, sliver = _strip_with_a_sliver()
    c = SOFT.plate_wave_speed
    target = SAFETY * 0.005 / c
    factor = (target / (SAFETY * sliver / c)) ** 2
    added = (factor - 1.0) * SOFT.density * THICKNESS * sliver * 0.025
    velocity = np.zeros((mesh.n_nodes, 3))
    velocity[:, 0] = 3.0 * np.sin(40.0 * mesh.coordinates[:, 0])
    velocity[:, 2] = 1.0
    control = Control(end_time=30 * target, output_interval=5 * target, time_step_safety=SAFETY,
                      mass_scaling_step=target, mass_scaling_limit=0.5)
    model = M.shell_model(mesh, THICKNESS, SOFT, control, velocity=velocity)
    res = paradyn.run(model, tmp_path / "scaled", ranks=1, threads=1)
    assert res.history["dt"][0] == pytest.approx(target, rel=1e-12)
    assert int(res.history["dt_element"][0]) == 3   # the sliver, now at the target step
    assert res.run["added_mass_kg"] == pytest.approx(added, rel=1e-12)
    model_mass = SOFT.density * THICKNESS * 0.077 * 0.025
    assert res.run["added_mass_fraction"] == pytest.approx(added / model_mass, rel=1e-12)
    report = json.loads(Path(res.outputs["summary"]).read_text())
    assert report["mass_scaling"]["added_kg"] == pytest.approx(added, rel=1e-12)
    assert report["accuracy"]["added_mass_fraction"] == pytest.approx(added / model_mass, rel=1e-12)
    assert "PARADYN-MASS_SCALING" in (tmp_path / "scaled" / "engine.log").read_text()
    # lumped masses with the sliver's density scaled: a quarter of each element's mass per node
    density = np.full(mesh.n_elements, SOFT.density)
    density[3] *= factor
    c4 = mesh.coordinates[mesh.quads]
    area = 0.5 * np.linalg.norm(np.cross(c4[:, 2] - c4[:, 0], c4[:, 3] - c4[:, 1]), axis=1)
    mass = np.zeros(mesh.n_nodes)
    np.add.at(mass, mesh.quads.ravel(), np.repeat(0.25 * density * THICKNESS * area, 4))
    momentum = np.einsum("n,fnc->fc", mass, res.velocity[:])
    scale = np.abs(mass[:, None] * velocity).sum()
    assert np.abs(momentum - momentum[0]).max() < 1e-12 * scale
    assert np.abs(momentum[0] - mass @ velocity).max() < 1e-12 * scale


def test_mass_scaling_beyond_the_limit_is_refused(tmp_path: Path) -> None:
    """The same strip with mass_scaling_limit = 1e-3: the sliver would need more; the run is
    refused before it starts (status 2), the message naming the added fraction and the limit."""
    mesh, _ = _strip_with_a_sliver()
    target = SAFETY * 0.005 / SOFT.plate_wave_speed
    control = Control(end_time=1e-3, output_interval=5e-4, mass_scaling_step=target, mass_scaling_limit=1e-3)
    path = deck.write_deck(M.shell_model(mesh, THICKNESS, SOFT, control), tmp_path / "deck.h5")
    with pytest.raises(EngineError) as refused:
        launch.run_engine(path, tmp_path / "results.h5")
    message = str(refused.value)
    assert refused.value.exit_code == 2, message
    assert "of the model's mass, over /control mass_scaling_limit" in message and "a fraction" in message


def test_a_restart_with_a_varying_step_is_bitwise_the_uninterrupted_run(tmp_path: Path) -> None:
    """The checkpoint keeps the step and the one before it (the velocity update takes their mean):
    restarted from it, the crushed plate's frames and history equal the uninterrupted run's bit
    for bit, dt included; the cycle counters are 64-bit in the checkpoint and in /run."""
    reference = deck.write_deck(_crushed_plate(), tmp_path / "plain.h5")
    launch.run_engine(reference, tmp_path / "reference.h5")
    with_checkpoints = deck.write_deck(_crushed_plate(checkpoint_interval=END_TIME / 3), tmp_path / "deck.h5")
    launch.run_engine(with_checkpoints, tmp_path / "results.h5")
    with h5py.File(tmp_path / "results.checkpoint.h5") as f:
        assert f.attrs["cycles"].dtype == np.int64 and f.attrs["dt_previous"] > 0
        assert f.attrs["dt"] != f.attrs["dt_first"]
    target = tmp_path / "restarted.h5"
    M.interrupted_copy(tmp_path / "results.h5", target)
    shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / "restarted.checkpoint.h5")
    launch.run_engine(with_checkpoints, target, restart=True)
    with h5py.File(tmp_path / "reference.h5") as a, h5py.File(target) as b:
        assert int(b.attrs["complete"]) == 1 and b["run"].attrs["cycles"].dtype == np.int64
        for group in ("frames", "history"):
            for name in a[group]:
                assert np.array_equal(a[group][name][()], b[group][name][()]), f"{group}/{name}"


@pytest.mark.mpi
def test_the_step_and_its_element_do_not_depend_on_the_layout(tmp_path: Path, crushed: paradyn.Results) -> None:
    """On 2 ranks x 2 threads the crushed plate takes the same steps, set by the same elements
    (the smallest id among equal steps), and reaches the same positions, bit for bit."""
    res = paradyn.run(_crushed_plate(), tmp_path / "two", ranks=2, threads=2, runner="mpirun", post=False)
    assert np.array_equal(res.history["dt"], crushed.history["dt"])
    assert np.array_equal(res.history["dt_element"], crushed.history["dt_element"])
    assert np.array_equal(res.displacement[-1], crushed.displacement[-1])


def test_scene_keys_reach_the_deck(tmp_path: Path) -> None:
    """[run] time_step_floor, mass_scaling_step and mass_scaling_limit go to /control."""
    text = (Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml").read_text()
    text = text.replace("[run]", "[run]\ntime_step_floor = 0.01\nmass_scaling_step = 1e-7\nmass_scaling_limit = 0.2", 1)
    scene_path = tmp_path / "scene.toml"
    scene_path.write_text(text)
    model = scene.build_model(scene.load_scene(scene_path))
    written = deck.write_deck(model, tmp_path / "deck.h5")
    with h5py.File(written) as f:
        attrs = f["control"].attrs
        assert attrs["time_step_floor"] == 0.01 and attrs["mass_scaling_step"] == 1e-7
        assert attrs["mass_scaling_limit"] == 0.2
    bad = text.replace("time_step_floor = 0.01", "time_step_floor = 2.0")
    scene_path.write_text(bad)
    with pytest.raises(scene.SceneError, match="time_step_floor"):
        scene.load_scene(scene_path)


def test_unchanged_model_helpers(tmp_path: Path) -> None:
    """replace() keeps the new Control fields (the defaults of the schema)."""
    control = replace(Control(end_time=1.0, output_interval=0.1), time_step_floor=0.2)
    assert control.time_step_floor == 0.2 and control.mass_scaling_limit == 0.05 and control.mass_scaling_step == 0.0
