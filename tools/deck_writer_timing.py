"""Wall time of a whole ``paradyn-run`` with the deck sent as a stream or written by h5py, side by side.

    python tools/deck_writer_timing.py [--rounds 7] [--threads 1 2] [--scene cases/pipe_whip/scene.toml]

Each round runs the command once per deck writer and thread count, the writers' order alternating
between rounds; every run is a fresh ``python -c`` process that calls ``paradyn-run``'s own entry
point, so both writers pay the same start-up. "stream" is the command as it is (the waiting engine
writes deck.h5 from the frontend's stream, docs/formats.md "Deck stream"); "h5py" has the frontend
write deck.h5 with h5py while the engine waits, then tells it to go. Prints each run's seconds,
the medians, the h5py / stream ratio and the median of the paired differences per thread count.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# the command as paradyn-run runs it; H5PY replaces the stream by h5py's file before the engine goes
# (the model was validated already, as before the stream: the file gets the same items, no second check)
RUN = "import sys\nfrom paradyn.commands import paradyn_run\nsys.argv = {argv!r}\n{patch}paradyn_run()\n"
H5PY = """from paradyn.running import workflow, engine_process
workflow.deck_stream.encode = lambda model: model
def write_with_h5py(self, model):
    import h5py
    from paradyn.deck.files import _write_contents
    with h5py.File(next(a for a in self.command if a.endswith("deck.h5")), "w") as f:
        _write_contents(f, model)
engine_process.AwaitingEngine.send_deck = write_with_h5py
"""


def one_run(writer: str, scene: Path, threads: int, out: Path) -> float:
    argv = ["paradyn-run", str(scene), "-o", str(out), "-n", "1", "-t", str(threads), "--force", "--quiet"]
    code = RUN.format(argv=argv, patch=H5PY if writer == "h5py" else "")
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, cwd=ROOT)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--scene", type=Path, default=ROOT / "cases" / "pipe_whip" / "scene.toml")
    args = parser.parse_args()
    seconds: dict[tuple[str, int], list[float]] = {}
    with tempfile.TemporaryDirectory() as folder:
        for k in range(args.rounds):
            writers = ("stream", "h5py") if k % 2 == 0 else ("h5py", "stream")
            for threads in args.threads:
                for writer in writers:
                    t = one_run(writer, args.scene, threads, Path(folder) / f"{writer}{threads}")
                    seconds.setdefault((writer, threads), []).append(t)
                    print(f"round {k + 1} threads {threads} {writer:6s} {t:.3f} s", flush=True)
    print("\nthreads | stream median (s) | h5py median (s) | h5py / stream | median of the rounds' h5py - stream (s) "
          "| rounds where h5py was slower")
    for threads in args.threads:
        stream, h5py = seconds[("stream", threads)], seconds[("h5py", threads)]
        paired = [h - s for h, s in zip(h5py, stream, strict=True)]
        print(f"{threads} | {statistics.median(stream):.3f} | {statistics.median(h5py):.3f} | "
              f"{statistics.median(h5py) / statistics.median(stream):.4f} | {statistics.median(paired):+.3f} | "
              f"{sum(d > 0 for d in paired)} of {len(paired)}")


if __name__ == "__main__":
    main()
