"""Idle contact pairs cost almost nothing and change nothing (issue 13, "idle is cheap";
docs/theory.md, contact activity; fortran/src/contact/search/contact_activity.f90).

At activity checks the engine bounds each side of a contact pass by a box and its largest speed;
a pass whose boxes, grown by twice the speed times the cycles to the next check, stay farther
apart than the two thicknesses runs no stage. Skipping is exact: a pass that cannot touch writes
no record, and the bucket sorts fall as without the skip, so the answer is bitwise that of the
same deck with /control contact_gather = "all" (no shortcut: every pass every cycle).

Scenes: two 0.1 m steel plates (6 x 6, 2 mm) facing across z; the upper one flies down at
50 m/s with a sideways drift and friction 0.3. Far apart it never arrives; "meeting" sets the
clearance so that the contact surfaces meet at half the end time.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
from contact_cases import PLATE, STEEL, N, T
from models import interrupted_copy
from paradyn.deck import Control, write_deck
from paradyn.running import launch

SPEED = 50.0          # m/s, the upper plate towards the lower one
END_TIME = 400.0e-6   # s
MEET_CLEARANCE = SPEED * 0.5 * END_TIME   # the contact surfaces meet at half the end time


def _plates(folder: Path, name: str, clearance: float, *, pairs: tuple = ((0, 1),), **control: object) -> Path:
    lower = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, 0.0))
    upper = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.4 * PLATE, -0.5 * PLATE, T + clearance))
    settings = Control(end_time=END_TIME, output_interval=END_TIME / 20, history_interval=END_TIME / 100,
                       **control)
    asm = M.contact_model([M.Body(lower, T), M.Body(upper, T, (3.0, 0.0, -SPEED))], STEEL, settings,
                          pairs=pairs, static_friction=0.3)
    return write_deck(asm.model, folder / name)


def _contact_line(log: Path) -> dict[str, int]:
    lines = [launch.parse_line(line) for line in log.read_text().splitlines()]
    found = [fields for kind, fields in filter(None, lines) if kind == "CONTACT"]
    return {k: int(v) for k, v in found[0].items()}


def _read(results: Path) -> dict:
    with h5py.File(results, "r") as f:
        data = {f"frames/{k}": f["/frames"][k][()] for k in f["/frames"]}
        data.update({f"history/{k}": f["/history"][k][()] for k in f["/history"]})
        data["cycles"] = int(f["/run"].attrs["cycles"])
    return data


def _run(deck: Path, ranks: int = 1, threads: int = 1, tag: str = "") -> dict:
    results = deck.with_name(f"{deck.stem}{tag}_{ranks}x{threads}.h5")
    log = results.with_suffix(".log")
    launch.run_engine(deck, results, ranks, threads, log_path=log)
    data = _read(results)
    data["contact"] = _contact_line(log) if "PARADYN-CONTACT" in log.read_text() else None
    return data


def _assert_same(data: dict, reference: dict, prefixes: tuple[str, ...] = ("frames/", "history/")) -> None:
    keys = [k for k in reference if k.startswith(prefixes)]
    assert keys and sorted(keys) == sorted(k for k in data if k.startswith(prefixes))
    for key in keys:
        assert np.array_equal(data[key], reference[key]), key


def test_a_pair_far_apart_is_idle_and_changes_nothing(tmp_path: Path) -> None:
    """Plates 0.1 m apart (the upper one covers 20 mm in the run): the declared pair is skipped
    every cycle but the first two (the first check needs the velocities of the cycle before it,
    for the accelerations), and the frames and histories are bitwise those of the same scene
    without the pair."""
    with_pair = _run(_plates(tmp_path, "pair.h5", 0.1))
    without = _run(_plates(tmp_path, "none.h5", 0.1, pairs=()))
    assert not np.any(with_pair.pop("history/contact_force"))   # the pair's force, zero while idle
    _assert_same(with_pair, without)
    assert without["contact"] is None
    assert with_pair["contact"]["idle_cycles"] == with_pair["cycles"] + 1 - 2   # cycles 0 and 1 run
    assert with_pair["contact"]["pass_steps"] == 2 * 2 and with_pair["contact"]["candidates"] == 0


@pytest.fixture(scope="module")
def meeting(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("contact_activity")
    return {"near": _plates(folder, "near.h5", MEET_CLEARANCE),
            "all": _plates(folder, "all.h5", MEET_CLEARANCE, contact_gather="all"),
            "near_fixed": _plates(folder, "near_fixed.h5", MEET_CLEARANCE, contact_sort_interval=7.0),
            "all_fixed": _plates(folder, "all_fixed.h5", MEET_CLEARANCE, contact_sort_interval=7.0,
                                 contact_gather="all")}


@pytest.mark.parametrize("sorting", ["automatic", "fixed"])
def test_a_pair_that_meets_later_gives_the_answer_without_the_skip(meeting, sorting) -> None:
    """The plates meet at half the end time: the pair is idle for a good part of the first half
    and then in contact (penetration > 0). Frames and histories are bitwise those of the run
    without shortcuts (contact_gather = "all"), with automatic sorting (a sort once a node has
    moved a tenth of a bucket) and with a sort every 7 cycles."""
    suffix = "" if sorting == "automatic" else "_fixed"
    skipping, reference = _run(meeting["near" + suffix]), _run(meeting["all" + suffix])
    _assert_same(skipping, reference)
    assert reference["history/contact_penetration"].max() > 0.0
    assert reference["contact"]["idle_cycles"] == 0
    idle = skipping["contact"]["idle_cycles"]
    assert 0.2 * skipping["cycles"] < idle < 0.5 * skipping["cycles"]
    assert skipping["contact"]["sorts"] == reference["contact"]["sorts"]


@pytest.mark.mpi
def test_a_pair_that_meets_later_is_bitwise_on_two_ranks_and_two_threads(meeting) -> None:
    """The same meeting plates on 2 ranks x 2 threads: bitwise the frames and contact histories
    of one rank and one thread (the activity check reduces minima, maxima and speeds, exact in
    any order; the element energies are summed per rank, equal to round-off only), and the
    same idle cycles."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    reference, data = _run(meeting["near"]), _run(meeting["near"], 2, 2)
    _assert_same(data, reference, ("frames/", "history/contact_"))
    assert data["contact"]["idle_cycles"] == reference["contact"]["idle_cycles"] > 0


