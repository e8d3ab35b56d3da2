"""End to end: `paradyn-run` (``paradyn.cli.main``) meshes a scene, runs the engine, post-processes.

The small plate (32 elements) and the pipe whip (1024 elements, 2500 cycles) run once per module
into temporary folders; the tests read what those runs left behind (docs/outputs.md).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import cli, deck
from paradyn.mesh import geometry
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"
PIPE_WHIP = ROOT / "cases" / "pipe_whip" / "scene.toml"


def _run(scene_path: Path, out: Path, *options: str) -> Path:
    status = cli.main([str(scene_path), "-o", str(out), "-q", *options])
    assert status == 0, (out / "engine.log").read_text() if (out / "engine.log").exists() else status
    return out


def _history_csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, values = rows[0], np.array(rows[1:], dtype=np.float64)
    assert header[0] == "time [s]" and all(name.endswith("]") for name in header)  # docs/outputs.md: units
    return {name.split(" [")[0]: values[:, j] for j, name in enumerate(header)}


def _last_frame(pvd: Path):
    import pyvista as pv

    reader = pv.get_reader(str(pvd))
    reader.set_active_time_value(reader.time_values[-1])
    block = reader.read()
    assert block.n_blocks == 1
    return reader.time_values, block[0]


# ------------------------------------------------------------------------------------------------
# small plate


@pytest.fixture(scope="module")
def plate_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _run(SMALL_PLATE, tmp_path_factory.mktemp("small_plate"), "-n", "1", "-t", "1", "--vtk-series")


@pytest.fixture(scope="module")
def plate_summary(plate_run: Path) -> dict:
    return json.loads((plate_run / "summary.json").read_text())


def test_small_plate_writes_every_output(plate_run: Path) -> None:
    """docs/outputs.md and the paradyn-run help: deck, results, log, VTKHDF, history, summary, the
    per-part series with --vtk-series; no pictures unless asked for."""
    for name in ("deck.h5", "results.h5", "engine.log", "results.vtkhdf", "plate.pvd", "history.csv",
                 "summary.json"):
        path = plate_run / name
        assert path.is_file() and path.stat().st_size > 0, name
    assert not list(plate_run.glob("*.png"))
    with h5py.File(plate_run / "results.h5", "r") as f:
        n_frames = f["/frames/time"].shape[0]
        assert int(f.attrs["complete"]) == 1
    frames = sorted((plate_run / "vtk").glob("plate_*.vtu"))
    assert [p.name for p in frames] == [f"plate_{k:05d}.vtu" for k in range(n_frames)]
    assert not list(plate_run.glob("*.png"))
    log = (plate_run / "engine.log").read_text()
    assert "PARADYN-START" in log and "PARADYN-DONE" in log


def test_small_plate_summary_has_every_key(plate_run: Path, plate_summary: dict) -> None:
    """docs/outputs.md, summary.json: run figures, phases, energy report and effects."""
    s = plate_summary
    for key in ("wall_s", "cycles", "dt_s", "elements", "nodes", "ranks", "threads",
                "element_cycles_per_s", "phase_s", "energy", "effects"):
        assert key in s and s[key] is not None, key
    assert s["complete"] is True
    assert (s["elements"], s["nodes"], s["ranks"], s["threads"]) == (32, 45, 1, 1)
    assert s["wall_s"] > 0 and s["dt_s"] > 0 and isinstance(s["cycles"], int) and s["cycles"] > 0
    assert s["element_cycles_per_s"] == pytest.approx(s["elements"] * s["cycles"] / s["wall_s"], rel=1e-6)
    assert set(s["phase_s"]) == {"elements", "contact", "communication", "output", "other"}
    assert all(v is not None and v >= 0 for v in s["phase_s"].values())
    # VmHWM of the engine: at least its own executable and MPI (a few MiB), far below the machine
    assert 5 < s["peak_memory_per_rank_mb"] < 2000
    assert s["load_imbalance"] == 1.0   # one rank: the busiest is the mean
    assert sum(s["phase_s"].values()) == pytest.approx(s["wall_s"], rel=1e-6, abs=1e-9)
    energy = s["energy"]
    for when in ("initial", "final"):
        assert set(energy[when]) >= {"kinetic", "internal", "hourglass", "contact", "external_work", "total"}
        assert all(isinstance(v, float) for v in energy[when].values())
    assert isinstance(energy["balance_error"], float)
    assert energy["initial"]["kinetic"] > 0 and energy["initial"]["internal"] == 0.0
    # the effect table: the engine's, in the order of the step, every declared effect active every cycle
    assert [row["name"] for row in s["effects"]] == ["point_loads", "time_integration", "fixed_boundaries",
                                                     "elastic_shells", "hourglass"]
    assert all(row["active_cycles"] == s["cycles"] and row["skipped_cycles"] == 0 for row in s["effects"])
    # no contact: no penetration indicator; the step is at most the stable one
    assert s["accuracy"]["peak_penetration_over_thickness"] is None
    assert 0 < s["accuracy"]["dt_over_stable_dt"] <= 1.0


def test_small_plate_initial_kinetic_energy_is_exact(plate_run: Path, plate_summary: dict) -> None:
    """Reference: lumped mass of a regular 8 x 4 grid (a quarter of each element's mass per corner:
    interior nodes 4/4, edge nodes 2/4, corners 1/4 of rho t A_e), with v = 1 m/s in z on every
    node except the clamped edge x = 0: KE = 1/2 sum m v^2."""
    model = deck.read_deck(plate_run / "deck.h5")
    element_mass = 7860.0 * 0.002 * (0.2 / 8) * (0.1 / 4)
    count = np.bincount(model.connectivity.ravel(), minlength=model.n_nodes)
    mass = 0.25 * element_mass * count
    free = np.all(model.fixed_dofs[:, :3] == 0, axis=1)
    expected = 0.5 * np.sum(mass[free] * np.sum(model.initial_velocity[free] ** 2, axis=1))
    assert plate_summary["energy"]["initial"]["kinetic"] == pytest.approx(expected, rel=1e-12)


def test_small_plate_vtk_series_has_every_frame(plate_run: Path) -> None:
    """docs/outputs.md, VTK time series: pyvista reads plate.pvd with one time step per field
    frame (the times of /frames/time), each a 32-quad grid at the deformed position."""
    import pyvista as pv

    with h5py.File(plate_run / "results.h5", "r") as f:
        times = f["/frames/time"][()]
        displacement = f["/frames/displacement"][()]
        x0 = f["/mesh/coordinates"][()]
    reader = pv.get_reader(str(plate_run / "plate.pvd"))
    assert len(reader.time_values) == len(times)
    np.testing.assert_array_equal(np.asarray(reader.time_values), times)
    for k in (0, len(times) // 2, len(times) - 1):
        reader.set_active_time_value(reader.time_values[k])
        grid = reader.read()[0]
        assert grid.n_cells == 32 and grid.n_points == 45
        ids = np.asarray(grid.point_data["node_id"])
        np.testing.assert_array_equal(grid.point_data["displacement"], displacement[k, ids])
        np.testing.assert_allclose(grid.points, x0[ids] + displacement[k, ids], rtol=0, atol=1e-15)


def test_small_plate_frames_follow_the_output_interval(plate_run: Path) -> None:
    """docs/formats.md /control output_interval: field frames every output_interval, the first
    at t = 0 and the last at the end time: 2e-4 / 2e-5 -> 11 frames, frame k within one time
    step of k * 2e-5."""
    with h5py.File(plate_run / "results.h5", "r") as f:
        times = f["/frames/time"][()]
        dt = float(f["/run"].attrs["dt_s"])
    assert len(times) == 11
    np.testing.assert_allclose(times, 2e-5 * np.arange(11), rtol=0, atol=dt)


def test_small_plate_energy_balance(plate_run: Path, plate_summary: dict) -> None:
    """Reference: central differences conserve KE(n-1/2 . n+1/2) + midpoint stress work exactly
    for a linear system (Belytschko, Liu & Moran sec. 6.2.3), so kinetic + internal + hourglass
    - external work stays constant up to the geometric nonlinearity: balance error < 1e-4."""
    assert plate_summary["energy"]["balance_error"] < 1e-4
    history = _history_csv(plate_run / "history.csv")
    total = history["total_energy"]
    reference = max(history["kinetic_energy"].max(), history["internal_energy"].max())
    assert np.abs(total - total[0]).max() < 1e-4 * reference
    assert history["internal_energy"][-1] > 0.01 * reference      # the plate did bend
    assert history["external_work"][-1] != 0.0                    # and the load did work


def test_small_plate_with_plots(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """paradyn-run help: energies.png, parts.png, tracked.png and deformed.png with --plots; no
    VTK output with --no-vtk, even with --vtk-series."""
    monkeypatch.setenv("PYVISTA_OFF_SCREEN", "true")
    out = _run(SMALL_PLATE, tmp_path / "plots", "-n", "1", "-t", "1", "--plots", "--no-vtk", "--vtk-series")
    for name in ("energies.png", "parts.png", "tracked.png", "deformed.png"):
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000, name
    assert not (out / "plate.pvd").exists() and not (out / "results.vtkhdf").exists()


def test_frame_membrane_stress_of_a_uniform_stretch(tmp_path: Path) -> None:
    """Reference: plane-stress Hooke's law. A free 4 x 2 plate given v = D (x - xc) along x:
    after the first step every element has sxx = E/(1-nu^2) D dt, syy = nu sxx, sxy = 0
    (mid-step rates, D dt = 1e-9), which /frames/element_membrane_stress must show."""
    mesh = geometry.plate((0.04, 0.02), (4, 2))
    rate, dt, young, nu = 1e3, 1e-12, 200e9, 0.3
    velocity = np.zeros_like(mesh.coordinates)
    velocity[:, 0] = rate * (mesh.coordinates[:, 0] - 0.02)
    model = deck.Model(
        coordinates=mesh.coordinates, connectivity=mesh.quads, element_part=np.zeros(8, dtype=np.int32),
        thickness=np.array([0.001]), part_material=np.array([0]), material_model=np.array([1]),
        density=np.array([7860.0]), youngs_modulus=np.array([young]), poisson_ratio=np.array([nu]),
        initial_velocity=velocity,
        control=deck.Control(end_time=2 * dt, output_interval=dt, history_interval=dt, time_step=dt))
    path = deck.write_deck(model, tmp_path / "deck.h5")
    launch.run_engine(path, tmp_path / "results.h5", 1, 1)
    with h5py.File(tmp_path / "results.h5", "r") as f:
        times = f["/frames/time"][()]
        membrane = f["/frames/element_membrane_stress"][()]
    assert times[1] == pytest.approx(dt, rel=1e-12)
    sxx = young / (1 - nu**2) * rate * dt
    np.testing.assert_allclose(membrane[1, :, 0], sxx, rtol=1e-6)
    np.testing.assert_allclose(membrane[1, :, 1], nu * sxx, rtol=1e-6)
    np.testing.assert_allclose(membrane[1, :, 2], 0.0, atol=1e-6 * sxx)


# ------------------------------------------------------------------------------------------------
# pipe whip


@pytest.fixture(scope="module")
def pipe_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _run(PIPE_WHIP, tmp_path_factory.mktemp("pipe_whip"), "-n", "1", "-t", "2", "--vtk-series")


def test_pipe_whip_upper_pipe_flies_freely_until_contact(pipe_run: Path) -> None:
    """Reference: rigid translation until the gap closes. The outer surfaces are 0.1 mm apart and
    the upper pipe moves at 2 m/s, so contact starts at 50 us (benchmarks.md). Before it, the
    history holds upper_*_dz = -2 t exactly and the lower pipe does not move; contact then starts
    within two history records of 50 us."""
    history = _history_csv(pipe_run / "history.csv")
    t = history["time"]
    assert t[0] == 0.0 and t[-1] == pytest.approx(2.5e-3, rel=1e-9) and len(t) == 251
    free = t < 45e-6
    for point in ("upper_contact", "upper_top", "upper_quarter"):
        np.testing.assert_allclose(history[f"{point}_dz"][free], -2.0 * t[free], rtol=0, atol=1e-12)
    for point in ("lower_contact", "lower_bottom", "lower_quarter"):
        np.testing.assert_array_equal(history[f"{point}_dz"][free], 0.0)
    first = t[np.argmax(history["contact_penetration"] > 0.0)]
    assert 49.9e-6 <= first <= 70e-6
    times, grid = _last_frame(pipe_run / "upper_pipe.pvd")
    assert len(times) == 51 and grid.n_cells == 512 and grid.n_points == 16 * 33


def test_pipe_whip_contact_slows_the_upper_pipe_and_bends_the_lower(pipe_run: Path) -> None:
    """Issue 4: both pipes deform, the lower pipe slows the upper one, no node passes through the
    other pipe, and the energy balances within 2 %. Kinetic energy is 1/2 m v^2 of the upper pipe
    (47.1 J for the 16-gon) at the start and turns into strain energy through the contact."""
    history = _history_csv(pipe_run / "history.csv")
    area = 512 * 2 * 0.08 * math.sin(math.pi / 16) * 2.0 / 32
    kinetic = 0.5 * 7860.0 * 0.003 * area * 2.0**2
    assert history["kinetic_energy"][0] == pytest.approx(kinetic, rel=1e-12)
    assert history["kinetic_energy"][-1] < 0.8 * kinetic            # the upper pipe was slowed
    assert history["internal_energy"][-1] > 0.1 * kinetic           # both pipes strained
    assert history["lower_contact_dz"][-1] < -5e-4                   # the lower pipe was pushed down
    assert history["upper_top_vz"][-1] > -1.9                        # and the upper pipe slowed
    # no pass-through: penetration past the contact surfaces stays far below half a thickness
    assert history["contact_penetration"].max() < 0.1 * 0.003
    # the mid-surfaces at the contact line stay about a wall thickness apart
    gap = (0.0831 + history["upper_contact_dz"]) - (0.08 + history["lower_contact_dz"])
    assert gap.min() > 0.9 * 0.003
    summary = json.loads((pipe_run / "summary.json").read_text())
    assert summary["energy"]["balance_error"] < 0.02
    accuracy = summary["accuracy"]   # issue 16: the run's own accuracy indicators
    assert accuracy["energy_balance_error"] == summary["energy"]["balance_error"]
    assert accuracy["peak_penetration_over_thickness"] == pytest.approx(history["contact_penetration"].max() / 0.003)
    assert 0 < accuracy["peak_contact_over_internal"] < 1 and 0 < accuracy["peak_hourglass_over_internal"] < 1
    peak_internal = history["internal_energy"].max()
    assert accuracy["peak_contact_over_internal"] == pytest.approx(history["contact_energy"].max() / peak_internal)
    assert accuracy["peak_hourglass_over_internal"] == pytest.approx(history["hourglass_energy"].max() / peak_internal)
    assert accuracy["dt_over_stable_dt"] == pytest.approx(summary["dt_s"] / summary["dt_stable_s"])
    assert accuracy["added_mass_fraction"] == 0.0
    assert accuracy["dt_min_s"] == pytest.approx(history["dt"].min()) and accuracy["dt_max_s"] >= accuracy["dt_min_s"]
    assert "contact" in [row["name"] for row in summary["effects"]]
    assert summary["phase_s"]["contact"] > 0 and summary["contact_phase_s"]["search"] > 0


def test_pipe_whip_two_parts(pipe_run: Path) -> None:
    """docs/outputs.md: one .pvd series per part; each grid holds only its own part's cells."""
    assert sorted(p.name for p in pipe_run.glob("*.pvd")) == ["lower_pipe.pvd", "upper_pipe.pvd"]
    for index, name in enumerate(("lower_pipe", "upper_pipe")):
        _, grid = _last_frame(pipe_run / f"{name}.pvd")
        assert set(np.asarray(grid.cell_data["part"]).tolist()) == {index}
    summary = json.loads((pipe_run / "summary.json").read_text())
    assert summary["parts"] == ["lower_pipe", "upper_pipe"]
    assert (summary["elements"], summary["nodes"], summary["threads"]) == (1024, 1056, 2)


