"""Run the verification problems of the one-point element with the fully integrated element
(``element = "full"``) and print a markdown table (``docs/validation.md``, "Fully integrated shell").

Usage (from the repository root)::

    .venv/bin/python tests/report_full_shell.py [--workdir DIR]

Columns: problem, mesh, the displacement over its reference, whether the relaxation settled
(relative change over the last 20 % of the run), the hourglass energy (zero for this element), the
stored energy over half the loads' work, and the wall-clock seconds of the engine call. The set-ups
are the one-point element's tests' (tests/test_verification.py, tests/test_warping.py).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import models as M
import test_verification as V
import test_warping as W
from paradyn.deck import Control

FULL = {"element": "full"}


def _row(problem: str, mesh: str, ratio: float, settled: float, run, clapeyron: float) -> str:
    h = run.results.history
    return (f"| {problem} | {mesh} | {ratio:.4f} | {settled:.1e} | {h['hourglass_energy'][-1]:.1g} "
            f"| {clapeyron:.4f} | {run.wall_s:.1f} |")


def roof(n: int, directory: Path):
    """The Scordelis-Lo quarter roof of test_verification.roof_runs; (w_B history, run, roof)."""
    r = M.scordelis_lo_quarter(n)
    control = Control(end_time=0.8, output_interval=0.4, history_interval=0.004,
                      mass_damping=V.ROOF_DAMPING, time_step_safety=V.SAFETY)
    model = r.model(control, r.WEIGHT * V.ROOF_LOAD_FACTOR, V.ROOF_DENSITY, ramp_time=0.2, **FULL)
    run = M.run(model, directory)
    w = -run.results.history["tracked_displacement"][:, 0, 2] / V.ROOF_LOAD_FACTOR
    u = run.results.displacement[-1]
    work = 0.5 * np.sum(-r.WEIGHT * V.ROOF_LOAD_FACTOR * r.weights * u[:, 2])
    return w, run, run.results.history["internal_energy"][-1] / work


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=None)
    args = parser.parse_args(argv)
    work = args.workdir or Path(tempfile.mkdtemp(prefix="paradyn-full-"))
    print("| problem | mesh | value / reference | settled | HG (J) | IE / (W/2) | wall s |")
    print("|---|---|---|---|---|---|---|")
    for n in (4, 8, 16):
        w, run, clapeyron = roof(n, work / f"roof{n}")
        print(_row("Scordelis-Lo roof, w_B", f"{n} x {n} quarter", w[-1] / V.ROOF_REFERENCE, V._settled(w), run,
                   clapeyron), flush=True)
    for load in W.TWISTED_BEAM:
        for n_width, n_length in ((2, 12), (4, 24), (8, 48)):
            u, reference, run, _ = W.twisted_beam_run(load, n_width, n_length,
                                                      work / f"beam_{load}_{n_width}x{n_length}", **FULL)
            clapeyron = run.results.history["internal_energy"][-1] / (0.5 * u[-1])
            print(_row(f"twisted beam, {load.replace('_', '-')}", f"{n_width} x {n_length}", u[-1] / reference,
                       W._settled(u), run, clapeyron), flush=True)
    for n in (4, 8, 16):
        u, run, _ = W.hemisphere_run(n, work / f"hemisphere_{n}", **FULL)
        h = run.results.history
        # the four loads F = 2 (scaled) times their displacements, halved
        clapeyron = h["internal_energy"][-1] / (0.5 * W.HEMISPHERE_LOAD * W.HEMISPHERE_LOAD_FACTOR ** 2
                                                * u[-1].sum())
        print(_row("pinched hemisphere", f"{n} x {n} per face", u[-1].mean() / W.HEMISPHERE_REFERENCE,
                   W._settled(u[:, 0]), run, clapeyron), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
