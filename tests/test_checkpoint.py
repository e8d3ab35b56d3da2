"""Checkpoints and restarts (DESIGN.md: "restarts from it to the same answer as an uninterrupted
run"; docs/outputs.md, "Checkpoints and restarts").

The reference is the uninterrupted run itself: a run restarted from a checkpoint on the same
layout must reproduce its results file bitwise (every frame and history record), and on another
number of ranks its displacements bitwise (the energies, summed per rank, to round-off). The
scene is the paper's pipe whip (contact, plasticity, fixed nodes) cut to 0.4 ms.
"""

from __future__ import annotations

import shutil
import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck, scene
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
END_TIME = 4e-4
CHECKPOINT_INTERVAL = 1.5e-4   # checkpoints at 0.15 and 0.3 ms; the file keeps the last


def _pipe_whip(folder: Path, name: str, **control: float) -> Path:
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "pipe_whip" / "scene.toml"))
    model.control.end_time = END_TIME
    model.control.output_interval = 1e-4
    for key, value in control.items():
        setattr(model.control, key, value)
    return deck.write_deck(model, folder / name)


def _read(path: Path) -> dict[str, np.ndarray]:
    with h5py.File(path, "r") as f:
        data = {f"frames/{k}": f["/frames"][k][()] for k in f["/frames"]}
        data.update({f"history/{k}": f["/history"][k][()] for k in f["/history"]})
        data["complete"] = f.attrs["complete"]
    return data


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("checkpoint")
    plain = _pipe_whip(folder, "plain.h5")
    with_checkpoints = _pipe_whip(folder, "deck.h5", checkpoint_interval=CHECKPOINT_INTERVAL)
    launch.run_engine(plain, folder / "reference.h5")
    launch.run_engine(with_checkpoints, folder / "results.h5")
    return {"folder": folder, "deck": with_checkpoints, "reference": folder / "reference.h5",
            "results": folder / "results.h5", "checkpoint": folder / "results.checkpoint.h5"}


def _interrupted_copy(results: Path, target: Path) -> None:
    """A copy of a finished run's results marked as an interrupted one (complete = 0), as a run that
    stopped at or after its checkpoint leaves them: what a restart continues."""
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)


def _restart_copy(runs: dict[str, Path], name: str, ranks: int = 1, threads: int = 1) -> Path:
    """Restart from the run's checkpoint into a copy of its results (and of the checkpoint)."""
    folder = runs["folder"]
    target = folder / f"{name}.h5"
    _interrupted_copy(runs["results"], target)
    shutil.copy(runs["checkpoint"], folder / f"{name}.checkpoint.h5")
    launch.run_engine(runs["deck"], target, ranks, threads, restart=True)
    return target


def test_checkpoints_leave_the_run_unchanged(runs: dict[str, Path]) -> None:
    """Writing checkpoints pauses the loop but changes nothing: results bitwise equal."""
    reference, data = _read(runs["reference"]), _read(runs["results"])
    for key in reference:
        assert np.array_equal(data[key], reference[key]), key
    with h5py.File(runs["checkpoint"], "r") as f:
        assert f.attrs["time"] == pytest.approx(2 * CHECKPOINT_INTERVAL, rel=1e-9)
        assert f.attrs["cycles"] == 300
    assert not (runs["folder"] / "results.checkpoint.h5.partial").exists()


def test_restart_on_the_same_layout_is_bitwise_the_uninterrupted_run(runs: dict[str, Path]) -> None:
    """The restarted run drops what the results held after the checkpoint, recomputes it, and
    every frame and history record equals the uninterrupted run's bit for bit."""
    restarted = _restart_copy(runs, "same_layout")
    reference, data = _read(runs["reference"]), _read(restarted)
    assert data["complete"] == 1
    for key in reference:
        assert data[key].shape == reference[key].shape, key
        assert np.array_equal(data[key], reference[key]), key


@pytest.mark.mpi
@pytest.mark.parametrize("ranks, threads", [(2, 1), (1, 2)])
def test_restart_on_another_layout(runs: dict[str, Path], ranks: int, threads: int) -> None:
    """A 1-rank checkpoint continued on 2 ranks or 2 threads: fields bitwise (the checkpoint is
    by global id; assembly is in fixed order); energies summed per rank agree to 1e-12."""
    restarted = _restart_copy(runs, f"layout_{ranks}x{threads}", ranks, threads)
    reference, data = _read(runs["reference"]), _read(restarted)
    for key in reference:
        if key.split("/")[-1] in ("kinetic_energy", "internal_energy", "hourglass_energy"):
            np.testing.assert_allclose(data[key], reference[key], rtol=1e-12, atol=1e-12 * np.abs(reference[key]).max())
        else:
            assert np.array_equal(data[key], reference[key]), key


