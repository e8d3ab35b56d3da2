"""The traffic counters of /run (messages_per_step, bytes_sent_per_step, bytes_received_per_step,
fortran/src/parallel/traffic_counter.f90), the set-up time, and the weak-scaling benchmark
(tools/weak_scaling.py, docs/performance.md "Beyond one machine")."""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck
from paradyn.deck import ELASTIC, Control, Model
from paradyn.running import launch

pytestmark = pytest.mark.mpi

ROOT = Path(__file__).resolve().parents[1]


def _tool():
    spec = importlib.util.spec_from_file_location("weak_scaling", ROOT / "tools" / "weak_scaling.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["weak_scaling"] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def tool():
    if shutil.which("mpirun") is None:
        pytest.skip("mpirun is not installed")
    return _tool()


def _strip_model(tool, n_ranks: int, n: int) -> Model:
    """The benchmark's clamped strip alone (no contact), n x n elements per segment."""
    coordinates, quads = tool.strip(n_ranks, n)
    fixed = np.zeros((len(coordinates), 6), dtype=np.int32)
    fixed[np.isclose(coordinates[:, 1], 0.0)] = 1
    velocity = np.zeros_like(coordinates)
    velocity[:, 2] = 1.0
    return Model(coordinates=coordinates, connectivity=quads, element_part=np.zeros(len(quads), dtype=np.int32),
                 thickness=np.array([1e-3]), part_material=np.zeros(1, dtype=np.int32),
                 material_model=np.array([ELASTIC]), density=np.array([7800.0]), youngs_modulus=np.array([2e11]),
                 poisson_ratio=np.array([0.3]), initial_velocity=velocity, fixed_dofs=fixed,
                 control=Control(end_time=2e-5, output_interval=2e-5, partition="blocks"))


def test_corner_exchange_traffic_is_counted(tool, tmp_path: Path) -> None:
    """Reference: each step rank 0 sends its neighbour the six corner values (48 bytes) of every
    corner it holds on a shared node (counted here from the mesh: the nodes of both blocks), one
    message, and one allreduce (the step's MINLOC, 16 bytes, one round on two ranks); every 16th
    cycle one more (the stop-signal poll, 4 bytes). On one rank nothing is sent."""
    n = 6
    model = _strip_model(tool, 2, n)
    path = deck.write_deck(model, tmp_path / "deck.h5")
    quads = np.asarray(model.connectivity)
    half = len(quads) // 2   # the paper's blocks: rank 0 holds the first half
    shared = np.intersect1d(quads[:half].ravel(), quads[half:].ravel())
    corners = int(np.isin(quads[:half], shared).sum())
    assert corners == 2 * (n + 1) - 2   # a column of n + 1 nodes: 2 corners inside, 1 at each end
    for ranks in (1, 2):
        launch.run_engine(path, tmp_path / f"r{ranks}.h5", ranks, 1, log_path=tmp_path / f"r{ranks}.log")
        with h5py.File(tmp_path / f"r{ranks}.h5", "r") as f:
            run = dict(f["run"].attrs)
        assert run["setup_s"] > 0.0
        if ranks == 1:
            assert run["messages_per_step"] == run["bytes_sent_per_step"] == run["bytes_received_per_step"] == 0.0
            continue
        cycles = float(run["cycles"])
        per_step = 48 * corners + 16
        # one more exchange and step than cycles (the forces and step at the start), the poll every 16th
        assert per_step <= run["bytes_sent_per_step"] <= per_step * (cycles + 1) / cycles + 4 / 16 + 1e-9
        assert run["bytes_received_per_step"] == run["bytes_sent_per_step"]   # symmetric cut
        assert 2.0 <= run["messages_per_step"] <= 2.0 * (cycles + 1) / cycles + 1 / 16 + 1e-9


def test_weak_scaling_table(tool, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """tools/weak_scaling.py runs one deck per rank count with the same elements per rank
    (segment^2 + plate^2), prints a Markdown row per layout, and no traffic on one rank."""
    assert tool.main([str(tmp_path), "--ranks", "1", "2", "--steps", "10", "--segment", "8", "--plate", "6"]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| ") and line[2].isdigit()]
    assert len(rows) == 2
    cells = [[float(c) for c in row.strip("| ").split(" | ")] for row in rows]
    assert [c[0] for c in cells] == [1, 2]
    assert [c[1] for c in cells] == [100, 200] and cells[0][2] == cells[1][2] == 100
    assert cells[0][6] == 0 and cells[1][6] > 0
    with h5py.File(tmp_path / "ranks_2" / "results.h5", "r") as f:
        assert f["run"].attrs["elements"] == 200 and f["run"].attrs["ranks"] == 2


def _contact_traffic(tool, folder: Path, ranks: int, gather: str | None) -> dict[str, float]:
    """/run of the benchmark's contact problem (8 x 8 segments, 6 x 6 plates, 30 steps)."""
    model = tool.weak_model(ranks, tool.Sizes(8, 6), 30)
    model.control.contact_gather = gather
    path = deck.write_deck(model, folder / f"deck_{ranks}_{gather}.h5")
    results = folder / f"results_{ranks}_{gather}.h5"
    launch.run_engine(path, results, ranks, 1)
    with h5py.File(results, "r") as f:
        return {key: float(f["run"].attrs[key]) for key in ("messages_per_step", "bytes_sent_per_step")}


def test_local_contact_traffic_does_not_grow_with_the_ranks(tool, tmp_path: Path) -> None:
    """Issue 19 item 5, docs/performance.md "Beyond one machine": with local contact a rank sends
    its ghosts and records only to the ranks near it, so from 4 to 8 ranks of the benchmark (each
    rank's plate on its own segment, every plate in contact) the most messages any rank sends per
    step grow only by the rounds of the reductions (four per step: the step's minimum, the
    contact's movement, the records' barrier and the contact's exact sums; one round more each
    from 4 to 8), and the bytes it
    sends stay within 10 % but for the one round more of the exact sums' reduction (a block of
    71 integers of 8 bytes per sum, core/exact_sum.f90: the energy and 3 for the one definition,
    and the penetration). Reference: the replicated scheme (/control contact_gather = "all"),
    whose five allgathers per step add at least 5 x 4 messages per rank from 4 to 8 ranks."""
    sums_round = 8 * (71 * (1 + 3) + 1)
    local = {ranks: _contact_traffic(tool, tmp_path, ranks, None) for ranks in (4, 8)}
    replicated = {ranks: _contact_traffic(tool, tmp_path, ranks, "all") for ranks in (4, 8)}
    assert replicated[8]["messages_per_step"] - replicated[4]["messages_per_step"] >= 20.0
    assert local[8]["messages_per_step"] - local[4]["messages_per_step"] <= 5.0
    assert local[8]["bytes_sent_per_step"] <= 1.1 * local[4]["bytes_sent_per_step"] + sums_round
    assert local[8]["messages_per_step"] < replicated[8]["messages_per_step"] / 2
