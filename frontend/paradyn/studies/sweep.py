"""``paradyn.study``: what accuracy costs in time, for any scene (issue 16, docs/accuracy-cost.md).

A study turns knobs of a scene (:mod:`paradyn.studies.design`), runs every configuration once
(:mod:`paradyn.studies.runs`, cached by deck content, spread over the cores by a process pool, one
progress bar across the runs), measures quantities of interest and their errors
(:mod:`paradyn.studies.error`, :mod:`paradyn.studies.analysis`) and writes the tables and the Pareto
plot (:mod:`paradyn.studies.output`). The package is not called ``study`` so that ``paradyn.study``
stays the function whatever is imported.
"""

from __future__ import annotations

import multiprocessing
import shutil
import tomllib
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from tqdm.auto import tqdm

from paradyn import scene
from paradyn.arguments import checked_arguments
from paradyn.results.reading import read
from paradyn.running import launch
from paradyn.scene.builder import Scene as SceneBuilder

from .analysis import StudyResult, StudyRun, analyse
from .design import Design, StudyError, apply, base_values, label
from .error import check_quantities, parse_target
from .output import write_outputs
from .runs import Prepared, adopt, execute, finished, prepare
from .spec import StudySpec, spec_from_table

__all__ = ["Design", "StudyError", "StudyResult", "StudySpec", "study"]


