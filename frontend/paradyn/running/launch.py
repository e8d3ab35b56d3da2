"""Launch the Fortran engine on a deck and follow its progress.

This module knows this machine: where the engine is, which cores this process may use, whether
it runs inside a Slurm allocation, and the default layout. From these it builds the runner
(:mod:`paradyn.running.runners`) that starts the engine: ``srun`` inside Slurm, the engine alone for one
rank, ``mpirun`` otherwise, or the one named. Success is the exit status plus the engine's final
``PARADYN-DONE`` line (:mod:`paradyn.running.engine_process`); the engine's own output goes to the log.
"""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Callable
from dataclasses import replace
from importlib import resources
from pathlib import Path

from paradyn._schema import STATUS_BAD_INPUT, STATUS_FAILURE

from .engine_process import AwaitingEngine, EngineError, EngineRun, Progress, parse_line
from .progress import RunProgress as ProgressBar  # the name before the tqdm display
from .runners import Machine, Runner, create_runner
from .runners import engine_environment as _environment_for

ENGINE_ENV = "PARADYN_ENGINE"
MIXED_ENGINE_ENV = "PARADYN_ENGINE_MIXED"   # the mixed-precision engine ([run] precision = "mixed")
# the engine of each precision (/control precision; docs/theory.md, "Precision"): its executable's
# name inside the package and the variable that points at another build of it
ENGINES = {"double": ("paradyn-engine", ENGINE_ENV), "mixed": ("paradyn-engine-mixed", MIXED_ENGINE_ENV)}
# "auto" (the default): pin ranks and threads to cores when the layout fits the cores other work
# leaves idle; "cores": pin whenever the layout fits; "none": let them float over the cores
BIND_ENV = "PARADYN_BIND"

__all__ = [
    "BIND_ENV", "ENGINES", "ENGINE_ENV", "MIXED_ENGINE_ENV", "AwaitingEngine", "EngineError", "EngineRun", "Progress",
    "ProgressBar",
    "available_cores", "binds_to_cores", "current_machine", "deck_precision", "default_layout", "engine_command",
    "engine_environment", "engine_path", "inside_slurm", "make_runner", "parse_line", "run_engine",
    "start_engine",
]


def engine_path(precision: str | None = None) -> Path:
    """The engine executable of ``precision`` ("double", the default, or "mixed"): $PARADYN_ENGINE
    (double) or $PARADYN_ENGINE_MIXED (mixed) if set, else the one installed inside the package."""
    precision = precision or "double"
    if precision not in ENGINES:
        raise EngineError(f"unknown precision {precision!r}; give one of {', '.join(ENGINES)}", STATUS_BAD_INPUT)
    name, variable = ENGINES[precision]
    override = os.environ.get(variable)
    if override:
        path = Path(override)
    else:
        path = Path(str(resources.files("paradyn") / "bin" / name))
    if not path.is_file():
        raise EngineError(
            f"the engine executable {path} does not exist; reinstall ParaDyn with `make install` "
            f"(or `pip install .`), or point ${variable} at a {name} you built with CMake "
            f"(-DPARADYN_PRECISION={precision})",
            exit_code=STATUS_FAILURE,
        )
    return path


def deck_precision(deck: Path) -> str:
    """The precision a deck asks for: its /control attribute ``precision``, "double" without it
    (or when the file cannot be read: the engine then says what is wrong with it)."""
    import h5py  # here, not at the top: paradyn-run's start-up loads only what it uses

    try:
        with h5py.File(deck, "r") as f:
            raw = f["control"].attrs.get("precision") if "control" in f else None
    except OSError:
        return "double"
    if isinstance(raw, bytes):
        raw = raw.decode("utf-8", "replace")
    return raw if isinstance(raw, str) and raw in ENGINES else "double"


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def pinning_allowed() -> bool:
    """False when $PARADYN_BIND is "none" (ranks and threads then float over the cores)."""
    return os.environ.get(BIND_ENV, "auto").lower() != "none"


BUSY_REFRESH_S = 30.0   # the load is read again after this long (a session runs many runs)
_busy_seen: list[tuple[float, float]] = []   # (monotonic time, busy cores) of the last reading


def busy_cores() -> float:
    """How many of this process's cores other work keeps busy: the 1-minute load average, as a
    share of the machine's cores times the cores this process may use; 0 when $PARADYN_BIND is
    "cores" (pin whenever the layout fits) or "none" (never pin), or the system has no load average. Read at most every
    30 s, so that the engine started before the imports and the run after them agree
    (docs/performance.md, "Threads on a busy machine")."""
    if os.environ.get(BIND_ENV, "auto").lower() in ("cores", "none") or not hasattr(os, "getloadavg"):
        return 0.0
    now = time.monotonic()
    if _busy_seen and now - _busy_seen[0][0] < BUSY_REFRESH_S:
        return _busy_seen[0][1]
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = 0.0
    busy = load * available_cores() / max(1, os.cpu_count() or 1)
    _busy_seen[:] = [(now, busy)]
    return busy


def binds_to_cores(ranks: int, threads: int) -> bool:
    """Pin every rank and thread to a core of its own when the layout fits the cores other work
    leaves idle (a rank or thread that migrates loses its cache and can land on a busy core,
    which the others then wait for; but one pinned to a core another program holds runs at its
    share of that core, and the others wait for it), unless $PARADYN_BIND is "none"."""
    return current_machine_layout().binds_to_cores(ranks, threads)


