"""paradyn-run starts a scene's engine before its heavy imports (paradyn.running.early_engine,
docs/performance.md "Fixed costs"): the engine used is that one when it fits the run, and it is
ended, having written nothing, on every path that does not run it."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from paradyn.cli import run_command
from paradyn.cli_parser import build_parser
from paradyn.running import launch, workflow
from paradyn.running.early_engine import scene_precision, start_early

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def _args(*argv: str) -> object:
    return build_parser().parse_args(list(argv))


def test_the_precision_is_read_from_the_scene_s_run_table(tmp_path: Path) -> None:
    assert scene_precision(SMALL_PLATE) == "double"   # names none
    mixed = tmp_path / "mixed.toml"
    mixed.write_text(SMALL_PLATE.read_text().replace("[run]\n", '[run]\nprecision = "mixed"\n', 1))
    assert scene_precision(mixed) == "mixed"
    odd = tmp_path / "odd.toml"
    odd.write_text(SMALL_PLATE.read_text().replace("[run]\n", '[run]\nprecision = "quad"\n', 1))
    broken = tmp_path / "broken.toml"
    broken.write_text("[run\nend_time = 1")
    # not settled here: the command's own path reports these
    assert scene_precision(odd) is None and scene_precision(broken) is None
    assert scene_precision(tmp_path / "missing.toml") is None and scene_precision(ROOT / "README.md") is None


@pytest.mark.parametrize("flag", ["--check", "--post", "--restart", "--sbatch"])
def test_commands_that_run_no_scene_now_start_nothing(tmp_path: Path, flag: str) -> None:
    assert start_early(_args(str(SMALL_PLATE), "-o", str(tmp_path / "out"), flag)) is None


def test_the_early_engine_runs_the_scene(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "out"
    args = _args(str(SMALL_PLATE), "-o", str(out), "-q", "-n", "1", "-t", "1")
    started = start_early(args)
    assert started is not None and "--await-deck" in started.process.args
    monkeypatch.setattr(launch, "start_engine", lambda *a, **k: pytest.fail("a second engine was started"))
    assert run_command(args, started) == 0
    assert started.process.returncode == 0 and (out / "results.h5").is_file()


def test_an_engine_for_another_layout_is_replaced(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    early = launch.start_engine(out / "deck.h5", out / "results.h5", 1, 2, None, "double")
    res = workflow.run(SMALL_PLATE, out, ranks=1, threads=1, post=False, started=early)
    # the same command line (threads go by the environment), so the environment decides
    assert early.command == res.engine_run.command
    assert early.process.wait(timeout=60) == 0   # cancelled (had it run, threads would be 2)
    assert res.complete and res.run["threads"] == 1


def test_a_bad_scene_ends_the_early_engine_with_nothing_written(tmp_path: Path) -> None:
    """The whole command, as a user runs it: status 2 with the scene's message, no deck, no
    results, and no engine left waiting (the command returns only once it has ended)."""
    bad = tmp_path / "bad.toml"
    bad.write_text(SMALL_PLATE.read_text().replace('origin = [0.0, 0.0, 0.0]',
                                                   'origin = [0.0, 0.0, 0.0]\nv_axis = [1.0, 1.0, 0.0]'))
    out = tmp_path / "out"
    ended = subprocess.run([sys.executable, "-c", "from paradyn.commands import paradyn_run; paradyn_run()",
                            str(bad), "-o", str(out), "-q", "-t", "1"], capture_output=True, text=True, timeout=120)
    assert ended.returncode == 2 and "perpendicular" in ended.stderr
    assert not (out / "deck.h5").exists() and not (out / "results.h5").exists()
    engines = subprocess.run(["pgrep", "-f", f"paradyn-engine.*{out}"], capture_output=True, text=True)
    assert engines.stdout == ""


def test_a_folder_of_another_scene_ends_the_early_engine(tmp_path: Path) -> None:
    out = tmp_path / "out"
    (out).mkdir()
    (out / "source.txt").write_text("/somewhere/else/scene.toml\n")
    (out / "summary.json").write_text("{}")
    args = _args(str(SMALL_PLATE), "-o", str(out), "-q", "-t", "1")
    started = start_early(args)
    assert started is not None
    assert run_command(args, started) == 2
    assert started.process.returncode == 0 and not (out / "deck.h5").exists()