def _hardening_pipe_whip(folder: Path, name: str, beta: float, **control: float) -> Path:
    """The pipe whip with the upper pipe on a second steel that yields at 20 MPa, so that it
    yields before the checkpoints, and hardens (Et = E/50) with mixing beta: below 1 its
    elements store a back stress; the lower pipe's (perfectly plastic) store none."""
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "pipe_whip" / "scene.toml"))
    model.control.end_time = END_TIME
    model.control.output_interval = 1e-4
    for key, value in control.items():
        setattr(model.control, key, value)
    for field in ("material_model", "density", "youngs_modulus", "poisson_ratio", "yield_stress",
                  "tangent_modulus", "hardening_mixing", "failure_strain", "failure_points"):
        values = getattr(model, field)
        setattr(model, field, np.append(values, values[0]))
    model.yield_stress[1] = 20e6
    model.tangent_modulus[1] = model.youngs_modulus[1] / 50.0
    model.hardening_mixing[1] = beta
    model.material_names = [*model.material_names, "hardening_steel"]
    model.part_material = np.array([0, 1])
    return deck.write_deck(model, folder / name)


@pytest.mark.mpi
def test_restart_with_back_stresses_is_bitwise(tmp_path: Path) -> None:
    """Kinematic hardening keeps a back stress in the checkpoint's element rows, which parts
    without it leave at zero: a restart on 1 and on 2 ranks continues bitwise (fields). The
    back stress matters here: the same run with isotropic hardening (beta = 1) differs."""
    plain = _hardening_pipe_whip(tmp_path, "plain.h5", 0.5)
    isotropic = _hardening_pipe_whip(tmp_path, "isotropic.h5", 1.0)
    with_checkpoints = _hardening_pipe_whip(tmp_path, "deck.h5", 0.5, checkpoint_interval=CHECKPOINT_INTERVAL)
    launch.run_engine(plain, tmp_path / "reference.h5")
    launch.run_engine(isotropic, tmp_path / "isotropic_results.h5")
    launch.run_engine(with_checkpoints, tmp_path / "results.h5")
    reference = _read(tmp_path / "reference.h5")
    # yielding from 0.1 ms on: the checkpoint kept (0.3 ms) holds back stresses
    assert reference["frames/element_plastic_strain"][2].max() > 0.0
    assert not np.array_equal(reference["frames/displacement"],
                              _read(tmp_path / "isotropic_results.h5")["frames/displacement"])
    for ranks in (1, 2):
        target = tmp_path / f"restart_{ranks}.h5"
        _interrupted_copy(tmp_path / "results.h5", target)
        shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / f"restart_{ranks}.checkpoint.h5")
        launch.run_engine(with_checkpoints, target, ranks, 1, restart=True)
        data = _read(target)
        for key in ("frames/displacement", "frames/velocity", "history/tracked_displacement"):
            assert np.array_equal(data[key], reference[key]), (ranks, key)


def test_restart_with_another_deck_is_refused(runs: dict[str, Path], tmp_path: Path) -> None:
    """A checkpoint of another deck: exit 2, a message that names the mismatch and the fix, and
    the results file untouched."""
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "small_plate" / "scene.toml"))
    other = deck.write_deck(model, tmp_path / "other.h5")
    _interrupted_copy(runs["results"], tmp_path / "results.h5")
    shutil.copy(runs["checkpoint"], tmp_path / "results.checkpoint.h5")
    before = (tmp_path / "results.h5").read_bytes()
    with pytest.raises(launch.EngineError) as error:
        launch.run_engine(other, tmp_path / "results.h5", restart=True)
    assert error.value.exit_code == 2
    assert "another deck" in str(error.value) and "restart with the deck" in str(error.value)
    assert (tmp_path / "results.h5").read_bytes() == before


@pytest.mark.parametrize("edit, group", [
    (lambda m: m.density.__imul__(1.01), "materials"),
    (lambda m: m.thickness.__imul__(1.01), "parts"),
    (lambda m: setattr(m.control, "mass_damping", 1.0), "control"),
])
def test_restart_with_the_same_mesh_but_another_model_is_refused(runs: dict[str, Path], tmp_path: Path,
                                                                  edit: Callable, group: str) -> None:
    """Issue 17: a checkpoint knows its deck by a fingerprint per group; the same mesh with another
    density, thickness or damping (same sizes and time step, so the old size checks passed) is
    refused naming the group that differs."""
    model = deck.read_deck(runs["deck"])
    edit(model)
    other = deck.write_deck(model, tmp_path / "other.h5")
    _interrupted_copy(runs["results"], tmp_path / "results.h5")
    shutil.copy(runs["checkpoint"], tmp_path / "results.checkpoint.h5")
    with pytest.raises(launch.EngineError) as error:
        launch.run_engine(other, tmp_path / "results.h5", restart=True)
    assert error.value.exit_code == 2
    assert f"its /{group} differs from this deck's" in str(error.value)
    assert "output_interval, history_interval, progress_interval, checkpoint_interval" in str(error.value)


