"""Run the stretched plate and strip of ``tests/test_thickness_output.py`` for the one-point, fully
integrated and triangle elements and print a markdown table of how far each element's thickness
strain ln(t / t0) is from the reference (docs/theory.md, "Shell thickness", holds it).

Usage (from the repository root)::

    .venv/bin/python tests/report_thickness.py [--workdir DIR]

Columns: case, element, the reference (-nu sigma / E for the elastic plate, sigma = E ln(1 + u/L);
-eps_p / 2 - nu sigma / E for the plastic strip, from each element's own eps_p and sigma), the mean
ln(t / t0) over the elements, the largest |ln(t / t0) / reference - 1|, and the engine's cycles.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import test_thickness_output as T


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=None, help="keep the runs here (default: a temporary folder)")
    args = parser.parse_args()
    work = args.workdir or Path(tempfile.mkdtemp(prefix="thickness-"))
    print("| case | element | reference eps_z | mean ln(t/t0) | largest relative error | cycles |")
    print("|---|---|---|---|---|---|")
    for element in T.ELEMENTS:
        run, t0, sigma = T._elastic_plate(element, work / f"elastic_{element}")
        frame = run.results.frame_arrays(-1)
        reference = np.full(run.results.n_elements, -T.STEEL.poisson * sigma / T.STEEL.young)
        _row("elastic plate, strain 1e-3", element, reference, np.log(frame.thickness / t0), run.cycles)
    for element in T.ELEMENTS:
        run, t0 = T._plastic_strip(element, work / f"plastic_{element}")
        frame = run.results.frame_arrays(-1)
        sigma, _ = T._principal(frame.membrane_stress)
        reference = -0.5 * frame.plastic_strain - T.STEEL.poisson * sigma / T.STEEL.young
        _row(f"J2 strip, eps_p {frame.plastic_strain.mean():.3f}", element, reference,
             np.log(frame.thickness / t0), run.cycles)


def _row(case: str, element: str, reference: np.ndarray, measured: np.ndarray, cycles: int) -> None:
    error = np.abs(measured / reference - 1.0).max()
    print(f"| {case} | {element} | {reference.mean():.5e} | {measured.mean():.5e} | {error:.1e} | {cycles} |")


if __name__ == "__main__":
    main()
