"""Issue 17 (and 14): runs that cannot go right are refused before they start, with a message
that names the problem, and a check that fails on one rank stops every rank (no hang)."""

from __future__ import annotations

import os
import subprocess
from dataclasses import replace
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck, scene
from paradyn._schema import STATUS_BAD_INPUT
from paradyn.mesh import geometry
from paradyn.running.launch import current_machine, engine_path
from paradyn.running.runners import MpirunRunner


def _strip(end_time: float = 2e-6, **control: float) -> deck.Model:
    mesh = geometry.plate((0.02, 0.01), (2, 1))   # nodes 0 1 2 / 3 4 5; elements (0 1 4 3), (1 2 5 4)
    return deck.Model(
        coordinates=mesh.coordinates, connectivity=mesh.quads,
        element_part=np.zeros(mesh.n_elements, dtype=np.int32), thickness=np.array([0.001]),
        part_material=np.array([0]), material_model=np.array([1]), density=np.array([7860.0]),
        youngs_modulus=np.array([200e9]), poisson_ratio=np.array([0.3]),
        control=deck.Control(end_time=end_time, output_interval=end_time, **control))


def _engine(deck_path: Path, ranks: int) -> subprocess.CompletedProcess[str]:
    """The engine under mpirun as paradyn-run starts it, with a timeout that turns a hang into a failure."""
    runner = MpirunRunner(replace(current_machine(), engine=engine_path()))
    command = runner.command(deck_path, deck_path.with_name("results.h5"), ranks, 1, False)
    env = dict(os.environ, **runner.environment(ranks, 1))
    return subprocess.run(command, env=env, capture_output=True, text=True, timeout=60)


@pytest.mark.mpi
@pytest.mark.parametrize("fault", ["zero_area", "bow_tie"])
def test_a_bad_element_on_the_second_rank_stops_both_ranks(tmp_path: Path, fault: str) -> None:
    """A zero-area or bow-tie element held by rank 1 (blocks: element 1 on rank 1) used to leave
    rank 0 waiting in the next collective forever; now the element is named before the run, once,
    and every rank stops with status 2 (the check that a node has mass, which runs on each rank's
    share, is agreed between the ranks for the same reason)."""
    path = deck.write_deck(_strip(), tmp_path / "deck.h5")
    with h5py.File(path, "r+") as f:
        xyz = f["/nodes/coordinates"][()]
        if fault == "zero_area":   # nodes 2 and 5 onto nodes 1 and 4
            xyz[2], xyz[5] = xyz[1].copy(), xyz[4].copy()
        else:                      # nodes 2 and 5 swapped: the element crosses itself
            xyz[[2, 5]] = xyz[[5, 2]]
        f["/nodes/coordinates"][...] = xyz
    done = _engine(path, ranks=2)
    assert done.returncode == STATUS_BAD_INPUT, done.stderr
    words = "collapsed or crossed"   # a bow-tie of a rectangle has parallel diagonals: no normal at all
    assert "element 1 (part 0, nodes [1, 2, 5, 4]) is collapsed or crossed at node" in done.stderr
    assert done.stderr.count("paradyn-engine: error:") == 1
    assert not path.with_name("results.h5").exists()
    with pytest.raises(deck.DeckError, match=words):   # the frontend names it too
        deck.validate_deck(path)


def test_an_absurd_step_count_is_refused_naming_the_estimate(tmp_path: Path) -> None:
    """A requested step of 1e-15 s over 1 ms is 1e12 steps: refused before the first step (it
    used to overflow the step count and take one step of end_time, exit 0)."""
    path = deck.write_deck(_strip(end_time=1e-3, time_step=1e-15), tmp_path / "deck.h5")
    done = _engine(path, ranks=1)
    assert done.returncode == STATUS_BAD_INPUT, done.stdout
    assert "1.000E+12 steps" in done.stderr and "end_time" in done.stderr


def test_damping_that_reverses_velocities_is_refused(tmp_path: Path) -> None:
    """mass_damping x dt >= 2 makes the update's factor 1 - a dt / 2 negative: the velocities flip
    every step and the kinetic energy turns negative (exit 0 before); now refused."""
    path = deck.write_deck(_strip(mass_damping=1e12), tmp_path / "deck.h5")
    done = _engine(path, ranks=1)
    assert done.returncode == STATUS_BAD_INPUT, done.stdout
    assert "mass_damping x dt" in done.stderr and "must be below 2" in done.stderr


def test_strong_but_sound_damping_runs(tmp_path: Path) -> None:
    """The control case: damping with a dt of 1 runs (a refusal must not catch it)."""
    model = _strip()
    path = deck.write_deck(model, tmp_path / "probe.h5")
    done = _engine(path, ranks=1)
    assert done.returncode == 0, done.stderr
    with h5py.File(path.with_name("results.h5")) as f:
        dt = float(f["run"].attrs["dt_s"])
    path = deck.write_deck(replace(model, control=replace(model.control, mass_damping=1.0 / dt)),
                           tmp_path / "deck.h5")
    done = _engine(path, ranks=1)
    assert done.returncode == 0, done.stderr


