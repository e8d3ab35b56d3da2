"""Runners: how the engine is started on some ranks and threads.

A :class:`Runner` turns (deck, results, ranks, threads, restart) into an argument list and an
environment; :meth:`Runner.run` starts the engine with them and follows it
(:func:`paradyn.running.engine_process.follow_engine`), or goes on with the engine that :meth:`Runner.start`
started before the deck was written. The members:

========== ===============================================================================
``direct`` the engine alone: one rank, no MPI launcher
``mpirun`` Open MPI's ``mpirun``, with every rank and thread pinned to cores of its own when
           the layout fits the machine, ``--oversubscribe`` when it does not
``srun``   Slurm's ``srun``, inside an allocation
``sbatch`` writes a Slurm job script (srun, then the post-processing) instead of running
========== ===============================================================================

:func:`create_runner` builds one by name; without a name it picks what ParaDyn always did:
``srun`` inside a Slurm allocation, else ``direct`` for one rank, else ``mpirun``. A runner only
knows the :class:`Machine` it is given (the engine, the cores, whether to pin), so it decides
nothing from hidden state; :func:`paradyn.running.launch.make_runner` gives it this machine's.
"""

from __future__ import annotations

import os
import shlex
import shutil
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from paradyn._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_STOPPED
from paradyn.atomic_write import write_text_atomic

from .engine_process import AwaitingEngine, EngineError, EngineRun, Progress, follow_engine, start_awaiting


@dataclass(frozen=True)
class Machine:
    """What a runner needs to know about where the engine runs."""

    engine: Path  # the paradyn-engine executable
    cores: int  # the cores this process may run on
    pinning: bool = True  # pin ranks and threads to cores when they fit ($PARADYN_BIND != none)
    busy_cores: float = 0.0  # how many of those cores other work keeps busy (the load average's share)

    def binds_to_cores(self, ranks: int, threads: int) -> bool:
        """Pin every rank and thread to a core of its own when the layout fits the cores that other
        work leaves idle (a rank or thread that migrates loses its cache and can land on a busy
        core, which the others then wait for; a thread pinned to a core that another program
        holds gets its share of that core, and the others wait for it at every barrier: 2 pinned
        threads beside a busy loop ran 10 x slower than 1, docs/performance.md)."""
        return self.pinning and ranks * threads + self.busy_cores <= self.cores + 0.5

    def oversubscribed(self, ranks: int, threads: int) -> bool:
        return ranks * threads > self.cores


# How an OpenMP thread waits at a barrier when the user says nothing (docs/performance.md,
# "Threads on a busy machine"): it sleeps at once. libgomp's default spins about 300 000 times
# first, and a thread that spins holds a core the late thread needs when other programs share the
# machine (even 10 000 spins collapsed there); more ranks x threads than cores are the same case
WAIT_POLICY = {"OMP_WAIT_POLICY": "passive"}
WAIT_VARIABLES = ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")


def engine_environment(threads: int, bind_threads: bool) -> dict[str, str]:
    """The engine's environment: this process's, with ``threads`` OpenMP threads (on neighbouring
    cores of the rank's own set when ``bind_threads``; the user's own placement wins) that wait at
    a barrier as :data:`WAIT_POLICY` says, unless the user set a wait policy of their own."""
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(threads)
    if threads > 1 and bind_threads:
        env.setdefault("OMP_PROC_BIND", "close")
        env.setdefault("OMP_PLACES", "cores")
    if threads > 1 and not any(name in env for name in WAIT_VARIABLES):
        env.update(WAIT_POLICY)
    env["SRUN_CPUS_PER_TASK"] = str(threads)
    env.setdefault("OMP_STACKSIZE", "64M")  # threads with large private arrays need more than the default
    env.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")  # containers without CMA
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
        env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    return env


# A batch system's host list: mpirun may then start ranks on other machines, where the network's
# own transport (UCX on InfiniBand) should be left to choose.
HOST_LIST_VARIABLES = ("PBS_NODEFILE", "LSB_HOSTS", "LSB_MCPU_HOSTS", "PE_HOSTFILE", "OAR_NODEFILE",
                       "OMPI_MCA_orte_default_hostfile")
