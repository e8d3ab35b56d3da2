"""The command-line entry points (``[project.scripts]`` of pyproject.toml).

Each sets the process environment, then loads its tool. One OpenBLAS thread: the commands do no
heavy linear algebra, and starting OpenBLAS's thread pool when numpy loads cost 70 ms of every
``paradyn-run`` (docs/performance.md, "Fixed costs"); a setting of the user's own wins, and a
Python session that imports paradyn keeps its own.

The command's imports (numpy, h5py and the package) run with Python's cyclic garbage collector
paused: it otherwise ran 76 times while they loaded, walking a heap that grows to 29 000
objects, a sixth of their time (docs/performance.md, "Fixed costs"). What they made is then frozen
(:func:`gc.freeze`), out of every later collection's way, and the collector resumes for the run.

A command ends with :func:`os._exit` once its streams are flushed: every file it wrote is closed
by then, and the interpreter's own clean-up (tearing down numpy, h5py and gmsh module by module)
took 25 ms of every ``paradyn-run`` (docs/performance.md, "Fixed costs"). Inside Python call
:func:`paradyn.cli.main` (or :func:`paradyn.run`), which returns.
"""

from __future__ import annotations

import contextlib
import gc
import os
import sys
from collections.abc import Callable, Iterator
from typing import NoReturn


def _settle_environment() -> None:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def paradyn_run() -> NoReturn:
    """``paradyn-run``: :func:`paradyn.cli.main`, with the engine of a scene's run started before
    the heavy imports (:mod:`paradyn.running.early_engine`), so that its start overlaps them."""
    _settle_environment()
    with _collector_paused():
        from .cli_parser import build_parser
        from .running.early_engine import start_early
    args = build_parser().parse_args()
    started = start_early(args)
    with _collector_paused():
        from .cli import run_command

    _leave(_run(lambda: run_command(args, started)))


def paradyn_study() -> NoReturn:
    """``paradyn-study``: :func:`paradyn.studies.cli.main`."""
    _settle_environment()
    with _collector_paused():
        from .studies.cli import main

    _leave(_run(main))


def paradyn_scaling() -> NoReturn:
    """``paradyn-scaling``: :func:`paradyn.benchmark.main`."""
    _settle_environment()
    with _collector_paused():
        from .benchmark import main

    _leave(_run(main))


@contextlib.contextmanager
def _collector_paused() -> Iterator[None]:
    """Imports without the cyclic collector; what they made is frozen out of later collections."""
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        gc.enable()


def _run(main: Callable[[], int]) -> int:
    """The tool's status; a reader of its output that stopped reading (``paradyn-run ... | head``)
    ends it quietly, as it does a Unix tool, instead of with a traceback."""
    try:
        return main()
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())   # the last flush goes nowhere
        return 0


def _leave(status: int | None) -> NoReturn:
    """End the process with ``status`` now: flush the streams, skip the interpreter's clean-up."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):   # a closed pipe or stream: nothing can reach it
            stream.flush()
    os._exit(status or 0)