def test_a_pair_brought_together_by_a_ramped_load_gives_the_answer_without_the_skip(tmp_path: Path) -> None:
    """The upper plate starts at rest 5 mm above the lower one and is pushed down by 500 N per
    node, ramped up over 100 us: at the first checks speed and acceleration are nearly zero, and
    the checks must come often enough to see the plate gather speed (the interval at most
    doubles from one check to the next). The plates meet (penetration > 0) and the run is
    bitwise that without the skip."""
    lower = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, 0.0))
    upper = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, T + 5.0e-3))
    push = M.Load(nodes=np.arange(lower.n_nodes, lower.n_nodes + upper.n_nodes), dof=3,
                  values=np.full(upper.n_nodes, -500.0), ramp_time=100.0e-6)
    decks = {}
    for gather in ("near", "all"):
        settings = Control(end_time=END_TIME, output_interval=END_TIME / 20, history_interval=END_TIME / 100,
                           contact_gather=gather)
        asm = M.contact_model([M.Body(lower, T, fixed=True), M.Body(upper, T)], STEEL, settings, loads=[push])
        decks[gather] = write_deck(asm.model, tmp_path / f"{gather}.h5")
    skipping, reference = _run(decks["near"]), _run(decks["all"])
    _assert_same(skipping, reference)
    assert reference["history/contact_penetration"].max() > 0.0
    assert skipping["contact"]["idle_cycles"] > 0.2 * skipping["cycles"]


def test_a_restart_while_idle_is_bitwise(tmp_path: Path) -> None:
    """A checkpoint while the pair is idle (at 220 us; the plates meet at 360 us): the run
    restarted from it checks the pair afresh, wakes it and meets, and reproduces the frames and
    histories of the run that wrote the checkpoint bitwise."""
    deck = _plates(tmp_path, "checkpointed.h5", SPEED * 0.9 * END_TIME, checkpoint_interval=220.0e-6)
    results = tmp_path / "results.h5"
    launch.run_engine(deck, results)
    with h5py.File(tmp_path / "results.checkpoint.h5", "r") as f:
        assert abs(float(f.attrs["time"]) - 220.0e-6) < 5.0e-6
    target = tmp_path / "restart.h5"
    interrupted_copy(results, target)
    shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / "restart.checkpoint.h5")
    launch.run_engine(deck, target, restart=True)
    reference, data = _read(results), _read(target)
    _assert_same(data, reference)
    assert reference["history/contact_penetration"].max() > 0.0