def test_a_row_count_mismatch_names_the_dataset_that_sets_the_count(tmp_path: Path) -> None:
    """A /parts/thickness with two rows for one part used to be blamed on /parts/material alone;
    both sides now name the dataset that set the number of parts."""
    path = deck.write_deck(_strip(), tmp_path / "deck.h5")
    with h5py.File(path, "r+") as f:
        del f["/parts/thickness"]
        f["/parts/thickness"] = np.array([0.001, 0.002])
    done = _engine(path, ranks=1)
    assert done.returncode == STATUS_BAD_INPUT
    words = "/parts/material has 1 rows but /parts/thickness, which sets the number of parts, has 2"
    assert words in done.stderr
    with pytest.raises(deck.DeckError, match=words):
        deck.validate_deck(path)


def test_a_checkpoint_interval_below_the_step_is_refused(tmp_path: Path) -> None:
    """Found by tests/test_fuzz.py: checkpoint_interval = 1e-300 paused at the same step for ever,
    writing the same checkpoint again and again. Now refused before the run; and every call of
    the time loop takes at least one step, whatever the pause time."""
    path = deck.write_deck(_strip(checkpoint_interval=1e-300), tmp_path / "deck.h5")
    done = _engine(path, ranks=1)
    assert done.returncode == STATUS_BAD_INPUT, done.stdout[-500:]
    assert "checkpoint_interval" in done.stderr and "is below the time step" in done.stderr


def test_a_model_beyond_the_node_memory_is_refused_naming_the_estimate(tmp_path: Path) -> None:
    """Issue 17, size guards: the engine estimates what a model needs per rank (every rank holds
    the global deck) and refuses it when the ranks of a node need more than the node has
    (PARADYN_MEMORY_MB, a batch job's share, else MemTotal); the control run below fits."""
    path = deck.write_deck(_strip(), tmp_path / "deck.h5")
    engine = [str(engine_path()), str(path), str(tmp_path / "results.h5")]
    small = subprocess.run(engine, env=dict(os.environ, PARADYN_MEMORY_MB="10"), capture_output=True, text=True,
                           timeout=60)
    assert small.returncode == STATUS_BAD_INPUT
    assert "the model (2 elements) on 1 rank(s) of this node needs about" in small.stderr
    assert "more than its 10 MiB" in small.stderr
    roomy = subprocess.run(engine, env=dict(os.environ, PARADYN_MEMORY_MB="4000"), capture_output=True, text=True,
                           timeout=60)
    assert roomy.returncode == 0, roomy.stderr


PIPE_WHIP = Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml"


@pytest.mark.parametrize("lowered, refused", [(0.11, True), (0.0, False)])
def test_contact_parts_that_cross_at_the_start_are_refused(tmp_path: Path, lowered: float, refused: bool) -> None:
    """Issue 17: the pipe whip's upper pipe lowered by 0.11 m crosses the lower pipe; contact used
    to never engage (the nodes are past the surface, beyond the search), a silent wrong answer.
    Now refused before the run, naming the pair and where; the paper's scene (3.1 mm apart) runs."""
    model = scene.build_model(scene.load_scene(PIPE_WHIP))
    upper = np.unique(model.connectivity[model.element_part == 1])
    model.coordinates[upper, 2] -= lowered
    model.control.end_time = 2e-6   # a step or two: only the set-up matters here
    model.control.output_interval = 1e-6
    path = deck.write_deck(model, tmp_path / "deck.h5")
    done = _engine(path, ranks=1)
    if refused:
        assert done.returncode == STATUS_BAD_INPUT, done.stdout[-500:]
        assert "the parts of /contact/pairs[0] cross at the start" in done.stderr
        assert "move the parts apart" in done.stderr
    else:
        assert done.returncode == 0, done.stderr


def test_a_plate_through_a_plate_is_refused_both_ways(tmp_path: Path) -> None:
    """A small plate standing through the middle of a large one: its sides pierce the large plate's
    elements (checked in both directions, so the order of the pair does not matter)."""
    flat = geometry.plate((0.1, 0.1), (2, 2))
    upright = geometry.plate((0.02, 0.02), (1, 1), origin=(0.01, 0.03, -0.01), u_axis=(1.0, 0.0, 0.0),
                             v_axis=(0.0, 0.0, 1.0))
    for first, second in ((flat, upright), (upright, flat)):
        coordinates = np.vstack([first.coordinates, second.coordinates])
        quads = np.vstack([first.quads, second.quads + first.n_nodes])
        parts = np.r_[np.zeros(first.n_elements, np.int32), np.ones(second.n_elements, np.int32)]
        model = deck.Model(
            coordinates=coordinates, connectivity=quads, element_part=parts, thickness=np.array([0.001, 0.001]),
            part_material=np.array([0, 0]), material_model=np.array([1]), density=np.array([7860.0]),
            youngs_modulus=np.array([200e9]), poisson_ratio=np.array([0.3]), contact_pairs=np.array([[0, 1]]),
            control=deck.Control(end_time=2e-6, output_interval=1e-6))
        path = deck.write_deck(model, tmp_path / "deck.h5")
        done = _engine(path, ranks=1)
        assert done.returncode == STATUS_BAD_INPUT and "cross at the start" in done.stderr


