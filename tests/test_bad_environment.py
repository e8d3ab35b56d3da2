"""Issue 17: bad files and folders get one clear message and a documented exit status, never a
traceback: an output path that is a file, under a file or read-only, a scene that is not UTF-8
text, a mesh file that is garbage, a mesh request beyond the machine, a truncated results file."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

import paradyn
from paradyn import cli, deck, scene
from paradyn._schema import STATUS_BAD_INPUT, STATUS_FAILURE
from paradyn.mesh import files as mesh_files
from paradyn.mesh import geometry
from paradyn.results.layout import ResultsError
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def _cli_error(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    status = cli.main(argv)
    return status, capsys.readouterr().err


@pytest.mark.parametrize("where", ["is_a_file", "under_a_file"])
def test_an_output_path_that_is_or_lies_under_a_file(tmp_path: Path, where: str,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "taken"
    blocker.write_text("not a folder")
    out = blocker if where == "is_a_file" else blocker / "run"
    status, err = _cli_error([str(SMALL_PLATE), "-o", str(out), "-q"], capsys)
    assert status == STATUS_BAD_INPUT
    assert f"{blocker} is a file; give a folder path" in err and "Traceback" not in err
    assert blocker.read_text() == "not a folder"   # nothing overwritten


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_output_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "locked"
    out.mkdir()
    out.chmod(0o500)
    status, err = _cli_error([str(SMALL_PLATE), "-o", str(out), "-q"], capsys)
    assert status == STATUS_BAD_INPUT and "not writable" in err


def test_a_read_only_output_folder_is_refused_by_its_permissions(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """As root (CI) a chmod does not stop writes, so the permission check itself is exercised."""
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    status, err = _cli_error([str(SMALL_PLATE), "-o", str(tmp_path / "out"), "-q"], capsys)
    assert status == STATUS_BAD_INPUT and "the output folder is not writable" in err


@pytest.mark.parametrize("content", [b"\xff\xfet\x00i\x00t\x00", b"\x00\x01\x02\x89PNG binary"])
def test_a_scene_that_is_not_utf8_text_is_named(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "scene.toml"
    path.write_bytes(content)
    with pytest.raises(scene.SceneError, match=rf"{path}: not a text file in UTF-8|{path}: not valid TOML"):
        scene.load_scene(path)


def test_a_garbage_mesh_file_is_an_error_not_an_exit(tmp_path: Path) -> None:
    """meshio ends the process (SystemExit) on some unreadable files; the frontend turns it into
    its own error naming the file."""
    path = tmp_path / "part.msh"
    path.write_bytes(b"garbage\x00\x01 not a mesh")
    with pytest.raises(geometry.GeometryError, match=r"meshio cannot read this file"):
        mesh_files.load_mesh(path)


def test_a_mesh_request_beyond_the_machine_is_refused_before_meshing(tmp_path: Path) -> None:
    text = SMALL_PLATE.read_text().replace("elements = [8, 4]", "elements = [100000, 100000]")
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(scene.SceneError, match=r"ask for 1e\+10 elements \(part 'plate'.*GiB to mesh and run"):
        scene.load_scene(path)


def test_a_truncated_results_file_is_called_truncated(tmp_path: Path) -> None:
    res = paradyn.run(SMALL_PLATE, tmp_path / "run", ranks=1, threads=1, post=False, progress=False)
    cut = tmp_path / "cut.h5"
    shutil.copyfile(res.path, cut)
    with open(cut, "r+b") as f:
        f.truncate(cut.stat().st_size // 3)
    with pytest.raises(ResultsError, match=r"is truncated"):
        paradyn.read(cut)


@pytest.fixture
def tiny_disk(tmp_path: Path):
    """A 300 kB file system (tmpfs; needs root, as CI has), unmounted afterwards."""
    mount = tmp_path / "tiny"
    mount.mkdir()
    made = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", str(mount)], capture_output=True)
    if made.returncode != 0:
        pytest.skip("cannot mount a small tmpfs here (needs root)")
    yield mount
    subprocess.run(["umount", str(mount)], check=True)


def test_a_full_disk_ends_the_run_with_status_1_and_a_message(tiny_disk: Path) -> None:
    """The engine used to write on after 'No space left on device', report DONE and segfault in
    MPI_Finalize; now it stops with status 1 and one message naming the file and the fix."""
    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    path = deck.write_deck(model, tiny_disk / "deck.h5")
    (tiny_disk / "filler").write_bytes(b"\0" * (300 * 1024 - path.stat().st_size - 40 * 1024))
    done = subprocess.run([str(launch.engine_path()), str(path), str(tiny_disk / "results.h5")],
                          env=launch.engine_environment(1), capture_output=True, text=True, timeout=60)
    assert done.returncode == STATUS_FAILURE, done.stderr[-2000:]
    assert "cannot write" in done.stderr and "the disk is full" in done.stderr
    assert "PARADYN-DONE" not in done.stdout and "Segmentation fault" not in done.stderr


def test_paradyn_run_on_a_full_disk_exits_1_with_a_message(tiny_disk: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The whole path: paradyn-run writes its deck, the engine fills the disk with the results and
    stops with status 1; paradyn-run exits 1 with the engine's message, no traceback."""
    (tiny_disk / "filler").write_bytes(b"\0" * (300 * 1024 - 80 * 1024))
    status = cli.main([str(SMALL_PLATE), "-o", str(tiny_disk / "run"), "-n", "1", "-t", "1", "-q", "--no-plots",
                       "--no-vtk"])
    err = capsys.readouterr().err
    assert status == STATUS_FAILURE, err
    assert "cannot write" in err and "Traceback" not in err
