"""Which output folder a run writes, and whose results a folder holds.

``paradyn-run SCENE`` without ``-o`` writes ``runs/<name>`` under the current folder: the scene's
folder name for a file called ``scene.toml`` (``cases/pipe_whip/scene.toml`` -> ``runs/pipe_whip``),
the file's own name otherwise (``plate_a.toml`` and ``plate_b.toml`` of one folder ->
``runs/plate_a`` and ``runs/plate_b``), and a deck's name for a deck. A run records its source in
``source.txt``; a folder that holds the results of another source (``source.txt``, or the
``scene`` entry of an older ``summary.json``) is refused unless ``--force`` says to replace them
(docs/outputs.md, "Output folders").
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from paradyn.atomic_write import write_text_atomic

SOURCE_FILE = "source.txt"
SCENE_FILE_NAME = "scene.toml"   # the usual name: its folder names the run
RUN_FILES = ("deck.h5", "results.h5", "results.checkpoint.h5", "summary.json")


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


def claim_output(out: Path, source: Path, force: bool = False) -> None:
    """Check that a run of ``source`` may write into ``out``, and record it there.

    Raises
    ------
    OutputFolderError
        ``out`` holds the run of another scene or deck and ``force`` is False (exit status 2)."""
    source = Path(source).resolve()
    out = output_folder(out)
    inside = out.resolve() in source.parents   # the folder's own deck, run again
    owner = recorded_source(out)
    has_run = any((out / name).exists() for name in RUN_FILES)
    if has_run and owner is not None and owner != source and not inside and not force:
        raise OutputFolderError(
            f"{out} holds the run of {owner}, not of {source}; give another folder with -o, or --force "
            f"to replace that run")
    if not inside:
        write_text_atomic(out / SOURCE_FILE, f"{source}\n")
