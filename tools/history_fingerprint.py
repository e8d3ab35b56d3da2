"""Bitwise fingerprints of the pipe-whip histories: python tools/history_fingerprint.py [OUT] [CASES...].

Meshes every ``cases/pipe_whip*`` scene (or the ones named), runs the engine on one rank with two
threads (``paradyn.run`` without post-processing), and prints one SHA-256 per case over every
``/history`` dataset of its ``results.h5`` (raw bytes, in name order) but the time step's own
records (``dt``, ``dt_stable``, ``dt_element``: STEP_NAMES, added with the step that follows the mesh)
and the per-part and per-contact records, the reaction, the eroded element count and the failed welds (LATER_NAMES,
added in issues 18, 33, 34 and 32), so that the digests compare with those of files written before them;
a second digest covers the step's records. A
change that must keep the answers (a restructure, a speed-up) keeps every line of this output:
run it before and after and compare with ``diff``. A change that moves the last bits compares the
two sets of runs record by record: ``python tools/history_fingerprint.py --compare OLD NEW`` prints,
for each case, the records' largest differences over their largest values.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

import h5py
import numpy as np

import paradyn

ROOT = Path(__file__).resolve().parents[1]
STEP_NAMES = ("dt", "dt_element", "dt_stable")
LATER_NAMES = ("contact_force", "part_hourglass_energy", "part_internal_energy", "part_kinetic_energy",
               "part_plastic_work", "reaction_force", "reaction_moment", "eroded_elements", "failed_welds",
               "failed_ties")


def history_digest(results: Path, step: bool = False) -> str:
    """SHA-256 of the history datasets, without the step's records (or of those alone, ``step``)."""
    digest = hashlib.sha256()
    with h5py.File(results, "r") as f:
        for name in sorted(f["history"]):
            if (name in STEP_NAMES) != step or name in LATER_NAMES:
                continue
            digest.update(name.encode())
            digest.update(f["history"][name][()].tobytes())
    return digest.hexdigest()


def compare(old: Path, new: Path, shown: int = 4) -> None:
    """Each case's history records, largest difference over largest value, the largest first."""
    for case in sorted(p.name for p in old.iterdir() if (p / "results.h5").exists()):
        with h5py.File(old / case / "results.h5", "r") as fa, h5py.File(new / case / "results.h5", "r") as fb:
            spread = {}
            for name in sorted(fa["history"]):
                a, b = fa["history"][name][()], fb["history"][name][()]
                if a.shape != b.shape:
                    spread[name] = float("inf")
                    continue
                spread[name] = float(np.max(np.abs(a - b), initial=0.0) / (np.max(np.abs(a), initial=0.0) or 1.0))
        worst = sorted(spread.items(), key=lambda item: -item[1])[:shown]
        print(f"{case:24s} " + ", ".join(f"{name} {value:.1e}" for name, value in worst), flush=True)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", type=Path, default=Path("runs/fingerprint"),
                        help="folder for the runs (default runs/fingerprint)")
    parser.add_argument("cases", nargs="*", help="case names (default: every cases/pipe_whip*)")
    parser.add_argument("--compare", nargs=2, type=Path, metavar=("OLD", "NEW"),
                        help="compare two folders of earlier runs record by record instead of running")
    args = parser.parse_args(argv)
    if args.compare:
        compare(*args.compare)
        return 0
    out = args.out
    names = args.cases or sorted(p.parent.name for p in (ROOT / "cases").glob("pipe_whip*/scene.toml"))
    for name in names:
        folder = out / name
        paradyn.run(ROOT / "cases" / name / "scene.toml", folder, ranks=1, threads=2, post=False)
        results = folder / "results.h5"
        print(f"{name:24s} {history_digest(results)}  step {history_digest(results, step=True)[:16]}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
