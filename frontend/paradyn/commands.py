"""The command-line entry points (``[project.scripts]`` of pyproject.toml).

Each sets the process environment, then loads its tool. One OpenBLAS thread: the commands do no
heavy linear algebra, and starting OpenBLAS's thread pool when numpy loads cost 70 ms of every
``paradyn-run`` (docs/performance.md, "Fixed costs"); a setting of the user's own wins, and a
Python session that imports paradyn keeps its own.
"""

from __future__ import annotations

import os


def _settle_environment() -> None:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def paradyn_run() -> int:
    """``paradyn-run``: :func:`paradyn.cli.main`."""
    _settle_environment()
    from .cli import main

    return main()


def paradyn_study() -> int:
    """``paradyn-study``: :func:`paradyn.study_cli.main`."""
    _settle_environment()
    from .study_cli import main

    return main()


def paradyn_scaling() -> int:
    """``paradyn-scaling``: :func:`paradyn.benchmark.main`."""
    _settle_environment()
    from .benchmark import main

    return main()
