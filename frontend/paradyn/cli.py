"""`paradyn-run`: mesh a scene, write the deck, run the engine, post-process the results."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from . import __version__, deck, launch, preflight, reading, scene, workflow
from ._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_OK
from .postprocess import post_process
from .progress import RunProgress
from .reports import accuracy_text, effect_table_text
from .run_folders import claim_output, default_output
from .runners import SbatchRunner

DESCRIPTION = """\
Run a ParaDyn scene end to end.

SCENE is a TOML scene file (see docs/scene.md), an LS-DYNA keyword deck (.k, .key, .dyn; the
subset of docs/keyword.md) or a deck.h5 written earlier (docs/formats.md).
--check SCENE meshes it and prints the mass per part, the stable step and its element, the
cycles, wall time and memory to expect, the initial contact penetrations and warnings for likely
unit mistakes, then stops (every run prints the same lines first, unless -q).
The output folder defaults to runs/<name> (the folder's name for a scene.toml, the file's name
otherwise); a folder holding another scene's run is refused unless --force.
Inside a Slurm allocation the engine runs under srun; --sbatch writes OUTDIR/job.sbatch instead
of running (submit it with sbatch; it runs the engine, continues in a new job when the time limit
stopped it with a checkpoint, then runs `paradyn-run --post OUTDIR`).
--post OUTDIR redoes the post-processing of a run from its results.h5 and deck.h5, also of a run
that was interrupted (what the results file holds so far).
Ctrl-C (or SIGTERM to the engine, as Slurm sends at the time limit) makes the engine write
OUTDIR/results.checkpoint.h5 and stop; `paradyn-run SCENE -o OUTDIR --restart` continues the run
from it, on any number of ranks and threads. [run] checkpoint_interval also writes one regularly.
paradyn-run meshes the parts with gmsh, writes OUTDIR/deck.h5 (checked before launch), runs the
engine under MPI (-n ranks) and OpenMP (-t threads per rank) with a progress bar, and writes into
OUTDIR:

  results.h5      everything the engine wrote (docs/formats.md)
  results.vtkhdf  every frame of every part in one file (VTKHDF), for ParaView or pyvista
  history.csv     time, energies, and dx..vz of every tracked point (units in the header)
  summary.json    wall time, cycles, time step, size, layout, speed, time per phase, energies, effects
  engine.log      the engine's own output
and on request (they cost seconds where the run may take less than one):
  <part>.pvd      with --vtk-series: a VTK time series per part (vtk/<part>_NNNNN.vtu)
  energies.png, parts.png, tracked.png, deformed.png   with --plots: pictures

Exit status: 0 on success, 2 for a bad scene or deck, 3 when the run went unstable, 4 when it was
stopped (Ctrl-C, SIGTERM) after writing its checkpoint, 1 otherwise.
"""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="paradyn-run", description=DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    ranks, threads = launch.default_layout()
    parser.add_argument("scene", type=Path, help="scene file (.toml), LS-DYNA keyword deck (.k) or deck (.h5)")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="output folder (default: runs/<name of the scene's folder> under the current folder)")
    parser.add_argument("-n", "--ranks", type=int, default=ranks, help=f"MPI ranks (default {ranks})")
    parser.add_argument("-t", "--threads", type=int, default=threads,
                        help=f"OpenMP threads per rank (default {threads}, one per core)")
    parser.add_argument("--plots", action="store_true",
                        help="also draw energies.png, parts.png, tracked.png and deformed.png")
    parser.add_argument("--vtk-series", action="store_true",
                        help="also write a .pvd series per part (for ParaView before 5.12)")
    parser.add_argument("--no-vtk", action="store_true", help="skip results.vtkhdf (and the .pvd series)")
    parser.add_argument("--no-plots", action="store_true", help="no pictures (the default; undoes --plots)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="no check report and no progress display (the check's warnings still)")
    parser.add_argument("--check", action="store_true",
                        help="check SCENE (mass, stable step, cycles, wall time, memory, initial penetrations, "
                             "unit warnings) and stop")
    parser.add_argument("--force", action="store_true",
                        help="write into an output folder that holds the run of another scene")
    parser.add_argument("--version", action="version", version=version_text())
    parser.add_argument("--sbatch", action="store_true",
                        help="write OUTDIR/job.sbatch for Slurm instead of running")
    batch = parser.add_argument_group("Slurm job script (with --sbatch)")
    batch.add_argument("--time", help="#SBATCH --time (e.g. 2:00:00); the engine checkpoints "
                                      f"{SbatchRunner.signal_lead_s} s before it and the job continues in a new one")
    batch.add_argument("--account", help="#SBATCH --account")
    batch.add_argument("--partition", help="#SBATCH --partition")
    batch.add_argument("--sbatch-line", action="append", default=[], metavar="OPTION",
                       help="another #SBATCH option: --sbatch-line=--mem=8G (repeatable)")
    parser.add_argument("--restart", action="store_true",
                        help="continue an interrupted run in the output folder from its checkpoint "
                             "(results.checkpoint.h5), with the folder's deck.h5")
    parser.add_argument("--post", action="store_true",
                        help="SCENE is an output folder of a finished run: only redo the post-processing")
    return parser


def version_text() -> str:
    """``paradyn-run --version``: the package's version and the engine it runs."""
    try:
        engine = str(launch.engine_path())
    except launch.EngineError:
        engine = "not built (make install)"
    return f"paradyn-run {__version__} (Python {sys.version.split()[0]}; engine {engine})"


