"""What paradyn-run shows while it works (issue 18, item 5): the tqdm display fits the terminal,
shows cycle, simulated time, dt and ETA, ends at 100 %, covers meshing and post-processing;
``--version``. (No VTK warning without a display: tests/test_python_api.py.)"""

from __future__ import annotations

import io
import sys
import threading
import types

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
