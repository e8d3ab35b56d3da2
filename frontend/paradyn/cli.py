"""`paradyn-run`: mesh a scene, write the deck, run the engine, post-process the results."""

from __future__ import annotations

import argparse
import shlex
import sys
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path

from . import deck, scene
from ._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_OK
from .cli_parser import build_parser
from .results import reading
from .results.postprocess import post_process
from .results.reports import accuracy_text, effect_table_text
from .running import launch, preflight, workflow
from .running.engine_process import AwaitingEngine, RunStopped
from .running.folders import default_output
from .running.progress import RunProgress
from .running.run_warnings import message_of
from .running.runners import SbatchRunner


def post_only(out_dir: Path, plots: bool, vtk: bool, vtk_series: bool = False) -> int:
    """Post-process the results.h5 and deck.h5 of a run in out_dir, finished or interrupted."""
    res_path, deck_path = out_dir / "results.h5", out_dir / "deck.h5"
    if not (res_path.is_file() and deck_path.is_file()):
        print(f"paradyn-run: error: {out_dir} holds no results.h5 and deck.h5; give the output folder of a run",
              file=sys.stderr)
        return STATUS_BAD_INPUT
    try:
        res = reading.read(res_path, deck=deck_path, allow_incomplete=True)
        if not res.complete:
            last = float(res.time_values[-1]) if res.n_frames else 0.0
            print(f"paradyn-run: {res_path} is of an unfinished run: post-processing its {res.n_frames} "
                  f"frame(s), to t = {last:.4g} s", file=sys.stderr)
        outputs = post_process(res, out_dir, {"post_processed": True, "complete": res.complete},
                               plots=plots, vtk=vtk, vtk_series=vtk_series)
    except (deck.DeckError, reading.ResultsError) as error:
        print(f"paradyn-run: error: {error}", file=sys.stderr)
        return STATUS_BAD_INPUT
    _print_outputs(outputs)
    return STATUS_OK


def _with_units(source: Path, units: str | None) -> Path | deck.Model:
    """The source as given, or with ``--units`` the model of a keyword deck read in those units."""
    if units is None:
        return source
    if source.suffix.lower() not in workflow.KEYWORD_SUFFIXES:
        raise ValueError(f"--units {units} applies to an LS-DYNA keyword deck (.k, .key, .dyn), not to {source}; "
                         f"a scene and a deck are in SI")
    from paradyn.keyword.scene import read_keyword  # loaded only for a keyword deck

    return read_keyword(source, units=units)


def check_only(source: Path, ranks: int, threads: int, quiet: bool, units: str | None = None) -> int:
    """``paradyn-run --check``: the check's lines, then the engine's own set-up of the deck."""
    try:
        if not source.is_file():
            raise scene.SceneError(f"{source}: no such file; give the path of a scene .toml, a keyword deck .k "
                                   "or a deck .h5")
        display = None if quiet else RunProgress()
        if display is None:
            model = workflow.model_of(_with_units(source, units))
        else:
            with display.stage("reading the deck" if source.suffix in workflow.DECK_SUFFIXES else "meshing"):
                model = workflow.model_of(_with_units(source, units))
        machine = preflight.this_machine(model.control.precision)   # cached
        if machine is None:
            with display.stage("measuring this machine's element rate (once)") if display else nullcontext():
                machine = preflight.this_machine(model.control.precision, measure=True)
        check = preflight.check_model(model, ranks, threads, machine)
        engine = preflight.engine_check(model)
    except launch.EngineError as error:
        return _error(error, error.exit_code)
    except (scene.SceneError, deck.DeckError, ValueError) as error:
        return _error(error, STATUS_BAD_INPUT)
    print("\n".join(check.lines()))
    print(f"engine: first step {engine.dt:.4e} s (stable {engine.dt_stable:.4e} s), {engine.steps} steps; "
          f"{len(engine.warnings) or 'no'} warning(s) at set-up")
    for line in engine.warnings:
        print("  " + line)
    return STATUS_OK


def batch_runner(args: argparse.Namespace) -> SbatchRunner | None:
    """The sbatch runner with the command line's Slurm options (None without --sbatch)."""
    slurm = (args.time, args.account, args.partition, *args.sbatch_line, *args.sbatch_prologue)
    if not args.sbatch:
        if any(slurm) or args.checkpoint_lead is not None or args.max_jobs is not None:
            raise ValueError("--time, --account, --partition, --sbatch-line, --sbatch-prologue, --checkpoint-lead "
                             "and --max-jobs go with --sbatch")
        return None
    runner = launch.make_runner(SbatchRunner.name, args.ranks)
    assert isinstance(runner, SbatchRunner)
    runner = replace(runner, time=args.time, account=args.account, partition=args.partition,
                     extra_lines=tuple(args.sbatch_line), prologue=tuple(args.sbatch_prologue))
    if args.checkpoint_lead is not None:
        runner = replace(runner, signal_lead_s=args.checkpoint_lead)
    if args.max_jobs is not None:
        runner = replace(runner, max_jobs=args.max_jobs)
    runner.directives(Path("."), args.ranks, args.threads, "check")   # refuses a bad --sbatch-line now
    return runner