def post_only(out_dir: Path, plots: bool, vtk: bool, vtk_series: bool = False) -> int:
    """Post-process the results.h5 and deck.h5 of a run in out_dir, finished or interrupted."""
    res_path, deck_path = out_dir / "results.h5", out_dir / "deck.h5"
    if not (res_path.is_file() and deck_path.is_file()):
        print(f"paradyn-run: error: {out_dir} holds no results.h5 and deck.h5; give the output folder of a run",
              file=sys.stderr)
        return STATUS_BAD_INPUT
    try:
        res = reading.read(res_path, deck=deck_path, allow_incomplete=True)
        if not res.complete:
            last = float(res.time_values[-1]) if res.n_frames else 0.0
            print(f"paradyn-run: {res_path} is of an unfinished run: post-processing its {res.n_frames} "
                  f"frame(s), to t = {last:.4g} s", file=sys.stderr)
        outputs = post_process(res, out_dir, {"post_processed": True, "complete": res.complete},
                               plots=plots, vtk=vtk, vtk_series=vtk_series)
    except (deck.DeckError, reading.ResultsError) as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return STATUS_BAD_INPUT
    _print_outputs(outputs)
    return STATUS_OK


def check_only(source: Path, ranks: int, threads: int, quiet: bool) -> int:
    """``paradyn-run --check``: the check's lines, then the engine's own set-up of the deck."""
    try:
        if not source.is_file():
            raise scene.SceneError(f"{source}: no such file; give the path of a scene .toml, a keyword deck .k "
                                   "or a deck .h5")
        display = None if quiet else RunProgress()
        if display is None:
            model = workflow.model_of(source)
        else:
            with display.stage("reading the deck" if source.suffix in workflow.DECK_SUFFIXES else "meshing"):
                model = workflow.model_of(source)
        check = preflight.check_model(model, ranks, threads)
        engine = preflight.engine_check(model)
    except launch.EngineError as error:
        return _error(error, error.exit_code)
    except (scene.SceneError, deck.DeckError, ValueError) as error:
        return _error(error, STATUS_BAD_INPUT)
    print("\n".join(check.lines()))
    print(f"engine: first step {engine.dt:.4e} s (stable {engine.dt_stable:.4e} s), {engine.steps} steps; "
          f"{len(engine.warnings) or 'no'} warning(s) at set-up")
    for line in engine.warnings:
        print("  " + line)
    return STATUS_OK


def batch_runner(args: argparse.Namespace) -> SbatchRunner | None:
    """The sbatch runner with the command line's Slurm options (None without --sbatch)."""
    slurm = (args.time, args.account, args.partition, *args.sbatch_line)
    if not args.sbatch:
        if any(slurm):
            raise ValueError("--time, --account, --partition and --sbatch-line go with --sbatch")
        return None
    runner = launch.make_runner(SbatchRunner.name, args.ranks)
    assert isinstance(runner, SbatchRunner)
    runner = replace(runner, time=args.time, account=args.account, partition=args.partition,
                     extra_lines=tuple(args.sbatch_line))
    runner.directives(Path("."), args.ranks, args.threads, "check")   # refuses a bad --sbatch-line now
    return runner


def _plots(args: argparse.Namespace) -> bool:
    return args.plots and not args.no_plots


def _print_outputs(outputs: dict[str, Path]) -> None:
    for label, path in outputs.items():
        print(f"  {label:18s} {path}")


def _error(error: Exception, status: int) -> int:
    print(f"paradyn-run: error: {error}", file=sys.stderr)
    return status


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.post:
        return post_only(args.scene.resolve(), plots=_plots(args), vtk=not args.no_vtk, vtk_series=args.vtk_series)
    if args.check:
        return check_only(args.scene, args.ranks, args.threads, args.quiet)
    out_dir = (args.output or default_output(args.scene)).resolve()
    try:
        runner = batch_runner(args)
        if args.scene.is_file():
            claim_output(out_dir, args.scene, force=args.force or args.restart)
        outcome = workflow.run(args.scene, out_dir, args.ranks, args.threads,
                               runner=runner, restart=args.restart,
                               progress=RunProgress(quiet=args.quiet), vtk=not args.no_vtk,
                               plots=_plots(args), vtk_series=args.vtk_series)
    except launch.EngineError as error:
        return _error(error, error.exit_code)
    except reading.ResultsError:
        raise  # the run finished but its results do not read: a bug to show in full
    except (scene.SceneError, deck.DeckError, ValueError) as error:
        return _error(error, STATUS_BAD_INPUT)
    except OSError as error:   # a disk that fills or a file system that fails while writing the outputs
        return _error(OSError(f"{error.strerror or error}; free space (or fix the file system) and rerun"),
                      STATUS_FAILURE)
    if isinstance(outcome, workflow.BatchJob):
        print(f"paradyn-run: wrote {outcome.script}; submit it with: sbatch {outcome.script}")
        return STATUS_OK
    done = outcome.engine_run.done
    print(f"paradyn-run: {done.get('cycles')} cycles in {float(done.get('wall_s', 'nan')):.2f} s "
          f"({float(done.get('element_cycles_per_s', 'nan')):.3e} element-cycles/s); effects:")
    print(effect_table_text(outcome))
    print(accuracy_text(outcome))
    for line in outcome.engine_run.warnings:   # said at the start too, but a long run scrolls it away
        print("  " + line.removeprefix("paradyn-engine: "))
    _print_outputs(outcome.outputs)
    return STATUS_OK


if __name__ == "__main__":
    sys.exit(main())
