"""Issue 17: bad files and folders get one clear message and a documented exit status, never a
traceback: an output path that is a file, under a file or read-only, a scene that is not UTF-8
text, a mesh file that is garbage, a mesh request beyond the machine, a truncated results file."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
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


def _paradyn_run(arguments: list[str], **kwargs: object) -> subprocess.CompletedProcess:
    """The command itself (paradyn.commands.paradyn_run: the engine started before the imports,
    os._exit at the end), as a user runs it."""
    return subprocess.run([sys.executable, "-c", "from paradyn.commands import paradyn_run; paradyn_run()",
                           *arguments], capture_output=True, text=True, env=launch.engine_environment(1),
                          timeout=300, **kwargs)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-32", "binary", "latin-1"])
def test_a_scene_that_is_not_utf8_through_the_command(tmp_path: Path, encoding: str) -> None:
    """Issue 34: the command's early engine start read the scene with tomllib before its own
    reader, and a UTF-16 (or binary) file ended in a traceback; now status 2 and one line."""
    path = tmp_path / "scene.toml"
    text = SMALL_PLATE.read_text().replace("Small cantilever plate", "Kragplatte für Stöße")
    binary = b"\x00\x01\x89PNG\r\n\x1a\n" + bytes(range(256))
    path.write_bytes(binary if encoding == "binary" else text.encode(encoding))
    done = _paradyn_run([str(path), "-o", str(tmp_path / "run"), "-q", "-t", "1"])
    assert done.returncode == STATUS_BAD_INPUT, done.stderr
    assert "Traceback" not in done.stderr and done.stderr.count("\n") == 1
    assert f"{path}: not a text file in UTF-8" in done.stderr and "save the scene as UTF-8 TOML" in done.stderr
    assert not (tmp_path / "run" / "deck.h5").exists()


def _left_behind(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name != "source.txt") if folder.is_dir() else []


def test_a_full_disk_while_the_deck_is_written(tiny_disk: Path) -> None:
    """Issue 34: HDF5 writing the deck onto a full disk spewed h5py's errors and crashed the
    process (status 245 or 139). The deck is now made in memory and written in one piece: status
    1, one message naming the deck and the disk, and no deck or temporary file left."""
    (tiny_disk / "filler").write_bytes(b"\0" * (300 * 1024 - 8 * 1024))
    out = tiny_disk / "run"
    done = _paradyn_run([str(SMALL_PLATE), "-o", str(out), "-q", "-t", "1"])
    assert done.returncode == STATUS_FAILURE, done.stderr[-3000:]
    assert done.stderr == (f"paradyn-run: error: cannot write {out / 'deck.h5'} (No space left on device); free space "
                           f"(or fix the file system) and rerun\n")
    assert _left_behind(out) == []


def test_a_deck_write_that_fails_leaves_nothing(tmp_path: Path) -> None:
    """The same without root (no tmpfs): a file size limit makes the deck's write fail (EFBIG; Python
    ignores SIGXFSZ), which must end the same way."""
    import resource

    out = tmp_path / "run"
    done = _paradyn_run([str(SMALL_PLATE), "-o", str(out), "-q", "-t", "1"],
                        preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (6000, 6000)))
    assert done.returncode == STATUS_FAILURE, done.stderr[-3000:]
    assert f"cannot write {out / 'deck.h5'} (File too large)" in done.stderr and "Traceback" not in done.stderr
    assert _left_behind(out) == []


def test_a_results_file_held_open_by_a_reader_is_named(tmp_path: Path) -> None:
    """Issue 34: a results.h5 open in h5py (a notebook that read the last run) made the engine say
    only "cannot create ...; check that the folder exists and is writable". Now the message says
    that another program holds it open and what to do; closed, the run goes."""
    import h5py

    res = paradyn.run(SMALL_PLATE, tmp_path, ranks=1, threads=1, post=False, progress=False)
    deck_path = tmp_path / "deck.h5"
    with h5py.File(res.path, "r"):
        with pytest.raises(launch.EngineError) as error:
            launch.run_engine(deck_path, res.path, 1, 1)
        assert error.value.exit_code == STATUS_FAILURE
        message = str(error.value)
        assert f"cannot create {res.path}: another program holds it open" in message
        assert "f.close()" in message and "check that the folder exists" not in message
    assert launch.run_engine(deck_path, res.path, 1, 1).exit_code == 0


@pytest.mark.parametrize("code", [0, 4, -1, 99])
def test_a_hand_written_deck_with_an_enum_out_of_range_is_refused_by_both(tmp_path: Path, code: int) -> None:
    """The schema's enum rule drives the frontend's validator and the engine's deck rules alike:
    an hourglass form code outside 1 (viscous), 2 (stiffness), 3 (physical) is refused by both,
    with status 2, naming the dataset, the entry and the codes (every enum: tests/test_schema_damage.py)."""
    import h5py

    path = deck.write_deck(scene.build_model(scene.load_scene(SMALL_PLATE)), tmp_path / "deck.h5")
    with h5py.File(path, "r+") as f:
        f["/parts/hourglass_form"][0] = code
    expected = f"/parts/hourglass_form[0] = {code} must be 1 or 2 or 3 (1 = viscous, 2 = stiffness, 3 = physical)"
    with pytest.raises(deck.DeckError, match=re.escape(expected)):
        deck.validate_deck(path)
    done = subprocess.run([str(launch.engine_path()), str(path), str(tmp_path / "results.h5")], cwd=tmp_path,
                          capture_output=True, text=True, env=launch.engine_environment(1), timeout=60)
    assert done.returncode == STATUS_BAD_INPUT and expected in done.stderr
    assert not (tmp_path / "results.h5").exists()


def test_settings_far_outside_any_sensible_range_are_named_by_the_command(tmp_path: Path) -> None:
    """Hourglass coefficient 1e6, penalty scale 1e6, output and history intervals longer than the
    run: the run goes (they are legal), but the command names each with the usual range, also
    with -q (docs/errors.md, "Warnings")."""
    text = (ROOT / "cases" / "pipe_whip" / "scene.toml").read_text()
    for old, new in (("hourglass_coefficient = 0.1", "hourglass_coefficient = 1e6"),
                     ("penalty_scale = 0.1 ", "penalty_scale = 1e6 "),
                     ("output_interval = 5e-5", "output_interval = 1.0"),
                     ("history_interval = 1e-5", "history_interval = 1.0")):
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    done = _paradyn_run([str(path), "--check", "-q"])
    assert done.returncode == 0, done.stderr
    for words in ("output_interval 1 s is longer than end_time", "history_interval 1 s is longer than end_time",
                  "hourglass coefficient 1e+06 is far above the usual 0.05 to 0.15",
                  "penalty scale 1e+06 is far above the usual 0.1"):
        assert "warning: " in done.stdout and words in done.stdout, words
