"""One rank on 1 and 2 threads with and without a competing busy loop, paired and interleaved:
python tools/loaded_threads.py DECK ROUNDS [--cores 0,1]

Each round runs every variant once, in turn (the order rotating from round to round), first with a
busy loop (``python -c 'while True: pass'``) pinned to the last core of ``--cores``, then on the
machine as it is. The engine runs alone (``paradyn-run``'s direct runner), with the environment
``paradyn-run`` gives it, and a variant's changes on top:

- ``1 thread``;
- ``2 threads, pinned, spinning``: the launcher before issue 34 (``OMP_PROC_BIND=close``,
  ``OMP_PLACES=cores``, libgomp's default wait: spin about 300 000 times at a barrier, then sleep);
- pinned or unpinned (``OMP_PROC_BIND``/``OMP_PLACES`` unset: the threads go where the kernel
  finds a free core), spinning, passive (``OMP_WAIT_POLICY=passive``: a waiting thread sleeps at
  once) or ``GOMP_SPINCOUNT=10000`` (spin that often, then sleep).

Prints the median engine wall time (``PARADYN-DONE wall_s``) of each variant under each condition,
its spread, and the median over the rounds of its time over the 1-thread time of the same round.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

from paradyn.running import launch
from paradyn.running.engine_process import parse_line

POLICY = ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")


def variants() -> dict[str, tuple[int, dict[str, str | None]]]:
    """Name -> (threads, environment changes; None removes the variable)."""
    pinned = {"OMP_PROC_BIND": "close", "OMP_PLACES": "cores"}
    unpinned = {"OMP_PROC_BIND": None, "OMP_PLACES": None}
    return {
        "1 thread": (1, {}),
        "2 threads, pinned, spinning (before)": (2, {**pinned, "OMP_WAIT_POLICY": None, "GOMP_SPINCOUNT": None}),
        "2 threads, pinned, passive": (2, {**pinned, "OMP_WAIT_POLICY": "passive", "GOMP_SPINCOUNT": None}),
        "2 threads, unpinned, spinning": (2, {**unpinned, "OMP_WAIT_POLICY": None, "GOMP_SPINCOUNT": None}),
        "2 threads, unpinned, passive": (2, {**unpinned, "OMP_WAIT_POLICY": "passive", "GOMP_SPINCOUNT": None}),
        "2 threads, unpinned, GOMP_SPINCOUNT=10000": (2, {**unpinned, "OMP_WAIT_POLICY": None,
                                                          "GOMP_SPINCOUNT": "10000"}),
    }


def run_once(deck: Path, folder: Path, threads: int, changes: dict[str, str | None]) -> float:
    env = launch.engine_environment(threads)
    for name, value in changes.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    done = subprocess.run(["nice", "-n", "10", str(launch.engine_path()), str(deck.resolve()),
                           str((folder / "results.h5").resolve())], cwd=folder, env=env, capture_output=True,
                          text=True, check=True)
    for line in done.stdout.splitlines():
        parsed = parse_line(line)
        if parsed and parsed[0] == "DONE":
            return float(parsed[1]["wall_s"])
    raise RuntimeError(f"no PARADYN-DONE line:\n{done.stdout}\n{done.stderr}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("deck", type=Path)
    parser.add_argument("rounds", type=int)
    parser.add_argument("--cores", default="0,1")
    parser.add_argument("--folder", type=Path, default=Path("runs/loaded_threads"))
    args = parser.parse_args()
    args.folder.mkdir(parents=True, exist_ok=True)
    table = variants()
    names = list(table)
    times: dict[tuple[str, str], list[float]] = {}
    for r in range(args.rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        for condition in ("busy loop on one core", "no added load"):
            busy = None
            if condition.startswith("busy"):
                busy = subprocess.Popen(["nice", "-n", "10", "taskset", "-c", args.cores.split(",")[-1],
                                         sys.executable, "-c", "while True: pass"])
            try:
                for name in order:
                    threads, changes = table[name]
                    wall = run_once(args.deck, args.folder, threads, changes)
                    times.setdefault((condition, name), []).append(wall)
                    print(f"round {r + 1} {condition}: {name}: {wall:.2f} s", file=sys.stderr, flush=True)
            finally:
                if busy is not None:
                    busy.kill()
                    busy.wait()
    print("| condition | variant | wall (s), median | lowest to highest | / 1 thread, median of rounds |")
    print("|---|---|---|---|---|")
    for condition in ("busy loop on one core", "no added load"):
        one = times[(condition, "1 thread")]
        for name in names:
            t = times[(condition, name)]
            ratio = statistics.median(a / b for a, b in zip(t, one, strict=True))
            print(f"| {condition} | {name} | {statistics.median(t):.2f} | {min(t):.2f} to {max(t):.2f} | "
                  f"{ratio:.2f} |")


if __name__ == "__main__":
    main()
