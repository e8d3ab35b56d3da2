"""Contact on several ranks and threads, through the whole stack: decks built in Python
(``tests/models.py``, ``contact_model``), ``paradyn-engine`` under MPI, results file.

The runs are compared bitwise with one rank and one thread, and the engine's per-rank contact
counts with the paper's block decomposition. Steel, plates and helpers are in
tests/contact_cases.py; the contact time scale of thin shells in tests/test_contact_impact.py.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
from contact_cases import PLATE, STEEL, H, N, T, _plate_pair
from paradyn.deck import Control, write_deck
from paradyn.running import launch

# ----------------------------------------------------------------------------------------------
# Decomposition independence


LAYOUTS = [(2, 1), (4, 1), (1, 2)]


@pytest.fixture(scope="module")
def layouts(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[int, int], dict[str, np.ndarray]]:
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    folder = tmp_path_factory.mktemp("contact_layouts")
    a_mesh, b_mesh = _plate_pair(clearance=1.0e-4, shift=0.25 * H)
    control = Control(end_time=40.0e-6, output_interval=2.0e-6)
    asm = M.contact_model([M.Body(a_mesh, T), M.Body(b_mesh, T, (2.0, 1.0, -5.0))], STEEL, control,
                          static_friction=0.3)
    deck_path = write_deck(asm.model, folder / "deck.h5")
    out = {}
    for ranks, threads in [(1, 1), *LAYOUTS]:
        results = folder / f"results_{ranks}x{threads}.h5"
        launch.run_engine(deck_path, results, ranks, threads,
                          log_path=folder / f"engine_{ranks}x{threads}.log")
        with h5py.File(results, "r") as f:
            out[(ranks, threads)] = {
                "displacement": f["/frames/displacement"][()], "velocity": f["/frames/velocity"][()],
                "contact_energy": f["/history/contact_energy"][()],
                "contact_penetration": f["/history/contact_penetration"][()],
                "contact_force": f["/history/contact_force"][()],
                "layout": (int(f["/run"].attrs["ranks"]), int(f["/run"].attrs["threads"])),
            }
    return out


@pytest.mark.mpi
@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda layout: f"{layout[0]}x{layout[1]}")
def test_contact_is_bitwise_independent_of_the_decomposition(layouts, layout):
    """docs/theory.md (parallel contact): each rank sums the records that touch its nodes in pass
    and slave order (local contact), so the frames of an
    oblique plate impact with friction (offset meshes, mu = 0.3, default step, 40 us, frames
    every 2 us) are bitwise equal on 1 rank x 1 thread, 2 and 4 ranks and 1 rank x 2 threads,
    and so are the contact energy, penetration and definition force histories (exact sums of
    every rank's terms, core/exact_sum: the same bits in any order)."""
    reference, data = layouts[(1, 1)], layouts[layout]
    assert data["layout"] == layout
    for key in ("displacement", "velocity", "contact_energy", "contact_penetration", "contact_force"):
        assert data[key].shape == reference[key].shape, key
        assert np.array_equal(data[key], reference[key]), key
    assert reference["contact_penetration"].max() > 0.0


def _contact_log(path: Path) -> list[dict[str, int]]:
    """The engine's PARADYN-CONTACT lines (one per rank): sorts, pass_steps, candidates (all
    ranks) and local_searches (this rank's blocks), summed over the run."""
    lines = [launch.parse_line(line) for line in path.read_text().splitlines()]
    return sorted(({k: int(v) for k, v in fields.items()} for kind, fields in filter(None, lines)
                   if kind == "CONTACT"), key=lambda f: f["rank"])


SLIDING_LAYOUTS = [(1, 1, "all"), (2, 1, "all"), (2, 1, "subset"), (3, 1, "subset"), (4, 1, "subset"),
                   (3, 1, "all"), (1, 2, "subset")]


@pytest.fixture(scope="module")
def sliding(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[int, int, str], dict]:
    """A 0.05 m plate (4 x 4) sliding at 100 m/s along x over a 0.1 m plate (6 x 6) and off its
    edge, pressed onto it at 3 m/s from 0.1 mm, mu = 0.3, 300 us at the default step: it moves
    a tenth of a bucket every 18 us, so the buckets are sorted again about 16 times and the set
    of nodes near contact changes as it goes."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    folder = tmp_path_factory.mktemp("contact_sliding")
    base = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, 0.0))
    slider = M.flat_plate((0.05, 0.05), (4, 4), origin=(-0.01, -0.025, T + 1.0e-4))
    decks = {}
    for gather, contact_gather in (("subset", None), ("all", "all")):   # /control contact_gather
        control = Control(end_time=300.0e-6, output_interval=10.0e-6, contact_gather=contact_gather)
        asm = M.contact_model([M.Body(base, T), M.Body(slider, T, (100.0, 0.0, -3.0))], STEEL, control,
                              static_friction=0.3)
        decks[gather] = write_deck(asm.model, folder / f"deck_{gather}.h5")
    out = {}
    for ranks, threads, gather in [(1, 1, "subset"), *SLIDING_LAYOUTS]:
        name = f"{ranks}x{threads}_{gather}"
        launch.run_engine(decks[gather], folder / f"results_{name}.h5", ranks, threads,
                          log_path=folder / f"engine_{name}.log")
        with h5py.File(folder / f"results_{name}.h5", "r") as f:
            out[(ranks, threads, gather)] = {
                "displacement": f["/frames/displacement"][()], "velocity": f["/frames/velocity"][()],
                "contact_energy": f["/history/contact_energy"][()],
                "contact_penetration": f["/history/contact_penetration"][()],
                "contact_force": f["/history/contact_force"][()],
                "log": _contact_log(folder / f"engine_{name}.log"),
            }
    return out


@pytest.mark.mpi
@pytest.mark.parametrize("layout", SLIDING_LAYOUTS, ids=lambda layout: f"{layout[0]}x{layout[1]}_{layout[2]}")
def test_gathering_only_the_nodes_near_contact_changes_nothing(sliding, layout):
    """docs/theory.md (parallel contact): on one rank, between sorts only the contact nodes that
    can come into contact before the next sort are read; on several, each rank holds only the
    master segments of other ranks near its own slaves (ghosts, chosen anew at each sort) and
    the records go only to the ranks that hold their nodes. Reference: 1 rank x 1
    thread; the replicated scheme (/control contact_gather = "all", every contact node on every
    rank) on 1, 2 and 3 ranks. A ghost missing would be read at a stale position and a record
    missing would lose a force, so the frames, contact energy, penetration and definition force of the sliding
    plate (many sorts, the slider crossing from one rank's elements onto another's, its ghosts
    coming and going) must be bitwise equal on 1, 2, 3 and 4 ranks and 2 threads."""
    reference, data = sliding[(1, 1, "subset")], sliding[layout]
    for key in ("displacement", "velocity", "contact_energy", "contact_penetration", "contact_force"):
        assert np.array_equal(data[key], reference[key]), key
    assert reference["contact_penetration"].max() > 0.0
    assert reference["log"][0]["sorts"] >= 10


@pytest.mark.mpi
@pytest.mark.parametrize("ranks", [2, 3, 4])
def test_each_rank_searches_the_slaves_it_owns(sliding, ranks):
    """Local contact (docs/theory.md, parallel contact): each rank finds the candidates of the
    slaves it owns and searches them itself, so over the ranks the candidates add up to those of
    one rank (each found once) and every rank searches what it found. The slider starts over
    the elements of one rank and crosses onto another's (the paper's blocks by element number),
    so the candidates of more than one rank must add up."""
    log = sliding[(ranks, 1, "subset")]["log"]
    one = sliding[(1, 1, "subset")]["log"][0]
    assert [f["rank"] for f in log] == list(range(ranks))
    assert all(f["local_searches"] == f["candidates"] for f in log)
    assert sum(f["candidates"] for f in log) == one["candidates"] > 0
    assert sum(f["candidates"] > 0 for f in log) >= 2
    assert all(f["sorts"] == one["sorts"] and f["pass_steps"] == one["pass_steps"] for f in log)


@pytest.mark.mpi
def test_local_contact_holds_the_domains_nodes_and_the_ghosts(sliding):
    """docs/theory.md ("Dividing the contact state", held slots): the contact state's per-node
    arrays hold a rank's domain's contact nodes and its ghosts, renumbered at each refresh, every
    contact node on one rank and in the replicated scheme. Reference: the engine's log, the most
    nodes each rank held at once (held) and the model's contact nodes (74: 7 x 7 and 5 x 5). On
    3 and 4 ranks the ranks whose domains lie away from the slider hold fewer than all (the
    answers stay bitwise those of one rank: test_gathering_only_the_nodes_near_contact_changes_nothing)."""
    one = sliding[(1, 1, "subset")]["log"][0]
    assert one["held"] == one["contact_nodes"] == 7 * 7 + 5 * 5
    assert all(f["held"] == f["contact_nodes"] for f in sliding[(2, 1, "all")]["log"])
    for ranks in (3, 4):
        held = [f["held"] for f in sliding[(ranks, 1, "subset")]["log"]]
        assert all(0 < h <= one["contact_nodes"] for h in held)
        assert min(held) < one["contact_nodes"], held


@pytest.mark.mpi
@pytest.mark.parametrize("ranks", [2, 3])
def test_candidate_blocks_are_equal_on_every_rank(sliding, ranks):
    """The paper's section 5, kept by the replicated scheme (/control contact_gather = "all"): the
    candidates of each pass are split into one block per rank whose sizes differ by at most one.
    Reference: the engine's per-rank counts over the run (log):
    every candidate is searched by exactly one rank (the local searches add up to the candidates)
    and no rank searched more than one candidate per pass and step above another."""
    log = sliding[(ranks, 1, "all")]["log"]
    assert [f["rank"] for f in log] == list(range(ranks))
    total, steps = log[0]["candidates"], log[0]["pass_steps"]
    assert all(f["candidates"] == total and f["pass_steps"] == steps for f in log)
    searches = [f["local_searches"] for f in log]
    assert sum(searches) == total > ranks * steps
    assert max(searches) - min(searches) <= steps


@pytest.mark.mpi
def test_local_contact_restarts_bitwise(tmp_path: Path):
    """A checkpoint of the sliding plate written on 3 ranks while it touches the other (40 us;
    contact from about 34 to 44 us): local contact keeps the last step's forces, which nodes
    carried one and the positions of the last sort on the ranks that hold them, and each rank
    writes the rows of the contact nodes it owns. The run continues bitwise on 3 ranks and on 2:
    frames, contact energy, penetration and definition force equal those of 1 rank x 1 thread
    uninterrupted."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    base = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, 0.0))
    slider = M.flat_plate((0.05, 0.05), (4, 4), origin=(-0.01, -0.025, T + 1.0e-4))
    control = Control(end_time=60.0e-6, output_interval=5.0e-6, checkpoint_interval=40.0e-6)
    asm = M.contact_model([M.Body(base, T), M.Body(slider, T, (100.0, 0.0, -3.0))], STEEL, control,
                          static_friction=0.3)
    deck_path = write_deck(asm.model, tmp_path / "deck.h5")
    launch.run_engine(deck_path, tmp_path / "reference.h5", 1, 1)
    launch.run_engine(deck_path, tmp_path / "results.h5", 3, 1)
    with h5py.File(tmp_path / "results.checkpoint.h5", "r") as f:   # rows (node, 7): 1 if it carried a force
        assert 0 < f.attrs["time"] < 60.0e-6 and f["contact"][()][:, 6].max() > 0 and f.attrs["contact_energy"] > 0
    names = ("/frames/displacement", "/frames/velocity", "/history/contact_energy", "/history/contact_penetration",
             "/history/contact_force")
    with h5py.File(tmp_path / "reference.h5", "r") as f:
        reference = {name: f[name][()] for name in names}
    assert reference["/history/contact_penetration"].max() > 0
    for ranks in (3, 2):
        target = tmp_path / f"restart_{ranks}.h5"
        shutil.copy(tmp_path / "results.h5", target)
        shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / f"restart_{ranks}.checkpoint.h5")
        with h5py.File(target, "r+") as f:
            f.attrs["complete"] = np.int32(0)
        launch.run_engine(deck_path, target, ranks, 1, restart=True)
        with h5py.File(target, "r") as f:
            assert f.attrs["complete"] == 1
            for name in names:
                assert np.array_equal(f[name][()], reference[name]), (ranks, name)