HWLOC_WITHOUT_IO = "-pci,-linuxio"   # hwloc's topology without the PCI devices (one machine)


def one_machine_mpi(env: dict[str, str]) -> dict[str, str]:
    """Open MPI's ob1 messaging layer (shared memory between the ranks of one machine) instead of
    probing the network libraries, which costs mpirun 0.16 s at start-up, and hwloc's topology
    without its I/O devices (reading every PCI device's configuration costs each process of the
    launch 13 ms; on one machine no network card is chosen by locality) (docs/performance.md,
    "Fixed costs"); the user's own settings win. (The engine alone, on one rank, settles its own
    start-up: fortran/src/app/singleton_start.f90.)"""
    return {**env, "OMPI_MCA_pml": env.get("OMPI_MCA_pml", "ob1"),
            "HWLOC_COMPONENTS": env.get("HWLOC_COMPONENTS", HWLOC_WITHOUT_IO)}


def _engine_arguments(deck: Path, results: Path, restart: bool, ranks: int | None = None) -> list[str]:
    """The engine's arguments; under a launcher, ``--expect-ranks`` makes it refuse to run on another
    number of ranks than it was asked for (an mpirun of another MPI starts N singletons of one rank)."""
    expect = [f"--expect-ranks={ranks}"] if ranks is not None else []
    return [str(deck), str(results), *(["--restart"] if restart else []), *expect]


@dataclass
class Runner(ABC):
    """Starts the engine on a deck; members differ in the command that launches it."""

    machine: Machine
    name: ClassVar[str] = ""

    @abstractmethod
    def command(self, deck: Path, results: Path, ranks: int, threads: int,
                restart: bool = False) -> list[str]:
        """The argument list that runs the engine on ``deck``, writing ``results``; ``restart``
        continues from the checkpoint beside the results (docs/outputs.md)."""

    def environment(self, ranks: int, threads: int) -> dict[str, str]:
        """The environment the engine runs in."""
        return engine_environment(threads, self.machine.binds_to_cores(ranks, threads))

    def run(
        self,
        deck: Path,
        results: Path,
        ranks: int = 1,
        threads: int = 1,
        on_progress: Callable[[Progress], None] | None = None,
        log_path: Path | None = None,
        restart: bool = False,
        on_warning: Callable[[str], None] | None = None,
        on_done: Callable[[EngineRun], None] | None = None,
        started: AwaitingEngine | None = None,
    ) -> EngineRun:
        """Run the engine to completion in the deck's folder; raise EngineError if it fails.
        ``on_done`` runs as the engine reports its end, before it has exited
        (:func:`~paradyn.running.engine_process.follow_engine`); ``started`` is the engine that
        :meth:`start` started for these arguments, told now to go on."""
        if ranks < 1 or threads < 1:
            raise EngineError(f"ranks ({ranks}) and threads ({threads}) must be at least 1", STATUS_BAD_INPUT)
        # the engine runs in the deck's folder, so relative paths would point elsewhere
        deck, results = Path(deck).resolve(), Path(results).resolve()
        command = started.command if started is not None else self.command(deck, results, ranks, threads, restart)
        return follow_engine(command, self.environment(ranks, threads), deck.parent, on_progress, log_path,
                             on_warning=on_warning, on_done=on_done, started=started)

    def start(self, deck: Path, results: Path, ranks: int = 1, threads: int = 1,
              restart: bool = False) -> AwaitingEngine:
        """Start the engine before ``deck`` exists: it starts MPI and HDF5 and waits
        (``--await-deck``, docs/performance.md "Fixed costs"); pass it to :meth:`run` once the deck
        is written, or call its ``cancel``."""
        if ranks < 1 or threads < 1:
            raise EngineError(f"ranks ({ranks}) and threads ({threads}) must be at least 1", STATUS_BAD_INPUT)
        deck, results = Path(deck).resolve(), Path(results).resolve()
        command = self.command(deck, results, ranks, threads, restart)
        return start_awaiting(command, self.environment(ranks, threads), deck.parent)


