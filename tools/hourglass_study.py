"""What the hourglass form does to hard impacts (issue 14): python tools/hourglass_study.py [--out DIR] [--cases A,B].

Runs each case below with the paper's element (stiffness form 0.1, no warping correction) and,
with the warping correction, the stiffness form at coefficients 0.1 and 0.01 and the physical
form (docs/theory.md, Hourglass control), one rank and two threads, and prints a markdown table:
the peak hourglass energy over the peak internal energy (the ``summary.json`` indicator
``peak_hourglass_over_internal``), and how far each tracked point's final vertical displacement
moves from the stiffness form at 0.1 with the correction (largest difference over the points,
relative to the largest displacement); and the tracked points' final vertical displacements
(mm). The cases are the paper's, some driven harder:

- ``case1``: cases/pipe_whip as it is (2 m/s, 2.5 ms);
- ``case1_100``: the same geometry with the upper pipe at 100 m/s, 5 ms;
- ``case1_thin``: walls of 0.3 mm, 20 m/s, 2.5 ms (t/R = 1/267);
- ``fig3``: cases/pipe_whip_fig3 (free pipes, 20 m/s, 60 ms);
- ``scaling``: cases/pipe_whip_scaling (40 x 80 per pipe, 1.7 ms); ``scaling_fine`` its 80 x 160 mesh
  (not in the default list: about a minute a run).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import h5py
import numpy as np

from paradyn import deck, scene
from paradyn._schema import ENUMS
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
# (hourglass form, coefficient, warping correction); "paper" is the paper's element, the other three the
# element of new scenes (warping correction on) with each hourglass form
FORMS = {"paper": ("stiffness", 0.1, False), "stiffness 0.1": ("stiffness", 0.1, True),
         "stiffness 0.01": ("stiffness", 0.01, True), "physical": ("physical", 0.1, True)}


def _case(name: str) -> deck.Model:
    base = {"case1": "pipe_whip", "case1_100": "pipe_whip", "case1_thin": "pipe_whip",
            "fig3": "pipe_whip_fig3", "scaling": "pipe_whip_scaling", "scaling_fine": "pipe_whip_scaling_fine"}[name]
    model = scene.build_model(scene.load_scene(ROOT / "cases" / base / "scene.toml"))
    if name == "case1_100":
        model.initial_velocity = 50.0 * model.initial_velocity
        model.control.end_time = 5.0e-3
        model.control.output_interval = 5.0e-4
    elif name == "case1_thin":
        model.initial_velocity = 10.0 * model.initial_velocity
        model.thickness = np.full_like(model.thickness, 0.3e-3)
    return model


def run_case(name: str, form: str, folder: Path) -> dict[str, np.ndarray | float]:
    model = _case(name)
    kind, coefficient, warping = FORMS[form]
    model.hourglass_form = np.full(len(model.thickness), ENUMS["hourglass_form"][kind], dtype=np.int32)
    model.hourglass_coefficient = np.full(len(model.thickness), coefficient)
    model.warping_correction = np.full(len(model.thickness), int(warping), dtype=np.int32)
    stem = f"{name}_{kind}_{coefficient}_{int(warping)}"
    deck_path = deck.write_deck(model, folder / f"{stem}.h5")
    results = folder / f"{stem}_results.h5"
    launch.run_engine(deck_path, results, 1, 2)
    with h5py.File(results, "r") as f:
        h = f["/history"]
        share = float(np.max(h["hourglass_energy"][()]) / np.max(h["internal_energy"][()]))
        final = h["tracked_displacement"][-1, :, 2]
        wall = float(f["/run"].attrs["wall_s"])
    return {"share": share, "final": final, "wall": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--cases", default="case1,case1_100,case1_thin,fig3,scaling")
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="hourglass_study_"))
    folder.mkdir(parents=True, exist_ok=True)
    print("| case | " + " | ".join(f"peak HG/IE, {f}" for f in FORMS) + " | tracked points moved, 0.01 | "
          "tracked points moved, physical |")
    print("|---|" + "---|" * (len(FORMS) + 2))
    finals = []
    for name in args.cases.split(","):
        runs = {form: run_case(name, form, folder) for form in FORMS}
        base = runs["stiffness 0.1"]["final"]
        scale = np.max(np.abs(base))
        moved = [np.max(np.abs(runs[f]["final"] - base)) / scale for f in ("stiffness 0.01", "physical")]
        print(f"| {name} | " + " | ".join(f"{runs[f]['share']:.3f}" for f in FORMS)
              + f" | {moved[0]:.3f} | {moved[1]:.3f} |", flush=True)
        finals.append(f"{name}: " + "; ".join(f"{f} " + " ".join(f"{-1e3 * z:.2f}" for z in runs[f]["final"])
                                               for f in FORMS))
    print("\nfinal vertical displacements of the tracked points (mm, downward positive):")
    print("\n".join(finals))


if __name__ == "__main__":
    main()
