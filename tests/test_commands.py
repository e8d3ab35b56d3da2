"""The command-line entry points (paradyn.commands) and the lazy package: docs/performance.md,
"Fixed costs". Not timed: these check the conditions the measured savings rest on."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

from paradyn import commands

CASES = Path(__file__).resolve().parents[1] / "cases"


def test_importing_paradyn_loads_no_numpy_until_a_name_is_used() -> None:
    """A command settles its environment before numpy loads, so the package's import must not
    load it; the public names and the submodules still resolve when used."""
    code = ("import sys, paradyn; assert 'numpy' not in sys.modules; "
            "assert paradyn.Scene.__name__ == 'Scene' and callable(paradyn.run) and callable(paradyn.study); "
            "assert paradyn.scene.load_scene and paradyn.deck.write_deck; print('numpy' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "True"
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        _ = __import__("paradyn").nothing_here


def test_the_commands_ask_for_one_openblas_thread_unless_the_user_chose(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("OPENBLAS_NUM_THREADS", raising=False)
    commands._settle_environment()
    import os

    assert os.environ["OPENBLAS_NUM_THREADS"] == "1"
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "4")
    commands._settle_environment()
    assert os.environ["OPENBLAS_NUM_THREADS"] == "4"


def test_each_command_runs_its_tool(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "argv", ["paradyn-run", "--version"])
    with pytest.raises(SystemExit) as stop:
        commands.paradyn_run()
    assert stop.value.code == 0
    for entry in (commands.paradyn_study, commands.paradyn_scaling):
        monkeypatch.setattr(sys, "argv", ["x", "--help"])
        with pytest.raises(SystemExit) as stop:
            entry()
        assert stop.value.code == 0


def test_the_console_script_flushes_everything_before_its_fast_exit(tmp_path: Path) -> None:
    """paradyn-run ends with os._exit (no interpreter clean-up): its piped output must still be
    whole, its files closed and its status the one main returned, for a run and for bad input."""
    script = Path(sys.executable).parent / "paradyn-run"
    out = tmp_path / "out"
    done = subprocess.run([str(script), str(CASES / "small_plate" / "scene.toml"), "-o", str(out), "-q"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.rstrip().endswith(str(out / "summary.json"))
    assert json.loads((out / "summary.json").read_text())["cycles"] == 48
    with h5py.File(out / "results.vtkhdf", "r") as f:
        assert f["VTKHDF/Steps"].attrs["NSteps"] > 1
    refused = subprocess.run([str(script), str(tmp_path / "missing.toml"), "-o", str(out)],
                             capture_output=True, text=True, timeout=60)
    assert refused.returncode == 2
    assert refused.stderr.startswith("paradyn-run: error: ") and "missing.toml" in refused.stderr


def test_the_commands_import_with_the_collector_paused_and_resume_it() -> None:
    """The collector is off while a command's imports run, and on again (with the imports' objects
    frozen) when its tool starts: a tool that made reference cycles would otherwise leak them."""
    seen: list[tuple[bool, int]] = []
    import gc

    with commands._collector_paused():
        seen.append((gc.isenabled(), gc.get_freeze_count()))
    seen.append((gc.isenabled(), gc.get_freeze_count()))
    gc.unfreeze()
    assert seen[0][0] is False and seen[1][0] is True
    assert seen[1][1] > 0


def test_a_reader_that_stops_reading_ends_the_command_quietly(tmp_path: Path) -> None:
    """paradyn-run SCENE | head: the pipe closes before the report is printed; the command ends
    with status 0 and no traceback, its files written."""
    script = Path(sys.executable).parent / "paradyn-run"
    out = tmp_path / "out"
    # unbuffered, so that the report's first print meets the closed pipe (buffered, the last flush would)
    process = subprocess.Popen([str(script), str(CASES / "small_plate" / "scene.toml"), "-o", str(out), "-q"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, "PYTHONUNBUFFERED": "1"})
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()   # the reader is gone before anything is printed
    errors = process.stderr.read()
    assert process.wait(timeout=300) == 0, errors
    assert "Traceback" not in errors and (out / "summary.json").is_file()
