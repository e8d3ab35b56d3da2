"""`paradyn-run`: mesh a scene, write the deck, run the engine, post-process the results."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import deck, launch, results, scene

DESCRIPTION = """\
Run a ParaDyn scene end to end.

SCENE is a TOML scene file (see docs/scene.md) or a deck.h5 written earlier (docs/formats.md).
Inside a Slurm allocation the engine runs under srun; --sbatch writes OUTDIR/job.sbatch instead
of running (submit it with sbatch; it runs the engine, then `paradyn-run --post OUTDIR`).
--post OUTDIR redoes the post-processing of a finished run from its results.h5 and deck.h5.
Ctrl-C (or SIGTERM to the engine, as Slurm sends at the time limit) makes the engine write
OUTDIR/results.checkpoint.h5 and stop; `paradyn-run SCENE -o OUTDIR --restart` continues the run
from it, on any number of ranks and threads. [run] checkpoint_interval also writes one regularly.
paradyn-run meshes the parts with gmsh, writes OUTDIR/deck.h5 (checked before launch), runs the
engine under MPI (-n ranks) and OpenMP (-t threads per rank) with a progress bar, and writes into
OUTDIR:

  results.h5      everything the engine wrote (docs/formats.md)
  <part>.pvd      a VTK time series per part (vtk/<part>_NNNNN.vtu), for ParaView or pyvista
  history.csv     time, energies, and dx..vz of every tracked point
  summary.json    wall time, cycles, time step, size, layout, speed, time per phase, energies, effects
  energies.png, tracked.png, deformed.png   plots (unless --no-plots)
  engine.log      the engine's own output

