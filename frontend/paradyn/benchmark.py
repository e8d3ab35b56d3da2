"""`paradyn-scaling`: run one case on several rank x thread layouts and report parallel speed.

For every layout the engine runs the same deck; the report gives wall time, element-cycles per
second, speed-up and parallel efficiency against the first layout, the time per phase and the load
imbalance between ranks. It is printed as a markdown table and written as JSON. With ``--repeat``
the layouts take turns (round after round), so a slow spell of a shared machine slows one round
of every layout rather than all runs of one; the speed-up is the median over rounds of the ratio
of the first layout's wall time to the layout's in the same round. The displacements of every
run are compared with the first run's (bitwise), so a speed-up never hides a different answer.
``--partition`` picks how elements are given to ranks; the report counts the shared nodes and
neighbours it makes.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from . import deck, scene
from ._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_OK
from .atomic_write import write_text_atomic
from .running import launch, workflow

PHASES = ("elements", "contact", "communication", "output", "other")


@dataclass
class LayoutResult:
    ranks: int
    threads: int
    wall_s: float
    element_cycles_per_s: float
    speed_up: float
    efficiency: float
    phase_s: dict[str, float]
    same_displacements: bool
    shared_nodes: int = 0       # nodes held by more than one rank
    max_neighbours: int = 0     # most ranks any one rank exchanges corner forces with
    peak_memory_mb: float = 0.0  # largest peak resident memory of any rank (MiB)
    load_imbalance: float = 1.0  # busiest rank's element + contact time over the mean of all ranks
    round_wall_s: list[float] = field(default_factory=list)   # wall time of each round
    round_speed_up: list[float] = field(default_factory=list)  # speed-up in each round


def element_owners(model: deck.Model, ranks: int) -> np.ndarray:
    """The rank (0-based) of every element as the engine partitions ``model`` on ``ranks``, from
    the engine's own routine (``paradyn._kernels.partition_elements``)."""
    from . import _kernels
    method = deck.PARTITIONS[model.control.partition or deck.DEFAULT_PARTITION]
    return np.asarray(_kernels.partition_elements(
        method, np.asfortranarray(np.asarray(model.coordinates, dtype=np.float64).T),
        np.asfortranarray(np.asarray(model.connectivity, dtype=np.int32).T + 1), ranks))


def partition_stats(model: deck.Model, ranks: int) -> tuple[int, int]:
    """(shared nodes, largest neighbour count) of the engine's partition of ``model`` on ``ranks``."""
    owner = element_owners(model, ranks)
    node = np.asarray(model.connectivity, dtype=np.int64).ravel()
    holder = np.repeat(np.asarray(owner, dtype=np.int64), 4)
    pairs = np.unique(node * ranks + holder)   # distinct (node, rank), sorted by node
    node_of, rank_of = pairs // ranks, pairs % ranks
    holders = np.bincount(node_of, minlength=model.n_nodes)
    start = np.concatenate(([0], np.cumsum(holders)))
    shared = holders > 1
    neighbours = np.zeros((ranks, ranks), dtype=bool)
    for n in np.flatnonzero(shared):
        r = rank_of[start[n]:start[n + 1]]
        neighbours[np.ix_(r, r)] = True
    np.fill_diagonal(neighbours, False)
    return int(shared.sum()), int(neighbours.sum(axis=1).max(initial=0))


def parse_layouts(text: str) -> list[tuple[int, int]]:
    """'1x1,1x2,2x1' -> [(1, 1), (1, 2), (2, 1)]."""
    layouts = []
    for item in text.split(","):
        try:
            ranks, threads = (int(v) for v in item.lower().split("x"))
        except ValueError:
            raise SystemExit(f"paradyn-scaling: error: layout '{item}' is not RANKSxTHREADS, e.g. 2x1") from None
        if ranks < 1 or threads < 1:
            raise SystemExit(f"paradyn-scaling: error: layout '{item}' needs at least 1 rank and 1 thread")
        layouts.append((ranks, threads))
    return layouts


def run_once(deck_path: Path, out_dir: Path, ranks: int, threads: int, k: int) -> tuple[dict, np.ndarray]:
    """One run of a layout (round ``k``): its /run attributes and displacements."""
    res = workflow.run(deck_path, out_dir, ranks, threads, post=False,
                       results_name=f"results_{ranks}x{threads}_{k}.h5",
                       log_name=f"engine_{ranks}x{threads}.log")
    return res.run, np.asarray(res.displacement)


def run_rounds(deck_path: Path, out_dir: Path, layouts: list[tuple[int, int]],
               repeat: int) -> list[list[tuple[dict, bool]]]:
    """rounds[k][i]: the /run attributes of layout i in round k, and whether its displacements are
    bitwise the first run's (only that run's displacements are kept)."""
    reference = None
    rounds = []
    for k in range(repeat):
        row = []
        for ranks, threads in layouts:
            run, displacement = run_once(deck_path, out_dir, ranks, threads, k)
            if reference is None:
                reference = displacement
            row.append((run, bool(np.array_equal(displacement, reference))))
        rounds.append(row)
    return rounds


