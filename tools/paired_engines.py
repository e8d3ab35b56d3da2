"""Paired timings of two engine builds on one deck: python tools/paired_engines.py OLD NEW DECK ROUNDS LAYOUT...

OLD and NEW are paradyn-engine binaries (for example one built from an earlier commit with
``cmake -S fortran -B /tmp/old``); LAYOUT is RANKSxTHREADS. Each round runs every layout with both
engines, old first in odd rounds and new first in even ones, so drifts of a shared machine fall on
both; each run's engine wall time is ``/run wall_s`` of its results file, its element phase
``/run phase_elements_s``, its contact phase ``/run phase_contact_s`` and that phase's stages
(sort, search, force), its output phase and its set-up (``/run phase_output_s``, ``setup_s``).
Prints, per layout and for each time, the medians, the spread (lowest and
highest) and the median of the per-round ratios old/new (above 1: NEW is faster), with their
range. DECK may be two decks, OLD_DECK,NEW_DECK, one per engine: the double and the mixed engine
each take only a deck of their precision (/control precision), the same model otherwise.
"""

from __future__ import annotations

import math
import os
import statistics
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import h5py

from paradyn.running.launch import current_machine
from paradyn.running.runners import MpirunRunner

TIMES = ("wall_s", "phase_elements_s", "phase_contact_s", "phase_contact_sort_s", "phase_contact_search_s",
         "phase_contact_force_s", "phase_output_s", "setup_s")


def run_once(engine: str, deck: Path, out: Path, ranks: int, threads: int) -> tuple[float, ...]:
    """One run of `engine` under mpirun, pinned as paradyn-run pins; its TIMES."""
    runner = MpirunRunner(replace(current_machine(), engine=Path(engine).resolve()))
    command = runner.command(deck.resolve(), out.resolve(), ranks, threads, False)
    env = dict(os.environ, **runner.environment(ranks, threads))
    subprocess.run(command, env=env, check=True, capture_output=True)
    with h5py.File(out, "r") as f:
        # NaN where an older engine did not write the time
        return tuple(float(f["run"].attrs.get(name, float("nan"))) for name in TIMES)


def main(argv: list[str]) -> int:
    old, new, deck, rounds, *layouts = argv
    builds = {"old": old, "new": new}
    old_deck, _, new_deck = deck.partition(",")
    decks = {"old": Path(old_deck), "new": Path(new_deck or old_deck)}
    times: dict[tuple[str, str], list[tuple[float, ...]]] = {}
    for k in range(int(rounds)):
        for layout in layouts:
            ranks, threads = (int(x) for x in layout.split("x"))
            for name in ("old", "new") if k % 2 == 0 else ("new", "old"):
                out = decks[name].parent / f"paired_{name}_{layout}.h5"
                times.setdefault((name, layout), []).append(run_once(builds[name], decks[name], out, ranks, threads))
    for layout in layouts:
        for j, name in enumerate(TIMES):
            o = [t[j] for t in times[("old", layout)]]
            n = [t[j] for t in times[("new", layout)]]
            if any(math.isnan(v) for v in o + n):
                print(f"{layout} {name}: not written by both engines")
                continue
            ratio = statistics.median(a / b for a, b in zip(o, n, strict=True))
            low, high = min(a / b for a, b in zip(o, n, strict=True)), max(a / b for a, b in zip(o, n, strict=True))
            print(f"{layout} {name}: old median {statistics.median(o):.4f} s ({min(o):.4f}-{max(o):.4f}), "
                  f"new median {statistics.median(n):.4f} s ({min(n):.4f}-{max(n):.4f}), "
                  f"per-round old/new median {ratio:.3f} ({low:.3f} to {high:.3f})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
