"""Weak scaling of the engine on one machine: python tools/weak_scaling.py OUT [--ranks 1 2 4 8 16] [--steps N].

The problem grows with the ranks: for P ranks, a clamped strip of P square plate segments (part 0)
and above each segment a smaller free plate (part 1) that falls onto it, with one contact pair
between the two parts. Elements are numbered segment after segment (the strip's segment r, then
plate r), so the paper's contiguous blocks give rank r segment r and plate r: each rank holds the
same number of elements whatever P, shares one row of nodes with each of its (at most two)
neighbours, and its contact is its own plate on its own segment.

Each layout runs under ``mpirun --oversubscribe`` (one thread per rank) and the table is read from
``/run`` of its results file: the largest peak resident memory of any rank, the set-up seconds
(MPI start-up to the time loop), seconds per step, and the most messages and bytes of any rank per
step (``traffic_counter``). Beyond the machine's cores the ranks share them, so seconds per step
grow with the oversubscription: memory and traffic are the measures of this table, times are not.
The table is printed as Markdown (docs/performance.md, "Beyond one machine").
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from paradyn.deck import ELASTIC, Control, Model, write_deck
from paradyn.mesh import geometry
from paradyn.running.launch import engine_path

SEGMENT = 0.1          # m, side of a strip segment
THICKNESS = 1.0e-3     # m
GAP = 1.05e-3          # m, mid-surface to mid-surface at the start: contact within a few steps
SPEED = 5.0            # m/s, the plates' initial downward speed
YOUNG, POISSON, DENSITY = 2.0e11, 0.3, 7800.0
COLUMNS = ("ranks", "elements", "elements_per_rank", "peak_memory_per_rank_mb", "setup_s", "s_per_step",
           "messages_per_step", "bytes_sent_per_step", "bytes_received_per_step")


@dataclass(frozen=True)
class Sizes:
    """Elements along each side of a strip segment and of a falling plate."""

    segment: int = 60
    plate: int = 48

    @property
    def per_rank(self) -> int:
        return self.segment**2 + self.plate**2


def strip(n_ranks: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The clamped strip of n_ranks segments of n x n elements: coordinates and quads, nodes
    numbered column after column along x, elements segment after segment."""
    columns, rows = n_ranks * n + 1, n + 1
    i, j = np.meshgrid(np.arange(columns), np.arange(rows), indexing="ij")
    coordinates = np.stack([i.ravel() * SEGMENT / n, j.ravel() * SEGMENT / n, np.zeros(i.size)], axis=1)
    segment, jj, ii = np.meshgrid(np.arange(n_ranks), np.arange(n), np.arange(n), indexing="ij")
    i0 = (segment * n + ii).ravel()
    j0 = jj.ravel()
    corner = i0 * rows + j0
    quads = np.stack([corner, corner + rows, corner + rows + 1, corner + 1], axis=1)
    return coordinates, quads


def weak_model(n_ranks: int, sizes: Sizes, steps: int, contact: bool = True) -> Model:
    """The weak-scaling deck for n_ranks ranks, running about `steps` steps (without the contact
    pair when not `contact`: the plates then fall freely)."""
    xs, qs = strip(n_ranks, sizes.segment)
    coords, quads, parts = [xs], [], []
    offset = len(xs)
    per_segment = sizes.segment**2
    for r in range(n_ranks):
        plate = geometry.plate(size=(0.8 * SEGMENT, 0.8 * SEGMENT), elements=(sizes.plate, sizes.plate),
                               origin=((r + 0.1) * SEGMENT, 0.1 * SEGMENT, GAP))
        quads += [qs[r * per_segment:(r + 1) * per_segment], plate.quads + offset]
        parts += [np.zeros(per_segment, dtype=np.int32), np.ones(plate.n_elements, dtype=np.int32)]
        coords.append(plate.coordinates)
        offset += plate.n_nodes
    coordinates = np.concatenate(coords)
    velocity = np.zeros_like(coordinates)
    velocity[len(xs):, 2] = -SPEED
    fixed = np.zeros((len(coordinates), 6), dtype=np.int32)
    edge_y = np.isclose(xs[:, 1], 0.0) | np.isclose(xs[:, 1], SEGMENT)
    fixed[:len(xs)][edge_y] = 1
    wave = np.sqrt(YOUNG / (DENSITY * (1.0 - POISSON**2)))
    dt = 0.9 * (0.8 * SEGMENT / sizes.plate) / wave
    end_time = steps * dt
    n_pairs = 1 if contact else 0
    return Model(
        coordinates=coordinates, connectivity=np.concatenate(quads), element_part=np.concatenate(parts),
        thickness=np.full(2, THICKNESS), part_material=np.zeros(2, dtype=np.int32),
        material_model=np.array([ELASTIC]), density=np.array([DENSITY]), youngs_modulus=np.array([YOUNG]),
        poisson_ratio=np.array([POISSON]),
        control=Control(end_time=end_time, output_interval=end_time, partition="blocks"),
        initial_velocity=velocity, fixed_dofs=fixed,
        contact_pairs=np.array([[0, 1]] * n_pairs, dtype=np.int32).reshape(n_pairs, 2),
        contact_penalty_scale=np.full(n_pairs, 0.1), contact_static_friction=np.zeros(n_pairs),
        contact_dynamic_friction=np.zeros(n_pairs), contact_friction_decay=np.zeros(n_pairs),
        contact_passes=np.full(n_pairs, 2, dtype=np.int32),
        title=f"weak scaling, {n_ranks} ranks",
    )


