"""`paradyn-run`: mesh a scene, write the deck, run the engine, post-process the results."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from . import deck, launch, reading, scene, workflow
from ._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_OK
from .postprocess import post_process
from .reports import accuracy_text, effect_table_text

DESCRIPTION = """\
Run a ParaDyn scene end to end.

SCENE is a TOML scene file (see docs/scene.md), an LS-DYNA keyword deck (.k, .key, .dyn; the
subset of docs/keyword.md) or a deck.h5 written earlier (docs/formats.md).
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
  results.vtkhdf  every frame of every part in one file (VTKHDF), for ParaView or pyvista
  <part>.pvd      a VTK time series per part (vtk/<part>_NNNNN.vtu), for ParaView or pyvista
  history.csv     time, energies, and dx..vz of every tracked point (units in the header)
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
    parser.add_argument("scene", type=Path, help="scene file (.toml), LS-DYNA keyword deck (.k) or deck (.h5)")
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


def post_only(out_dir: Path, plots: bool, vtk: bool) -> int:
    """Post-process the results.h5 and deck.h5 of a finished run in out_dir."""
    res_path, deck_path = out_dir / "results.h5", out_dir / "deck.h5"
    if not (res_path.is_file() and deck_path.is_file()):
        print(f"paradyn-run: error: {out_dir} holds no results.h5 and deck.h5; give the output folder of a run",
              file=sys.stderr)
        return STATUS_BAD_INPUT
    try:
        res = reading.read(res_path, deck=deck_path)
        outputs = post_process(res, out_dir, {"post_processed": True}, plots=plots, vtk=vtk)
    except (deck.DeckError, reading.ResultsError) as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return STATUS_BAD_INPUT
    _print_outputs(outputs)
    return STATUS_OK


def _print_outputs(outputs: dict[str, Path]) -> None:
    for label, path in outputs.items():
        print(f"  {label:18s} {path}")


def _error(error: Exception, status: int) -> int:
    print(f"paradyn-run: error: {error}", file=sys.stderr)
    return status


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.post:
        return post_only(args.scene.resolve(), plots=not args.no_plots, vtk=not args.no_vtk)
    out_dir = (args.output or default_output(args.scene)).resolve()
    try:
        outcome = workflow.run(args.scene, out_dir, args.ranks, args.threads,
                               runner="sbatch" if args.sbatch else None, restart=args.restart,
                               progress=not args.quiet, vtk=not args.no_vtk, plots=not args.no_plots)
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
