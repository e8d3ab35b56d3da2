"""Launch the Fortran engine on a deck and follow its progress.

The engine runs as a subprocess with an argument list and a working folder (never a shell string,
never ``os.chdir``). One rank runs the engine directly; several ranks run it under ``mpirun``.
Success is the exit status plus the engine's final ``PARADYN-DONE`` line; the engine's own output
goes to ``engine.log`` in the output folder.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Callable, Iterator, TextIO

ENGINE_ENV = "PARADYN_ENGINE"
BIND_ENV = "PARADYN_BIND"   # "none": let the ranks and threads float over the cores
_FIELD = re.compile(r"(\w+)=\s*(\S+)")


class EngineError(RuntimeError):
    """The engine stopped with a non-zero status; ``exit_code`` keeps that status."""

    def __init__(self, message: str, exit_code: int) -> None:
        super().__init__(message)
        self.exit_code = exit_code


@dataclass
class Progress:
    """One progress line of the engine (times in seconds)."""

    cycle: int
    time: float
    dt: float
    end_time: float
    wall_s: float

    @property
    def fraction(self) -> float:
        return min(1.0, self.time / self.end_time) if self.end_time > 0 else 0.0

    @property
    def eta_s(self) -> float | None:
        f = self.fraction
        return self.wall_s * (1.0 - f) / f if f > 0 else None


@dataclass
class EngineRun:
    """What the launcher learned from one engine run."""

    command: list[str]
    exit_code: int
    start: dict[str, str] = field(default_factory=dict)
    done: dict[str, str] = field(default_factory=dict)
    log_path: Path | None = None


def engine_path() -> Path:
    """The engine executable: $PARADYN_ENGINE if set, else the one installed inside the package."""
    override = os.environ.get(ENGINE_ENV)
    if override:
        path = Path(override)
    else:
        path = Path(str(resources.files("paradyn") / "bin" / "paradyn-engine"))
    if not path.is_file():
        raise EngineError(
            f"the engine executable {path} does not exist; reinstall ParaDyn with `make install` "
            f"(or `pip install .`), or point ${ENGINE_ENV} at a paradyn-engine you built with CMake",
            exit_code=1,
        )
    return path


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def binds_to_cores(ranks: int, threads: int) -> bool:
    """Pin every rank and thread to a core of its own when the layout fits the machine (a rank
    or thread that migrates loses its cache and can land on a busy core, which the others then
    wait for), unless $PARADYN_BIND is "none"."""
    return os.environ.get(BIND_ENV, "cores").lower() != "none" and ranks * threads <= available_cores()


def default_layout() -> tuple[int, int]:
    """One rank and one thread per core this process may use (its CPU affinity, as pinning counts
    them): OpenMP inside a rank is the cheapest layout on one machine."""
    return 1, available_cores()


def engine_environment(threads: int, ranks: int = 1) -> dict[str, str]:
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    if threads > 1 and binds_to_cores(ranks, threads):
        # threads on neighbouring cores of the rank's own set; the user's settings win
        env.setdefault("OMP_PROC_BIND", "close")
        env.setdefault("OMP_PLACES", "cores")
    env["SRUN_CPUS_PER_TASK"] = str(threads)
    env.setdefault("OMP_STACKSIZE", "64M")  # threads with large private arrays need more than the default
    env.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")  # containers without CMA
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
        env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    return env


def inside_slurm() -> bool:
    """True inside a Slurm allocation (SLURM_JOB_ID set and srun on PATH)."""
    return "SLURM_JOB_ID" in os.environ and shutil.which("srun") is not None


def srun_command(engine: str, deck: Path, results: Path, ranks: int, threads: int,
                 restart: bool = False) -> list[str]:
    # Slurm 22.05 and later: srun does not inherit --cpus-per-task, so it is passed explicitly
    return ["srun", "-n", str(ranks), f"--cpus-per-task={threads}", "--export=ALL", engine, str(deck), str(results),
            *(["--restart"] if restart else [])]


def engine_command(deck: Path, results: Path, ranks: int, threads: int, restart: bool = False) -> list[str]:
    """The argument list that runs the engine on `ranks` MPI ranks: srun inside a Slurm
    allocation, the engine itself for one rank, mpirun otherwise. restart: continue from the
    checkpoint beside the results (docs/outputs.md, "Checkpoints and restarts")."""
    engine = str(engine_path())
    arguments = [str(deck), str(results), *(["--restart"] if restart else [])]
    if inside_slurm():
        return srun_command(engine, deck, results, ranks, threads, restart)
    if ranks == 1:
        return [engine, *arguments]
    mpirun = shutil.which("mpirun") or shutil.which("mpiexec")
    if mpirun is None:
        raise EngineError("mpirun is not on PATH; install Open MPI (apt-get install openmpi-bin)", 1)
    command = [mpirun, "-n", str(ranks), "-x", "OMP_NUM_THREADS"]
    if binds_to_cores(ranks, threads):
        # each rank on `threads` cores of its own; engine_environment places the threads on them
        command += ["--map-by", f"slot:PE={threads}", "--bind-to", "core"]
        if threads > 1:
            command += ["-x", "OMP_PROC_BIND", "-x", "OMP_PLACES"]
    else:
        command += ["--bind-to", "none"]
    if ranks * threads > available_cores():
        command.append("--oversubscribe")
    return command + [engine, *arguments]


def sbatch_script(deck: Path, results: Path, ranks: int, threads: int, job_name: str,
                  post_command: list[str]) -> str:
    """A batch script that runs the engine with srun on `ranks` x `threads`, then `post_command`."""
    engine = str(engine_path())
    folder = results.parent
    lines = [
        "#!/bin/bash",
        f"#SBATCH --job-name={job_name}",
        f"#SBATCH --ntasks={ranks}",
        f"#SBATCH --cpus-per-task={threads}",
        f"#SBATCH --output={folder}/slurm-%j.out",
        "set -euo pipefail",
        f"export OMP_NUM_THREADS={threads}",
        f"export SRUN_CPUS_PER_TASK={threads}",
        "export OMP_STACKSIZE=${OMP_STACKSIZE:-64M}",
        " ".join(shlex.quote(a) for a in srun_command(engine, deck, results, ranks, threads)),
        " ".join(shlex.quote(a) for a in post_command),
    ]
    return "\n".join(lines) + "\n"


def parse_line(line: str) -> tuple[str, dict[str, str]] | None:
    """Split `PARADYN-KIND key=value ...` into (KIND, {key: value}); None for other lines."""
    if not line.startswith("PARADYN-"):
        return None
    head = line.split(maxsplit=1)[0]
    fields = dict(_FIELD.findall(line[len(head):]))  # Fortran may pad values: `time= 1.0E-03`
    return head[len("PARADYN-"):], fields


def run_engine(
    deck: Path,
    results: Path,
    ranks: int = 1,
    threads: int = 1,
    on_progress: Callable[[Progress], None] | None = None,
    log_path: Path | None = None,
    restart: bool = False,
) -> EngineRun:
    """Run the engine to completion; raise EngineError with the engine's message if it fails.

    Ctrl-C (KeyboardInterrupt) does not kill the run: the engine is asked to stop with SIGUSR1
    (which mpirun forwards to every rank), writes its checkpoint and exits with status 4; the
    EngineError then says how to continue. The engine runs in its own session so that the
    terminal's SIGINT reaches only this process, not mpirun (which would kill the ranks)."""
    if ranks < 1 or threads < 1:
        raise EngineError(f"ranks ({ranks}) and threads ({threads}) must be at least 1", 2)
    # the engine runs in the deck's folder, so relative paths would point elsewhere
    deck, results = Path(deck).resolve(), Path(results).resolve()
    command = engine_command(deck, results, ranks, threads, restart)
    run = EngineRun(command=command, exit_code=-1, log_path=log_path)
    log: TextIO = open(log_path, "w") if log_path else open(os.devnull, "w")
    errors: list[str] = []
    with log, subprocess.Popen(
        command, cwd=deck.parent, env=engine_environment(threads, ranks), stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT, text=True, bufsize=1, start_new_session=True,
    ) as process:
        assert process.stdout is not None
        for line in _lines_until_done(process):
            log.write(line)
            parsed = parse_line(line)
            if line.startswith("paradyn-engine: "):
                errors.append(line.strip())
            if parsed is None:
                continue
            kind, fields = parsed
            if kind == "START":
                run.start = fields
            elif kind == "DONE":
                run.done = fields
            elif kind == "PROGRESS" and on_progress is not None:
                on_progress(Progress(int(fields["cycle"]), float(fields["time"]), float(fields["dt"]),
                                     float(fields["end_time"]), float(fields["wall_s"])))
        run.exit_code = process.wait()
    if run.exit_code != 0 or not run.done:
        message = "; ".join(e for e in errors if "error" in e) or (
            f"the engine stopped with status {run.exit_code} without finishing"
            + (f"; see {log_path}" if log_path else ""))
        raise EngineError(message, run.exit_code or 1)
    return run


