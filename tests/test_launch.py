"""The launcher: Slurm's srun inside an allocation, the --sbatch script, and --post.

Reference: ECOSYSTEM.md (Slurm 22.05 and later: srun does not inherit --cpus-per-task, pass it and
export OMP_NUM_THREADS) and docs/outputs.md (what paradyn-run writes).
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

import pytest

from paradyn import cli
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def fake_srun(folder: Path) -> None:
    path = folder / "srun"
    path.write_text("#!/bin/sh\nexit 0\n")
    path.chmod(path.stat().st_mode | stat.S_IEXEC)


def test_inside_an_allocation_the_engine_runs_under_srun(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fake_srun(tmp_path)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setenv("SLURM_JOB_ID", "42")
    command = launch.engine_command(Path("/d/deck.h5"), Path("/d/results.h5"), 4, 2)
    assert command[:5] == ["srun", "-n", "4", "--cpus-per-task=2", "--export=ALL"]
    assert command[-3:] == ["/d/deck.h5", "/d/results.h5", "--expect-ranks=4"]
    assert launch.engine_environment(2)["SRUN_CPUS_PER_TASK"] == "2"


def test_outside_an_allocation_mpirun_is_used(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("SLURM_JOB_ID", raising=False)
    command = launch.engine_command(Path("/d/deck.h5"), Path("/d/results.h5"), 2, 1)
    assert Path(command[0]).name in ("mpirun", "mpiexec") and command[1:3] == ["-n", "2"]
    assert launch.engine_command(Path("/d/deck.h5"), Path("/d/results.h5"), 1, 1)[0] == str(launch.engine_path())


def test_a_layout_that_fits_the_cores_is_pinned(monkeypatch: pytest.MonkeyPatch) -> None:
    """Ranks and threads get cores of their own when they fit (a migrating rank lands on a busy
    core and the others wait for it); more than the cores float, oversubscribed; PARADYN_BIND=none
    turns pinning off; the user's own OpenMP placement wins."""
    monkeypatch.delenv("SLURM_JOB_ID", raising=False)
    monkeypatch.delenv(launch.BIND_ENV, raising=False)
    monkeypatch.delenv("OMP_PROC_BIND", raising=False)
    monkeypatch.delenv("OMP_PLACES", raising=False)
    monkeypatch.setattr(launch, "available_cores", lambda: 4)
    monkeypatch.setattr(launch, "busy_cores", lambda: 0.0)   # an idle machine (tests/test_busy_machine.py: a busy one)
    deck, results = Path("/d/deck.h5"), Path("/d/results.h5")

    def options(ranks: int, threads: int) -> str:
        return " ".join(launch.engine_command(deck, results, ranks, threads)[1:-2])

    assert "--map-by slot:PE=2 --bind-to core -x OMP_PROC_BIND -x OMP_PLACES" in options(2, 2)
    assert "--map-by slot:PE=1 --bind-to core" in options(4, 1)
    assert "--bind-to none --oversubscribe" in options(4, 2)
    env = launch.engine_environment(2, 2)
    assert (env["OMP_PROC_BIND"], env["OMP_PLACES"]) == ("close", "cores")
    assert "OMP_PROC_BIND" not in launch.engine_environment(4, 2)   # does not fit: threads float
    monkeypatch.setenv("OMP_PROC_BIND", "spread")
    assert launch.engine_environment(2, 2)["OMP_PROC_BIND"] == "spread"
    monkeypatch.setenv(launch.BIND_ENV, "none")
    assert "--bind-to none" in options(2, 1) and "--oversubscribe" not in options(2, 1)


def test_the_default_layout_is_one_thread_per_core_this_process_may_use(monkeypatch: pytest.MonkeyPatch) -> None:
    """README: without -n/-t, one rank with a thread per core; the cores are those of the CPU
    affinity (a container or a batch job may allow fewer than the machine has), as pinning counts."""
    if hasattr(launch.os, "sched_getaffinity"):
        monkeypatch.setattr(launch.os, "sched_getaffinity", lambda pid: {0, 2, 5})
        monkeypatch.setattr(launch.os, "cpu_count", lambda: 8)
        assert launch.default_layout() == (1, 3)
    monkeypatch.setattr(launch, "available_cores", lambda: 6)
    assert launch.default_layout() == (1, 6)


def test_sbatch_writes_a_job_script_and_runs_nothing(tmp_path: Path) -> None:
    status = cli.main([str(SMALL_PLATE), "-o", str(tmp_path), "-n", "2", "-t", "3", "--sbatch"])
    assert status == 0
    script = (tmp_path / "job.sbatch").read_text()
    for line in ("#SBATCH --ntasks=2", "#SBATCH --cpus-per-task=3", "export OMP_NUM_THREADS=3",
                 "export SRUN_CPUS_PER_TASK=3"):
        assert line in script
    assert f"srun -n 2 --cpus-per-task=3 --export=ALL --input=0 {launch.engine_path()} {tmp_path / 'deck.h5'}" in script
    assert f"-m paradyn.cli --post {tmp_path}" in script
    assert (tmp_path / "deck.h5").is_file() and not (tmp_path / "results.h5").exists()


def test_post_redoes_the_outputs_of_a_finished_run(tmp_path: Path) -> None:
    assert cli.main([str(SMALL_PLATE), "-o", str(tmp_path), "-n", "1", "-t", "1", "-q", "--no-plots"]) == 0
    (tmp_path / "history.csv").unlink()
    (tmp_path / "summary.json").unlink()
    assert cli.main([str(tmp_path), "--post", "--no-plots"]) == 0
    assert (tmp_path / "history.csv").is_file()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert [row["name"] for row in summary["effects"]] == ["point_loads", "time_integration", "fixed_boundaries",
                                                           "elastic_shells", "hourglass"]
    assert summary["cycles"] > 0


def test_post_on_a_folder_without_results_fails_clearly(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main([str(tmp_path), "--post"]) == 2
    assert "holds no results.h5 and deck.h5" in capsys.readouterr().err