@dataclass
class DirectRunner(Runner):
    """The engine alone, on one rank (an MPI program runs as a singleton without a launcher)."""

    name: ClassVar[str] = "direct"

    def command(self, deck: Path, results: Path, ranks: int, threads: int,
                restart: bool = False) -> list[str]:
        if ranks != 1:
            raise EngineError(f"the direct runner starts one rank, not {ranks}; use runner='mpirun' "
                              f"(or 'srun' inside Slurm) for several ranks", STATUS_BAD_INPUT)
        return [str(self.machine.engine), *_engine_arguments(deck, results, restart)]


@dataclass
class MpirunRunner(Runner):
    """``mpirun -n RANKS``: ranks pinned to ``threads`` cores each when the layout fits the
    machine, floating otherwise; ``--oversubscribe`` when ranks x threads exceed the cores."""

    name: ClassVar[str] = "mpirun"

    def command(self, deck: Path, results: Path, ranks: int, threads: int,
                restart: bool = False) -> list[str]:
        mpirun = shutil.which("mpirun") or shutil.which("mpiexec")
        if mpirun is None:
            raise EngineError("mpirun is not on PATH; install Open MPI (apt-get install openmpi-bin)", STATUS_FAILURE)
        command = [mpirun, "-n", str(ranks), "-x", "OMP_NUM_THREADS"]
        if self.machine.binds_to_cores(ranks, threads):
            # each rank on `threads` cores of its own; the environment places the threads on them
            command += ["--map-by", f"slot:PE={threads}", "--bind-to", "core"]
            if threads > 1:
                command += ["-x", "OMP_PROC_BIND", "-x", "OMP_PLACES"]
        else:
            command += ["--bind-to", "none"]
        if self.machine.oversubscribed(ranks, threads):
            command.append("--oversubscribe")
        return [*command, str(self.machine.engine), *_engine_arguments(deck, results, restart, ranks)]

    def environment(self, ranks: int, threads: int) -> dict[str, str]:
        env = super().environment(ranks, threads)
        if any(name in env for name in HOST_LIST_VARIABLES):
            return env
        # (more ranks x threads than cores wait passively too, as WAIT_POLICY says: spinning, 2 ranks
        # x 2 threads on 2 cores spun 250 ms a cycle, against 0.2 ms for one rank)
        return one_machine_mpi(env)


@dataclass
class SrunRunner(Runner):
    """Slurm's ``srun`` inside an allocation (Slurm places the ranks and threads)."""

    name: ClassVar[str] = "srun"

    def command(self, deck: Path, results: Path, ranks: int, threads: int,
                restart: bool = False) -> list[str]:
        # Slurm 22.05 and later: srun does not inherit --cpus-per-task, so it is passed explicitly;
        # standard input goes to rank 0 alone, the one that reads it (--await-deck's go: by default
        # srun copies it to every task, and the others would never drain theirs)
        return ["srun", "-n", str(ranks), f"--cpus-per-task={threads}", "--export=ALL", "--input=0",
                str(self.machine.engine), *_engine_arguments(deck, results, restart, ranks)]


def slurm_seconds(text: str) -> int:
    """Seconds of a Slurm ``--time`` (``MM``, ``MM:SS``, ``HH:MM:SS``, ``D-HH``, ``D-HH:MM``,
    ``D-HH:MM:SS``); ValueError for anything else (``UNLIMITED`` included: a chain needs a limit)."""
    days, dash, clock = text.strip().rpartition("-")
    parts = clock.split(":")
    try:
        if dash and not days.isdigit():
            raise ValueError
        numbers = [int(part) for part in parts]
        if any(n < 0 for n in numbers) or not 1 <= len(numbers) <= 3:
            raise ValueError
    except ValueError:
        raise ValueError(f"--time {text!r} is not a Slurm time limit; give MM, HH:MM:SS or D-HH:MM:SS "
                         f"(e.g. 2:00:00)") from None
    if days:   # D-HH, D-HH:MM, D-HH:MM:SS
        hours, minutes, seconds = [*numbers, 0, 0][:3]
        return ((int(days) * 24 + hours) * 60 + minutes) * 60 + seconds
    if len(numbers) == 1:
        return numbers[0] * 60   # MM
    if len(numbers) == 2:
        return numbers[0] * 60 + numbers[1]   # MM:SS
    return (numbers[0] * 60 + numbers[1]) * 60 + numbers[2]