def test_restart_may_change_the_output_intervals(runs: dict[str, Path], tmp_path: Path) -> None:
    """The /control attributes of schema [deck] restart_may_change are left out of the fingerprint:
    a restart with another history and progress interval runs (the answer is the same)."""
    model = deck.read_deck(runs["deck"])
    model.control.history_interval = 2 * model.control.history_interval
    model.control.progress_interval = 3.0
    edited = deck.write_deck(model, tmp_path / "deck.h5")
    _interrupted_copy(runs["results"], tmp_path / "results.h5")
    shutil.copy(runs["checkpoint"], tmp_path / "results.checkpoint.h5")
    launch.run_engine(edited, tmp_path / "results.h5", restart=True)
    with h5py.File(tmp_path / "results.h5", "r") as f:
        assert f.attrs["complete"] == 1


def test_restart_without_a_checkpoint_is_refused(runs: dict[str, Path], tmp_path: Path) -> None:
    with pytest.raises(launch.EngineError) as error:
        launch.run_engine(runs["deck"], tmp_path / "results.h5", restart=True)
    assert error.value.exit_code == 2
    assert "does not exist" in str(error.value) and "checkpoint_interval" in str(error.value)


def test_negative_checkpoint_interval_is_refused(tmp_path: Path) -> None:
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "small_plate" / "scene.toml"))
    model.control.checkpoint_interval = -1.0
    with pytest.raises(deck.DeckError, match="checkpoint_interval"):
        deck.write_deck(model, tmp_path / "deck.h5")


def _start_and_stop(command: list[str], cwd: Path, stop: signal.Signals) -> tuple[int, str]:
    """Start a command in its own session, send `stop` once the engine reports progress."""
    env = launch.engine_environment(1)
    # a test suite started in the background (`make test &`) ignores SIGINT, and a Python started
    # with SIGINT ignored keeps it ignored: give the command the default, as a terminal's has
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, start_new_session=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert process.stdout is not None
    output = []
    for line in process.stdout:
        output.append(line)
        if "PROGRESS" in line or "% cycle " in line:   # the engine's line, or paradyn-run's (not a terminal)
            process.send_signal(stop)
            break
    output.extend(process.stdout)
    return process.wait(timeout=120), "".join(output)


@pytest.mark.mpi
@pytest.mark.parametrize("ranks", [1, 2])
def test_a_stop_signal_writes_a_checkpoint_to_restart_from(runs: dict[str, Path], tmp_path: Path, ranks: int) -> None:
    """SIGUSR1 to the launcher (mpirun forwards it; the engine alone takes it too) stops the run
    at the next poll with a checkpoint, exit status 4 and an incomplete results file; the
    restart then finishes the run to the uninterrupted answer."""
    model = deck.read_deck(runs["deck"])
    model.control.checkpoint_interval = 0.0
    model.control.progress_interval = 1e-3   # report progress (and so get stopped) early
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    results = tmp_path / "results.h5"
    status, output = _start_and_stop(launch.engine_command(deck_path, results, ranks, 1), tmp_path,
                                     signal.SIGUSR1)
    assert status == 4, output
    assert "stopped by a signal" in output and "--restart" in output
    with h5py.File(tmp_path / "results.checkpoint.h5", "r") as f:
        stopped_at = int(f.attrs["cycles"])
    assert 0 < stopped_at < 400
    assert _read(results)["complete"] == 0
    launch.run_engine(deck_path, results, ranks, 1, restart=True)
    reference, data = _read(runs["reference"]), _read(results)
    for key in reference:
        if key.startswith("frames/") or key.split("/")[-1] in ("time", "tracked_displacement", "contact_energy"):
            assert np.array_equal(data[key], reference[key]), key


def _long_small_plate(tmp_path: Path) -> Path:
    """The small plate run for 0.2 s (a thousand times longer), with early progress lines."""
    scene_text = (ROOT / "cases" / "small_plate" / "scene.toml").read_text()
    for old, new in [("end_time = 2e-4 ", "end_time = 0.2 "), ("output_interval = 2e-5 ", "output_interval = 2e-3 "),
                     ("history_interval = 2e-6 ", "history_interval = 2e-4 "),
                     ("[run]\n", "[run]\nprogress_interval = 0.001\n")]:
        assert old in scene_text
        scene_text = scene_text.replace(old, new, 1)
    scene_path = tmp_path / "scene.toml"
    scene_path.write_text(scene_text)
    return scene_path


