"""``paradyn.run``: a scene, a model or a deck in; the engine run; a results object out.

The one sequence every caller used to write by hand (``paradyn-run``, ``paradyn-scaling``, the
test models, the studies): write the deck into the output folder, run the engine through a runner
(:mod:`paradyn.running.runners`), read ``results.h5``, post-process as asked.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from paradyn import deck, scene
from paradyn.arguments import checked_arguments
from paradyn.results.postprocess import post_process
from paradyn.results.reading import Results, read
from paradyn.scene.builder import Scene as SceneBuilder

from . import launch, preflight
from .engine_process import Progress, RunStopped
from .folders import check_owner, claim_output, output_folder, source_identity
from .progress import RunProgress
from .restart import restart_deck
from .run_warnings import EngineWarning, KeywordWarning, ModelWarning, check_line, issue, message_of
from .runners import Runner, SbatchRunner

Source = str | Path | scene.Scene | SceneBuilder | deck.Model  # what paradyn.run accepts
DECK_SUFFIXES = (".h5", ".hdf5")
KEYWORD_SUFFIXES = (".k", ".key", ".dyn")   # LS-DYNA keyword decks (docs/keyword.md)


@dataclass(frozen=True)
class BatchJob:
    """A Slurm job script written by the ``sbatch`` runner instead of a run."""

    script: Path
    deck: Path

    @property
    def submit_command(self) -> list[str]:
        return ["sbatch", str(self.script)]


@checked_arguments("paradyn.run")
def run(
    source: Source,
    out: str | Path,
    ranks: int | None = None,
    threads: int | None = None,
    runner: str | Runner | None = None,
    *,
    post: bool = True,
    vtk: bool = True,
    history: bool = True,
    summary: bool = True,
    plots: bool = False,
    vtk_series: bool = False,
    restart: bool = False,
    progress: bool | RunProgress | Callable[[Progress], None] = False,
    extra: dict[str, Any] | None = None,
    results_name: str = "results.h5",
    log_name: str | None = "engine.log",
    started: launch.AwaitingEngine | None = None,
    force: bool = False,
) -> Results | BatchJob:
    """Write the deck of ``source`` into ``out``, run the engine, post-process, return the results.

    Parameters
    ----------
    source : str, Path, paradyn.Scene, paradyn.scene.Scene or paradyn.deck.Model
        A scene file (``.toml``), a deck file (``.h5``, read and checked), an LS-DYNA keyword
        deck (``.k``, ``.key``, ``.dyn``: docs/keyword.md), a scene built in Python
        (:class:`paradyn.Scene`) or loaded with :func:`paradyn.scene.load_scene`, or a model.
    out : str or Path
        The output folder (created): ``deck.h5``, ``results.h5``, ``engine.log`` and the post-processing
        outputs go there (docs/outputs.md). A folder that holds another source's run is refused
        (``force=True`` replaces it); one reused is cleaned first (docs/scene.md, "Output folders").
    ranks, threads : int, optional
        MPI ranks and OpenMP threads per rank; by default one rank with a thread per core this
        process may use (:func:`paradyn.running.launch.default_layout`).
    runner : str or Runner, optional
        ``"direct"``, ``"mpirun"``, ``"srun"``, ``"sbatch"`` or a :class:`~paradyn.running.runners.Runner`;
        by default srun inside a Slurm allocation, the engine alone on one rank, mpirun otherwise.
        ``"sbatch"`` writes ``out/job.sbatch`` (the engine under srun, then
        ``paradyn-run --post``) and returns a :class:`BatchJob` instead of running.
    post : bool
        False skips all post-processing (the flags below then do nothing).
    vtk, history, summary, plots, vtk_series : bool
        ``results.vtkhdf``, ``history.csv`` and ``summary.json`` (on by default); the PNG pictures
        and a ``.pvd`` series per part (off by default; ``--plots``, ``--vtk-series``).
    restart : bool
        Continue the run in ``out`` from its checkpoint, with the deck already there (the
        checkpoint belongs to it; ``source`` is not written again).
    progress : bool, RunProgress or callable
        True shows the run on standard error (:class:`paradyn.running.progress.RunProgress`: meshing, the
        check's lines of :mod:`paradyn.running.preflight`, the engine's cycles, its warnings as they come,
        post-processing), as does a RunProgress of your own (``RunProgress(quiet=True)``: only the
        check's warnings); a callable receives every :class:`~paradyn.running.launch.Progress`. Without a
        RunProgress, the check's and the engine's warnings go through Python's :mod:`warnings`
        (:class:`paradyn.ModelWarning`, :class:`paradyn.EngineWarning`); both kept in ``engine_run.warnings``.
    extra : dict, optional
        Entries added to ``summary.json`` (after ``scene`` and ``command``).
    results_name, log_name : str
        File names of the results and of the engine's log in ``out`` (``log_name=None``: no log).
    started : AwaitingEngine, optional
        An engine :func:`paradyn.running.launch.start_engine` started for this run, waiting for its deck
        (``paradyn-run`` starts it before its imports: :mod:`paradyn.running.early_engine`). It is used
        if its command is the one this run needs, else cancelled; it is cancelled if the run
        fails before its deck is written.
    force : bool
        Replace the run of another scene or deck in ``out`` (``paradyn-run --force``).

    Returns
    -------
    Results or BatchJob
        The results (frames read on demand), with ``engine_run`` (the command, the engine's
        START and DONE fields, the time it took) and ``outputs`` (label -> path of each file
        post-processing wrote); a :class:`BatchJob` for the ``sbatch`` runner.

    Raises
    ------
    paradyn.scene.SceneError, paradyn.deck.DeckError
        A bad scene or deck (nothing was run).
    ValueError
        ``restart`` without a checkpoint in ``out``, an unknown runner name, or ``out`` holding the
        run of another source (:class:`paradyn.running.folders.OutputFolderError`).
    paradyn.running.launch.EngineError
        The engine failed or was stopped; ``exit_code`` is its status (4: stopped after writing
        its checkpoint, continue with ``restart=True``).

    Examples
    --------
    >>> import paradyn
    >>> res = paradyn.run("cases/small_plate/scene.toml", "runs/small_plate", ranks=1, threads=2)
    >>> res.run["cycles"], res.outputs["summary"]                   # doctest: +SKIP
    (48, PosixPath('runs/small_plate/summary.json'))
    >>> quick = paradyn.run(model, "runs/try", runner="mpirun", ranks=2, post=False)  # doctest: +SKIP
    >>> quick.displacement[-1].max()                                # doctest: +SKIP
    """
    batch = runner == SbatchRunner.name or isinstance(runner, SbatchRunner)
    if started is not None and (restart or batch):   # these start their own engine, or none
        started.cancel()
        started = None
    ranks, threads = (a if a is not None else b for a, b in zip((ranks, threads), launch.default_layout(), strict=True))
    display = progress if isinstance(progress, RunProgress) else (RunProgress() if progress is True else None)
    folder = _Folder(force=force, results_name=results_name)
    out, deck_path, started = _prepare(source, out, ranks, threads, runner, restart, batch, display, folder, started)
    if batch:
        return _write_batch_job(runner, deck_path, out / results_name, ranks, threads,
                                _post_command(out, vtk=vtk, plots=plots, vtk_series=vtk_series) if post else None)
    on_progress = display if display is not None else (progress if callable(progress) else None)
    asked = {"vtk": vtk, "history": history, "summary": summary, "plots": plots, "vtk_series": vtk_series}
    finish = _Finish(out / results_name, deck_path, display, post, _source_name(source), extra, asked, folder.warnings)
    try:
        engine_run = launch.run_engine(deck_path, out / results_name, ranks, threads, on_progress=on_progress,
                                       log_path=out / log_name if log_name else None, restart=restart, runner=runner,
                                       on_warning=display.warning if display is not None else _engine_warning,
                                       on_done=finish, started=started)
    except RunStopped as stop:   # the stop names the call that continues it
        raise stop.continuing(_source_text(source), out) from None
    finally:
        _close(started, display)
    return finish.results if finish.results is not None else finish(engine_run)


def _close(started: launch.AwaitingEngine | None, display: RunProgress | None) -> None:
    """After the engine: an engine started early but never told to go is ended (a failure before
    the run must not leave it waiting), and the progress display closed."""
    if started is not None:
        started.cancel()
    if display is not None:
        display.close()


def _source_text(source: Source) -> str:
    """``source`` as a continuing call writes it: a path's repr, else the name of what it is."""
    if isinstance(source, str | Path):
        return repr(str(source))
    return f"<the same {type(source).__name__}>"


@dataclass
class _Folder:
    """How a new run takes its output folder (docs/scene.md, "Output folders"), and the check's
    warnings of the model it wrote there."""

    force: bool = False
    results_name: str = "results.h5"
    warnings: list[str] = field(default_factory=list)


def _prepare(source: Source, out: str | Path, ranks: int, threads: int, runner: str | Runner | None, restart: bool,
             batch: bool, display: RunProgress | None, folder: _Folder,
             started: launch.AwaitingEngine | None) -> tuple[Path, Path, launch.AwaitingEngine | None]:
    """The output folder, the run's deck (written, or the folder's for a restart) and the engine
    started while the scene was meshed (``started`` when it fits); a failure ends that engine.
    A new run is refused a folder that holds another source's run before anything is read."""
    try:
        _check_source(source)
        if not restart:
            check_owner(Path(out), source_identity(source), folder.force)
        out = output_folder(out)
        if restart:
            return out, restart_deck(out, _restart_model(source)), None
        loaded = _loaded(source)
        if not batch and (precision := _precision(loaded)) is not None:
            # the engine starts MPI while the scene is meshed and its deck written
            started = _engine_for(started, out / "deck.h5", out / folder.results_name, ranks, threads, runner,
                                  precision)
        return out, _write_deck(source, loaded, out, ranks, threads, display, started, folder), started
    except BaseException:
        if started is not None:
            started.cancel()
        raise


def _engine_for(started: launch.AwaitingEngine | None, deck_path: Path, results: Path, ranks: int, threads: int,
                runner: str | Runner | None, precision: str) -> launch.AwaitingEngine:
    """``started`` if it is the engine this run needs (the same command and environment: the
    threads are in the environment), else a new one started."""
    if started is not None:
        chosen = launch.make_runner(runner, ranks, precision)
        if (started.command == chosen.command(deck_path.resolve(), results.resolve(), ranks, threads)
                and started.environment == chosen.environment(ranks, threads)):
            return started
        started.cancel()
    return launch.start_engine(deck_path, results, ranks, threads, runner, precision)


@dataclass
class _Finish:
    """Reads the results and post-processes them when the engine prints its DONE line: its
    results file is complete then, and this overlaps the engine's own exit."""

    results_path: Path
    deck_path: Path
    display: RunProgress | None
    post: bool
    scene: str | None
    extra: dict[str, Any] | None
    options: dict[str, bool]
    read_warnings: list[str] = field(default_factory=list)   # kept lines: the keyword reader's, the check's
    results: Results | None = None

    def __call__(self, engine_run: launch.EngineRun) -> Results:
        if self.display is not None:
            self.display.finish_engine(engine_run.done)
        # the reader's and the check's warnings first, then the engine's (the order they were said in)
        engine_run.warnings[:0] = self.read_warnings
        results = read(self.results_path, deck=self.deck_path)
        results.engine_run = engine_run
        if self.post:
            details = {"scene": self.scene, "command": engine_run.command, "warnings": list(engine_run.warnings),
                       **_restart_details(engine_run), **(self.extra or {})}
            with _stage(self.display, "post-processing"):
                results.outputs = post_process(results, self.results_path.parent, details, **self.options)
        self.results = results
        return results


def _engine_warning(line: str) -> None:
    """An engine warning, as it comes, through Python's warnings (no display shows it)."""
    issue([message_of(line)], EngineWarning)


def _restart_details(engine_run: launch.EngineRun) -> dict[str, Any]:
    """For a restart, summary.json's ``restart``: where it continued from and the cycles it ran
    (``wall_s`` and ``element_cycles_per_s`` are this part's; ``cycles`` counts from the start)."""
    if not engine_run.restart:
        return {}
    return {"restart": {"from_time_s": float(engine_run.restart.get("time", "nan")),
                        "from_cycle": int(engine_run.restart.get("cycle", 0)), "cycles": engine_run.cycles_run}}


def _stage(display: RunProgress | None, name: str) -> AbstractContextManager[None]:
    return display.stage(name) if display is not None else nullcontext()


def _is_scene(source: Source) -> bool:
    return isinstance(source, (scene.Scene, SceneBuilder)) or (isinstance(source, (str, Path)) and
                                                Path(source).suffix not in DECK_SUFFIXES)


def _check_source(source: Source) -> None:
    if isinstance(source, (str, Path)):
        path = Path(source)
        if not path.is_file():
            raise scene.SceneError(f"{path}: no such file; give the path of a scene .toml, a keyword deck .k "
                                   "or a deck .h5")
    elif not isinstance(source, (scene.Scene, SceneBuilder, deck.Model)):
        raise TypeError(f"cannot run a {type(source).__name__}; give a scene .toml or deck .h5 path, "
                        f"a paradyn.Scene, a paradyn.scene.Scene or a paradyn.deck.Model")


def _source_name(source: Source) -> str | None:
    """The file a run came from, for the summary (None for a scene or model built in Python)."""
    if isinstance(source, (str, Path)):
        return str(Path(source).resolve())
    if isinstance(source, scene.Scene):
        return str(Path(source.path).resolve())
    return None


def model_of(source: Source) -> deck.Model:
    """The deck model of a scene file, a deck file, a loaded scene or a model."""
    if isinstance(source, deck.Model):
        return source
    if isinstance(source, SceneBuilder):
        return source.build()
    if isinstance(source, scene.Scene):
        return scene.build_model(source)
    path = Path(source)
    if path.suffix in DECK_SUFFIXES:
        return deck.read_deck(path)
    if path.suffix.lower() in KEYWORD_SUFFIXES:
        from paradyn.keyword.scene import read_keyword  # loaded only for a keyword deck

        return read_keyword(path)
    return scene.build_model(scene.load_scene(path))


def _write_deck(source: Source, loaded: Source, out: Path, ranks: int, threads: int, display: RunProgress | None,
                started: launch.AwaitingEngine | None, folder: _Folder) -> Path:
    """Mesh (or read) ``loaded`` and check it; issue its warnings (a filter that makes them errors
    stops here, the folder untouched); clean the folder of an earlier run and record the source;
    write the deck and show the check's lines. A failure ends ``started``."""
    try:
        with _stage(display, "meshing" if _is_scene(source) else "reading the model"):
            model, read_warnings = _model_and_warnings(loaded, shown=display is not None)
        check = preflight.check_model(model, ranks, threads)
        folder.warnings = [check_line(w) for w in (*read_warnings, *check.warnings)]
        if display is None:
            issue(read_warnings, KeywordWarning)
            issue(check.warnings, ModelWarning)
        claim_output(out, source_identity(source), force=True, clean=True, results_name=folder.results_name)
        deck_path = deck.write_deck(model, out / "deck.h5")   # a waiting engine reads it once told to go
        if display is not None:
            display.report(check.lines())
    except BaseException:
        if started is not None:
            started.cancel()
        raise
    return deck_path


def _model_and_warnings(source: Source, shown: bool) -> tuple[deck.Model, list[str]]:
    """The model of ``source`` and, for a keyword deck, the reader's warnings (unsupported cards and
    fields, the units), printed on standard error as ``read_keyword`` does when ``shown``."""
    if isinstance(source, (str, Path)) and Path(source).suffix.lower() in KEYWORD_SUFFIXES:
        from paradyn.keyword.scene import load_keyword  # loaded only for a keyword deck

        read = load_keyword(source)
        for line in read.warnings if shown else ():
            print(f"paradyn: warning: {line}", file=sys.stderr)
        return read.model, list(read.warnings)
    return model_of(source), []


def _loaded(source: Source) -> Source:
    """A scene file loaded (its ``[run]`` says which engine runs it); any other source as it is."""
    if isinstance(source, (str, Path)) and _is_scene(source) and Path(source).suffix.lower() not in KEYWORD_SUFFIXES:
        return scene.load_scene(source)
    return source


def _precision(source: Source) -> str | None:
    """The precision a loaded scene or a model asks for ("double" when it names none); None for a
    source that says so only once it is built or read."""
    if isinstance(source, scene.Scene):
        return source.run.precision or "double"
    if isinstance(source, deck.Model):
        return source.control.precision or "double"
    return None


def prepare_deck(source: Source, out_dir: Path) -> Path:
    """Write (or check and copy) the deck of ``source`` into ``out_dir``; return its path."""
    return deck.write_deck(model_of(source), out_dir / "deck.h5")


def _restart_model(source: Source) -> deck.Model | None:
    """The model a restart compares with the run's deck: the scene or model as it is now (a deck
    file given as the source is the run's own deck or another one, and the engine checks it)."""
    if isinstance(source, (str, Path)) and Path(source).suffix in DECK_SUFFIXES:
        return None
    return model_of(source)


def _post_command(out_dir: Path, vtk: bool, plots: bool, vtk_series: bool = False) -> list[str]:
    """``paradyn-run --post OUT`` as a batch job runs it, with this Python."""
    command = [sys.executable, "-m", "paradyn.cli", "--post", str(out_dir.resolve())]
    return command + ["--plots"] * plots + ["--vtk-series"] * (vtk and vtk_series) + ["--no-vtk"] * (not vtk)


def _write_batch_job(runner: str | Runner, deck_path: Path, results: Path, ranks: int, threads: int,
                     post_command: list[str] | None) -> BatchJob:
    batch = launch.make_runner(runner, ranks, launch.deck_precision(deck_path))
    assert isinstance(batch, SbatchRunner)
    if batch.post_command is None:
        batch = replace(batch, post_command=post_command)
    script = batch.write_job(deck_path.resolve(), results.resolve(), ranks, threads)
    return BatchJob(script=script, deck=deck_path)