def current_machine_layout() -> Machine:
    """This machine's cores and pinning, without the engine (:func:`current_machine` adds it)."""
    return Machine(engine=Path(), cores=available_cores(), pinning=pinning_allowed(), busy_cores=busy_cores())


def default_layout() -> tuple[int, int]:
    """One rank and one thread per core this process may use (its CPU affinity, as pinning counts
    them): OpenMP inside a rank is the cheapest layout on one machine."""
    return 1, available_cores()


def engine_environment(threads: int, ranks: int = 1) -> dict[str, str]:
    """The environment the engine runs in on ``ranks`` x ``threads`` on this machine."""
    return _environment_for(threads, bind_threads=binds_to_cores(ranks, threads))


def inside_slurm() -> bool:
    """True inside a Slurm allocation (SLURM_JOB_ID set and srun on PATH)."""
    return "SLURM_JOB_ID" in os.environ and shutil.which("srun") is not None


def current_machine(precision: str | None = None) -> Machine:
    """This machine, as runners see it: the engine of ``precision`` (double by default), the cores
    this process may use, $PARADYN_BIND."""
    return replace(current_machine_layout(), engine=engine_path(precision))


def make_runner(runner: str | Runner | None = None, ranks: int = 1, precision: str | None = None) -> Runner:
    """A runner for this machine: ``runner`` itself if it is one, else the one of that name
    (``"direct"``, ``"mpirun"``, ``"srun"``, ``"sbatch"``); ``None`` or ``"auto"``: srun inside
    a Slurm allocation, the engine alone for one rank, mpirun otherwise.

    Examples
    --------
    >>> from paradyn.running import launch
    >>> launch.make_runner("mpirun").command(Path("d/deck.h5"), Path("d/results.h5"), 2, 1)  # doctest: +SKIP
    ['/usr/bin/mpirun', '-n', '2', '-x', 'OMP_NUM_THREADS', '--map-by', 'slot:PE=1', ...]
    """
    if isinstance(runner, Runner):
        # a runner made before the deck (paradyn-run --sbatch) has the double engine; a mixed deck
        # takes the mixed one (the double engine would refuse it)
        if precision == "mixed" and runner.machine.engine != engine_path("mixed"):
            return replace(runner, machine=replace(runner.machine, engine=engine_path("mixed")))
        return runner
    return create_runner(runner, current_machine(precision), ranks, inside_slurm())


def engine_command(deck: Path, results: Path, ranks: int, threads: int, restart: bool = False) -> list[str]:
    """The argument list the automatic runner uses to run the engine on `ranks` MPI ranks: srun
    inside a Slurm allocation, the engine itself for one rank, mpirun otherwise. restart: continue
    from the checkpoint beside the results (docs/outputs.md, "Checkpoints and restarts")."""
    return make_runner(None, ranks, deck_precision(deck)).command(deck, results, ranks, threads, restart)


def run_engine(
    deck: Path,
    results: Path,
    ranks: int = 1,
    threads: int = 1,
    on_progress: Callable[[Progress], None] | None = None,
    log_path: Path | None = None,
    restart: bool = False,
    runner: str | Runner | None = None,
    on_warning: Callable[[str], None] | None = None,
    on_done: Callable[[EngineRun], None] | None = None,
    started: AwaitingEngine | None = None,
) -> EngineRun:
    """Run the engine to completion; raise EngineError with the engine's message if it fails.
    ``started``: the engine :func:`start_engine` started with these arguments before the deck
    was written.

    ``on_done`` runs as the engine prints its ``PARADYN-DONE`` line (its results file closed),
    while the engine process ends (:func:`paradyn.running.engine_process.follow_engine`).

    ``runner`` picks how (see :func:`make_runner`; by default as :func:`engine_command`); the
    engine is that of the deck's precision (:func:`deck_precision`).
    Ctrl-C (KeyboardInterrupt) does not kill the run: the engine is asked to stop with SIGUSR1
    (which mpirun forwards to every rank), writes its checkpoint and exits with status 4; the
    EngineError then says how to continue."""
    if ranks < 1 or threads < 1:
        raise EngineError(f"ranks ({ranks}) and threads ({threads}) must be at least 1", STATUS_BAD_INPUT)
    precision = None if started is not None else deck_precision(deck)   # a started engine is the deck's already
    return make_runner(runner, ranks, precision).run(deck, results, ranks, threads, on_progress=on_progress,
                                                                 log_path=log_path, restart=restart,
                                                                 on_warning=on_warning, on_done=on_done,
                                                                 started=started)


def start_engine(deck: Path, results: Path, ranks: int = 1, threads: int = 1, runner: str | Runner | None = None,
                 precision: str | None = None) -> AwaitingEngine:
    """Start the engine of ``precision`` for a deck not yet written (``--await-deck``): MPI's
    start-up overlaps the meshing and the deck's writing (docs/performance.md, "Fixed costs").
    Hand it to :func:`run_engine` (``started=``) once the deck is there, or cancel it."""
    return make_runner(runner, ranks, precision).start(deck, results, ranks, threads)