def _plots(args: argparse.Namespace) -> bool:
    return args.plots and not args.no_plots


def _print_outputs(outputs: dict[str, Path]) -> None:
    for label, path in outputs.items():
        print(f"  {label:18s} {path}")


def _error(error: Exception, status: int) -> int:
    print(f"paradyn-run: error: {error}", file=sys.stderr)
    return status


def continue_command(args: argparse.Namespace) -> list[str]:
    """The ``paradyn-run`` command that continues the run of ``args`` from its checkpoint: the same
    source, output folder and options, with ``--restart`` (without ``--force``)."""
    ranks, threads = launch.default_layout()
    command = ["paradyn-run", str(args.scene), "-o", str(args.output or default_output(args.scene))]
    command += ["-n", str(args.ranks)] * (args.ranks != ranks) + ["-t", str(args.threads)] * (args.threads != threads)
    command += ["--units", args.units] * (args.units is not None)
    for flag in ("quiet", "plots", "no_vtk", "vtk_series"):
        command += [f"--{flag.replace('_', '-')}"] * bool(getattr(args, flag))
    return [*command, "--restart"]


def stopped_text(stop: RunStopped, args: argparse.Namespace) -> str:
    """The one message of a run stopped with its checkpoint: where, and the command to go on."""
    return (f"paradyn-run: stopped by a signal at t = {stop.time:.6g} s (cycle {stop.cycle}); the checkpoint "
            f"{stop.checkpoint} holds the state.\ncontinue with: {shlex.join(continue_command(args))}")


def finished_text(run: launch.EngineRun) -> str:
    """The run's line: its cycles and wall time, and for a restart the cycles of this part (the
    rate counts those alone: the engine's wall time starts at the restart)."""
    done = run.done
    wall, rate = float(done.get("wall_s", "nan")), float(done.get("element_cycles_per_s", "nan"))
    if run.restart:
        counted = (f"{run.cycles_run} cycles from the restart at cycle {run.restart.get('cycle')} (t = "
                   f"{float(run.restart.get('time', 'nan')):.4g} s) to cycle {done.get('cycles')}")
    else:
        counted = f"{done.get('cycles')} cycles"
    return f"paradyn-run: {counted} in {wall:.2f} s ({rate:.3e} element-cycles/s); effects:"


def main(argv: list[str] | None = None) -> int:
    """``paradyn-run`` with the arguments ``argv`` (default: the command line's); its exit status."""
    return run_command(build_parser().parse_args(argv))


def run_command(args: argparse.Namespace, started: AwaitingEngine | None = None) -> int:
    """``paradyn-run`` with parsed arguments; ``started``: its engine, started before the imports
    (:mod:`paradyn.running.early_engine`), ended here if the run did not take it (cancelling an engine
    told to go, or already ended, does nothing)."""
    try:
        return _run_parsed(args, started)
    finally:
        if started is not None:
            started.cancel()


def _run_parsed(args: argparse.Namespace, started: AwaitingEngine | None) -> int:
    if args.post:
        return post_only(args.scene.resolve(), plots=_plots(args), vtk=not args.no_vtk, vtk_series=args.vtk_series)
    if args.check:
        return check_only(args.scene, args.ranks, args.threads, args.quiet, args.units)
    out_dir = (args.output or default_output(args.scene)).resolve()
    try:
        runner = batch_runner(args)
        outcome = workflow.run(_with_units(args.scene, args.units), out_dir, args.ranks, args.threads,
                               runner=runner, restart=args.restart,
                               progress=RunProgress(quiet=args.quiet), vtk=not args.no_vtk,
                               plots=_plots(args), vtk_series=args.vtk_series, started=started,
                               force=args.force)   # the folder rule: running/folders.py
    except RunStopped as stop:
        print(stopped_text(stop, args), file=sys.stderr)
        return stop.exit_code
    except launch.EngineError as error:
        return _error(error, error.exit_code)
    except reading.ResultsError:
        raise  # the run finished but its results do not read: a bug to show in full
    except (scene.SceneError, deck.DeckError, ValueError) as error:
        return _error(error, STATUS_BAD_INPUT)
    except OSError as error:   # a disk that fills or a file system that fails while writing the outputs
        return _error(OSError(f"{error.strerror or error}; free space (or fix the file system) and rerun"),
                      STATUS_FAILURE)
    if isinstance(outcome, workflow.BatchJob):
        print(f"paradyn-run: wrote {outcome.script}; submit it with: sbatch {outcome.script}")
        return STATUS_OK
    print(finished_text(outcome.engine_run))
    print(effect_table_text(outcome))
    print(accuracy_text(outcome))
    for line in outcome.engine_run.warnings:   # said at the start too, but a long run scrolls it away
        print("  warning: " + message_of(line))   # the reader's, the check's and the engine's
    _print_outputs(outcome.outputs)
    return STATUS_OK


if __name__ == "__main__":
    sys.exit(main())
