"""The runs of a study: mesh a configuration, key it by its deck's content, run it once (issue 16).

Every configuration is meshed and written as a deck in a staging folder; the SHA-256 of the deck's
contents (every dataset's bytes, every attribute, by name) and the layout (ranks x threads) name
its run folder ``runs/<key>``. A run folder with ``run.json`` is a finished run and is never run
again, so a study extended with more knob values only runs what is new; two configurations with
the same deck (a knob value that changes nothing) run once. Both steps are plain functions of
picklable arguments, for a process pool.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import time
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from paradyn import deck
from paradyn.atomic_write import write_text_atomic
from paradyn.results import reports
from paradyn.results.reading import read
from paradyn.running import launch
from paradyn.running.engine_process import EngineError
from paradyn.scene.building import build_model
from paradyn.scene.specs import Scene

from .design import Config, apply

RUN_RECORD = "run.json"   # written last: a run folder with it is a finished run


@dataclass
class Prepared:
    """A configuration meshed and written: its deck in ``staging``, its key, the seconds it took and
    the largest distance between a tracked node and its requested point (m)."""

    config: Config
    key: str
    staging: Path
    prepare_s: float
    track_offset_m: float


def deck_digest(path: Path) -> str:
    """SHA-256 of a deck's contents: names, dtypes, shapes and bytes of every dataset and every
    attribute, in name order (the HDF5 file's own bytes also hold times and addresses)."""
    sha = hashlib.sha256()

    def attributes(obj: h5py.HLObject) -> None:
        for name in sorted(obj.attrs):
            value = np.asarray(obj.attrs[name])
            sha.update(f"@{name}:{value.dtype.str}:{value.shape}:".encode())
            sha.update(value.tobytes() if value.dtype.kind != "O" else repr(value.tolist()).encode())

    with h5py.File(path, "r") as f:
        attributes(f)
        names: list[str] = []
        f.visit(names.append)
        for name in sorted(names):
            obj = f[name]
            sha.update(f"/{name}:".encode())
            if isinstance(obj, h5py.Dataset):
                data = np.ascontiguousarray(obj[()])
                sha.update(f"{data.dtype.str}:{data.shape}:".encode())
                sha.update(data.tobytes())
            attributes(obj)
    return sha.hexdigest()


def prepare(scene: Scene, config: Config, staging_root: Path, end_time: float | None,
            ranks: int, threads: int) -> Prepared:
    """Mesh ``scene`` with ``config`` set, write its deck under ``staging_root``, key it."""
    start = time.perf_counter()
    variant = apply(scene, config)
    if end_time is not None:
        variant.run.end_time = end_time
    # fields only at the start and the end: the study reads the history, and big meshes stay small on disk
    variant.run.output_interval = variant.run.end_time
    model = build_model(variant)
    staging = staging_root / uuid.uuid4().hex
    deck.write_deck(model, staging / "deck.h5")
    offsets = [float(np.linalg.norm(model.coordinates[node] - np.asarray(track.point)))
               for track, node in zip(variant.tracks, model.tracked_nodes, strict=True)]
    key = f"{deck_digest(staging / 'deck.h5')[:20]}-{engine_digest(model.control.precision)}-{ranks}x{threads}"
    return Prepared(config, key, staging, time.perf_counter() - start, max(offsets, default=0.0))


def engine_digest(precision: str | None = None) -> str:
    """A short hash of the path, size and modification time of the engine of ``precision``: a
    rebuilt engine runs anew."""
    engine = launch.engine_path(precision)
    stat = engine.stat()
    return hashlib.sha256(f"{engine}:{stat.st_size}:{stat.st_mtime_ns}".encode()).hexdigest()[:8]


def finished(folder: Path) -> dict[str, Any] | None:
    """The record of a finished run in ``folder``, or None."""
    path = folder / RUN_RECORD
    return json.loads(path.read_text()) if path.is_file() else None


def execute(folder: Path, ranks: int, threads: int, prepare_s: float, track_offset_m: float) -> dict[str, Any]:
    """Run the engine on ``folder/deck.h5``; write ``summary.json`` and, last, ``run.json`` (the cost
    and accuracy indicators); return the record. A failed run returns a record with ``error``
    and writes no ``run.json``, so that the next study tries it again."""
    start = time.perf_counter()
    try:
        engine = launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, threads,
                                   log_path=folder / "engine.log")
        results = read(folder / "results.h5", deck=folder / "deck.h5")
        summary = reports.write_summary(results, folder / "summary.json", {"study_run": True})
    except (EngineError, OSError, ValueError) as exc:
        return {"error": str(exc).strip().splitlines()[-1] if str(exc).strip() else type(exc).__name__}
    memory = summary.get("peak_memory_per_rank_mb")
    record = {
        "engine_s": engine.elapsed_s,
        "loop_s": summary.get("wall_s"),
        "whole_s": prepare_s + (time.perf_counter() - start),
        "core_s": engine.elapsed_s * ranks * threads,
        "cycles": summary.get("cycles"),
        "peak_memory_mb": memory * ranks if memory is not None else None,
        "elements": summary.get("elements"),
        "ranks": ranks, "threads": threads,
        "dt_s": summary.get("dt_s"),
        "track_offset_m": track_offset_m,
        "accuracy": summary["accuracy"],
        "finished_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    write_text_atomic(folder / RUN_RECORD, json.dumps(record, indent=2) + "\n")
    return record


def adopt(prepared: Prepared, runs_root: Path) -> Path:
    """Move a staged deck into its run folder (kept if the folder already holds one); return the folder."""
    folder = runs_root / prepared.key
    if not (folder / "deck.h5").is_file():
        folder.mkdir(parents=True, exist_ok=True)
        shutil.move(str(prepared.staging / "deck.h5"), folder / "deck.h5")
    shutil.rmtree(prepared.staging, ignore_errors=True)
    return folder

