"""Precision as a choice (issue 19, item 4; docs/theory.md, "Precision").

The mixed engine (paradyn-engine-mixed) computes the element kernel, the material return and the
element state in single precision; positions, velocities, the nodal sums, energies and histories
stay double. Its pipe whip (cases/pipe_whip, 2500 steps) must agree with the double engine's
within a tolerance derived from single precision, keep the energy balanced, and say which engine
ran; positions in single precision would not pass the same tolerance; a wrong precision is refused.

The tolerance on the tracked displacements, relative to their largest value:
``TOLERANCE = U * G * sqrt(N)`` with U = 2**-24 (6.0e-8, single precision's unit roundoff),
G = 10 (the chain of about ten rounded operations from a node's position to its force; each
rounding is at most U relative) and sqrt(N), N = 2500 steps, for rounding errors of independent
sign accumulated by the time integration (a random walk: their sum grows as sqrt(N), not N).
This gives 3.0e-5. docs/performance.md, "Precision", has what the engines measured.
"""

from __future__ import annotations

import math
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn import cli, deck, scene
from paradyn.results import reports
from paradyn.running import launch
from paradyn.studies.design import KNOBS, apply, base_values

ROOT = Path(__file__).resolve().parents[1]
PIPE_WHIP = ROOT / "cases" / "pipe_whip" / "scene.toml"
U = 2.0**-24          # single precision's unit roundoff
GROWTH = 10.0         # rounded operations from a node's position to its force
STEPS = 2500          # the pipe whip: 2.5 ms at 1 us
TOLERANCE = U * GROWTH * math.sqrt(STEPS)


