"""`paradyn-run`'s command line: its options and help. Light (no numpy, h5py or gmsh), so that the
command can read its arguments and start the engine before the heavy imports
(:mod:`paradyn.running.early_engine`)."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from . import __version__
from .running import launch
from .running.runners import SbatchRunner

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
paradyn-run meshes the parts (or reads their mesh files), writes OUTDIR/deck.h5 (checked before
launch), runs the engine under MPI (-n ranks) and OpenMP (-t threads per rank) with a progress
bar, and writes into OUTDIR:

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
    parser.add_argument("--units", metavar="SYSTEM",
                        help="the unit system of a keyword deck without *CONTROL_UNITS: SI, mm-t-s, mm-kg-ms or "
                             "mm-g-ms (docs/keyword.md, Units); its numbers are converted to SI")
    parser.add_argument("--check", action="store_true",
                        help="check SCENE (mass, stable step, cycles, wall time, memory, initial penetrations, "
                             "unit warnings) and stop")
    parser.add_argument("--force", action="store_true",
                        help="write into an output folder that holds the run of another scene")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="the package's version and the engine's build (commit, precision, compiler and "
                             "flags, MPI, HDF5), then exit")
    parser.add_argument("--sbatch", action="store_true",
                        help="write OUTDIR/job.sbatch for Slurm instead of running")
    batch = parser.add_argument_group("Slurm job script (with --sbatch)")
    batch.add_argument("--time", help="#SBATCH --time (e.g. 2:00:00); the engine checkpoints "
                                      f"{SbatchRunner.signal_lead_s} s before it and the job continues in a new one")
    batch.add_argument("--account", help="#SBATCH --account")
    batch.add_argument("--partition", help="#SBATCH --partition")
    batch.add_argument("--sbatch-line", action="append", default=[], metavar="OPTION",
                       help="another #SBATCH option: --sbatch-line=--mem=8G (repeatable)")
    batch.add_argument("--sbatch-prologue", action="append", default=[], metavar="LINE",
                       help="a shell line run before the engine: --sbatch-prologue 'module load openmpi' "
                            "(repeatable)")
    batch.add_argument("--checkpoint-lead", type=int, default=None, metavar="SECONDS",
                       help=f"seconds before the time limit at which the engine checkpoints and the job "
                            f"continues in a new one (default {SbatchRunner.signal_lead_s})")
    batch.add_argument("--max-jobs", type=int, default=None, metavar="N",
                       help=f"jobs in the chain of continuations at most, the first included (default "
                            f"{SbatchRunner.max_jobs})")
    parser.add_argument("--restart", action="store_true",
                        help="continue an interrupted run in the output folder from its checkpoint "
                             "(results.checkpoint.h5), with the folder's deck.h5")
    parser.add_argument("--post", action="store_true",
                        help="SCENE is an output folder of a finished run: only redo the post-processing")
    return parser


def version_text() -> str:
    """``paradyn-run --version``: the package's version, the engine it runs and that engine's own
    ``--version`` (its commit, precision, compiler and flags, MPI and HDF5)."""
    try:
        engine = launch.engine_path()
    except launch.EngineError:
        return f"paradyn-run {__version__} (Python {sys.version.split()[0]}; engine not built: make install)"
    head = f"paradyn-run {__version__} (Python {sys.version.split()[0]}; engine {engine})"
    try:
        build = subprocess.run([str(engine), "--version"], capture_output=True, text=True, timeout=60,
                               env=launch.engine_environment(1)).stdout.strip()
    except (OSError, subprocess.TimeoutExpired) as exc:
        build = f"(the engine's --version failed: {exc})"
    return f"{head}\n{build}"


class _Version(argparse.Action):
    """--version, computed only when asked for (it runs the engine once)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:
        print(version_text())
        parser.exit()
