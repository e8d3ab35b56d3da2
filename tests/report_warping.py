"""Run the warped-element problems of ``tests/test_warping.py`` on three meshes each, with the
warping correction and without it, and print a markdown table (``docs/validation.md`` holds it).

Usage (from the repository root)::

    .venv/bin/python tests/report_warping.py [--workdir DIR] [--hourglass-form FORM]

Columns: problem, mesh, correction on/off, the displacement over its reference, whether the
relaxation settled (relative change over the last 20 % of the run), the hourglass energy over the
internal energy, and the wall-clock seconds of the engine call. The set-ups are those of the tests
(``twisted_beam_run``, ``hemisphere_run``); the tests check only the finest mesh with the correction.
``--hourglass-form`` runs every case with that form (``stiffness`` takes the coefficient 0.1);
without it, the default of new decks.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import test_warping as W


def _row(problem: str, mesh: str, on: bool, ratio: float, settled: float, run) -> str:
    h = run.results.history
    hg = h["hourglass_energy"][-1] / h["internal_energy"][-1]
    return (f"| {problem} | {mesh} | {'on' if on else 'off'} | {ratio:.3f} | {settled:.1e} | {hg:.3f} "
            f"| {run.wall_s:.1f} |")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=None)
    parser.add_argument("--hourglass-form", default=None, choices=("physical", "stiffness", "viscous"))
    args = parser.parse_args(argv)
    form = {} if args.hourglass_form is None else {"hourglass_form": args.hourglass_form}
    work = args.workdir or Path(tempfile.mkdtemp(prefix="paradyn-warping-"))
    print("| problem | mesh | correction | value / reference | settled | HG / IE | wall s |")
    print("|---|---|---|---|---|---|---|")
    for load in W.TWISTED_BEAM:
        for n_width, n_length in ((2, 12), (4, 24), (8, 48)):
            for on in (True, False):
                folder = work / f"beam_{load}_{n_width}x{n_length}_{int(on)}"
                u, reference, run, _ = W.twisted_beam_run(load, n_width, n_length, folder,
                                                          warping_correction=on, **form)
                print(_row(f"twisted beam, {load.replace('_', '-')}", f"{n_width} x {n_length}", on,
                           u[-1] / reference, W._settled(u), run), flush=True)
    for n in (4, 8, 16):
        for on in (True, False):
            u, run, _ = W.hemisphere_run(n, work / f"hemisphere_{n}_{int(on)}", warping_correction=on, **form)
            print(_row("pinched hemisphere", f"{n} x {n} per face", on, u[-1].mean() / W.HEMISPHERE_REFERENCE,
                       W._settled(u[:, 0]), run), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
