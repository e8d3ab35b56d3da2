"""paradyn.run, the facade: a scene file, a loaded scene, a model or a deck in; the deck written
into the output folder, the engine run through a runner, the post-processing asked for, and the
results object out (README.md, "Using it")."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import pytest

import paradyn
from paradyn import deck, scene
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"
EFFECTS = ["point_loads", "time_integration", "fixed_boundaries", "elastic_shells", "hourglass"]


@pytest.fixture(scope="module")
def plate_model() -> deck.Model:
    return scene.build_model(scene.load_scene(SMALL_PLATE))


def test_a_scene_file_runs_end_to_end_with_every_output(tmp_path: Path) -> None:
    res = paradyn.run(SMALL_PLATE, tmp_path, ranks=1, threads=1, vtk_series=True)
    assert isinstance(res, paradyn.Results) and res.complete
    assert list(res.outputs) == ["results", "vtk plate", "vtkhdf", "history", "summary"]
    assert all(path.is_file() for path in res.outputs.values())
    assert (tmp_path / "deck.h5").is_file() and (tmp_path / "engine.log").is_file()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["scene"] == str(SMALL_PLATE) and summary["command"] == res.engine_run.command
    assert [row["name"] for row in summary["effects"]] == EFFECTS == res.effects
    assert res.engine_run.done["cycles"] == str(res.run["cycles"]) and res.engine_run.elapsed_s > 0


def test_post_false_writes_the_deck_and_results_only(tmp_path: Path, plate_model: deck.Model) -> None:
    res = paradyn.run(plate_model, tmp_path, ranks=1, threads=1, post=False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.h5", "engine.log", "results.h5", "source.txt"]
    assert res.outputs == {} and res.n_frames > 0 and res.part_names == ["plate"]


def test_each_kind_of_source_gives_the_same_history(tmp_path: Path, plate_model: deck.Model) -> None:
    from numpy.testing import assert_array_equal

    first = paradyn.run(SMALL_PLATE, tmp_path / "file", ranks=1, threads=1, post=False)
    sources = {"scene": scene.load_scene(SMALL_PLATE), "model": plate_model,
               "deck": tmp_path / "file" / "deck.h5"}
    for name, source in sources.items():
        res = paradyn.run(source, tmp_path / name, ranks=1, threads=1, post=False)
        for column, values in first.history.items():
            assert_array_equal(res.history[column], values, err_msg=f"{name}: {column}")


def test_flags_choose_the_outputs_and_names_choose_the_files(tmp_path: Path, plate_model: deck.Model) -> None:
    res = paradyn.run(plate_model, tmp_path, ranks=1, threads=1, vtk=False, summary=False, plots=False,
                      results_name="plate.h5", log_name=None, extra={"case": "plate"})
    assert list(res.outputs) == ["results", "history"] and res.path == tmp_path / "plate.h5"
    assert not (tmp_path / "summary.json").exists() and not (tmp_path / "engine.log").exists()


def test_the_sbatch_runner_writes_a_job_and_runs_nothing(tmp_path: Path, plate_model: deck.Model) -> None:
    job = paradyn.run(plate_model, tmp_path, ranks=2, threads=3, runner="sbatch", plots=True)
    assert isinstance(job, paradyn.BatchJob) and job.submit_command == ["sbatch", str(job.script)]
    text = job.script.read_text()
    assert "#SBATCH --ntasks=2" in text and f"--post {tmp_path.resolve()} --plots" in text
    assert not (tmp_path / "results.h5").exists()


def test_mistakes_are_named_before_anything_runs(tmp_path: Path, plate_model: deck.Model) -> None:
    with pytest.raises(scene.SceneError, match="no such file"):
        paradyn.run(tmp_path / "missing.toml", tmp_path / "out")
    with pytest.raises(TypeError, match=r"paradyn\.deck\.Model"):
        paradyn.run({"title": "a dict"}, tmp_path / "out")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="unknown runner 'local'"):
        paradyn.run(plate_model, tmp_path / "out", ranks=1, threads=1, runner="local")
    with pytest.raises(ValueError, match=r"holds no deck\.h5 and results\.checkpoint\.h5"):
        paradyn.run(plate_model, tmp_path / "empty", restart=True)
    with pytest.raises(launch.EngineError, match="must be at least 1"):
        paradyn.run(plate_model, tmp_path / "out", ranks=0, threads=1)


@pytest.mark.parametrize("ranks", [1, 2])
def test_the_engine_writes_the_run_names_so_results_h5_stands_alone(tmp_path: Path, plate_model: deck.Model,
                                                                     ranks: int) -> None:
    """docs/formats.md (results): the engine copies the deck's title, part names and tracked names
    into results.h5 and writes the effects it ran, so a results file read without its deck still
    names everything (the names of cases/small_plate/scene.toml)."""
    paradyn.run(plate_model, tmp_path, ranks=ranks, threads=1, post=False)
    with h5py.File(tmp_path / "results.h5", "r") as f:
        assert f.attrs["title"] == "Small cantilever plate"
        assert list(f["mesh"].attrs["part_names"]) == ["plate"]
        assert list(f["history"].attrs["tracked_names"]) == ["tip_corner", "tip_middle", "middle"]
        assert f["run"].attrs["effects"] == ",".join(EFFECTS)
    (tmp_path / "deck.h5").unlink()
    alone = paradyn.read(tmp_path / "results.h5")
    assert (alone.title, alone.part_names, alone.effects) == ("Small cantilever plate", ["plate"], EFFECTS)
    assert alone.tracked_names == ["tip_corner", "tip_middle", "middle"]


def test_a_scene_s_engine_starts_while_it_is_meshed_and_ends_if_meshing_fails(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """docs/performance.md, "Fixed costs": a scene file's engine is started (``--await-deck``) before
    the scene is meshed, and told to go on once its deck is written; a scene that fails to mesh
    ends that engine (status 0, nothing written) before the error reaches the caller."""
    started: list[launch.AwaitingEngine] = []
    original = launch.start_engine

    def recording(*args: object, **kwargs: object) -> launch.AwaitingEngine:
        started.append(original(*args, **kwargs))  # type: ignore[arg-type]
        return started[-1]

    monkeypatch.setattr(launch, "start_engine", recording)
    res = paradyn.run(SMALL_PLATE, tmp_path / "good", ranks=1, threads=1, post=False)
    assert len(started) == 1 and started[0].process.returncode == 0 and res.complete
    assert "--await-deck" in started[0].process.args and "--await-deck" not in res.engine_run.command
    bad = tmp_path / "bad.toml"
    bad.write_text(SMALL_PLATE.read_text().replace('origin = [0.0, 0.0, 0.0]',
                                                   'origin = [0.0, 0.0, 0.0]\nv_axis = [1.0, 1.0, 0.0]'))
    with pytest.raises(scene.SceneError, match="perpendicular"):
        paradyn.run(bad, tmp_path / "bad", ranks=1, threads=1)
    assert len(started) == 2 and started[1].process.returncode == 0
    assert not (tmp_path / "bad" / "results.h5").exists() and not (tmp_path / "bad" / "deck.h5").exists()
    # a failure after the deck is written, before the engine is told to go, ends it too
    def failing(*args: object, **kwargs: object) -> launch.EngineRun:
        raise launch.EngineError("the launcher failed", 1)

    monkeypatch.setattr(launch, "run_engine", failing)
    with pytest.raises(launch.EngineError, match="the launcher failed"):
        paradyn.run(SMALL_PLATE, tmp_path / "late", ranks=1, threads=1)
    assert len(started) == 3 and started[2].process.returncode == 0
    assert not (tmp_path / "late" / "results.h5").exists()


def test_an_engine_awaiting_its_deck_runs_on_go_only(tmp_path: Path, plate_model: deck.Model) -> None:
    """paradyn-engine --await-deck (docs/formats.md): the line ``go`` runs the deck; end of input or
    any other line ends it with status 0, having written nothing."""
    import subprocess

    deck_path = deck.write_deck(plate_model, tmp_path / "deck.h5")
    command = [str(launch.engine_path()), str(deck_path), str(tmp_path / "r.h5"), "--await-deck"]
    for given in ("", "stop\n"):
        ended = subprocess.run(command, input=given, capture_output=True, text=True, timeout=60,
                               env=launch.engine_environment(1))
        assert ended.returncode == 0 and "PARADYN-START" not in ended.stdout
        assert not (tmp_path / "r.h5").exists()
    ran = subprocess.run(command, input="go\n", capture_output=True, text=True, timeout=120,
                         env=launch.engine_environment(1))
    assert ran.returncode == 0 and "PARADYN-DONE" in ran.stdout and (tmp_path / "r.h5").is_file()
