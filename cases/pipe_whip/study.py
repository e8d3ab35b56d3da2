"""Pipe whip case 1: mesh density and through-thickness points.

    .venv/bin/python cases/pipe_whip/study.py [--threads 2] [--end-time 2.5e-3]
                                              [--fine-end-time 1e-3] [--workdir DIR]

Runs case 1 (cases/pipe_whip/scene.toml) with both pipes meshed 16 x 32, 32 x 64 and 64 x 128
(elements around x along) with 5 points through the thickness, and the 16 x 32 mesh with 3 and 7
points. Every variant is the case's scene, read with paradyn.scene.load_scene and edited (mesh
counts, integration points, run length, one field frame at the end), meshed with
paradyn.scene.build_model, and run with paradyn.run on one rank (deck written, engine run,
results read, no post-processing).

The tracked points of the scene are given by coordinates; on every mesh the script checks that the
node it tracks lies exactly on the requested point (a node ring at x = 0 and x = 0.5, a node at
the top and bottom of each ring), so the same material points are compared on every mesh.

It prints one markdown table: the six tracked downward displacements at 1 ms and the upper ring's
centre (mean of its top and bottom nodes), in mm; the upper ring's centre at 2.5 ms and the
largest effective plastic strain at the end, where plasticity has begun (nothing yields before
about 2 ms, so at 1 ms the through-thickness points cannot differ); then the wall time of the
engine's time loop, cycles, element-cycles/s and the energy balance error of each run
(docs/outputs.md); last the published values at 1 ms. --fine-end-time shortens the 64 x 128 run
(1 ms is all the 1 ms columns need); by default it runs as long as the others. The whole study
takes about 40 s on two cores.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import paradyn
from paradyn import deck, reports, scene

HERE = Path(__file__).resolve().parent
SCENE = HERE / "scene.toml"
sys.path.insert(0, str(HERE))
from compare import POINTS, REFERENCES  # noqa: E402  (case 1's points and the papers' values)

TABLE_TIME = 1e-3  # s
LATE_TIME = 2.5e-3  # s
# (elements around, elements along, through-thickness points), first the case itself
VARIANTS = [(16, 32, 5), (32, 64, 5), (64, 128, 5), (16, 32, 3), (16, 32, 7)]


def variant_scene(base: scene.Scene, around: int, along: int, points: int, end_time: float) -> scene.Scene:
    """Case 1 with both pipes meshed around x along, `points` through the thickness, run to end_time."""
    parts = [dataclasses.replace(
        p, integration_points=points,
        geometry=dataclasses.replace(p.geometry, elements_around=around, elements_along=along))
        for p in base.parts]
    run = dataclasses.replace(base.run, end_time=end_time, output_interval=end_time)
    return dataclasses.replace(base, parts=parts, run=run,
                               title=f"{base.title} ({around} x {along}, {points} points)")


def check_tracked_nodes(sc: scene.Scene, model: deck.Model) -> float:
    """Largest distance between a tracked node and its requested point (m); fails above 1e-9 m."""
    worst = 0.0
    for track, node in zip(sc.tracks, model.tracked_nodes, strict=True):
        distance = float(np.linalg.norm(model.coordinates[node] - np.asarray(track.point)))
        if distance > 1e-9:
            raise SystemExit(f"study.py: tracked point '{track.name}' {list(track.point)} is "
                             f"{distance:.3g} m from its node on this mesh; the meshes do not compare")
        worst = max(worst, distance)
    return worst


def run_variant(base: scene.Scene, around: int, along: int, points: int, end_time: float,
                threads: int, workdir: Path) -> dict:
    sc = variant_scene(base, around, along, points, end_time)
    model = scene.build_model(sc)
    check_tracked_nodes(sc, model)
    folder = workdir / f"mesh_{around}x{along}_ip{points}"
    res = paradyn.run(model, folder, ranks=1, threads=threads, post=False)
    run = res.engine_run
    history = res.history_table()
    down = {p: -1e3 * float(np.interp(TABLE_TIME, history["time"], history[f"{p}_dz"])) for p in POINTS}
    down["upper_centre"] = 0.5 * (down["upper_contact"] + down["upper_top"])
    late = None
    if history["time"][-1] >= LATE_TIME * (1 - 1e-9):
        late = -1e3 * 0.5 * float(np.interp(LATE_TIME, history["time"],
                                            history["upper_contact_dz"] + history["upper_top_dz"]))
    energy = reports.energy_report(res)
    return {
        "mesh": f"{around} x {along}", "points": points, "elements": res.n_elements,
        "end_time": end_time, "down": down, "late": late,
        "plastic_strain": float(res.plastic_strain[-1].max()),
        "wall_s": float(run.done["wall_s"]), "total_s": run.elapsed_s, "cycles": int(run.done["cycles"]),
        "rate": float(run.done["element_cycles_per_s"]), "balance": energy["balance_error"],
        "dt": float(res.run["dt_s"]),
        "max_penetration": float(np.max(history["contact_penetration"])),
    }


def table(rows: list[dict]) -> str:
    columns = [*POINTS, "upper_centre"]
    lines = ["| mesh (per pipe) | points | end (ms) | " + " | ".join(columns) +
             f" | upper_centre, {LATE_TIME * 1e3:g} ms | max plastic strain at end"
             " | wall (s) | cycles | element-cycles/s | energy balance error |",
             "|" + "---|" * (len(columns) + 9)]
    for r in rows:
        lines.append(f"| {r['mesh']} | {r['points']} | {1e3 * r['end_time']:g} | " +
                     " | ".join(f"{r['down'][c]:.3f}" for c in columns) +
                     (f" | {r['late']:.3f}" if r["late"] is not None else " | -") +
                     f" | {r['plastic_strain']:.2e}" +
                     f" | {r['wall_s']:.1f} | {r['cycles']} | {r['rate']:.3g} | {r['balance']:.1e} |")
    for label, index in (("Har (GT-PARADYN), 16 x 32", 0), ("Malone & Johnson 1994", 1)):
        lines.append(f"| {label} | - | - | " +
                     " | ".join(REFERENCES.get(c, ("-", "-"))[index] for c in columns) + " | | | | | | |")
    return "\n".join(lines)


def commit() -> str:
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain"], cwd=HERE, capture_output=True,
                               text=True, check=True).stdout.strip()
        return head + (" + uncommitted changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--threads", type=int, default=2, help="OpenMP threads per run (default 2)")
    parser.add_argument("--end-time", type=float, default=2.5e-3, help="run length, s (default 2.5e-3)")
    parser.add_argument("--fine-end-time", type=float, default=None,
                        help="run length of the 64 x 128 mesh, s (default: --end-time)")
    parser.add_argument("--workdir", type=Path, default=None,
                        help="keep decks and results here (default: a temporary folder)")
    args = parser.parse_args(argv)
    if args.fine_end_time is None:
        args.fine_end_time = args.end_time
    if min(args.end_time, args.fine_end_time) < TABLE_TIME:
        parser.error(f"the runs must reach {TABLE_TIME * 1e3:g} ms")
    base = scene.load_scene(SCENE)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pipe_whip_study_") as tmp:
        workdir = (args.workdir or Path(tmp)).resolve()  # the engine starts in the deck folder
        rows = []
        for around, along, points in VARIANTS:
            end_time = args.fine_end_time if around >= 64 else args.end_time
            row = run_variant(base, around, along, points, end_time, args.threads, workdir)
            print(f"  {row['mesh']:9s} {points} points: {row['cycles']} cycles, {row['wall_s']:.1f} s",
                  file=sys.stderr, flush=True)
            rows.append(row)
    print(table(rows))
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    steps = ", ".join(sorted({f"{r['dt']:.3g}" for r in rows}))
    print(f"\nDownward displacements in mm at {TABLE_TIME * 1e3:g} ms; upper_centre is the mean of "
          f"upper_contact and upper_top. Commit {commit()}; one rank, {args.threads} OpenMP threads; "
          f"dt = {steps} s; largest contact penetration "
          f"{max(r['max_penetration'] for r in rows):.2g} m; total {time.perf_counter() - start:.0f} s; "
          f"load average {load:.1f} at the end.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