@dataclass
class SbatchRunner(SrunRunner):
    """Writes a Slurm job script that runs the engine with srun, then ``post_command``; it runs
    nothing itself (submit the script with ``sbatch``).

    ``time``, ``account`` and ``partition`` become ``#SBATCH`` lines, as does every entry of
    ``extra_lines`` (``"--mem=8G"`` or ``"#SBATCH --mem=8G"``); ``prologue`` lines (``module load
    openmpi``) run before the engine. Slurm is asked for SIGUSR1 ``signal_lead_s`` seconds before
    the time limit (``--signal``, sent to the engine's ranks): the engine writes its checkpoint and
    stops with status 4, and the script then submits itself again with ``PARADYN_CONTINUE=1``,
    which runs the engine with ``--restart``, up to ``max_jobs`` jobs in all; a job that Slurm
    requeues (``SLURM_RESTART_COUNT``) continues from the checkpoint too (docs/scene.md, "Slurm")."""

    name: ClassVar[str] = "sbatch"
    post_command: list[str] | None = None
    time: str | None = None          # --time, Slurm's formats (MM, HH:MM:SS, D-HH:MM)
    account: str | None = None
    partition: str | None = None
    extra_lines: tuple[str, ...] = ()
    signal_lead_s: int = 300
    prologue: tuple[str, ...] = ()   # shell lines before the engine (module load ...)
    max_jobs: int = 20               # jobs in a chain of continuations, the first included

    def check(self) -> None:
        """Refuse options the job could not honour (ValueError, naming the fix)."""
        if self.time is not None:
            limit = slurm_seconds(self.time)
            if limit <= self.signal_lead_s:
                raise ValueError(f"--time {self.time} ({limit} s) is not longer than the checkpoint lead of "
                                 f"{self.signal_lead_s} s (the engine checkpoints that long before the limit): "
                                 f"give a --time above {self.signal_lead_s // 60}:{self.signal_lead_s % 60:02d} "
                                 f"(e.g. 1:00:00), or a shorter --checkpoint-lead")
        if self.signal_lead_s < 1:
            raise ValueError(f"--checkpoint-lead {self.signal_lead_s} must be at least 1 s")
        if self.max_jobs < 1:
            raise ValueError(f"--max-jobs {self.max_jobs} must be at least 1")
        for line in self.prologue:
            if "\n" in line or not line.strip():
                raise ValueError(f"--sbatch-prologue {line!r} must be one non-empty shell line")
            if line.strip().startswith("#SBATCH"):
                raise ValueError(f"--sbatch-prologue {line!r} is an #SBATCH option, which sbatch reads only above "
                                 f"the commands; give it with --sbatch-line")

    def directives(self, folder: Path, ranks: int, threads: int, job_name: str) -> list[str]:
        """The ``#SBATCH`` lines."""
        self.check()
        options = [f"--job-name={job_name}", f"--ntasks={ranks}", f"--cpus-per-task={threads}",
                   f"--output={folder}/slurm-%j.out", f"--signal=USR1@{self.signal_lead_s}", "--requeue"]
        options += [f"--{key}={value}" for key, value in
                    (("time", self.time), ("account", self.account), ("partition", self.partition)) if value]
        lines = [f"#SBATCH {option}" for option in options]
        for line in self.extra_lines:
            text = line.strip().removeprefix("#SBATCH").strip()
            if not text.startswith("-") or "\n" in text:
                raise ValueError(f"--sbatch-line {line!r} is not an sbatch option; give one like --mem=8G")
            lines.append(f"#SBATCH {text}")
        return lines

    def script(self, deck: Path, results: Path, ranks: int, threads: int, job_name: str) -> str:
        """The job script's text: the prologue, the engine under srun (continuing from the checkpoint
        when the job is a continuation or was requeued by Slurm), a new job when the engine stopped
        at the time limit (status 4) and the chain has jobs left, else the post-processing."""
        folder = results.parent
        script_path = shlex.quote(str(folder / "job.sbatch"))
        checkpoint = shlex.quote(str(results.with_name(results.stem + ".checkpoint.h5")))
        lines = [
            "#!/bin/bash",
            *self.directives(folder, ranks, threads, job_name),
            "set -uo pipefail",
            *self.prologue,
            f"export OMP_NUM_THREADS={threads}",
            f"export SRUN_CPUS_PER_TASK={threads}",
            "export OMP_STACKSIZE=${OMP_STACKSIZE:-64M}",
            "# threads wait at a barrier as paradyn-run's do, unless the job sets a policy of its own",
            'if [ -z "${OMP_WAIT_POLICY:-}${GOMP_SPINCOUNT:-}" ]; then '
            + "; ".join(f"export {name}={value}" for name, value in WAIT_POLICY.items()) + "; fi",
            "job=${PARADYN_JOB_NUMBER:-1}   # this job's place in the chain of continuations",
            "# a continuation (PARADYN_CONTINUE) or a job Slurm requeued goes on from the checkpoint",
            'restart=""',
            'if { [ -n "${PARADYN_CONTINUE:-}" ] || [ "${SLURM_RESTART_COUNT:-0}" -gt 0 ]; } '
            f'&& [ -f {checkpoint} ]; then restart=--restart; fi',
            "status=0",
            shlex.join(self.command(deck, results, ranks, threads)) + " $restart || status=$?",
            f"if [ \"$status\" -eq {STATUS_STOPPED} ]; then",
            f"  if [ \"$job\" -ge {self.max_jobs} ]; then",
            f'    echo "paradyn: the engine stopped with its checkpoint after {self.max_jobs} jobs (--max-jobs); '
            f'continue with: sbatch --export=ALL,PARADYN_CONTINUE=1 {script_path}"',
            f"    exit {STATUS_STOPPED}",
            "  fi",
            '  echo "paradyn: the engine stopped with its checkpoint (time limit); continuing in job $((job + 1))"',
            f"  sbatch --export=ALL,PARADYN_CONTINUE=1,PARADYN_JOB_NUMBER=$((job + 1)) {script_path}",
            "  exit $?",
            "fi",
            'if [ "$status" -ne 0 ]; then exit "$status"; fi',
        ]
        if self.post_command:
            lines.append(shlex.join(self.post_command))
        return "\n".join(lines) + "\n"

    def write_job(self, deck: Path, results: Path, ranks: int, threads: int,
                  job_name: str | None = None) -> Path:
        """Write ``job.sbatch`` beside ``results``; return its path."""
        folder = results.parent
        text = self.script(deck, results, ranks, threads, job_name or f"paradyn-{folder.name}")
        return write_text_atomic(folder / "job.sbatch", text)

    def run(self, deck: Path, results: Path, ranks: int = 1, threads: int = 1,
            on_progress: Callable[[Progress], None] | None = None, log_path: Path | None = None,
            restart: bool = False, on_warning: Callable[[str], None] | None = None,
            on_done: Callable[[EngineRun], None] | None = None, started: AwaitingEngine | None = None) -> EngineRun:
        raise EngineError("the sbatch runner writes a job script and runs nothing; call "
                          "write_job(...), or paradyn.run(..., runner='sbatch'), then submit the "
                          "script with sbatch", STATUS_BAD_INPUT)


RUNNERS: dict[str, type[Runner]] = {
    cls.name: cls for cls in (DirectRunner, MpirunRunner, SrunRunner, SbatchRunner)
}


def automatic_runner_name(ranks: int, inside_slurm: bool) -> str:
    """srun inside a Slurm allocation, else the engine alone for one rank, else mpirun."""
    if inside_slurm:
        return SrunRunner.name
    return DirectRunner.name if ranks == 1 else MpirunRunner.name


def create_runner(name: str | None, machine: Machine, ranks: int = 1, inside_slurm: bool = False) -> Runner:
    """The runner called ``name`` (one of :data:`RUNNERS`) on ``machine``; ``None`` or ``"auto"``
    picks :func:`automatic_runner_name`."""
    if name is None or name == "auto":
        name = automatic_runner_name(ranks, inside_slurm)
    if name not in RUNNERS:
        raise ValueError(f"unknown runner {name!r}; choose one of {', '.join(RUNNERS)} or 'auto'")
    return RUNNERS[name](machine)
