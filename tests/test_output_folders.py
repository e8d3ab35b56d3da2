"""The folder rule in Python (issue 34): ``paradyn.run`` refuses a folder that holds the run of
another scene (as ``paradyn-run`` does) unless ``force=True``, and a folder that is reused is
cleaned of the earlier run's outputs before the new run writes, so no stale frame, picture or
history sits beside the new results; any other file of the folder stays."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import paradyn
from paradyn import cli
from paradyn.running.folders import OutputFolderError, clean_outputs

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def _copy(folder: Path, name: str, load: str = "-20.0") -> Path:
    path = folder / name
    path.write_text(SMALL_PLATE.read_text().replace("value = -20.0", f"value = {load}"))
    return path


def _plate(title: str) -> paradyn.Scene:
    s = paradyn.Scene(title, end_time=1e-4, output_interval=2.5e-5)
    s.add_material("steel", model="elastic", density=7860.0, youngs_modulus=2e11, poisson_ratio=0.3)
    s.add_part("plate", material="steel", thickness=0.002, initial_velocity=[0.0, 0.0, 1.0],
               geometry=paradyn.Plate((0.2, 0.1), (4, 2)))
    return s


def test_another_scenes_run_is_refused_unless_forced(tmp_path: Path) -> None:
    first, second, out = _copy(tmp_path, "a.toml"), _copy(tmp_path, "b.toml", "-10.0"), tmp_path / "run"
    paradyn.run(first, out, ranks=1, threads=1, post=False)
    before = (out / "results.h5").stat().st_mtime_ns
    with pytest.raises(OutputFolderError, match=f"holds the run of {first}, not of {second}.*force=True"):
        paradyn.run(second, out, ranks=1, threads=1, post=False)
    assert (out / "results.h5").stat().st_mtime_ns == before
    paradyn.run(second, out, ranks=1, threads=1, post=False, force=True)
    assert (out / "source.txt").read_text().strip() == str(second)


def test_scenes_built_in_python_are_told_apart_by_title(tmp_path: Path) -> None:
    paradyn.run(_plate("plate A"), tmp_path, ranks=1, threads=1, post=False)
    assert (tmp_path / "source.txt").read_text().strip() == "paradyn.Scene 'plate A'"
    paradyn.run(_plate("plate A"), tmp_path, ranks=1, threads=1, post=False)   # the same scene, edited: a rerun
    with pytest.raises(OutputFolderError, match=re.escape("holds the run of paradyn.Scene 'plate A', not of "
                                                          "paradyn.Scene 'plate B'")):
        paradyn.run(_plate("plate B"), tmp_path, ranks=1, threads=1, post=False)


def test_a_rerun_leaves_no_file_of_the_earlier_run(tmp_path: Path) -> None:
    out = tmp_path / "run"
    first = paradyn.run(SMALL_PLATE, out, ranks=1, threads=1, vtk_series=True)
    assert (out / "plate.pvd").is_file() and len(list((out / "vtk").glob("plate_*.vtu"))) == first.n_frames
    for picture in ("energies.png", "deformed.png", "tracked.png"):   # as --plots leaves them
        (out / picture).write_bytes(b"old picture")
    (out / "notes.txt").write_text("mine")
    (out / "vtk" / "mine.vtu").write_text("mine")
    paradyn.run(SMALL_PLATE, out, ranks=1, threads=1, post=False)
    assert sorted(p.name for p in out.iterdir()) == ["deck.h5", "engine.log", "notes.txt", "results.h5",
                                                     "source.txt", "vtk"]
    assert [p.name for p in (out / "vtk").iterdir()] == ["mine.vtu"]
    paradyn.run(SMALL_PLATE, out, ranks=1, threads=1, vtk=False)
    assert not (out / "results.vtkhdf").exists() and (out / "history.csv").is_file()
    assert json.loads((out / "summary.json").read_text())["scene"] == str(SMALL_PLATE)


def test_a_bad_scene_leaves_the_earlier_run_as_it_was(tmp_path: Path) -> None:
    paradyn.run(SMALL_PLATE, tmp_path, ranks=1, threads=1, vtk=False)
    names = sorted(p.name for p in tmp_path.iterdir())
    bad = paradyn.Scene("Small cantilever plate", end_time=1e-4, output_interval=2.5e-5)
    with pytest.raises(paradyn.scene.SceneError):   # no part: refused before the folder is touched
        paradyn.run(bad, tmp_path, ranks=1, threads=1, force=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == names


def test_the_command_keeps_its_rule(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    first, second, out = _copy(tmp_path, "a.toml"), _copy(tmp_path, "b.toml", "-10.0"), tmp_path / "run"
    quick = ["-n", "1", "-t", "1", "-q", "--no-plots", "--no-vtk"]
    assert cli.main([str(first), "-o", str(out), *quick, "--vtk-series"]) == 0
    assert cli.main([str(second), "-o", str(out), *quick]) == 2
    assert "--force" in capsys.readouterr().err
    assert cli.main([str(second), "-o", str(out), *quick, "--force"]) == 0
    assert not (out / "plate.pvd").exists() and (out / "source.txt").read_text().strip() == str(second)


def test_cleaning_keeps_the_source_and_other_files(tmp_path: Path) -> None:
    for name in ("deck.h5", "results.h5", "results.checkpoint.h5", "history.csv", "results.vtkhdf", "a.pvd",
                 "b.pvd", "job.sbatch", "user.h5", "slurm-12.out"):
        (tmp_path / name).write_text("x")
    (tmp_path / "vtk").mkdir()
    for name in ("a_00000.vtu", "a_00001.vtu", "b_00000.vtu", "c_00000.vtu"):
        (tmp_path / "vtk" / name).write_text("x")
    removed = clean_outputs(tmp_path, keep=(tmp_path / "deck.h5").resolve())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.h5", "slurm-12.out", "user.h5", "vtk"]
    assert [p.name for p in (tmp_path / "vtk").iterdir()] == ["c_00000.vtu"]
    assert len(removed) == 10