@pytest.mark.mpi
@pytest.mark.parametrize("height", [-0.01, 0.005])
def test_a_crossing_beyond_256_grid_cells_is_found(tmp_path: Path, height: float) -> None:
    """The crossing check bins elements in at most 256 cells a side: a strip 2000 elements long
    gets cells larger than its elements (surface_overlap.bin_elements), and a plate standing
    through its far end, past the 256th element, is still found, at the same point on 1 and 3
    ranks (each rank tests its block of the sides); the same plate lifted clear of the strip runs."""
    flat = geometry.plate((2.0, 0.001), (2000, 1))
    upright = geometry.plate((0.0005, 0.02), (1, 1), origin=(1.9502, 0.0, height), u_axis=(0.0, 1.0, 0.0),
                             v_axis=(0.0, 0.0, 1.0))
    upright.coordinates[:, 1] += 0.00025
    coordinates = np.vstack([flat.coordinates, upright.coordinates])
    quads = np.vstack([flat.quads, upright.quads + flat.n_nodes])
    parts = np.r_[np.zeros(flat.n_elements, np.int32), np.ones(upright.n_elements, np.int32)]
    model = deck.Model(
        coordinates=coordinates, connectivity=quads, element_part=parts, thickness=np.array([0.0001, 0.0001]),
        part_material=np.array([0, 0]), material_model=np.array([1]), density=np.array([7860.0]),
        youngs_modulus=np.array([200e9]), poisson_ratio=np.array([0.3]), contact_pairs=np.array([[0, 1]]),
        control=deck.Control(end_time=2e-7, output_interval=1e-7))
    path = deck.write_deck(model, tmp_path / "deck.h5")
    answers = []
    for ranks in (1, 3):   # each rank tests its block of the sides: the same first crossing as one rank
        done = _engine(path, ranks=ranks)
        if height < 0:
            assert done.returncode == STATUS_BAD_INPUT and "cross at the start" in done.stderr, done.stderr[-500:]
            answers.append([line for line in done.stderr.splitlines() if "cross at the start" in line])
        else:
            assert done.returncode == 0, done.stderr[-500:]
    assert answers == [] or answers[0] == answers[1]


def test_an_energy_error_past_the_limit_stops_the_run(tmp_path: Path) -> None:
    """Issue 15, guards: /control energy_error_limit stops a run whose energy balance error passes
    it (status 3, the results so far kept, a diagnosis), as LS-DYNA's energy ratio termination. A
    small plate keeps its energy to a small error: the run without a limit finishes, and the same
    run with a limit a thousand times below its own final error stops."""
    model = scene.build_model(scene.load_scene(PIPE_WHIP.parent.parent / "small_plate" / "scene.toml"))
    path = deck.write_deck(model, tmp_path / "deck.h5")
    free = _engine(path, ranks=1)
    assert free.returncode == 0, free.stderr
    with h5py.File(path.with_name("results.h5")) as f:
        h = f["history"]
        total = h["kinetic_energy"][()] + h["internal_energy"][()] + h["hourglass_energy"][()] - h["external_work"][()]
        scale = max(h["kinetic_energy"][()].max(), h["internal_energy"][()].max(), np.abs(h["external_work"][()]).max())
        error = abs(total[-1] - total[0]) / scale
    assert 0 < error < 1e-2
    limited = deck.write_deck(replace(model, control=replace(model.control, energy_error_limit=error / 1e3)),
                              tmp_path / "limited.h5")
    done = _engine(limited, ranks=1)
    assert done.returncode == 3, done.stdout[-400:]
    assert "the energy balance error reached" in done.stderr and "energy_error_limit" in done.stderr
    with h5py.File(limited.with_name("results.h5")) as f:
        assert int(f.attrs["complete"]) == 0 and f["history/time"].shape[0] >= 1
        stopped_at = float(f["history/time"][-1])
    # with checkpoints, the stopped state is kept as one (the last good state, issue 15)
    kept = deck.write_deck(replace(model, control=replace(model.control, energy_error_limit=error / 1e3,
                                                          checkpoint_interval=model.control.end_time / 2)),
                           tmp_path / "kept" / "deck.h5")
    done = _engine(kept, ranks=1)
    assert done.returncode == 3
    checkpoint_lines = [line for line in done.stdout.splitlines() if line.startswith("PARADYN-CHECKPOINT")]
    assert checkpoint_lines and float(checkpoint_lines[-1].split("time=")[1].split()[0]) == pytest.approx(stopped_at)
