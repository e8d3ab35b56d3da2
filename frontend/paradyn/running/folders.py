"""Which output folder a run writes, and whose results a folder holds.

``paradyn-run SCENE`` without ``-o`` writes ``runs/<name>`` under the current folder: the scene's
folder name for a file called ``scene.toml`` (``cases/pipe_whip/scene.toml`` -> ``runs/pipe_whip``),
the file's own name otherwise (``plate_a.toml`` and ``plate_b.toml`` of one folder ->
``runs/plate_a`` and ``runs/plate_b``), and a deck's name for a deck. A run records its source in
``source.txt``; a folder that holds the results of another source (``source.txt``, or the
``scene`` entry of an older ``summary.json``) is refused unless ``--force`` (``force=True``) says to
replace them. A scene built in Python is recorded as ``paradyn.Scene '<title>'``, a deck model as
``paradyn.deck.Model '<title>'``. A folder that is reused (the same source again, or another one
with ``--force``) is cleaned of the earlier run's outputs before the new run writes its deck
(:func:`clean_outputs`), so no frame, picture or history of the old run sits beside the new
results (docs/scene.md, "Output folders").
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from pathlib import Path

from paradyn.atomic_write import write_text_atomic

SOURCE_FILE = "source.txt"
SCENE_FILE_NAME = "scene.toml"   # the usual name: its folder names the run
RUN_FILES = ("deck.h5", "results.h5", "results.checkpoint.h5", "summary.json")
# what a run and its post-processing write (docs/outputs.md), removed before a folder is reused;
# vtk/<part>_NNNNN.vtu go with them, and any other file of the folder stays
OUTPUT_FILES = (*RUN_FILES, SOURCE_FILE, "engine.log", "results.vtkhdf", "history.csv", "energies.png",
                "parts.png", "tracked.png", "deformed.png", "job.sbatch")
VTK_FOLDER = "vtk"


class OutputFolderError(ValueError):
    """The output folder cannot be made or written: a bad command line or call (exit status 2)."""


def output_folder(out: str | Path) -> Path:
    """The output folder, created, after checking that a run can write there (issue 17: a path that
    is a file, lies under a file, or is read-only gets a message, not a traceback halfway)."""
    out = Path(out)
    blocking = next((p for p in [out, *out.parents] if p.exists() and not p.is_dir()), None)
    if blocking is not None:
        raise OutputFolderError(f"{out}: cannot be the output folder, {blocking} is a file; give a folder path "
                      f"(paradyn-run -o FOLDER)")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputFolderError(f"{out}: cannot create the output folder ({exc.strerror}); give a folder you can "
                      f"write (paradyn-run -o FOLDER)") from exc
    if not os.access(out, os.W_OK | os.X_OK):
        raise OutputFolderError(f"{out}: the output folder is not writable; give a folder you can write "
                      f"(paradyn-run -o FOLDER), or change its permissions")
    return out


def default_output(source: Path, cwd: Path | None = None) -> Path:
    """``runs/<name>`` under ``cwd`` (default: the current folder) for a scene or deck file."""
    source = Path(source)
    name = source.resolve().parent.name if source.name == SCENE_FILE_NAME else source.stem
    return (cwd or Path.cwd()) / "runs" / (name or "run")


def recorded_source(out: Path) -> Path | None:
    """The scene or deck whose run wrote ``out`` (None when nothing says)."""
    record = out / SOURCE_FILE
    if record.is_file():
        text = record.read_text(errors="replace").strip()
        return Path(text) if text else None
    summary = out / "summary.json"
    if summary.is_file():
        try:
            scene = json.loads(summary.read_text()).get("scene")
        except (ValueError, OSError, AttributeError):
            return None
        return Path(scene) if isinstance(scene, str) and scene else None
    return None


def claim_output(out: Path, source: Path | str, force: bool = False, *, clean: bool = False,
                 results_name: str = "results.h5") -> None:
    """Check that a run of ``source`` may write into ``out``, and record it there.

    ``source`` is a scene or deck file, or the name of a source built in Python
    (:func:`source_identity`). With ``clean``, the earlier run's outputs are removed first
    (:func:`clean_outputs`; ``results_name``: the run's results file, if not ``results.h5``).

    Raises
    ------
    OutputFolderError
        ``out`` holds the run of another scene or deck and ``force`` is False (exit status 2)."""
    check_owner(out, source, force)
    out = output_folder(out)
    source = _identity(source)
    inside = isinstance(source, Path) and out.resolve() in source.parents   # the folder's own deck, run again
    if clean:
        clean_outputs(out, keep=source if isinstance(source, Path) else None, results_name=results_name)
    if not inside:
        write_text_atomic(out / SOURCE_FILE, f"{source}\n")


def check_owner(out: Path, source: Path | str, force: bool = False) -> None:
    """Refuse ``out`` when it holds the run of another source than ``source`` (unless ``force``)."""
    out, source = Path(out), _identity(source)
    if force or not out.is_dir():
        return
    inside = isinstance(source, Path) and out.resolve() in source.parents
    owner = recorded_source(out)
    has_run = any((out / name).exists() for name in RUN_FILES)
    if has_run and owner is not None and owner != Path(str(source)) and not inside:   # as source.txt reads back
        raise OutputFolderError(
            f"{out} holds the run of {owner}, not of {source}; give another folder (-o, or paradyn.run's out), or "
            f"--force (force=True) to replace that run")


def source_identity(source: object) -> Path | str:
    """What ``source.txt`` records for a source: a file's resolved path; ``paradyn.Scene '<title>'``
    for a scene built in Python, ``paradyn.deck.Model '<title>'`` for a model."""
    if isinstance(source, str | Path):
        return Path(source).resolve()
    path = getattr(source, "path", None)
    if isinstance(path, Path) and path.suffix:   # a scene loaded from its file
        return path.resolve()
    title = getattr(source, "title", "")
    module = type(source).__module__
    kind = "paradyn.Scene" if module.startswith("paradyn.scene") else "paradyn.deck.Model"
    return f"{kind} {str(title)!r}"


def clean_outputs(out: Path, keep: Path | None = None, results_name: str = "results.h5") -> list[Path]:
    """Remove the outputs an earlier run wrote into ``out`` (:data:`OUTPUT_FILES`, the ``.pvd``
    series and their ``vtk/*.vtu`` frames, a results file of another name and its checkpoint),
    except ``keep`` (the source file when it lies in the folder); return what was removed.

    Raises
    ------
    OutputFolderError
        A file cannot be removed (held by another program, or the folder is read-only)."""
    removed = []
    for path in _outputs(Path(out), results_name):
        if keep is not None and path.resolve() == keep:
            continue
        try:
            path.unlink()
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise OutputFolderError(f"{path}: cannot remove the earlier run's output ({exc.strerror}); close "
                                    f"the program that holds it, or give another folder") from exc
        removed.append(path)
    frames = Path(out) / VTK_FOLDER
    if frames.is_dir() and not any(frames.iterdir()):
        frames.rmdir()
    return removed


def _outputs(out: Path, results_name: str) -> Iterator[Path]:
    """The files of ``out`` that a run of ParaDyn writes (whether or not they exist)."""
    checkpoint = Path(results_name).with_suffix(".checkpoint.h5").name
    for name in dict.fromkeys((*OUTPUT_FILES, results_name, checkpoint)):
        yield out / name
    for pvd in sorted(out.glob("*.pvd")):
        yield pvd
        frames = out / VTK_FOLDER
        if frames.is_dir():
            yield from sorted(frames.glob(f"{pvd.stem}_[0-9][0-9][0-9][0-9][0-9].vtu"))


def _identity(source: Path | str) -> Path | str:
    """A file (Path) resolved; a name of a source built in Python (str) as it is."""
    return Path(source).resolve() if isinstance(source, Path) else source