def run_layouts(deck_path: Path, out_dir: Path, layouts: list[tuple[int, int]],
                repeat: int = 1, model: deck.Model | None = None) -> list[LayoutResult]:
    """Run every layout `repeat` times, in rounds; each layout is reported by its run of median
    wall time (timings on shared machines are noisy: quote medians)."""
    rounds = run_rounds(deck_path, out_dir, layouts, repeat)
    base_walls = [float(r[0][0]["wall_s"]) for r in rounds]
    results: list[LayoutResult] = []
    for i, (ranks, threads) in enumerate(layouts):
        runs = sorted((r[i][0] for r in rounds), key=lambda run: float(run["wall_s"]))
        run = runs[len(runs) // 2]
        walls = [float(r[i][0]["wall_s"]) for r in rounds]
        speed_ups = [b / w for b, w in zip(base_walls, walls, strict=True)]
        speed_up = float(np.median(speed_ups))
        shared, neighbours = partition_stats(model, ranks) if model is not None else (0, 0)
        results.append(LayoutResult(
            ranks=ranks, threads=threads, wall_s=float(run["wall_s"]),
            element_cycles_per_s=float(run["element_cycles_per_s"]), speed_up=speed_up,
            efficiency=speed_up * layouts[0][0] * layouts[0][1] / (ranks * threads),
            phase_s={p: float(run[f"phase_{p}_s"]) for p in PHASES},
            same_displacements=all(r[i][1] for r in rounds),
            shared_nodes=shared, max_neighbours=neighbours,
            peak_memory_mb=float(run.get("peak_memory_per_rank_mb", 0.0)),
            load_imbalance=float(run.get("load_imbalance", 1.0)),
            round_wall_s=walls, round_speed_up=speed_ups,
        ))
    return results


def markdown(results: list[LayoutResult]) -> str:
    lines = ["| layout | wall (s) | element-cycles/s | speed-up | efficiency | "
             + " | ".join(PHASES) + " | imbalance | peak MiB/rank | same answer |",
             "|" + "---|" * (8 + len(PHASES))]
    for r in results:
        lines.append(f"| {r.ranks} x {r.threads} | {r.wall_s:.2f} | {r.element_cycles_per_s:.3e} | "
                     f"{r.speed_up:.2f} | {100 * r.efficiency:.0f} % | "
                     + " | ".join(f"{r.phase_s[p]:.2f}" for p in PHASES)
                     + f" | {r.load_imbalance:.2f} | {r.peak_memory_mb:.0f} | "
                     + f"{'yes' if r.same_displacements else 'NO'} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="paradyn-scaling",
        description="Run a scene (or deck) on several MPI rank x OpenMP thread layouts and report "
                    "wall time, element-cycles/s, speed-up, parallel efficiency and time per phase "
                    "(markdown on standard output, JSON in the output folder).")
    parser.add_argument("scene", type=Path, help="scene .toml or deck .h5")
    parser.add_argument("--layouts", default="1x1,1x2,2x1",
                        help="comma-separated RANKSxTHREADS; the first is the baseline (default 1x1,1x2,2x1)")
    parser.add_argument("--repeat", type=int, default=1,
                        help="rounds: every layout runs once per round; medians are reported (default 1)")
    parser.add_argument("--partition", choices=tuple(deck.PARTITIONS), default=None,
                        help="how elements are given to ranks: contiguous 'blocks' by element number or "
                             "'rcb' (recursive coordinate bisection); default: the scene's [run] partition, "
                             f"else {deck.DEFAULT_PARTITION}")
    parser.add_argument("--end-time", type=float, default=None, metavar="SECONDS",
                        help="simulated time of each run (default: the scene's end_time); a short one times "
                             "the layouts in seconds")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="output folder (default runs/scaling_<name of the scene's folder>)")
    args = parser.parse_args(argv)
    if args.end_time is not None and not args.end_time > 0.0:
        parser.error(f"--end-time must be > 0 seconds, got {args.end_time}")
    layouts = parse_layouts(args.layouts)
    name = args.scene.resolve().parent.name if args.scene.suffix == ".toml" else args.scene.stem
    out_dir = (args.output or Path.cwd() / "runs" / f"scaling_{name}").resolve()
    out_dir.mkdir(parents=True, exist_ok=True)
    try:
        model = workflow.model_of(args.scene)
        if args.partition is not None:
            model.control.partition = args.partition
        if args.end_time is not None:   # frames and records stay inside the shorter run
            model.control.output_interval = min(model.control.output_interval, args.end_time)
            model.control.end_time = args.end_time
        deck_path = deck.write_deck(model, out_dir / "deck.h5")
    except (scene.SceneError, deck.DeckError) as error:
        print(f"paradyn-scaling: error: {error}", file=sys.stderr)
        return STATUS_BAD_INPUT
    try:
        results = run_layouts(deck_path, out_dir, layouts, max(1, args.repeat), model)
    except launch.EngineError as error:
        print(f"paradyn-scaling: error: {error}", file=sys.stderr)
        return error.exit_code
    partition = model.control.partition or deck.DEFAULT_PARTITION
    report = {"scene": str(args.scene.resolve()), "elements": model.n_elements, "nodes": model.n_nodes,
              "repeat": max(1, args.repeat), "partition": partition,
              "layouts": [asdict(r) for r in results]}
    write_text_atomic(out_dir / "scaling.json", json.dumps(report, indent=2) + "\n")
    print(markdown(results))
    if args.repeat > 1:
        for r in results[1:]:
            print(f"paradyn-scaling: speed-up of {r.ranks} x {r.threads} in each round: "
                  + " ".join(f"{v:.2f}" for v in r.round_speed_up))
    for ranks in sorted({r.ranks for r in results if r.ranks > 1}):
        row = next(r for r in results if r.ranks == ranks)
        print(f"paradyn-scaling: partition {partition} on {ranks} ranks: {row.shared_nodes} shared nodes, "
              f"at most {row.max_neighbours} neighbours per rank")
    print(f"paradyn-scaling: wrote {out_dir / 'scaling.json'}")
    return STATUS_OK if all(r.same_displacements for r in results) else STATUS_FAILURE


if __name__ == "__main__":
    sys.exit(main())
