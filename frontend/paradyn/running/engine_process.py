"""Follow one engine process: its progress lines, Ctrl-C, its exit status.

A runner (:mod:`paradyn.running.runners`) decides the argument list and the environment; this module
starts the process with them (never a shell string, never ``os.chdir``), turns the engine's
``PARADYN-*`` lines into :class:`Progress` records, writes everything the engine prints to a log,
and decides success: the exit status plus the final ``PARADYN-DONE`` line (docs/formats.md,
"Engine progress lines").
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import signal
import subprocess
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

from paradyn._schema import STATUS_FAILURE, STATUS_OK, STATUS_STOPPED

_FIELD = re.compile(r"(\w+)=\s*(\S+)")


class EngineError(RuntimeError):
    """The engine stopped with a non-zero status; ``exit_code`` keeps that status."""

    def __init__(self, message: str, exit_code: int) -> None:
        super().__init__(message)
        self.exit_code = exit_code


class RunStopped(EngineError):
    """The engine was asked to stop (Ctrl-C, SIGTERM, SIGUSR1, a batch system's time limit), wrote
    its checkpoint and exited with status 4: not an error, a pause. ``time`` and ``cycle`` are
    where it stopped, ``checkpoint`` the file that holds the state; ``str()`` says how to go on
    from Python, and ``paradyn-run`` prints its own command (:func:`paradyn.cli.stopped_text`)."""

    def __init__(self, time: float, cycle: int, checkpoint: Path, how: str = "") -> None:
        self.time, self.cycle, self.checkpoint = time, cycle, checkpoint
        how = how or "paradyn.run(SOURCE, OUT, restart=True) or `paradyn-run SOURCE -o OUT --restart`"
        super().__init__(f"stopped by a signal at t = {time:.6g} s (cycle {cycle}); the checkpoint {checkpoint} "
                         f"holds the state: continue with {how}", STATUS_STOPPED)

    def continuing(self, source: str, out: Path) -> RunStopped:
        """The same stop, its message naming the call that continues it: ``source`` as the caller
        wrote it (a path's repr, or a placeholder for a scene or model object) and the folder."""
        call = f"paradyn.run({source}, {str(out)!r}, restart=True)"
        return RunStopped(self.time, self.cycle, self.checkpoint, how=call)

    @classmethod
    def of(cls, run: EngineRun, folder: Path) -> RunStopped:
        """The stop of ``run``, from its last ``PARADYN-CHECKPOINT`` line (paths relative to the
        engine's folder made whole)."""
        fields = run.checkpoint
        path = Path(fields.get("path", "results.checkpoint.h5"))
        return cls(float(fields.get("time", "nan")), int(fields.get("cycle", 0)), folder / path)


@dataclass
class Progress:
    """One progress line of the engine (times in seconds). ``start_time``: the simulated time this
    engine process started from (a restart's, from its ``PARADYN-RESTART`` line; 0 otherwise), since
    ``wall_s`` counts from that start: the rate, and so the ETA, come from this part of the run."""

    cycle: int
    time: float
    dt: float
    end_time: float
    wall_s: float
    start_time: float = 0.0

    @property
    def fraction(self) -> float:
        return min(1.0, self.time / self.end_time) if self.end_time > 0 else 0.0

    @property
    def eta_s(self) -> float | None:
        done = self.time - self.start_time
        if done <= 0 or self.end_time <= 0:
            return None
        return self.wall_s * max(self.end_time - self.time, 0.0) / done


@dataclass
class EngineRun:
    """What the launcher learned from one engine run: the command, the exit status, the fields of
    the engine's START and DONE lines, the log, the seconds from start to exit, and the engine's
    warnings (a requested step above the stable one, initial contact penetrations)."""

    command: list[str]
    exit_code: int
    start: dict[str, str] = field(default_factory=dict)
    done: dict[str, str] = field(default_factory=dict)
    log_path: Path | None = None
    elapsed_s: float = 0.0
    warnings: list[str] = field(default_factory=list)   #: the engine's ``paradyn-engine: warning:`` lines
    restart: dict[str, str] = field(default_factory=dict)      #: a restart's time and cycle (PARADYN-RESTART)
    checkpoint: dict[str, str] = field(default_factory=dict)   #: the last checkpoint written (PARADYN-CHECKPOINT)

    @property
    def cycles_run(self) -> int | None:
        """The cycles this engine process ran (a restart's own, not those before its checkpoint)."""
        if "cycles" not in self.done:
            return None
        return int(self.done["cycles"]) - int(self.restart.get("cycle", 0))


def parse_line(line: str) -> tuple[str, dict[str, str]] | None:
    """Split `PARADYN-KIND key=value ...` into (KIND, {key: value}); None for other lines."""
    if not line.startswith("PARADYN-"):
        return None
    head = line.split(maxsplit=1)[0]
    fields = dict(_FIELD.findall(line[len(head):]))  # Fortran may pad values: `time= 1.0E-03`
    return head[len("PARADYN-"):], fields


def follow_engine(
    command: list[str],
    environment: dict[str, str],
    folder: Path,
    on_progress: Callable[[Progress], None] | None = None,
    log_path: Path | None = None,
    *,
    on_warning: Callable[[str], None] | None = None,
    done_kind: str = "DONE",
    on_done: Callable[[EngineRun], None] | None = None,
    started: AwaitingEngine | None = None,
) -> EngineRun:
    """Run ``command`` in ``folder`` to completion; raise EngineError with the engine's message
    if it fails. ``started``: the engine was started before its deck existed
    (:func:`start_awaiting`); it is told to go on and followed from there.

    ``on_progress`` gets every progress line, ``on_warning`` every ``paradyn-engine: warning:``
    line as it comes (the initial penetrations come before the first cycle). The run succeeded
    when the status is 0 and the engine printed its ``PARADYN-<done_kind>`` line (``CHECK`` for
    ``paradyn-engine --check``).

    ``on_done`` is called once, with the run so far, as the ``PARADYN-<done_kind>`` line arrives:
    the engine has closed its results file then, and what the caller does with it (reading,
    post-processing) overlaps the engine's own ending (MPI_Finalize; under mpirun the launcher's
    too). The exit status is checked after it returns, as always.

    Ctrl-C (KeyboardInterrupt) does not kill the run: the engine is asked to stop with SIGUSR1
    (which mpirun forwards to every rank), writes its checkpoint and exits with status 4; the
    EngineError then says how to continue. The engine runs in its own session so that the
    terminal's SIGINT reaches only this process, not mpirun (which would kill the ranks)."""
    run = EngineRun(command=command, exit_code=-1, log_path=log_path)
    lines = _LineReader(run, on_progress, on_warning, done_kind, on_done)
    errors = lines.errors
    clock_start = time.perf_counter()
    process = started.go() if started is not None else _spawn(command, environment, folder)
    with EngineLog(log_path) as log, process:
        previous = _forward_stop_signals(process)
        try:
            _read_until_done(process, log, lines)
            run.exit_code = process.wait()
        finally:
            for number, handler in previous.items():
                signal.signal(number, handler)
    run.elapsed_s = time.perf_counter() - clock_start
    if run.exit_code == STATUS_STOPPED and run.checkpoint:
        raise RunStopped.of(run, folder)
    if run.exit_code != STATUS_OK or not run.done:
        message = "; ".join(e for e in errors if "error" in e) or (
            f"the engine stopped with status {run.exit_code} without finishing"
            + (f"; see {log_path}" if log_path and not log.error else ""))
        message = explain_cannot_create(message, folder)
        raise EngineError(message + (f" ({log.error})" if log.error else ""), run.exit_code or STATUS_FAILURE)
    if log.error:   # the run finished; only its log is short
        raise OSError(errno.ENOSPC if "space" in log.error else errno.EIO, log.error, str(log_path))
    return run


_CANNOT_CREATE = re.compile(r"cannot create (?:the checkpoint )?(\S+?);")


def explain_cannot_create(message: str, folder: Path) -> str:
    """The engine's "cannot create FILE" with its reason when that is another program holding the
    file open (an ``h5py.File`` not closed, in this Python session or a notebook; HDFView; any
    HDF5 reader), whose HDF5 lock refuses the engine's create; else the message as it was."""
    found = _CANNOT_CREATE.search(message)
    if found is None:
        return message
    path = folder / found.group(1).removesuffix(".partial")
    if not held_open(path):
        return message
    return (message.replace("; check that the folder exists and is writable", "") +
            ": another program holds it open (an h5py.File not closed, in this Python session or a notebook, "
            "HDFView, another reader of HDF5); close it there (h5py: f.close(), or open it with `with "
            "h5py.File(...)`), or give another output folder, then run again")


def held_open(path: Path) -> bool:
    """True when another open of ``path`` holds a lock on it (HDF5's readers hold a shared flock,
    which the engine's create, asking for an exclusive one, is refused)."""
    import fcntl

    try:
        descriptor = os.open(path, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:
        return False
    finally:
        os.close(descriptor)   # closing drops the lock if it was taken
    return False


def _spawn(command: list[str], environment: dict[str, str], folder: Path, *,
           stdin: int | None = None) -> subprocess.Popen:
    return subprocess.Popen(command, cwd=folder, env=environment, stdin=stdin, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, bufsize=1, start_new_session=True)


@dataclass
class AwaitingEngine:
    """An engine started with ``--await-deck``: it starts MPI and HDF5 while the frontend still
    writes its deck, then waits for :meth:`go` (docs/formats.md, "Checkpoint": the command line).
    ``command`` is the run's own command, without the flag."""

    process: subprocess.Popen
    command: list[str]
    environment: dict[str, str] = field(default_factory=dict)   #: the one it was started in

    def go(self) -> subprocess.Popen:
        """The deck is written: the engine reads it and runs."""
        self._tell("go\n")
        return self.process

    def cancel(self) -> None:
        """No run will come: the engine ends with status 0 without running (the deck file, if written,
        stays). Nothing once it was told to go (its run is followed, and ended, elsewhere)."""
        assert self.process.stdin is not None
        if self.process.stdin.closed:
            return
        self._tell("")
        with self.process:
            self.process.wait()

    def _tell(self, line: str) -> None:
        assert self.process.stdin is not None
        if self.process.stdin.closed:
            return
        with contextlib.suppress(BrokenPipeError):   # an engine that failed to start: its status tells
            self.process.stdin.write(line)
            self.process.stdin.close()


def start_awaiting(command: list[str], environment: dict[str, str], folder: Path) -> AwaitingEngine:
    """Start ``command`` with ``--await-deck`` in ``folder`` (which must exist); it reads no deck
    until :meth:`AwaitingEngine.go`."""
    process = _spawn([*command, "--await-deck"], environment, folder, stdin=subprocess.PIPE)
    return AwaitingEngine(process, command, environment)


class EngineLog:
    """engine.log, written line by line; a disk that fills stops the log, not the run (the engine's
    own status then says what happened to the results), and the failure is kept in ``error``."""

    def __init__(self, path: Path | None) -> None:
        self.path, self.error = path, ""
        self.stream: TextIO | None = None
        try:
            self.stream = open(path or os.devnull, "w")  # noqa: SIM115 - closed in __exit__
        except OSError as error:
            self.error = f"cannot write {path} ({error.strerror})"

    def write(self, line: str) -> None:
        if self.stream is None:
            return
        try:
            self.stream.write(line)
        except OSError as error:
            self.error = f"cannot write {self.path} ({error.strerror})"
            self.close()

    def close(self) -> None:
        stream, self.stream = self.stream, None
        if stream is not None:
            try:
                stream.close()
            except OSError as error:
                self.error = f"cannot write {self.path} ({error.strerror})"

    def __enter__(self) -> EngineLog:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _forward_stop_signals(process: subprocess.Popen) -> dict[int, Any]:
    """While the engine runs, SIGTERM and SIGUSR1 to this process become SIGUSR1 to the engine (which
    mpirun forwards to every rank): the engine writes its checkpoint and exits with status 4, and so
    does paradyn-run (issue 17), instead of this process dying and leaving the run without a
    checkpoint. Returns the handlers to restore (none outside the main thread, where Python cannot
    set them)."""
    if threading.current_thread() is not threading.main_thread():
        return {}

    def forward(number: int, frame: object) -> None:
        if process.poll() is None:
            process.send_signal(signal.SIGUSR1)

    return {number: signal.signal(number, forward) for number in (signal.SIGTERM, signal.SIGUSR1)}


@dataclass
class _LineReader:
    """Takes the engine's output lines one by one into an :class:`EngineRun` and the listeners."""

    run: EngineRun
    on_progress: Callable[[Progress], None] | None
    on_warning: Callable[[str], None] | None
    done_kind: str
    on_done: Callable[[EngineRun], None] | None = None
    errors: list[str] = field(default_factory=list)

    def take(self, line: str) -> None:
        """Record what one output line of the engine says."""
        if line.startswith("paradyn-engine: "):
            self.errors.append(line.strip())
        if line.startswith("paradyn-engine: warning:"):
            self.run.warnings.append(line.strip())
            if self.on_warning is not None:
                self.on_warning(line.strip())
        parsed = parse_line(line)
        if parsed is None:
            return
        kind, fields = parsed
        if kind == "START":
            self.run.start = fields
        elif kind == "RESTART":
            self.run.restart = fields
        elif kind == "CHECKPOINT":
            self.run.checkpoint = fields
        elif kind == self.done_kind:
            self.run.done = fields
            if self.on_done is not None:
                self.on_done(self.run)
        elif kind == "PROGRESS" and self.on_progress is not None:
            self.on_progress(Progress(int(fields["cycle"]), float(fields["time"]), float(fields["dt"]),
                                      float(fields["end_time"]), float(fields["wall_s"]),
                                      float(self.run.restart.get("time", 0.0))))


def _read_until_done(process: subprocess.Popen, log: EngineLog, lines: _LineReader) -> None:
    """Log and take every output line of the engine until it exits. On Ctrl-C, ask the engine to
    checkpoint and stop (SIGUSR1), and keep reading until it has; a second Ctrl-C gives up.

    The KeyboardInterrupt may arrive while a line is read or while it is handled (the progress
    bar writing, for instance): both are inside the guarded loop, so either way the engine gets
    its stop signal rather than being orphaned mid-run."""
    assert process.stdout is not None
    stop_sent = False
    while True:
        try:
            for line in process.stdout:
                log.write(line)
                lines.take(line)
            return
        except KeyboardInterrupt:
            if stop_sent:
                raise
            process.send_signal(signal.SIGUSR1)
            stop_sent = True
