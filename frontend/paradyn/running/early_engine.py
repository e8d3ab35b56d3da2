"""The engine of a ``paradyn-run SCENE.toml`` started before the command's heavy imports.

The engine's own start (MPI, HDF5, its libraries: about 22 ms on one rank) and the frontend's
imports (numpy, h5py, the package: about 100 ms) then run side by side, and the engine waits
(``--await-deck``) until the scene is meshed and its deck written (docs/performance.md, "Fixed
costs"). This module imports nothing heavy: it reads only the scene's ``[run] precision``, which
chooses the engine, with :mod:`tomllib`.

Only a plain run of a scene file starts early. Anything this module cannot settle (a keyword deck
or deck.h5, whose precision is known once read; a scene that does not parse; an output folder
that cannot be made) starts nothing here, and the command's own path reports it as before. The
command hands the engine to :func:`paradyn.running.workflow.run` (``started=``), which checks that it is
the engine the run needs (else cancels it and starts the right one) and cancels it when the run
fails before its deck is written; an engine left waiting also ends when the command's process
does (its standard input closes).
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

from paradyn._schema import ENUMS

from . import launch
from .engine_process import AwaitingEngine, EngineError
from .folders import OutputFolderError, default_output, output_folder

RESULTS_NAME = "results.h5"   # what paradyn-run writes (workflow.run's default)


def scene_precision(path: Path) -> str | None:
    """The precision a scene file's ``[run]`` asks for ("double" when it names none); None when the
    file is no scene this can read (the command's own path then says what is wrong)."""
    if path.suffix.lower() != ".toml" or not path.is_file():
        return None
    try:
        with path.open("rb") as stream:
            table = tomllib.load(stream)
    except (OSError, ValueError):   # unreadable, not UTF-8 (UnicodeDecodeError), not TOML (TOMLDecodeError)
        return None
    run = table.get("run", {})
    precision = run.get("precision", "double") if isinstance(run, dict) else None
    return precision if precision in ENUMS["precision"] else None


def start_early(args: argparse.Namespace) -> AwaitingEngine | None:
    """The engine for ``paradyn-run``'s parsed ``args``, started and waiting for its deck; None when
    the command does not run a scene file now (``--check``, ``--post``, ``--restart``, ``--sbatch``,
    another kind of source) or something is not settled yet."""
    if args.check or args.post or args.restart or args.sbatch:
        return None
    precision = scene_precision(args.scene)
    if precision is None:
        return None
    out = (args.output or default_output(args.scene)).resolve()
    try:
        out = output_folder(out)
        return launch.start_engine(out / "deck.h5", out / RESULTS_NAME, args.ranks, args.threads, None, precision)
    except (OutputFolderError, EngineError, OSError):
        return None
