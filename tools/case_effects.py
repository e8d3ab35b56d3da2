"""The effect table of every case: python tools/case_effects.py [OUT] [CASES...].

Runs each ``cases/*/scene.toml`` (or the case folders named) on one rank with two threads
without post-processing, and prints the effect table the engine wrote into its results.h5 (issue
13: what each case declares, the cycles each effect was active and skipped, and its wall
seconds). docs/performance.md quotes its output.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import paradyn
from paradyn.results.reports import effect_table_text

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str]) -> int:
    out = Path(argv[0]) if argv else Path(tempfile.mkdtemp(prefix="paradyn-case-effects-"))
    names = argv[1:] or sorted(p.parent.name for p in (ROOT / "cases").glob("*/scene.toml"))
    for name in names:
        results = paradyn.run(ROOT / "cases" / name / "scene.toml", out / name, ranks=1, threads=2,
                              post=False, progress=False)
        print(f"{name}: {int(results.run['cycles'])} cycles, {float(results.run['wall_s']):.2f} s")
        print(effect_table_text(results))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
