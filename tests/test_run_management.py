"""Runs and clusters (issue 18, item 7): default output folders that never collide silently,
``--post`` of an interrupted run, the Slurm options of ``--sbatch`` and the job's continuation
after a time-limit stop, and the engine's check of its rank count."""

from __future__ import annotations

import json
import os
import stat
import subprocess
from pathlib import Path

import h5py
import pytest

from paradyn import cli, deck, scene
from paradyn.running import folders as run_folders
from paradyn.running import launch, runners
from paradyn.running.launch import EngineError, Progress

SMALL_PLATE = Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml"
QUICK = ["-n", "1", "-t", "1", "-q", "--no-plots", "--no-vtk"]


def test_default_output_names_the_scene(tmp_path: Path) -> None:
    folder = tmp_path / "study"
    assert run_folders.default_output(folder / "scene.toml", tmp_path) == tmp_path / "runs" / "study"
    assert run_folders.default_output(folder / "plate_a.toml", tmp_path) == tmp_path / "runs" / "plate_a"
    assert run_folders.default_output(folder / "old" / "deck.h5", tmp_path) == tmp_path / "runs" / "deck"


def test_two_scenes_of_one_folder_run_into_two_folders(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    for name in ("plate_a.toml", "plate_b.toml"):
        (tmp_path / name).write_text(SMALL_PLATE.read_text())
        assert cli.main([name, *QUICK]) == 0
        out = tmp_path / "runs" / Path(name).stem
        assert (out / "results.h5").is_file()
        assert (out / "source.txt").read_text().strip() == str(tmp_path / name)


def test_another_scenes_run_is_not_replaced_without_force(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    first, second, out = tmp_path / "a.toml", tmp_path / "b.toml", tmp_path / "run"
    first.write_text(SMALL_PLATE.read_text())
    second.write_text(SMALL_PLATE.read_text().replace("value = -20.0", "value = -10.0"))
    assert cli.main([str(first), "-o", str(out), *QUICK]) == 0
    assert cli.main([str(first), "-o", str(out), *QUICK]) == 0   # the same scene again: its own folder
    before = (out / "results.h5").stat().st_mtime_ns
    capsys.readouterr()
    assert cli.main([str(second), "-o", str(out), *QUICK]) == 2
    err = capsys.readouterr().err
    assert f"holds the run of {first}, not of {second}" in err and "--force" in err
    assert (out / "results.h5").stat().st_mtime_ns == before
    assert cli.main([str(second), "-o", str(out), *QUICK, "--force"]) == 0
    assert (out / "source.txt").read_text().strip() == str(second)


def test_an_older_run_is_recognised_by_its_summary(tmp_path: Path) -> None:
    (tmp_path / "results.h5").write_bytes(b"")
    (tmp_path / "summary.json").write_text(json.dumps({"scene": "/somewhere/else.toml"}))
    with pytest.raises(ValueError, match=r"holds the run of /somewhere/else\.toml"):
        run_folders.claim_output(tmp_path, SMALL_PLATE)


def test_post_of_an_interrupted_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A run stopped by Ctrl-C (status 4, a checkpoint and a partial results.h5) is post-processed
    from the command line: what the results file holds so far, marked complete = false."""
    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    model.control.end_time, model.control.output_interval = 0.2, 2e-3
    model.control.history_interval, model.control.progress_interval = 2e-4, 1e-3
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    stops: list[float] = []

    def interrupt_past_two_ms(progress: Progress) -> None:
        # progress lines come by wall time, so the stop waits for simulated time: records exist then
        if not stops and progress.time >= 2e-3:
            stops.append(progress.time)
            raise KeyboardInterrupt

    with pytest.raises(EngineError) as error:
        launch.run_engine(deck_path, tmp_path / "results.h5", 1, 1, on_progress=interrupt_past_two_ms)
    assert error.value.exit_code == 4
    with h5py.File(tmp_path / "results.h5") as h5:
        assert int(h5.attrs["complete"]) == 0
    assert cli.main([str(tmp_path), "--post", "--no-plots", "--no-vtk"]) == 0
    assert "unfinished run" in capsys.readouterr().err
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["complete"] is False
    history = (tmp_path / "history.csv").read_text().splitlines()
    assert 2 < len(history) < 1000   # a header and the records written before the stop, not the 1001 of the run


def _machine() -> runners.Machine:
    return runners.Machine(engine=Path("/opt/paradyn-engine"), cores=8)


def test_sbatch_options_become_sbatch_lines(tmp_path: Path) -> None:
    status = cli.main([str(SMALL_PLATE), "-o", str(tmp_path), "-n", "4", "-t", "2", "-q", "--sbatch",
                       "--time", "2:00:00", "--account", "proj42", "--partition", "short",
                       "--sbatch-line=--mem=8G", "--sbatch-line", "#SBATCH --constraint=skylake"])
    assert status == 0
    lines = (tmp_path / "job.sbatch").read_text().splitlines()
    for line in ("#SBATCH --time=2:00:00", "#SBATCH --account=proj42", "#SBATCH --partition=short",
                 "#SBATCH --mem=8G", "#SBATCH --constraint=skylake", "#SBATCH --signal=USR1@300"):
        assert line in lines, line
    first_command = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    assert all(line.startswith("#SBATCH") for line in lines[1:first_command])   # sbatch reads them only there
    assert any("--expect-ranks=4 $restart" in line for line in lines)


@pytest.mark.parametrize("arguments, message", [
    (["--sbatch", "--sbatch-line", "echo hello"], "is not an sbatch option"),
    (["--time", "1:00:00"], "go with --sbatch"),
])
def test_bad_slurm_options_are_refused(tmp_path: Path, arguments: list[str], message: str,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    assert cli.main([str(SMALL_PLATE), "-o", str(tmp_path / "run"), "-q", *arguments]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "run" / "job.sbatch").exists()


def _fake_slurm(folder: Path) -> dict[str, str]:
    """srun and sbatch that record their arguments; srun exits with $FAKE_SRUN_STATUS."""
    for name, body in (("srun", 'echo "$@" >> "$FAKE_LOG.srun"; exit "${FAKE_SRUN_STATUS:-0}"'),
                       ("sbatch", 'echo "$@" >> "$FAKE_LOG.sbatch"')):
        path = folder / name
        path.write_text(f"#!/bin/bash\n{body}\n")
        path.chmod(path.stat().st_mode | stat.S_IEXEC)
    env = {k: v for k, v in os.environ.items() if k != "PARADYN_CONTINUE"}
    env.update(PATH=f"{folder}{os.pathsep}{os.environ['PATH']}", FAKE_LOG=str(folder / "log"))
    return env


def test_the_job_continues_after_a_time_limit_stop(tmp_path: Path) -> None:
    """Status 4 (stopped at Slurm's signal, checkpoint written) submits the script again with
    PARADYN_CONTINUE=1, which runs the engine with --restart; the post-processing runs only after
    the run finished; another failure ends the job with its status."""
    marker = tmp_path / "post-processed"
    batch = runners.SbatchRunner(_machine(), post_command=["touch", str(marker)], time="10")
    script = batch.write_job(tmp_path / "deck.h5", tmp_path / "results.h5", 2, 1)
    env = _fake_slurm(tmp_path)
    first = subprocess.run(["bash", str(script)], env={**env, "FAKE_SRUN_STATUS": "4"}, capture_output=True, text=True)
    assert first.returncode == 0 and "continuing in job 2" in first.stdout
    assert (tmp_path / "log.sbatch").read_text().split() == ["--export=ALL,PARADYN_CONTINUE=1,PARADYN_JOB_NUMBER=2",
                                                             str(script)]
    assert "--restart" not in (tmp_path / "log.srun").read_text() and not marker.exists()
    (tmp_path / "results.checkpoint.h5").write_bytes(b"")   # what the stopped engine wrote
    second = subprocess.run(["bash", str(script)], env={**env, "PARADYN_CONTINUE": "1"}, capture_output=True)
    assert second.returncode == 0 and marker.exists()
    assert (tmp_path / "log.srun").read_text().splitlines()[-1].endswith("--expect-ranks=2 --restart")
    failed = subprocess.run(["bash", str(script)], env={**env, "FAKE_SRUN_STATUS": "3"}, capture_output=True)
    assert failed.returncode == 3 and len((tmp_path / "log.sbatch").read_text().splitlines()) == 1


def test_the_engine_refuses_another_rank_count(tmp_path: Path) -> None:
    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    engine = str(launch.engine_path())
    for argument, message in (("--expect-ranks=2", "launched on 1 MPI rank(s) but --expect-ranks=2"),
                              ("--expect-ranks=two", "bad --expect-ranks=two")):
        run = subprocess.run([engine, str(deck_path), argument], cwd=tmp_path, capture_output=True, text=True,
                             env=launch.engine_environment(1))
        assert run.returncode == 2 and message in run.stderr, run.stderr
    assert not (tmp_path / "results.h5").exists()
    ok = subprocess.run([engine, str(deck_path), "--expect-ranks=1"], cwd=tmp_path, capture_output=True, text=True,
                        env=launch.engine_environment(1))
    assert ok.returncode == 0 and "PARADYN-DONE" in ok.stdout


def test_a_requeued_job_continues_and_the_chain_has_a_limit(tmp_path: Path) -> None:
    """Issue 34: a job Slurm requeues (SLURM_RESTART_COUNT > 0: a node failure, a preemption) used
    to start the run over; it now continues from the checkpoint when there is one (else starts
    anew). A chain of continuations stops after --max-jobs jobs, saying how to go on."""
    batch = runners.SbatchRunner(_machine(), time="1:00:00", max_jobs=3)
    script = batch.write_job(tmp_path / "deck.h5", tmp_path / "results.h5", 2, 1)
    assert "#SBATCH --requeue" in script.read_text().splitlines()
    env = _fake_slurm(tmp_path)
    fresh = subprocess.run(["bash", str(script)], env={**env, "SLURM_RESTART_COUNT": "1"}, capture_output=True)
    assert fresh.returncode == 0   # no checkpoint yet: the requeued job starts the run
    assert not (tmp_path / "log.srun").read_text().rstrip().endswith("--restart")
    (tmp_path / "results.checkpoint.h5").write_bytes(b"")
    requeued = subprocess.run(["bash", str(script)], env={**env, "SLURM_RESTART_COUNT": "1"}, capture_output=True)
    assert requeued.returncode == 0
    assert (tmp_path / "log.srun").read_text().splitlines()[-1].endswith("--expect-ranks=2 --restart")
    first = subprocess.run(["bash", str(script)], env={**env, "FAKE_SRUN_STATUS": "4"}, capture_output=True)
    assert first.returncode == 0   # not the first run: no PARADYN_CONTINUE, so the checkpoint is not taken
    assert not (tmp_path / "log.srun").read_text().splitlines()[-1].endswith("--restart")
    last = subprocess.run(["bash", str(script)], capture_output=True, text=True,
                          env={**env, "FAKE_SRUN_STATUS": "4", "PARADYN_CONTINUE": "1", "PARADYN_JOB_NUMBER": "3"})
    assert last.returncode == 4
    assert "after 3 jobs (--max-jobs); continue with: sbatch --export=ALL,PARADYN_CONTINUE=1 " in last.stdout
    assert len((tmp_path / "log.sbatch").read_text().splitlines()) == 1   # only the first stop submitted


def test_a_time_limit_within_the_checkpoint_lead_is_refused(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 34: --time 4:00 with the 300 s lead would get its stop signal before it starts; refused
    (status 2) naming the lead and the fix, and nothing written. A shorter lead lets it through."""
    out = tmp_path / "run"
    assert cli.main([str(SMALL_PLATE), "-o", str(out), "-q", "--sbatch", "--time", "4:00"]) == 2
    err = capsys.readouterr().err
    assert "--time 4:00 (240 s) is not longer than the checkpoint lead of 300 s" in err and "--checkpoint-lead" in err
    assert not (out / "job.sbatch").exists()
    assert cli.main([str(SMALL_PLATE), "-o", str(out), "-q", "--sbatch", "--time", "4:00",
                     "--checkpoint-lead", "60", "--max-jobs", "5"]) == 0
    text = (out / "job.sbatch").read_text()
    assert "#SBATCH --signal=USR1@60" in text and '[ "$job" -ge 5 ]' in text
    for limit, seconds in (("30", 1800), ("30:15", 1815), ("2:00:00", 7200), ("1-2", 93600),
                           ("1-0:30", 88200), ("1-00:00:05", 86405)):
        assert runners.slurm_seconds(limit) == seconds, limit
    for bad in ("UNLIMITED", "1:2:3:4", "x-1", "-5"):
        with pytest.raises(ValueError, match="is not a Slurm time limit"):
            runners.slurm_seconds(bad)


def test_the_prologue_runs_before_the_engine(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Issue 34: --sbatch-prologue adds shell lines (module load ...) after the #SBATCH lines and
    before the engine; an #SBATCH line there is refused (sbatch would not read it)."""
    out = tmp_path / "run"
    assert cli.main([str(SMALL_PLATE), "-o", str(out), "-q", "--sbatch", "--sbatch-prologue", "module load openmpi/4.1",
                     "--sbatch-prologue", "module load hdf5"]) == 0
    lines = (out / "job.sbatch").read_text().splitlines()
    load = lines.index("module load openmpi/4.1")
    assert lines[load + 1] == "module load hdf5"
    assert max(i for i, line in enumerate(lines) if line.startswith("#SBATCH")) < load
    assert load < next(i for i, line in enumerate(lines) if line.startswith("srun "))
    assert cli.main([str(SMALL_PLATE), "-o", str(tmp_path / "bad"), "-q", "--sbatch",
                     "--sbatch-prologue", "#SBATCH --mem=8G"]) == 2
    assert "give it with --sbatch-line" in capsys.readouterr().err