@pytest.mark.mpi
def test_local_contact_with_a_fixed_sort_interval_and_rcb_is_bitwise(tmp_path: Path):
    """With a fixed sort interval local contact also takes new ghosts between sorts, once a node has
    moved a tenth of the smallest bucket since the last refresh. Here a slider crosses a clamped
    0.6 m strip at 300 m/s, held onto it by a body load (4e5 m/s^2, so it bounces along it), and
    the buckets are sorted only every 200 steps, in which it moves 12 cm, five elements; recursive
    coordinate bisection cuts the strip along its length. Without those refreshes 3 and 5 ranks
    lose masters and differ (seen); with them the frames, contact energy and penetration are
    bitwise those of one rank on 2, 3 and 5 ranks."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    strip = M.flat_plate((0.6, 0.1), (36, 6), origin=(-0.3, -0.05, 0.0))
    slider = M.flat_plate((0.05, 0.05), (4, 4), origin=(-0.28, -0.025, T + 1.0e-4))
    control = Control(end_time=500.0e-6, output_interval=10.0e-6, partition="rcb", contact_sort_interval=200,
                      gravity_z=-4.0e5)
    asm = M.contact_model([M.Body(strip, T, fixed=True), M.Body(slider, T, (300.0, 0.0, -3.0))], STEEL, control,
                          static_friction=0.3)
    deck_path = write_deck(asm.model, tmp_path / "deck.h5")
    names = ("/frames/displacement", "/frames/velocity", "/history/contact_energy", "/history/contact_penetration")
    runs = {}
    for ranks in (1, 2, 3, 5):
        launch.run_engine(deck_path, tmp_path / f"results_{ranks}.h5", ranks, 1)
        with h5py.File(tmp_path / f"results_{ranks}.h5", "r") as f:
            runs[ranks] = {name: f[name][()] for name in names}
    penetration = runs[1]["/history/contact_penetration"]
    assert (penetration > 0).mean() > 0.5   # in contact most of the run
    for ranks in (2, 3, 5):
        for name in names:
            assert np.array_equal(runs[ranks][name], runs[1][name]), (ranks, name)