Exit status: 0 on success, 2 for a bad scene or deck, 3 when the run went unstable, 4 when it was
stopped (Ctrl-C, SIGTERM) after writing its checkpoint, 1 otherwise.
"""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="paradyn-run", description=DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    ranks, threads = launch.default_layout()
    parser.add_argument("scene", type=Path, help="scene file (.toml) or deck (.h5)")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="output folder (default: runs/<name of the scene's folder> under the current folder)")
    parser.add_argument("-n", "--ranks", type=int, default=ranks, help=f"MPI ranks (default {ranks})")
    parser.add_argument("-t", "--threads", type=int, default=threads,
                        help=f"OpenMP threads per rank (default {threads}, one per core)")
    parser.add_argument("--no-vtk", action="store_true", help="skip the VTK time series")
    parser.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    parser.add_argument("--sbatch", action="store_true",
                        help="write OUTDIR/job.sbatch for Slurm instead of running")
    parser.add_argument("--restart", action="store_true",
                        help="continue an interrupted run in the output folder from its checkpoint "
                             "(results.checkpoint.h5), with the folder's deck.h5")
    parser.add_argument("--post", action="store_true",
                        help="SCENE is an output folder of a finished run: only redo the post-processing")
    return parser


def default_output(scene_path: Path) -> Path:
    name = scene_path.resolve().parent.name if scene_path.suffix == ".toml" else scene_path.stem
    return Path.cwd() / "runs" / name


def prepare_deck(source: Path, out_dir: Path) -> Path:
    """Write (or check and copy) the deck into the output folder; return its path."""
    target = out_dir / "deck.h5"
    if source.suffix in (".h5", ".hdf5"):
        model = deck.read_deck(source)
    else:
        model = scene.build_model(scene.load_scene(source))
    deck.write_deck(model, target)
    return target


def restart_deck(out_dir: Path) -> Path:
    """The deck of the interrupted run in out_dir, kept as it was (the checkpoint belongs to it)."""
    deck_path, checkpoint = out_dir / "deck.h5", out_dir / "results.checkpoint.h5"
    if not (deck_path.is_file() and checkpoint.is_file()):
        raise ValueError(f"{out_dir} holds no deck.h5 and results.checkpoint.h5 to restart from; give the "
                         f"output folder (-o) of a run that wrote a checkpoint ([run] checkpoint_interval, "
                         f"or a run stopped with Ctrl-C or SIGTERM)")
    return deck_path


def post_process(res_path: Path, out_dir: Path, effects: list[str], extra: dict, plots: bool,
                 vtk: bool) -> dict[str, Path]:
    res = results.read(res_path, deck=out_dir / "deck.h5")
    outputs: dict[str, Path] = {"results": res_path}
    if vtk:
        for pvd in results.write_vtk_series(res, out_dir):
            outputs[f"vtk {pvd.stem}"] = pvd
    outputs["history"] = results.write_history_csv(res, out_dir / "history.csv")
    summary_path = out_dir / "summary.json"
    results.write_summary(res, summary_path, effects=effects, extra=extra)
    outputs["summary"] = summary_path
    if plots:
        from . import plots as plotting
        outputs["energies plot"] = plotting.plot_energies(res, out_dir / "energies.png")
        if res.n_tracked:
            outputs["tracked plot"] = plotting.plot_tracked_histories(res, out_dir / "tracked.png")
        outputs["deformed picture"] = plotting.render_deformed(res, out_dir / "deformed.png")
    return outputs


def post_only(out_dir: Path, plots: bool, vtk: bool) -> int:
    """Post-process the results.h5 and deck.h5 of a finished run in out_dir."""
    res_path, deck_path = out_dir / "results.h5", out_dir / "deck.h5"
    if not (res_path.is_file() and deck_path.is_file()):
        print(f"paradyn-run: error: {out_dir} holds no results.h5 and deck.h5; give the output folder of a run",
              file=sys.stderr)
        return 2
    try:
        effects = scene.effects(deck.read_deck(deck_path))
        outputs = post_process(res_path, out_dir, effects, {"post_processed": True}, plots=plots, vtk=vtk)
    except (deck.DeckError, results.ResultsError) as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return 2
    for label, path in outputs.items():
        print(f"  {label:18s} {path}")
    return 0


def write_sbatch(deck_path: Path, out_dir: Path, args: argparse.Namespace) -> int:
    post = [sys.executable, "-m", "paradyn.cli", "--post", str(out_dir)]
    post += ["--no-plots"] * args.no_plots + ["--no-vtk"] * args.no_vtk
    script = launch.sbatch_script(deck_path, out_dir / "results.h5", args.ranks, args.threads,
                                  f"paradyn-{out_dir.name}", post)
    path = out_dir / "job.sbatch"
    path.write_text(script)
    print(f"paradyn-run: wrote {path}; submit it with: sbatch {path}")
    return 0


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.post:
        return post_only(args.scene.resolve(), plots=not args.no_plots, vtk=not args.no_vtk)
    out_dir = (args.output or default_output(args.scene)).resolve()
    try:
        if not args.scene.is_file():
            raise scene.SceneError(f"{args.scene}: no such file; give the path of a scene .toml or a deck .h5")
        out_dir.mkdir(parents=True, exist_ok=True)
        deck_path = restart_deck(out_dir) if args.restart else prepare_deck(args.scene, out_dir)
    except (scene.SceneError, deck.DeckError, ValueError) as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return 2
    if args.sbatch:
        try:
            return write_sbatch(deck_path, out_dir, args)
        except launch.EngineError as error:
            print(f"paradyn-run: error: {error}", file=sys.stderr)
            return error.exit_code
    res_path = out_dir / "results.h5"
    bar = None if args.quiet else launch.ProgressBar()
    try:
        run = launch.run_engine(deck_path, res_path, args.ranks, args.threads, on_progress=bar,
                                log_path=out_dir / "engine.log", restart=args.restart)
    except launch.EngineError as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return error.exit_code
    finally:
        if bar is not None:
            bar.close()
    effects = run.start.get("effects", "").split(",")
    extra = {"scene": str(args.scene.resolve()), "command": run.command}
    outputs = post_process(res_path, out_dir, effects, extra, plots=not args.no_plots, vtk=not args.no_vtk)
    print(f"paradyn-run: {run.done.get('cycles')} cycles in {float(run.done.get('wall_s', 'nan')):.2f} s "
          f"({float(run.done.get('element_cycles_per_s', 'nan')):.3e} element-cycles/s), effects: {', '.join(effects)}")
    for label, path in outputs.items():
        print(f"  {label:18s} {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