def run_layout(engine: Path, directory: Path, n_ranks: int, sizes: Sizes, steps: int,
               contact: bool = True) -> dict[str, float]:
    """Write the deck for n_ranks, run it under mpirun and return the table row from /run."""
    directory.mkdir(parents=True, exist_ok=True)
    deck = write_deck(weak_model(n_ranks, sizes, steps, contact), directory / "deck.h5")
    results = directory / "results.h5"
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        raise SystemExit("weak_scaling: no mpirun on PATH; install Open MPI (setup/system-packages.sh)")
    command = [mpirun, "-n", str(n_ranks), "--oversubscribe", "--bind-to", "none", "-x", "OMP_NUM_THREADS",
               str(engine), str(deck), str(results)]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"weak_scaling: the engine failed on {n_ranks} ranks (exit {done.returncode}):\n"
                         f"{done.stderr[-2000:]}")
    with h5py.File(results, "r") as f:
        run = {name: float(value) for name, value in f["run"].attrs.items() if np.ndim(value) == 0
               and not isinstance(value, (str, bytes))}
    row = {name: run.get(name, float("nan")) for name in COLUMNS}
    row["elements_per_rank"] = run["elements"] / n_ranks
    row["s_per_step"] = run["wall_s"] / max(run["cycles"], 1.0)
    return row


def markdown(rows: list[dict[str, float]]) -> str:
    """The table of the rows, one line per layout."""
    head = "| " + " | ".join(COLUMNS) + " |\n|" + "---|" * len(COLUMNS) + "\n"
    formats = ("{:.0f}", "{:.0f}", "{:.0f}", "{:.1f}", "{:.3f}", "{:.5f}", "{:.1f}", "{:.0f}", "{:.0f}")
    return head + "".join("| " + " | ".join(f.format(row[c]) for f, c in zip(formats, COLUMNS, strict=True)) + " |\n"
                          for row in rows)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="folder for the decks and results (one subfolder per layout)")
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    parser.add_argument("--steps", type=int, default=200, help="time steps of each run (about)")
    parser.add_argument("--segment", type=int, default=Sizes.segment, help="elements along a strip segment")
    parser.add_argument("--plate", type=int, default=Sizes.plate, help="elements along a falling plate")
    parser.add_argument("--no-contact", action="store_true", help="leave the contact pair out (the plates fall freely)")
    parser.add_argument("--engine", type=Path, default=None, help="paradyn-engine (default: the installed one)")
    args = parser.parse_args(argv)
    engine = (args.engine or engine_path()).resolve()
    sizes = Sizes(args.segment, args.plate)
    rows = []
    for n_ranks in args.ranks:
        rows.append(run_layout(engine, args.out / f"ranks_{n_ranks}", n_ranks, sizes, args.steps, not args.no_contact))
        print(" ".join(f"{c}={rows[-1][c]:.6g}" for c in COLUMNS), flush=True)
    print(markdown(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
