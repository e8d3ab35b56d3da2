"""Runners (paradyn.running.runners) and their factory: the automatic choice is what paradyn-run always did
(srun inside a Slurm allocation, the engine alone on one rank, mpirun otherwise), a name picks a
member, and each member builds the command README.md and docs/outputs.md describe."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from paradyn.running import launch, runners
from paradyn.running.engine_process import EngineError

DECK, RESULTS = Path("/d/deck.h5"), Path("/d/results.h5")
ENGINE = Path("/opt/paradyn-engine")
SMALL_PLATE = Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml"


def machine(cores: int = 4, pinning: bool = True) -> runners.Machine:
    return runners.Machine(engine=ENGINE, cores=cores, pinning=pinning)


@pytest.mark.parametrize("ranks, in_slurm, expected", [
    (1, False, "direct"), (2, False, "mpirun"), (1, True, "srun"), (4, True, "srun"),
])
def test_the_automatic_choice_is_srun_in_slurm_else_direct_for_one_rank_else_mpirun(
        ranks: int, in_slurm: bool, expected: str) -> None:
    assert runners.automatic_runner_name(ranks, in_slurm) == expected
    for name in (None, "auto"):
        runner = runners.create_runner(name, machine(), ranks, in_slurm)
        assert runner.name == expected and type(runner) is runners.RUNNERS[expected]


@pytest.mark.parametrize("name", ["direct", "mpirun", "srun", "sbatch"])
def test_a_name_picks_that_runner_whatever_the_allocation(name: str) -> None:
    for in_slurm in (False, True):
        runner = runners.create_runner(name, machine(), ranks=1, inside_slurm=in_slurm)
        assert runner.name == name and runner.machine == machine()


def test_an_unknown_name_lists_the_runners() -> None:
    with pytest.raises(ValueError, match="unknown runner 'slurm'; choose one of direct, mpirun, srun, sbatch"):
        runners.create_runner("slurm", machine())


def test_direct_runs_the_engine_alone_on_one_rank_only() -> None:
    direct = runners.DirectRunner(machine())
    assert direct.command(DECK, RESULTS, 1, 2) == [str(ENGINE), str(DECK), str(RESULTS)]
    assert direct.command(DECK, RESULTS, 1, 2, restart=True)[-1] == "--restart"
    with pytest.raises(EngineError, match="use runner='mpirun'"):
        direct.command(DECK, RESULTS, 2, 1)


def test_mpirun_pins_a_layout_that_fits_and_oversubscribes_one_that_does_not() -> None:
    if launch.shutil.which("mpirun") is None and launch.shutil.which("mpiexec") is None:
        pytest.skip("no mpirun on PATH")
    pinned = runners.MpirunRunner(machine(cores=4)).command(DECK, RESULTS, 2, 2)
    assert Path(pinned[0]).name in ("mpirun", "mpiexec") and pinned[1:3] == ["-n", "2"]
    assert " ".join(pinned[3:]).startswith("-x OMP_NUM_THREADS --map-by slot:PE=2 --bind-to core "
                                           "-x OMP_PROC_BIND -x OMP_PLACES")
    assert pinned[-4:] == [str(ENGINE), str(DECK), str(RESULTS), "--expect-ranks=2"]
    floating = runners.MpirunRunner(machine(cores=4)).command(DECK, RESULTS, 4, 2)
    assert "--bind-to none --oversubscribe" in " ".join(floating)
    unpinned = runners.MpirunRunner(machine(cores=4, pinning=False)).command(DECK, RESULTS, 2, 1)
    assert "--bind-to none" in " ".join(unpinned) and "--oversubscribe" not in unpinned


def test_the_environment_places_threads_only_when_the_layout_is_pinned(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("OMP_PROC_BIND", raising=False)
    monkeypatch.delenv("OMP_PLACES", raising=False)
    fits = runners.MpirunRunner(machine(cores=4)).environment(2, 2)
    assert (fits["OMP_NUM_THREADS"], fits["OMP_PROC_BIND"], fits["OMP_PLACES"]) == ("2", "close", "cores")
    assert fits["SRUN_CPUS_PER_TASK"] == "2"
    assert "OMP_PROC_BIND" not in runners.MpirunRunner(machine(cores=2)).environment(2, 2)


def test_threads_of_an_oversubscribed_layout_wait_without_spinning(monkeypatch: pytest.MonkeyPatch) -> None:
    """More ranks x threads than cores: the OpenMP threads sleep at a barrier (a spinning one holds
    the core the others need); since issue 34 a layout that fits does too (a busy machine is the
    same case: tests/test_busy_machine.py); one thread has no barrier, and the user's policy wins."""
    for name in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT", *runners.HOST_LIST_VARIABLES):
        monkeypatch.delenv(name, raising=False)
    assert runners.MpirunRunner(machine(cores=2)).environment(2, 2)["OMP_WAIT_POLICY"] == "passive"
    assert runners.MpirunRunner(machine(cores=4)).environment(2, 2)["OMP_WAIT_POLICY"] == "passive"
    assert "OMP_WAIT_POLICY" not in runners.MpirunRunner(machine(cores=2)).environment(4, 1)
    monkeypatch.setenv("OMP_WAIT_POLICY", "active")
    assert runners.MpirunRunner(machine(cores=2)).environment(2, 2)["OMP_WAIT_POLICY"] == "active"


