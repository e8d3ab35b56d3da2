"""What declared but idle effects cost (issue 13): python tools/effect_costs.py [--rounds N] [--threads T] [--out DIR].

Builds the scenes in a temporary folder (or DIR), runs the variants of each comparison in turns,
round after round (so a slow spell of a shared machine slows one round of every variant rather
than all runs of one), and prints median wall times (``/run wall_s`` of the engine) and the
median of the per-round ratios:

(a) cases/two_pipes_apart (the pipes never come near each other) with its contact pair, over the
    same scene without the pair (target: at most 1.03);
(b) cases/two_pipes_meet (the pipes first touch at half the end time): the contact phase
    (``/run phase_contact_s``) of a run stopped at 0.45 ms, just before the touch, as a share of
    its wall time, beside the same with the skipping of idle pairs off (``contact_gather =
    "all"``), and the contact seconds after the touch (the full run less the short one);
(c) cases/two_pipes_meet with a yield stress that is never reached (1e12 Pa, J2 plasticity), over
    the same scene declared elastic (target: at most 1.05).

The runs are one rank with T threads (default 1). Timings on a shared machine are rough.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import statistics
import sys
import tempfile
from pathlib import Path

import h5py
import numpy as np

from paradyn import deck, scene
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
BEFORE_TOUCH = 0.45e-3   # s: two_pipes_meet's pipes touch at 0.5 ms
NEVER_YIELDS = 1.0e12    # Pa


def _model(case: str, *, without_contact: bool = False) -> deck.Model:
    sc = scene.load_scene(ROOT / "cases" / case / "scene.toml")
    if without_contact:
        sc = dataclasses.replace(sc, contacts=[])
    return scene.build_model(sc)


def build_decks(folder: Path) -> dict[str, Path]:
    """Every variant's deck, by name."""
    models = {"apart_pair": _model("two_pipes_apart"),
              "apart_none": _model("two_pipes_apart", without_contact=True)}
    for name, gather, end in (("meet_before", None, BEFORE_TOUCH), ("meet_before_all", "all", BEFORE_TOUCH),
                              ("meet_full", None, None)):
        model = _model("two_pipes_meet")
        model.control.contact_gather = gather
        if end is not None:
            model.control.end_time = end
        models[name] = model
    j2 = _model("two_pipes_meet")
    j2.yield_stress = np.full_like(j2.yield_stress, NEVER_YIELDS)
    elastic = _model("two_pipes_meet")
    elastic.material_model = np.full_like(elastic.material_model, deck.ELASTIC)
    elastic.yield_stress = elastic.tangent_modulus = elastic.hardening_mixing = None
    models.update(j2_unyielded=j2, elastic=elastic)
    return {name: deck.write_deck(model, folder / f"{name}.h5") for name, model in models.items()}


def run_once(deck_path: Path, threads: int) -> dict[str, float]:
    """One engine run: its /run wall and contact seconds, the CPU seconds of the engine process
    (less disturbed than wall time by other work on a shared machine), the largest plastic
    strain and the time of the first penetration."""
    results = deck_path.with_name(deck_path.stem + "_results.h5")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    launch.run_engine(deck_path, results, 1, threads)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    with h5py.File(results, "r") as f:
        run = f["/run"].attrs
        penetration = f["/history/contact_penetration"][()] if "contact_penetration" in f["/history"] else [0.0]
        time = f["/history/time"][()] if "time" in f["/history"] else None
        touch = float(time[np.argmax(np.asarray(penetration) > 0.0)]) if time is not None and np.max(penetration) > 0 \
            else float("nan")
        return {"wall_s": float(run["wall_s"]), "cpu_s": cpu, "contact_s": float(run["phase_contact_s"]),
                "plastic": float(f["/frames/element_plastic_strain"][()].max()), "touch_s": touch}


def median_ratio(times: dict[str, list[dict[str, float]]], top: str, bottom: str, key: str = "wall_s") -> float:
    return statistics.median(a[key] / b[key] for a, b in zip(times[top], times[bottom], strict=True))


def report(times: dict[str, list[dict[str, float]]]) -> None:
    def med(name: str, key: str = "wall_s") -> float:
        return statistics.median(r[key] for r in times[name])

    print("(a) two pipes apart, pair declared / no pair: wall "
          f"{med('apart_pair'):.3f} s / {med('apart_none'):.3f} s, "
          f"median per-round ratio {median_ratio(times, 'apart_pair', 'apart_none'):.3f} (target <= 1.03); CPU "
          f"{med('apart_pair', 'cpu_s'):.3f} s / {med('apart_none', 'cpu_s'):.3f} s, ratio "
          f"{median_ratio(times, 'apart_pair', 'apart_none', 'cpu_s'):.3f}; the pair's contact phase "
          f"{med('apart_pair', 'contact_s'):.4f} s = {100 * med('apart_pair', 'contact_s') / med('apart_pair'):.2f} % "
          "of its wall time")
    before, before_all = med("meet_before", "contact_s"), med("meet_before_all", "contact_s")
    full = med("meet_full", "contact_s")
    print(f"(b) two pipes meeting at {times['meet_full'][0]['touch_s'] * 1e3:.3f} ms (first penetration):")
    print(f"    to {BEFORE_TOUCH * 1e3:.2f} ms: contact {before:.4f} s of {med('meet_before'):.3f} s wall "
          f"({100 * before / med('meet_before'):.2f} %); without the skip {before_all:.4f} s of "
          f"{med('meet_before_all'):.3f} s ({100 * before_all / med('meet_before_all'):.2f} %)")
    print(f"    after {BEFORE_TOUCH * 1e3:.2f} ms (full run less the short one): contact {full - before:.4f} s "
          f"(full run {full:.4f} s of {med('meet_full'):.3f} s wall)")
    plastic = max(r["plastic"] for r in times["j2_unyielded"])
    print("(c) two pipes meeting, J2 never yielding / elastic: wall "
          f"{med('j2_unyielded'):.3f} s / {med('elastic'):.3f} s, "
          f"median per-round ratio {median_ratio(times, 'j2_unyielded', 'elastic'):.3f} (target <= 1.05); CPU "
          f"{med('j2_unyielded', 'cpu_s'):.3f} s / {med('elastic', 'cpu_s'):.3f} s, ratio "
          f"{median_ratio(times, 'j2_unyielded', 'elastic', 'cpu_s'):.3f} (largest plastic strain {plastic:g})")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--out", type=Path, default=None, help="keep the decks and results here")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as temporary:
        folder = args.out or Path(temporary)
        folder.mkdir(parents=True, exist_ok=True)
        decks = build_decks(folder)
        times: dict[str, list[dict[str, float]]] = {name: [] for name in decks}
        for k in range(args.rounds):
            names = list(decks) if k % 2 == 0 else list(reversed(decks))
            for name in names:
                times[name].append(run_once(decks[name], args.threads))
        report(times)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
