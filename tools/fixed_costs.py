"""What a whole ``paradyn-run`` costs beyond the engine's time loop (issue 19, item 3).

Each round runs the scene three ways, in fresh processes so that imports count:

- ``paradyn-run SCENE -o TMP -q`` as a user does: the whole wall time, and the engine's own loop
  time from summary.json (``wall_s``); the difference is the fixed cost;
- the same stages one by one, each timed inside one process (interpreter and imports, meshing,
  h5py, deck, check, engine process against its loop, reading and post-processing; the command
  itself writes its deck with h5py while its waiting engine starts MPI);
- ``python -c pass``, the interpreter alone;
- ``paradyn.run`` twice in one interpreter: the second call's wall time less its loop is what a
  Python session (a notebook, a script looping over runs) pays, with no imports left to make.

Rounds alternate the three, so a slow spell of a shared machine falls on all of them; the table
gives medians. Usage (docs/performance.md, "Fixed costs")::

    .venv/bin/python tools/fixed_costs.py cases/pipe_whip/scene.toml --repeat 7 [--threads 1] [--plots]
        [--compare OLD_PARADYN_RUN]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# run in a fresh interpreter: prints the seconds of every stage as JSON
STAGES = r"""
import json, sys, time
t0 = time.perf_counter()
from paradyn import commands
commands._settle_environment()   # as the command does, before numpy loads
from paradyn import cli, deck, launch, preflight, reading, scene
from paradyn.results.postprocess import post_process
t1 = time.perf_counter()
source, out, threads, plots = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4] == "1"
model = scene.build_model(scene.load_scene(source))
t2 = time.perf_counter()
import h5py   # the command loads it to write its deck
t2h = time.perf_counter()
path = deck.write_deck(model, out + "/deck.h5")
t3 = time.perf_counter()
preflight.check_model(model, 1, threads)
t4 = time.perf_counter()
run = launch.run_engine(path, out + "/results.h5", 1, threads)
t5 = time.perf_counter()
post_process(reading.read(out + "/results.h5", deck=path), out, plots=plots)
t6 = time.perf_counter()
loop = float(run.done["wall_s"])
print(json.dumps({"imports": t1 - t0, "meshing": t2 - t1, "h5py": t2h - t2, "deck": t3 - t2h, "check": t4 - t3,
                  "engine start and end": t5 - t4 - loop, "post-processing": t6 - t5}))
"""


# run in a fresh interpreter: paradyn.run twice, prints the second call's seconds beyond its loop
IN_SESSION = r"""
import sys, tempfile, time
from pathlib import Path
import paradyn
for _ in range(2):
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        results = paradyn.run(sys.argv[1], out, ranks=1, threads=int(sys.argv[2]), plots=sys.argv[3] == "1")
        cost = time.perf_counter() - start - float(results.engine_run.done["wall_s"])
print(cost)
"""


def _wall(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def whole_run(command: str, scene: Path, threads: int, flags: list[str]) -> tuple[float, float]:
    """Wall seconds of ``command SCENE -o TMP -q`` and its engine's loop seconds."""
    with tempfile.TemporaryDirectory() as out:
        elapsed = _wall([command, str(scene), "-o", out, "-q", "-t", str(threads), *flags])
        return elapsed, float(json.loads((Path(out) / "summary.json").read_text())["wall_s"])


def one_round(scene: Path, threads: int, plots: bool, compare: str | None) -> dict[str, float]:
    """The seconds of every stage, of the whole command and of its loop in one round."""
    python = sys.executable
    flags = ["--plots"] if plots else []
    other = {}
    if compare:
        other_elapsed, other_loop = whole_run(compare, scene, threads, [])
        other = {"compared: whole": other_elapsed, "compared: time loop": other_loop,
                 "compared: fixed cost": other_elapsed - other_loop}
    elapsed, loop = whole_run(str(Path(python).with_name("paradyn-run")), scene, threads, flags)
    with tempfile.TemporaryDirectory() as staged:
        stages = json.loads(subprocess.run([python, "-c", STAGES, str(scene), staged, str(threads),
                                            "1" if plots else "0"], check=True, capture_output=True,
                                           text=True).stdout)
    interpreter = _wall([python, "-c", "pass"])
    in_session = float(subprocess.run([python, "-c", IN_SESSION, str(scene), str(threads), "1" if plots else "0"],
                                      check=True, capture_output=True, text=True).stdout)
    return {"whole paradyn-run": elapsed, "time loop": loop, "fixed cost (whole - loop)": elapsed - loop,
            "interpreter": interpreter, **stages, "paradyn.run again in one interpreter: fixed cost": in_session,
            **other}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1, help="OpenMP threads of the engine (default 1)")
    parser.add_argument("--plots", action="store_true", help="ask for the pictures too")
    parser.add_argument("--compare", help="another paradyn-run command (an older checkout's), timed whole in "
                                          "the same rounds with its own default outputs")
    args = parser.parse_args(argv)
    rounds = [one_round(args.scene.resolve(), args.threads, args.plots, args.compare) for _ in range(args.repeat)]
    print(f"| {args.scene} ({args.repeat} rounds, {args.threads} thread(s)) | median s | min s | max s |")
    print("|---|---|---|---|")
    for name in rounds[0]:
        values = [r[name] for r in rounds]
        print(f"| {name} | {statistics.median(values):.3f} | {min(values):.3f} | {max(values):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