@pytest.mark.mpi
@pytest.mark.parametrize("stop, ranks", [(signal.SIGTERM, 1), (signal.SIGTERM, 2), (signal.SIGUSR1, 1)])
def test_every_stop_signal_to_paradyn_run_checkpoints(tmp_path: Path, stop: signal.Signals, ranks: int) -> None:
    """Issue 17: SIGTERM (a batch system's stop) and SIGUSR1 to paradyn-run itself reach the engine,
    which writes its checkpoint; paradyn-run exits with the engine's status 4, on 1 or 2 ranks."""
    out = tmp_path / "out"
    command = [sys.executable, "-m", "paradyn.cli", str(_long_small_plate(tmp_path)), "-o", str(out), "-n",
               str(ranks), "-t", "1", "--no-plots", "--no-vtk"]
    status, output = _start_and_stop(command, tmp_path, stop)
    assert status == 4, output
    assert (out / "results.checkpoint.h5").is_file()
    assert "stopped by a signal" in output


def test_ctrl_c_on_paradyn_run_checkpoints_and_restart_finishes(tmp_path: Path) -> None:
    """paradyn-run turns Ctrl-C (SIGINT) into a checkpoint and exit status 4, and
    `paradyn-run --restart` in the same folder finishes the run (complete results)."""
    out = tmp_path / "out"
    command = [sys.executable, "-m", "paradyn.cli", str(_long_small_plate(tmp_path)), "-o", str(out), "-n", "1",
               "-t", "1", "--no-plots", "--no-vtk"]
    status, output = _start_and_stop(command, tmp_path, signal.SIGINT)
    assert status == 4, output
    assert (out / "results.checkpoint.h5").is_file()
    finished = subprocess.run([*command, "--restart", "-q"], cwd=tmp_path, capture_output=True, text=True,
                              env=launch.engine_environment(1), timeout=300)
    assert finished.returncode == 0, finished.stderr
    with h5py.File(out / "results.h5", "r") as f:
        assert f.attrs["complete"] == 1
        assert f["/frames/time"][-1] == pytest.approx(0.2, rel=1e-12)
        assert f["/frames/time"].shape == (101,)


def test_restart_with_an_edited_scene_takes_intervals_and_refuses_the_rest(tmp_path: Path) -> None:
    """Issue 17: --restart used to ignore an edited scene without a word. Now a new end time (the
    model's own) is refused naming it, and a new history interval is taken into the run's deck."""
    scene_path = _long_small_plate(tmp_path)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "paradyn.cli", str(scene_path), "-o", str(out), "-n", "1", "-t", "1",
               "--no-plots", "--no-vtk"]
    status, _ = _start_and_stop(command, tmp_path, signal.SIGINT)
    assert status == 4
    text = scene_path.read_text()
    scene_path.write_text(text.replace("end_time = 0.2 ", "end_time = 0.3 ", 1))
    refused = subprocess.run([*command, "--restart", "-q"], cwd=tmp_path, capture_output=True, text=True,
                             env=launch.engine_environment(1), timeout=300)
    assert refused.returncode == 2
    assert "the scene changed since the run started (/control end_time)" in refused.stderr
    scene_path.write_text(text.replace("history_interval = 2e-4 ", "history_interval = 4e-4 ", 1))
    taken = subprocess.run([*command, "--restart", "-q"], cwd=tmp_path, capture_output=True, text=True,
                           env=launch.engine_environment(1), timeout=300)
    assert taken.returncode == 0, taken.stderr
    assert "restart takes the scene's new /control history_interval" in taken.stdout
    assert deck.read_deck(out / "deck.h5").control.history_interval == pytest.approx(4e-4)


def test_restart_over_a_finished_run_is_refused(runs: dict[str, Path], tmp_path: Path) -> None:
    """Issue 17: a checkpoint left from before a run finished used to be continued over the finished
    results; now the engine refuses (status 2) and the results stay as they were."""
    shutil.copy(runs["results"], tmp_path / "results.h5")
    shutil.copy(runs["checkpoint"], tmp_path / "results.checkpoint.h5")
    before = (tmp_path / "results.h5").read_bytes()
    with pytest.raises(launch.EngineError) as error:
        launch.run_engine(runs["deck"], tmp_path / "results.h5", restart=True)
    assert error.value.exit_code == 2
    assert "holds a finished run (complete = 1)" in str(error.value)
    assert (tmp_path / "results.h5").read_bytes() == before