@checked_arguments("paradyn.study")
def study(source: str | Path | scene.Scene | SceneBuilder, out: str | Path, *, progress: bool = True,
          command: str | None = None, **options: Any) -> StudyResult:
    """Run a study of a scene and write its tables and plot into ``out``.

    Parameters
    ----------
    source : str, Path, paradyn.Scene or paradyn.scene.Scene
        The scene; its ``[study]`` table (of the file, or of a :class:`paradyn.Scene`'s tables),
        when it has one, gives the defaults of every option.
    out : str or Path
        The study folder: ``runs/<key>/`` (one folder per distinct deck, reused by later studies),
        ``study.csv``, ``study.json``, ``study.md`` and ``pareto.png``.
    progress : bool
        One progress bar across the runs (tqdm) on standard error.
    command : str, optional
        The command line to record in the outputs.
    **options
        ``design`` ("one_at_a_time", "grid", "list"), ``knobs`` (knob -> list of values),
        ``runs`` (list of knob -> value), ``quantities`` (name -> text such as
        ``"upper_top.dz@1e-3"``), ``reference`` ("richardson" or "finest"), ``reference_values``
        (name -> value), ``target`` (0.01 or "1%"), ``target_quantities``, ``cost`` ("core_s",
        "engine_s", "whole_s", "cycles", "peak_memory_mb"), ``end_time``, ``threads`` (per run),
        ``jobs`` (runs at once; default: cores // threads). Docs: docs/accuracy-cost.md.

    Returns
    -------
    StudyResult

    Raises
    ------
    paradyn.studies.design.StudyError
        A bad knob, value, quantity or option (nothing was run).
    paradyn.scene.SceneError
        A bad scene, or a configuration whose scene cannot be meshed.

    Examples
    --------
    >>> import paradyn
    >>> result = paradyn.study("cases/small_plate/scene.toml", "runs/plate_study",
    ...                        knobs={"mesh": [1, 2, 4]}, quantities={"tip": "tip_corner.dz:final"},
    ...                        target="1%")                        # doctest: +SKIP
    >>> result.analysis.target_answer                            # doctest: +SKIP
    """
    if isinstance(source, SceneBuilder):
        sc, table = source.validate(), source.to_dict().get("study", {})
    else:
        sc = source if isinstance(source, scene.Scene) else scene.load_scene(source)
        table = _study_table(sc)
    spec = _spec(sc, table, options)
    configs = spec.design.configurations(sc)
    for config in configs:
        apply(sc, config)   # a configuration that cannot be set (a mesh factor) fails here, before any run
    quantities = spec.parsed_quantities(sc)
    check_quantities(quantities, [t.name for t in sc.tracks], spec.end_time or sc.run.end_time)
    out = Path(out)
    runs_root, staging_root = out / "runs", out / "staging"
    runs_root.mkdir(parents=True, exist_ok=True)
    jobs = spec.jobs or max(1, launch.available_cores() // spec.threads)
    with _pool(jobs, len(configs)) as pool, tqdm(total=len(configs), desc="study runs", unit="run",
                                                  disable=not progress) as bar:
        futures = [pool.submit(prepare, sc, c, staging_root, spec.end_time, 1, spec.threads) for c in configs]
        prepared = [f.result() for f in futures]
        records, pending = _start_runs(pool, prepared, runs_root, spec.threads, bar)
        keys = {future: key for key, future in pending.items()}
        for future in as_completed(keys):
            records[keys[future]] = future.result()
            first = next(p for p in prepared if p.key == keys[future])
            bar.set_postfix_str(label(first.config)[:40], refresh=False)
            bar.update(sum(p.key == keys[future] for p in prepared))
    shutil.rmtree(staging_root, ignore_errors=True)
    runs = [StudyRun(p.config, p.key, p.key not in pending, records[p.key]) for p in prepared]
    _measure(runs, quantities, runs_root)
    base = base_values(sc)
    analysis = analyse(runs, quantities, spec, base)
    result = StudyResult(spec, runs, analysis, ran=len(pending))
    result.outputs = write_outputs(result, quantities, out, sc, command)
    return result


def _spec(sc: scene.Scene, table: dict[str, Any], options: dict[str, Any]) -> StudySpec:
    spec = spec_from_table(table, str(sc.path)) if table else StudySpec()
    if options.get("target") is not None:
        options["target"] = parse_target(options["target"])
    spec = spec.merged(**options)
    spec.check()
    return spec


def _study_table(sc: scene.Scene) -> dict[str, Any]:
    """The scene file's ``[study]`` table ({} without one, or for a scene built in Python)."""
    path = Path(sc.path)
    if not path.is_file():
        return {}
    return tomllib.loads(path.read_text(encoding="utf-8")).get("study", {})


class _Inline(Executor):
    """Runs each call at once, in this process: a study of one job needs no pool."""

    def submit(self, fn: Any, /, *args: Any, **kwargs: Any) -> Future:
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:   # handed to the caller by future.result()
            future.set_exception(exc)
        return future


def _pool(jobs: int, n: int) -> Executor:
    if jobs == 1 or n == 1:
        return _Inline()
    # spawn: the workers start clean (gmsh, HDF5 and threads of this process are not forked)
    return ProcessPoolExecutor(max_workers=min(jobs, n), mp_context=multiprocessing.get_context("spawn"))


def _start_runs(pool: Executor, prepared: list[Prepared], runs_root: Path, threads: int,
                bar: tqdm) -> tuple[dict[str, dict[str, Any]], dict[str, Future]]:
    """Adopt every staged deck; tick the cached runs off; submit the rest, one run per distinct deck."""
    records: dict[str, dict[str, Any]] = {}
    pending: dict[str, Future] = {}
    for p in prepared:
        folder = adopt(p, runs_root)
        if p.key in records or p.key in pending:
            continue
        record = finished(folder)
        if record is not None:
            records[p.key] = record
            bar.update(sum(q.key == p.key for q in prepared))
        else:
            pending[p.key] = pool.submit(execute, folder, 1, threads, p.prepare_s, p.track_offset_m)
    return records, pending


def _measure(runs: list[StudyRun], quantities: list[Any], runs_root: Path) -> None:
    """Each finished run's quantities, from its history."""
    tables: dict[str, dict[str, Any]] = {}
    for run in runs:
        if not run.ok:
            continue
        if run.key not in tables:
            tables[run.key] = read(runs_root / run.key / "results.h5").history_table()
        run.values = {q.name: q.value(tables[run.key]) for q in quantities}