def _mixed_scene(path: Path) -> Path:
    """cases/pipe_whip with [run] precision = "mixed", written to ``path``."""
    text = PIPE_WHIP.read_text().replace("[run]\n", '[run]\nprecision = "mixed"\n', 1)
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def pipe_whips(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The pipe whip run by each engine (1 rank, 2 threads): precision -> results.h5."""
    folder = tmp_path_factory.mktemp("precision")
    runs = {}
    for precision, source in (("double", PIPE_WHIP), ("mixed", _mixed_scene(folder / "mixed.toml"))):
        paradyn.run(source, folder / precision, ranks=1, threads=2, post=False)
        runs[precision] = folder / precision / "results.h5"
    return runs


def _history(path: Path, name: str) -> np.ndarray:
    with h5py.File(path, "r") as f:
        return f["history"][name][()]


def test_the_tolerance_is_what_the_docstring_derives() -> None:
    assert pytest.approx(3.0e-5, rel=0.01) == TOLERANCE


def test_each_engine_records_its_precision(pipe_whips: dict[str, Path]) -> None:
    for precision, path in pipe_whips.items():
        with h5py.File(path, "r") as f:
            assert f["run"].attrs["precision"] == precision
        start = [line for line in (path.parent / "engine.log").read_text().splitlines() if "PARADYN-START" in line]
        assert start and start[0].endswith(f" precision={precision}")
        summary = reports.write_summary(paradyn.read(path, deck=path.parent / "deck.h5"), path.parent / "summary.json")
        assert summary["precision"] == precision


def test_mixed_pipe_whip_agrees_with_double_within_the_tolerance(pipe_whips: dict[str, Path]) -> None:
    """At the end, and at every record on the way: after n steps within U G sqrt(n)."""
    double = _history(pipe_whips["double"], "tracked_displacement")
    mixed = _history(pipe_whips["mixed"], "tracked_displacement")
    assert double.shape == mixed.shape and np.isfinite(mixed).all()
    scale = np.abs(double).max()
    difference = np.abs(mixed - double).max() / scale
    assert 0 < difference <= TOLERANCE   # not bitwise the double engine, and within the tolerance
    steps = np.maximum(np.rint(_history(pipe_whips["double"], "time") / 1e-6), 1.0)
    per_record = np.abs(mixed - double).reshape(len(steps), -1).max(axis=1) / scale
    assert (per_record <= U * GROWTH * np.sqrt(steps)).all()
    for name in ("internal_energy", "kinetic_energy"):
        a, b = _history(pipe_whips["double"], name), _history(pipe_whips["mixed"], name)
        assert np.abs(b - a).max() <= TOLERANCE * np.abs(a).max()


def test_mixed_pipe_whip_keeps_the_energy_balanced(pipe_whips: dict[str, Path]) -> None:
    """The balance error of docs/outputs.md (reports.energy_report: the change of kinetic +
    internal + hourglass + contact - external work over the largest energy): the mixed engine's
    within the tolerance of the double engine's."""
    errors = {precision: reports.energy_report(paradyn.read(path, deck=path.parent / "deck.h5"))["balance_error"]
              for precision, path in pipe_whips.items()}
    assert abs(errors["mixed"] - errors["double"]) <= TOLERANCE
    assert errors["mixed"] < 1e-6


def test_positions_in_single_precision_would_fail_the_tolerance(pipe_whips: dict[str, Path]) -> None:
    """The wrong design: the positions themselves in single. Integrating the tracked nodes' own
    velocities (the double run's history, held over each record's 10 steps) from their initial
    positions, x += dt v, rounded to single every step, drifts from the same sum in double by far
    more than the tolerance: a step moves a node by 2e-6 m, and single precision resolves 6e-8
    of its 0.1 to 2 m coordinate. The mixed engine keeps positions in double and passes."""
    with h5py.File(pipe_whips["double"], "r") as f:
        velocity = f["history/tracked_velocity"][()]          # (records, tracked, 3)
        displacement = f["history/tracked_displacement"][()]
        times = f["history/time"][()]
        model = deck.read_deck(pipe_whips["double"].parent / "deck.h5")
    start = model.coordinates[np.asarray(model.tracked_nodes)]   # (tracked, 3)
    steps = round((times[1] - times[0]) / 1e-6)
    x64, x32 = start.astype(np.float64), start.astype(np.float32)
    for v in velocity[:-1]:
        for _ in range(steps):
            x64 = x64 + 1e-6 * v
            x32 = (x32 + np.float32(1e-6) * v.astype(np.float32)).astype(np.float32)
    drift = np.abs(x32.astype(np.float64) - x64).max() / np.abs(displacement).max()
    assert drift > 5 * TOLERANCE   # 3.4e-4 measured: 11 times the tolerance


def test_study_knob_precision_sets_the_scene() -> None:
    sc = scene.load_scene(PIPE_WHIP)
    assert base_values(sc)["precision"] == "double"
    assert apply(sc, (("precision", "mixed"),)).run.precision == "mixed"
    assert apply(sc, (("precision", "double"),)).run.precision is None   # the base deck, bitwise
    assert KNOBS["precision"].check("quad") == "must be one of double, mixed"


def test_a_bad_precision_is_refused_with_status_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "quad.toml"
    bad.write_text(PIPE_WHIP.read_text().replace("[run]\n", '[run]\nprecision = "quad"\n', 1))
    out = tmp_path / "out"
    assert cli.main([str(bad), "-o", str(out), "--quiet"]) == 2
    message = capsys.readouterr().err
    assert "'precision' = 'quad' in [run] is not one of: double, mixed" in message
    assert not (out / "results.h5").exists()


def test_the_double_engine_refuses_a_mixed_deck(tmp_path: Path) -> None:
    model = scene.build_model(scene.load_scene(_mixed_scene(tmp_path / "mixed.toml")))
    path = deck.write_deck(model, tmp_path / "deck.h5")
    done = subprocess.run([str(launch.engine_path("double")), str(path), str(tmp_path / "results.h5")],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 2
    assert 'precision = "mixed" but this engine computes in double precision; run paradyn-engine-mixed' in done.stderr
    assert not (tmp_path / "results.h5").exists()


def test_the_mixed_kernel_benchmark_runs_in_single(tmp_path: Path) -> None:
    bench = launch.engine_path("mixed").with_name("paradyn-kernel-benchmark-mixed")
    done = subprocess.run([str(bench), "512", "30"], capture_output=True, text=True, check=True)
    assert "element kernel in single precision" in done.stdout
    rates = [float(line.split(":")[1].split()[0]) for line in done.stdout.splitlines() if "us per" in line]
    # 4 quadrilateral, 2 fully integrated and 4 triangle lines, 2 piecewise_linear; -1: a NaN or an
    # inverted element; -2: never yielded
    assert len(rates) == 12 and min(rates) > 0
    updates = [float(x) for x in re.findall(r"(-?[\d.]+) ns per point update", done.stdout)]
    assert len(updates) == 5 and min(updates) > 0   # the stress update alone; -1: a point never yielded


def test_the_mixed_engine_is_bitwise_independent_of_the_threads(pipe_whips: dict[str, Path], tmp_path: Path) -> None:
    """Single precision keeps the engine's rule: an element's arithmetic does not depend on the
    group or thread that computes it (no FMA contraction in the kernel), so 1 and 2 threads agree."""
    paradyn.run(_mixed_scene(tmp_path / "mixed.toml"), tmp_path / "one", ranks=1, threads=1, post=False)
    for name in ("tracked_displacement", "internal_energy", "contact_force"):
        assert np.array_equal(_history(tmp_path / "one" / "results.h5", name), _history(pipe_whips["mixed"], name))
