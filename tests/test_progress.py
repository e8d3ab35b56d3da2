"""What paradyn-run shows while it works (issue 18, item 5): the tqdm display fits the terminal,
shows cycle, simulated time, dt and ETA, ends at 100 %, covers meshing and post-processing;
``--version``. (No VTK warning without a display: tests/test_python_api.py.)"""

from __future__ import annotations

import io
import sys
import threading
import types
from pathlib import Path

import pytest

from paradyn import cli
from paradyn.running import progress
from paradyn.running.engine_process import Progress
from paradyn.running.progress import clock


def _frames(text: str) -> list[str]:
    """What a terminal shows in turn: the text between carriage returns and newlines."""
    return [part for line in text.split("\n") for part in line.split("\r") if part]


@pytest.mark.parametrize("columns", [80, 60])
def test_the_engine_bar_fits_the_terminal_and_shows_cycle_time_dt_eta(
        columns: int, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", str(columns))
    stream = io.StringIO()
    display = progress.RunProgress(stream=stream, live=True)
    for cycle in (10, 2000, 123456):
        display(Progress(cycle, cycle * 1.1e-7, 1.1e-7, 123456 * 1.1e-7 * 1.25, wall_s=0.01 * cycle))
    display.finish_engine({"cycles": "154320", "time": "1.6975e-02", "wall_s": "1543.2"})
    frames = _frames(stream.getvalue())
    assert max(len(f) for f in frames) <= columns - 1
    last_running = next(f for f in reversed(frames) if "cycle 123456" in f)
    assert last_running.startswith("cycle 123456 t 1.358e-02 s dt 1.10e-07 s ETA 5:09")   # 1234.56 s x 0.25 / 0.8
    assert "80%" in last_running
    assert frames[-1].startswith("cycle 154320 t 1.698e-02 s done in 25:43") and "100%" in frames[-1]


def test_without_a_terminal_a_line_every_tenth() -> None:
    stream = io.StringIO()
    display = progress.RunProgress(stream=stream, live=False)
    for k in range(1, 101):
        display(Progress(k, k * 1e-6, 1e-6, 1e-4, wall_s=k * 0.01))
    lines = stream.getvalue().splitlines()
    assert len(lines) == 11 and "\r" not in stream.getvalue()   # the first line, then one per tenth
    assert lines[0].startswith("  1.0% cycle 1 t 1.000e-06 s dt 1.00e-06 s ETA 0:01")
    assert lines[1].startswith(" 10.0% cycle 10 t 1.000e-05 s")
    assert lines[-1].startswith("100.0% cycle 100")


def test_warnings_print_above_the_bar() -> None:
    stream = io.StringIO()
    display = progress.RunProgress(stream=stream, live=True)
    display(Progress(1, 1e-6, 1e-6, 1e-4, 0.1))
    display.warning("paradyn-engine: warning: initial penetration in /contact/pairs[0]")
    display(Progress(2, 2e-6, 1e-6, 1e-4, 0.2))
    display.close()
    assert "  warning: initial penetration in /contact/pairs[0]\n" in stream.getvalue()


def test_a_stage_shows_its_running_seconds(monkeypatch: pytest.MonkeyPatch) -> None:
    """The stage's clock is redrawn while it runs and its last line says how long it took. The
    stage reads a clock of the test's own, on which 62.34 s pass inside the stage, and the body
    waits for the redraw that shows them (an event), so nothing depends on how busy the machine is."""
    now = [1000.0]
    monkeypatch.setattr(progress, "time", types.SimpleNamespace(monotonic=lambda: now[0]))
    monkeypatch.setattr(progress, "REFRESH_S", 0.01)
    shown = threading.Event()

    def watched_clock(seconds: float | None) -> str:
        if seconds is not None and seconds > 60:
            shown.set()   # the ticker draws this text next, before the stage can end (it joins the ticker)
        return clock(seconds)

    monkeypatch.setattr(progress, "clock", watched_clock)
    stream = io.StringIO()
    with progress.RunProgress(stream=stream, live=True).stage("meshing"):
        now[0] += 62.34
        assert shown.wait(timeout=120)   # a bound on a hang only: the stage ends once the ticker has drawn
    frames = _frames(stream.getvalue())
    assert frames[0] == "meshing" and "meshing 1:02" in frames
    assert frames[-1].startswith("meshing done in 62.3 s")
    quiet = io.StringIO()
    with progress.RunProgress(stream=quiet, live=False).stage("post-processing"):
        pass
    assert quiet.getvalue() == "post-processing ...\n"


def test_a_notebook_is_told_by_its_kernel(monkeypatch: pytest.MonkeyPatch) -> None:
    """In Jupyter (an IPython kernel, whose config has IPKernelApp) the display is live whatever the
    stream says, and tqdm.auto draws its widget; a terminal IPython or plain Python is not a notebook."""
    assert progress.in_notebook() is False

    class Shell:
        def __init__(self, config: dict[str, object]) -> None:
            self.config = config

    for config, expected in (({"IPKernelApp": {}}, True), ({"TerminalInteractiveShell": {}}, False)):
        fake = types.ModuleType("IPython")
        fake.get_ipython = lambda config=config: Shell(config)   # type: ignore[attr-defined]
        monkeypatch.setitem(sys.modules, "IPython", fake)
        assert progress.in_notebook() is expected
        assert progress.RunProgress(stream=io.StringIO()).live is expected


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as done:
        cli.main(["--version"])
    assert done.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("paradyn-run 0.1.0 (Python ") and "engine " in out
    # the engine's own --version: its build
    assert "\nparadyn-engine " in out and " precision, " in out
    for line in ("compiler: ", "flags: ", "MPI: ", "HDF5: "):
        assert f"\n{line}" in out


def test_piped_to_a_file_the_run_ends_at_100_percent() -> None:
    """Issue 34: the engine's last progress line comes before its end, so a log file never saw
    100 %; the DONE line now writes it (once), also for a run that printed no progress line."""
    stream = io.StringIO()
    display = progress.RunProgress(stream=stream, live=False)
    for k in range(1, 96):
        display(Progress(k, k * 1e-6, 1e-6, 1e-4, wall_s=k * 0.01))
    display.finish_engine({"cycles": "100", "time": "1.0e-04", "wall_s": "1.0"})
    display.finish_engine({"cycles": "100", "time": "1.0e-04", "wall_s": "1.0"})
    lines = stream.getvalue().splitlines()
    assert lines[-2].startswith(" 90.0% cycle 90")
    assert lines[-1] == "100.0% cycle 100 t 1.000e-04 s done in 0:01"
    assert sum(line.startswith("100.0%") for line in lines) == 1
    silent = io.StringIO()
    progress.RunProgress(stream=silent, live=False).finish_engine({"cycles": "7", "time": "1e-4", "wall_s": "0.1"})
    assert silent.getvalue().startswith("100.0% cycle 7 ")
    quiet = io.StringIO()
    progress.RunProgress(stream=quiet, live=False, quiet=True).finish_engine({"cycles": "7"})
    assert quiet.getvalue() == ""


def test_a_terminal_shows_100_percent_even_without_a_progress_line() -> None:
    """A restart close to its end (or a short run) prints no progress line before DONE: the bar
    still ends at 100 %."""
    stream = io.StringIO()
    progress.RunProgress(stream=stream, live=True).finish_engine({"cycles": "9", "time": "2e-4", "wall_s": "0.4"})
    frames = _frames(stream.getvalue())
    assert frames[-1].startswith("cycle 9 t 2.000e-04 s done in 0:00") and "100%" in frames[-1]


def test_after_a_restart_the_eta_comes_from_this_part_of_the_run() -> None:
    """Issue 34: the engine's wall_s counts from the restart, so the ETA must divide by the
    simulated time since the checkpoint, not since zero (13x too small for a restart at 12/13)."""
    from paradyn.running.engine_process import EngineRun, _LineReader

    seen: list[Progress] = []
    run = EngineRun(command=[], exit_code=-1)
    reader = _LineReader(run, seen.append, None, "DONE")
    reader.take("PARADYN-RESTART time= 1.200000E-01 cycle=12000\n")
    reader.take("PARADYN-PROGRESS cycle=12100 time= 1.210000E-01 dt= 1.0000E-06 end_time= 1.3000E-01 wall_s=2.000\n")
    reader.take("PARADYN-DONE cycles=13000 time= 1.300000E-01 wall_s=18.000 element_cycles_per_s= 1.0E+06\n")
    assert seen[0].start_time == pytest.approx(0.12)
    assert seen[0].eta_s == pytest.approx(2.0 * 0.009 / 0.001)   # 18 s: 9 ms left at 1 ms per 2 s
    assert Progress(12100, 0.121, 1e-6, 0.13, 2.0).eta_s == pytest.approx(2.0 * 0.009 / 0.121)  # the old answer
    assert run.cycles_run == 1000
    text = cli.finished_text(run)
    assert text.startswith("paradyn-run: 1000 cycles from the restart at cycle 12000 (t = 0.12 s) to cycle 13000 "
                           "in 18.00 s")


def test_a_stopped_run_says_once_how_to_continue() -> None:
    """Issue 34: the stop said "error" twice, offered the raw engine command first and a
    `paradyn-run --restart` without the scene and -o it needs. Now one message, with the command."""
    from paradyn.cli_parser import build_parser
    from paradyn.running.engine_process import EngineRun, RunStopped

    run = EngineRun(command=[], exit_code=4, checkpoint={"time": "5.0E-02", "cycle": "4321",
                                                         "path": "/r/out/results.checkpoint.h5"})
    stop = RunStopped.of(run, Path("/r/out"))
    assert stop.exit_code == 4 and stop.cycle == 4321 and "error" not in str(stop)
    args = build_parser().parse_args(["cases/my plate/scene.toml", "-o", "runs/a", "-n", "1", "-t", "1",
                                      "--no-vtk", "--force"])
    text = cli.stopped_text(stop, args)
    assert "error" not in text
    assert text.splitlines() == [
        "paradyn-run: stopped by a signal at t = 0.05 s (cycle 4321); the checkpoint "
        "/r/out/results.checkpoint.h5 holds the state.",
        "continue with: paradyn-run 'cases/my plate/scene.toml' -o runs/a" +
        (" -n 1" if cli.launch.default_layout()[0] != 1 else "") +
        (" -t 1" if cli.launch.default_layout()[1] != 1 else "") + " --no-vtk --restart"]


def test_a_run_stopped_from_python_names_the_call_that_continues_it() -> None:
    """Issue 34: paradyn.run's stop said "paradyn.run(SOURCE, OUT, restart=True)"; now the call
    names the source as it was given and the folder."""
    from paradyn.running.engine_process import EngineRun, RunStopped
    from paradyn.running.workflow import _source_text

    run = EngineRun(command=[], exit_code=4, checkpoint={"time": "5.0E-02", "cycle": "7", "path": "c.h5"})
    stop = RunStopped.of(run, Path("/r/out")).continuing(_source_text("cases/plate/scene.toml"), Path("runs/p"))
    assert stop.exit_code == 4 and stop.cycle == 7 and stop.checkpoint == Path("/r/out/c.h5")
    assert str(stop).endswith("continue with paradyn.run('cases/plate/scene.toml', 'runs/p', restart=True)")
    import paradyn
    assert _source_text(paradyn.Scene("s", end_time=1e-3, output_interval=1e-4)) == "<the same Scene>"