def _lines_until_done(process: subprocess.Popen) -> Iterator[str]:
    """The engine's output lines; on Ctrl-C, ask the engine to checkpoint and stop, and keep
    reading until it has."""
    assert process.stdout is not None
    stop_sent = False
    while True:
        try:
            for line in process.stdout:
                yield line
            return
        except KeyboardInterrupt:
            if stop_sent:
                raise
            process.send_signal(signal.SIGUSR1)
            stop_sent = True


class ProgressBar:
    """A one-line progress bar on a terminal, or a line every tenth of the run otherwise."""

    def __init__(self, stream: TextIO = sys.stderr, width: int = 30) -> None:
        self.stream = stream
        self.width = width
        self.tty = stream.isatty()
        self.last_tenth = -1
        self.started = time.monotonic()

    def __call__(self, p: Progress) -> None:
        eta = p.eta_s
        text = (f"t = {p.time:.4e} / {p.end_time:.4e} s  cycle {p.cycle}  dt {p.dt:.3e} s  "
                f"ETA {eta:.1f} s" if eta is not None else "")
        if self.tty:
            filled = int(self.width * p.fraction)
            self.stream.write(f"\r[{'#' * filled}{'.' * (self.width - filled)}] {100 * p.fraction:5.1f}% {text}")
            self.stream.flush()
        elif int(10 * p.fraction) > self.last_tenth:
            self.last_tenth = int(10 * p.fraction)
            self.stream.write(f"{100 * p.fraction:5.1f}% {text}\n")

    def close(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()