def test_mpirun_on_one_machine_asks_for_shared_memory_messaging(monkeypatch: pytest.MonkeyPatch) -> None:
    """docs/performance.md, "Fixed costs": mpirun's ranks use Open MPI's ob1 layer (no network
    probing at start-up) unless the user chose one, or a batch system's host list may put the
    ranks on other machines; srun and the engine alone are left as they are."""
    for name in ("OMPI_MCA_pml", "HWLOC_COMPONENTS", *runners.HOST_LIST_VARIABLES):
        monkeypatch.delenv(name, raising=False)
    assert runners.MpirunRunner(machine()).environment(2, 1)["OMPI_MCA_pml"] == "ob1"
    # and hwloc without its PCI devices (13 ms of every process's start)
    assert runners.MpirunRunner(machine()).environment(2, 1)["HWLOC_COMPONENTS"] == "-pci,-linuxio"
    monkeypatch.setenv("HWLOC_COMPONENTS", "-opencl")
    assert runners.MpirunRunner(machine()).environment(2, 1)["HWLOC_COMPONENTS"] == "-opencl"
    monkeypatch.delenv("HWLOC_COMPONENTS")
    assert "OMPI_MCA_pml" not in runners.SrunRunner(machine()).environment(2, 1)
    assert "OMPI_MCA_pml" not in runners.DirectRunner(machine()).environment(1, 1)
    monkeypatch.setenv("OMPI_MCA_pml", "ucx")
    assert runners.MpirunRunner(machine()).environment(2, 1)["OMPI_MCA_pml"] == "ucx"
    monkeypatch.delenv("OMPI_MCA_pml")
    monkeypatch.setenv("PBS_NODEFILE", "/var/spool/pbs/aux/1.server")
    assert "OMPI_MCA_pml" not in runners.MpirunRunner(machine()).environment(2, 1)
    assert "HWLOC_COMPONENTS" not in runners.MpirunRunner(machine()).environment(2, 1)


def test_srun_passes_the_cpus_per_task() -> None:
    command = runners.SrunRunner(machine()).command(DECK, RESULTS, 4, 3)
    assert command == ["srun", "-n", "4", "--cpus-per-task=3", "--export=ALL", "--input=0", str(ENGINE), str(DECK),
                       str(RESULTS), "--expect-ranks=4"]


def test_sbatch_writes_a_job_script_and_refuses_to_run(tmp_path: Path) -> None:
    post = ["python", "-m", "paradyn.cli", "--post", str(tmp_path)]
    batch = runners.SbatchRunner(machine(), post_command=post)
    script = batch.write_job(tmp_path / "deck.h5", tmp_path / "results.h5", 2, 3)
    assert script == tmp_path / "job.sbatch"
    lines = script.read_text().splitlines()
    assert lines[0] == "#!/bin/bash" and f"#SBATCH --job-name=paradyn-{tmp_path.name}" in lines
    srun = (f"srun -n 2 --cpus-per-task=3 --export=ALL --input=0 {ENGINE} {tmp_path / 'deck.h5'} "
            f"{tmp_path / 'results.h5'} --expect-ranks=2 $restart || status=$?")
    assert srun in lines
    assert lines[-1] == " ".join(post)
    with pytest.raises(EngineError, match="writes a job script"):
        batch.run(tmp_path / "deck.h5", tmp_path / "results.h5")


def test_make_runner_uses_this_machine_and_keeps_a_runner_it_is_given(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("SLURM_JOB_ID", raising=False)
    monkeypatch.setattr(launch, "available_cores", lambda: 3)
    monkeypatch.setenv(launch.BIND_ENV, "none")
    runner = launch.make_runner("mpirun")
    assert runner.machine == runners.Machine(launch.engine_path(), 3, pinning=False)
    assert launch.make_runner(runner) is runner
    assert launch.make_runner(None, ranks=1).name == "direct"
    fake = tmp_path / "srun"
    fake.write_text("#!/bin/sh\nexit 0\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    monkeypatch.setenv("SLURM_JOB_ID", "7")
    assert launch.make_runner(None, ranks=1).name == "srun"


def test_run_engine_takes_a_runner_by_name(tmp_path: Path) -> None:
    """The small plate on one rank under mpirun gives the same history as the engine alone."""
    import h5py
    import numpy as np

    from paradyn import deck, scene

    if launch.shutil.which("mpirun") is None:
        pytest.skip("no mpirun on PATH")
    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    direct = launch.run_engine(deck_path, tmp_path / "direct.h5", 1, 1, runner="direct")
    under_mpirun = launch.run_engine(deck_path, tmp_path / "mpirun.h5", 1, 1, runner="mpirun")
    assert Path(direct.command[0]) == launch.engine_path()
    assert Path(under_mpirun.command[0]).name in ("mpirun", "mpiexec")
    with h5py.File(tmp_path / "direct.h5") as a, h5py.File(tmp_path / "mpirun.h5") as b:
        for name in a["history"]:
            assert np.array_equal(a["history"][name][()], b["history"][name][()]), name


def test_ctrl_c_while_a_progress_line_is_handled_still_stops_with_a_checkpoint(tmp_path: Path) -> None:
    """Ctrl-C can land while the launcher handles a line (the progress bar writing) rather than
    while it waits for one: the engine must still get SIGUSR1, checkpoint and exit with status 4
    (docs/outputs.md, "Checkpoints and restarts")."""
    from paradyn import deck, scene

    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    model.control.end_time, model.control.output_interval = 0.2, 2e-3
    model.control.history_interval, model.control.progress_interval = 2e-4, 1e-3
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    seen = []

    def interrupted_once(progress: object) -> None:
        seen.append(progress)
        if len(seen) == 1:
            raise KeyboardInterrupt

    with pytest.raises(EngineError, match="stopped by a signal") as error:
        launch.run_engine(deck_path, tmp_path / "results.h5", 1, 1, on_progress=interrupted_once)
    assert error.value.exit_code == 4 and (tmp_path / "results.checkpoint.h5").is_file()
