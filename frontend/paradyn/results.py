"""Read ParaDyn results files and turn them into files other tools read.

The results file (``results.h5``) follows docs/formats.md, version 1.  This module reads it
into a :class:`Results` object and writes

* a ParaView/pyvista time series per part (``<part>.pvd`` + ``vtk/<part>_<k:05d>.vtu``),
* the history as plain CSV,
* an energy report and a ``summary.json``.

docs/outputs.md describes every output file, its columns, keys and units.
"""

from __future__ import annotations

import json
import math
import os
import re
import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

import h5py
import numpy as np

if TYPE_CHECKING:  # pyvista is imported lazily: it is slow to import and only needed for meshes
    import pyvista

SUPPORTED_RESULTS_VERSIONS = (1,)
DECK_FILE_NAME = "deck.h5"

ENERGY_NAMES = (
    "kinetic_energy",
    "internal_energy",
    "hourglass_energy",
    "contact_energy",
    "external_work",
)
TRACKED_COMPONENTS = ("dx", "dy", "dz", "vx", "vy", "vz")
PHASE_NAMES = ("elements", "contact", "communication", "output", "other")
CONTACT_PHASE_NAMES = ("sort", "search", "force")  # the contact phase split

_FRAME_DATASETS = {
    "displacement": "/frames/displacement",
    "velocity": "/frames/velocity",
    "membrane_stress": "/frames/element_membrane_stress",
    "von_mises": "/frames/element_von_mises",
    "plastic_strain": "/frames/element_plastic_strain",
}
_MEMBRANE_COMPONENTS = ("sxx", "syy", "sxy")
_VTK_QUAD = 9


class ResultsError(ValueError):
    """A results (or deck) file cannot be read as ParaDyn results."""


class IncompleteResultsError(ResultsError):
    """The results file has ``complete = 0``: the run did not finish."""


# --------------------------------------------------------------------------------------------
# The Results object
# --------------------------------------------------------------------------------------------


@dataclass(repr=False)
class Results:
    """Everything in a ParaDyn results file, in SI units, indices 0-based.

    Arrays (``n_frames`` field frames, ``n_records`` history records):

    * ``coordinates`` (n_nodes, 3) m, ``connectivity`` (n_elements, 4),
      ``element_part`` (n_elements,)
    * ``frame_times`` (n_frames,) s
    * ``displacement``, ``velocity`` (n_frames, n_nodes, 3) m, m/s
    * ``membrane_stress`` (n_frames, n_elements, 3) Pa (sxx, syy, sxy)
    * ``von_mises`` (n_frames, n_elements) Pa, ``plastic_strain`` (n_frames, n_elements)
    * ``history``: ``time`` (n_records,) s, the five energies (J), ``tracked_displacement`` and
      ``tracked_velocity`` (n_records, n_tracked, 3)

    ``run`` holds the ``/run`` attributes (empty if the run stopped before writing them).
    Names come from the deck when one was found; otherwise ``part_<i>`` and ``node_<id>``
    (``tracked_<i>`` when the tracked node ids are unknown too).
    """

    path: Path
    version: int
    complete: bool
    coordinates: np.ndarray
    connectivity: np.ndarray
    element_part: np.ndarray
    frame_times: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    membrane_stress: np.ndarray
    von_mises: np.ndarray
    plastic_strain: np.ndarray
    history: dict[str, np.ndarray]
    run: dict[str, Any]
    part_names: list[str]
    tracked_names: list[str]
    title: str = ""
    tracked_nodes: np.ndarray | None = None
    end_time: float | None = None
    deck_path: Path | None = None
    _grid_cache: dict[Any, Any] = field(default_factory=dict, repr=False, compare=False)

    def __repr__(self) -> str:
        state = "complete" if self.complete else "INCOMPLETE"
        return (
            f"Results({str(self.path)!r}, {state}, title={self.title!r}, "
            f"nodes={self.n_nodes}, elements={self.n_elements}, parts={self.part_names}, "
            f"frames={self.n_frames}, history_records={self.n_records}, "
            f"tracked={self.tracked_names})"
        )

    # ---- sizes -------------------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.connectivity.shape[0])

    @property
    def n_parts(self) -> int:
        return len(self.part_names)

    @property
    def n_frames(self) -> int:
        return int(self.frame_times.shape[0])

    @property
    def n_records(self) -> int:
        return int(self.history["time"].shape[0])

    @property
    def n_tracked(self) -> int:
        return int(self.history["tracked_displacement"].shape[1])

    # ---- meshes ------------------------------------------------------------------------------
    def frame_index(self, k: int) -> int:
        """Normalise a frame index (negative counts from the end); raise if out of range."""
        if self.n_frames == 0:
            raise IndexError(f"{self.path} holds no field frames (the run wrote none)")
        if not -self.n_frames <= k < self.n_frames:
            raise IndexError(
                f"frame {k} does not exist: {self.path} holds {self.n_frames} frames "
                f"(indices 0..{self.n_frames - 1}, or negative from the end)"
            )
        return k % self.n_frames

    def part_index(self, part: int | str) -> int:
        """Part index from an index or a part name."""
        if isinstance(part, str):
            if part not in self.part_names:
                raise KeyError(f"no part named {part!r}; the parts are {self.part_names}")
            return self.part_names.index(part)
        if not 0 <= part < self.n_parts:
            raise IndexError(f"part {part} does not exist; parts are 0..{self.n_parts - 1}")
        return int(part)

    def frame(
        self, k: int = -1, part: int | str | None = None, deformed: bool = True
    ) -> "pyvista.UnstructuredGrid":
        """Field frame ``k`` as a pyvista grid of VTK_QUAD cells.

        Points are at the deformed position (``deformed=False``: the initial one); point data
        ``displacement``, ``velocity``, ``node_id``; cell data ``membrane_stress``,
        ``von_mises``, ``plastic_strain``, ``part``, ``element_id``.  The field data
        ``TimeValue`` holds the frame time.  ``part`` restricts the grid to one part.
        """
        k = self.frame_index(k)
        key = ("all",) if part is None else ("part", self.part_index(part))
        if key not in self._grid_cache:
            elements = (
                np.arange(self.n_elements)
                if part is None
                else np.flatnonzero(self.element_part == key[1])
            )
            self._grid_cache[key] = _topology(self, elements)
        topo = self._grid_cache[key]
        grid = topo.grid.copy(deep=True)
        _fill_frame(grid, self, topo, k, deformed)
        return grid

    def plot(
        self,
        path: str | Path | None = None,
        frame: int = -1,
        scalars: str = "plastic_strain",
        **kwargs: Any,
    ) -> Path | None:
        """Render a frame coloured by ``scalars``.

        With ``path`` the picture is written off screen to that PNG (works without a display)
        and the path is returned; without it, an interactive window opens.
        """
        from . import plots

        if path is not None:
            return plots.render_deformed(self, path, frame=frame, scalars=scalars, **kwargs)
        plots.show_deformed(self, frame=frame, scalars=scalars, **kwargs)
        return None

    # ---- history -----------------------------------------------------------------------------
    def total_energy(self) -> np.ndarray:
        """kinetic + internal + hourglass + contact - external_work, per history record (J)."""
        h = self.history
        return (
            h["kinetic_energy"]
            + h["internal_energy"]
            + h["hourglass_energy"]
            + h["contact_energy"]
            - h["external_work"]
        )

    def tracked_columns(self) -> list[str]:
        """Column-safe tracked point names (unique, no commas or blanks)."""
        return _unique_safe_names(self.tracked_names, "tracked")

    def history_table(self) -> dict[str, np.ndarray]:
        """The history as columns, in the order of the CSV file (see docs/outputs.md)."""
        h = self.history
        table: dict[str, np.ndarray] = {"time": h["time"]}
        for name in ENERGY_NAMES:
            table[name] = h[name]
        table["total_energy"] = self.total_energy()
        table["contact_penetration"] = h["contact_penetration"]
        disp, vel = h["tracked_displacement"], h["tracked_velocity"]
        for i, name in enumerate(self.tracked_columns()):
            for c, axis in enumerate("xyz"):
                table[f"{name}_d{axis}"] = disp[:, i, c]
            for c, axis in enumerate("xyz"):
                table[f"{name}_v{axis}"] = vel[:, i, c]
        return table


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


def read(
    path: str | Path,
    deck: str | Path | None = None,
    allow_incomplete: bool = False,
) -> Results:
    """Read a ParaDyn results file.

    ``deck`` names the deck the run used, for part and tracked point names; by default
    ``deck.h5`` beside the results file is used when it exists and matches the mesh.
    ``allow_incomplete=True`` reads a file whose run did not finish, keeping only the frames and
    history records that were written completely.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no results file at {path}; check the path or run the deck first")
    try:
        h5 = h5py.File(path, "r")
    except OSError as exc:
        raise ResultsError(_open_error(path, exc)) from exc
    with h5:
        version, complete = _check_header(h5, path, allow_incomplete)
        mesh = _read_mesh(h5, path)
        n_nodes, n_elements = mesh["coordinates"].shape[0], mesh["connectivity"].shape[0]
        frames = _read_frames(h5, path, complete, n_nodes, n_elements)
        history = _read_history(h5, path, complete)
        run = _read_run(h5)
    names = _deck_names(path, deck, mesh)
    n_parts = max(
        len(names.part_names),
        names.n_parts,
        int(mesh["part"].max()) + 1 if mesh["part"].size else 0,
    )
    part_names = _part_names(names.part_names, n_parts)
    tracked_names = _tracked_names(names, history["tracked_displacement"].shape[1])
    return Results(
        path=path,
        version=version,
        complete=complete,
        coordinates=mesh["coordinates"],
        connectivity=mesh["connectivity"],
        element_part=mesh["part"],
        frame_times=frames["time"],
        displacement=frames["displacement"],
        velocity=frames["velocity"],
        membrane_stress=frames["membrane_stress"],
        von_mises=frames["von_mises"],
        plastic_strain=frames["plastic_strain"],
        history=history,
        run=run,
        part_names=part_names,
        tracked_names=tracked_names,
        title=names.title,
        tracked_nodes=names.tracked_nodes,
        end_time=names.end_time,
        deck_path=names.path,
    )


def _open_error(path: Path, exc: OSError) -> str:
    text = str(exc)
    if "lock" in text.lower():
        return (
            f"{path} is locked, probably by an engine that is still writing it; wait for the "
            f"run to finish, or set HDF5_USE_FILE_LOCKING=FALSE to read it anyway ({text})"
        )
    return f"{path} is not a ParaDyn results file: it cannot be opened as HDF5 ({text})"


def _check_header(h5: h5py.File, path: Path, allow_incomplete: bool) -> tuple[int, bool]:
    if "paradyn_results_version" not in h5.attrs:
        if "paradyn_deck_version" in h5.attrs:
            raise ResultsError(
                f"{path} is a ParaDyn deck, not a results file; run it with the engine and "
                f"read the results.h5 it writes"
            )
        raise ResultsError(
            f"{path} is not a ParaDyn results file: the root attribute "
            f"'paradyn_results_version' is missing"
        )
    version = int(np.asarray(h5.attrs["paradyn_results_version"]).reshape(-1)[0])
    if version not in SUPPORTED_RESULTS_VERSIONS:
        raise ResultsError(
            f"{path} has results version {version}, but this frontend reads version(s) "
            f"{', '.join(map(str, SUPPORTED_RESULTS_VERSIONS))}; use a frontend that matches "
            f"the engine that wrote it"
        )
    complete = bool(int(np.asarray(h5.attrs.get("complete", 0)).reshape(-1)[0]))
    if not complete and not allow_incomplete:
        raise IncompleteResultsError(
            f"{path}: the run did not finish (root attribute complete = 0); pass "
            f"allow_incomplete=True to read what was written"
        )
    return version, complete


def _required(h5: h5py.File, name: str, path: Path) -> np.ndarray:
    if name not in h5:
        raise ResultsError(
            f"{path} is not a complete ParaDyn results file: dataset {name} is missing "
            f"(see docs/formats.md)"
        )
    return np.asarray(h5[name][()])


def _read_mesh(h5: h5py.File, path: Path) -> dict[str, np.ndarray]:
    coords = _required(h5, "/mesh/coordinates", path).astype(np.float64, copy=False)
    conn = _required(h5, "/mesh/connectivity", path).astype(np.int64, copy=False)
    part = _required(h5, "/mesh/part", path).astype(np.int64, copy=False).reshape(-1)
    if coords.ndim != 2 or coords.shape[1] != 3:
        raise ResultsError(
            f"{path}: /mesh/coordinates has shape {coords.shape}, expected (n_nodes, 3)"
        )
    if conn.ndim != 2 or conn.shape[1] != 4:
        raise ResultsError(
            f"{path}: /mesh/connectivity has shape {conn.shape}, expected (n_elements, 4)"
        )
    if part.shape[0] != conn.shape[0]:
        raise ResultsError(
            f"{path}: /mesh/part has {part.shape[0]} entries but /mesh/connectivity has "
            f"{conn.shape[0]} elements"
        )
    if conn.size and (conn.min() < 0 or conn.max() >= coords.shape[0]):
        raise ResultsError(
            f"{path}: /mesh/connectivity refers to node {int(conn.max())} (or a negative "
            f"index) but there are {coords.shape[0]} nodes; indices are 0-based"
        )
    if part.size and part.min() < 0:
        raise ResultsError(f"{path}: /mesh/part has a negative part index {int(part.min())}")
    return {"coordinates": coords, "connectivity": conn, "part": part}


def _available_rows(
    h5: h5py.File, names: dict[str, str], complete: bool, path: Path, group: str
) -> int:
    """Number of rows present in every dataset; a mismatch is an error in a complete file."""
    lengths = {name: (h5[ds].shape[0] if ds in h5 else 0) for name, ds in names.items()}
    counts = set(lengths.values())
    if complete and len(counts) > 1:
        detail = ", ".join(f"{names[n]}: {c}" for n, c in lengths.items())
        raise ResultsError(
            f"{path}: the {group} datasets disagree on their length ({detail}); the file is "
            f"damaged, re-run the deck"
        )
    return min(counts) if counts else 0


def _read_frames(
    h5: h5py.File, path: Path, complete: bool, n_nodes: int, n_elements: int
) -> dict[str, np.ndarray]:
    names = {"time": "/frames/time", **_FRAME_DATASETS}
    if complete:
        for ds in names.values():
            _ensure(h5, ds, path)
    n = _available_rows(h5, names, complete, path, "/frames")
    shapes = {
        "time": (),
        "displacement": (n_nodes, 3),
        "velocity": (n_nodes, 3),
        "membrane_stress": (n_elements, 3),
        "von_mises": (n_elements,),
        "plastic_strain": (n_elements,),
    }
    out: dict[str, np.ndarray] = {}
    for name, ds in names.items():
        out[name] = _rows(h5, ds, n, shapes[name], path)
    return out


def _read_history(h5: h5py.File, path: Path, complete: bool) -> dict[str, np.ndarray]:
    energy = {name: f"/history/{name}" for name in ("time", *ENERGY_NAMES)}
    tracked = {
        "tracked_displacement": "/history/tracked_displacement",
        "tracked_velocity": "/history/tracked_velocity",
    }
    if complete:
        for ds in energy.values():
            _ensure(h5, ds, path)
    present_tracked = {k: v for k, v in tracked.items() if v in h5}
    n = _available_rows(h5, {**energy, **present_tracked}, complete, path, "/history")
    out = {name: _rows(h5, ds, n, (), path) for name, ds in energy.items()}
    # deepest contact penetration (m); zeros for files written before the engine had contact
    out["contact_penetration"] = _rows(h5, "/history/contact_penetration", n, (), path)
    n_tracked = h5[tracked["tracked_displacement"]].shape[1] if present_tracked else 0
    for name, ds in tracked.items():
        out[name] = _rows(h5, ds, n, (n_tracked, 3), path)
    return out


def _ensure(h5: h5py.File, name: str, path: Path) -> None:
    if name not in h5:
        raise ResultsError(
            f"{path} says the run is complete but dataset {name} is missing; the file is "
            f"damaged or was written by another program (see docs/formats.md)"
        )


def _rows(h5: h5py.File, name: str, n: int, tail: tuple[int, ...], path: Path) -> np.ndarray:
    if name not in h5 or n == 0:
        return np.zeros((n, *tail), dtype=np.float64)
    data = np.asarray(h5[name][:n], dtype=np.float64)
    if data.shape[1:] != tail:
        expected = "(n,)" if not tail else f"(n, {', '.join(map(str, tail))})"
        raise ResultsError(
            f"{path}: dataset {name} has shape {h5[name].shape}, expected {expected} "
            f"(see docs/formats.md)"
        )
    return data


def _read_run(h5: h5py.File) -> dict[str, Any]:
    if "run" not in h5:
        return {}
    return {str(k): _py(v) for k, v in h5["run"].attrs.items()}


def _py(value: Any) -> Any:
    """numpy scalars, bytes and small arrays to plain Python values (for JSON)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray):
        if value.size == 1:
            return _py(value.reshape(-1)[0])
        return [_py(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    return value


# ---- names from the deck -------------------------------------------------------------------


@dataclass
class _DeckNames:
    path: Path | None = None
    title: str = ""
    part_names: list[str] = field(default_factory=list)
    n_parts: int = 0
    tracked_names: list[str] = field(default_factory=list)
    tracked_nodes: np.ndarray | None = None
    end_time: float | None = None


def _deck_names(
    results_path: Path, deck: str | Path | None, mesh: dict[str, np.ndarray]
) -> _DeckNames:
    if deck is None:
        candidate = results_path.parent / DECK_FILE_NAME
        if not candidate.is_file():
            return _DeckNames()
        try:
            return _read_deck_names(candidate, mesh)
        except (ResultsError, OSError) as exc:
            warnings.warn(f"ignoring {candidate} for names: {exc}", stacklevel=3)
            return _DeckNames()
    deck = Path(deck)
    if not deck.is_file():
        raise FileNotFoundError(
            f"no deck at {deck}; pass the deck.h5 the run used, or leave deck=None"
        )
    return _read_deck_names(deck, mesh)


def _read_deck_names(deck: Path, mesh: dict[str, np.ndarray]) -> _DeckNames:
    try:
        h5 = h5py.File(deck, "r")
    except OSError as exc:
        raise ResultsError(
            f"{deck} is not a ParaDyn deck: it cannot be opened as HDF5 ({exc})"
        ) from exc
    with h5:
        if "paradyn_deck_version" not in h5.attrs:
            raise ResultsError(
                f"{deck} is not a ParaDyn deck (no root attribute paradyn_deck_version)"
            )
        n_nodes = h5["/nodes/coordinates"].shape[0] if "/nodes/coordinates" in h5 else None
        if n_nodes is not None and n_nodes != mesh["coordinates"].shape[0]:
            raise ResultsError(
                f"{deck} has {n_nodes} nodes but the results have "
                f"{mesh['coordinates'].shape[0]}; it is not the deck of this run"
            )
        names = _DeckNames(path=deck)
        names.title = (_strings(h5.attrs.get("title"), one=True) or [""])[0]
        if "parts" in h5:
            names.part_names = _strings(h5["parts"].attrs.get("names"))
            if "thickness" in h5["parts"]:
                names.n_parts = int(h5["parts/thickness"].shape[0])
        if "output" in h5:
            names.tracked_names = _strings(h5["output"].attrs.get("tracked_names"))
            if "tracked_nodes" in h5["output"]:
                tracked = np.asarray(h5["output/tracked_nodes"][()])
                names.tracked_nodes = tracked.astype(np.int64).reshape(-1)
        if "control" in h5 and "end_time" in h5["control"].attrs:
            names.end_time = float(np.asarray(h5["control"].attrs["end_time"]).reshape(-1)[0])
    return names


def _strings(value: Any, one: bool = False) -> list[str]:
    """h5py string attribute (str, bytes, or an array of either) to a list of str."""
    if value is None:
        return []
    if isinstance(value, (str, bytes, np.str_, np.bytes_)):
        items = [value]
    else:
        items = list(np.asarray(value).reshape(-1))
    out = [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in items]
    return out[:1] if one else out


def _part_names(deck_names: list[str], n_parts: int) -> list[str]:
    names = [n.strip() for n in deck_names[:n_parts]]
    names += [f"part_{i}" for i in range(len(names), n_parts)]
    return [n if n else f"part_{i}" for i, n in enumerate(names)]


def _tracked_names(names: _DeckNames, n_tracked: int) -> list[str]:
    out: list[str] = []
    for i in range(n_tracked):
        if i < len(names.tracked_names) and names.tracked_names[i].strip():
            out.append(names.tracked_names[i].strip())
        elif names.tracked_nodes is not None and i < names.tracked_nodes.shape[0]:
            out.append(f"node_{int(names.tracked_nodes[i])}")
        else:
            out.append(f"tracked_{i}")
    return out


def _unique_safe_names(names: list[str], fallback: str) -> list[str]:
    """Names usable as file names and CSV column names: [A-Za-z0-9_.-], unique."""
    out: list[str] = []
    seen: set[str] = set()
    for i, name in enumerate(names):
        safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_.") or f"{fallback}_{i}"
        candidate, n = safe, 1
        while candidate in seen:
            n += 1
            candidate = f"{safe}_{n}"
        seen.add(candidate)
        out.append(candidate)
    return out


# --------------------------------------------------------------------------------------------
# Meshes for pyvista / VTK
# --------------------------------------------------------------------------------------------


@dataclass
class _Topology:
    """A grid of some elements with its own compact node numbering."""

    grid: Any  # pyvista.UnstructuredGrid at the initial positions
    nodes: np.ndarray  # global node index of each local point
    elements: np.ndarray  # global element index of each cell


def _topology(results: Results, elements: np.ndarray) -> _Topology:
    import pyvista as pv

    conn = results.connectivity[elements]
    nodes, local = np.unique(conn, return_inverse=True)
    local = local.reshape(-1, 4)
    cells = np.hstack([np.full((local.shape[0], 1), 4, dtype=np.int64), local]).ravel()
    celltypes = np.full(local.shape[0], _VTK_QUAD, dtype=np.uint8)
    grid = pv.UnstructuredGrid(cells, celltypes, results.coordinates[nodes].copy())
    grid.point_data["node_id"] = nodes.astype(np.int64)
    grid.cell_data["element_id"] = elements.astype(np.int64)
    grid.cell_data["part"] = results.element_part[elements].astype(np.int32)
    return _Topology(grid=grid, nodes=nodes, elements=elements)


def _fill_frame(grid: Any, results: Results, topo: _Topology, k: int, deformed: bool) -> None:
    disp = results.displacement[k, topo.nodes]
    x0 = results.coordinates[topo.nodes]
    grid.points = x0 + disp if deformed else x0.copy()
    grid.point_data["displacement"] = disp
    grid.point_data["velocity"] = results.velocity[k, topo.nodes]
    grid.cell_data["membrane_stress"] = results.membrane_stress[k, topo.elements]
    grid.cell_data["von_mises"] = results.von_mises[k, topo.elements]
    grid.cell_data["plastic_strain"] = results.plastic_strain[k, topo.elements]
    grid.field_data["TimeValue"] = np.array([results.frame_times[k]])
    array = grid.GetCellData().GetArray("membrane_stress")
    for c, name in enumerate(_MEMBRANE_COMPONENTS):
        array.SetComponentName(c, name)


def write_vtk_series(results: Results, out_dir: str | Path) -> list[Path]:
    """Write one ParaView time series per part; return the ``.pvd`` paths.

    Layout: ``out_dir/<part>.pvd`` referencing ``out_dir/vtk/<part>_<k:05d>.vtu`` (binary,
    VTK_QUAD cells at the deformed position).  Old ``vtk/<part>_#####.vtu`` files of the same
    parts are removed first, so a shorter re-run leaves no stale frames.  Parts without
    elements get no series.
    """
    out_dir = Path(out_dir)
    vtk_dir = out_dir / "vtk"
    vtk_dir.mkdir(parents=True, exist_ok=True)
    if results.n_frames == 0:
        raise ResultsError(f"{results.path} holds no field frames; there is nothing to write")
    pvds: list[Path] = []
    for part, stem in enumerate(_unique_safe_names(results.part_names, "part")):
        elements = np.flatnonzero(results.element_part == part)
        if elements.size == 0:
            continue
        _remove_stale_frames(vtk_dir, stem)
        topo = _topology(results, elements)
        files = []
        for k in range(results.n_frames):
            _fill_frame(topo.grid, results, topo, k, deformed=True)
            vtu = vtk_dir / f"{stem}_{k:05d}.vtu"
            topo.grid.save(vtu, binary=True)
            files.append(vtu.relative_to(out_dir).as_posix())
        pvd = out_dir / f"{stem}.pvd"
        _atomic_write_text(pvd, _pvd_xml(results.frame_times, files))
        pvds.append(pvd)
    return pvds


def _remove_stale_frames(vtk_dir: Path, stem: str) -> None:
    pattern = re.compile(re.escape(stem) + r"_\d{5}\.vtu")
    for old in vtk_dir.glob(f"{stem}_*.vtu"):
        if pattern.fullmatch(old.name):
            old.unlink()


def _pvd_xml(times: np.ndarray, files: list[str]) -> str:
    """PVD collection: one DataSet per frame; one part per file, so part is always 0."""
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
    ]
    for t, f in zip(times.tolist(), files):
        lines.append(
            f'    <DataSet timestep="{float(t)!r}" group="" part="0" file={quoteattr(f)}/>'
        )
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# History CSV, energy report, summary
# --------------------------------------------------------------------------------------------


def write_history_csv(results: Results, path: str | Path) -> Path:
    """Write the history table (see :meth:`Results.history_table`) as CSV; return the path.

    One header line, comma separated, every value written with Python's ``repr`` (shortest
    text that reads back to the same float64).
    """
    path = Path(path)
    table = results.history_table()
    columns = np.column_stack([np.asarray(v, dtype=np.float64) for v in table.values()])
    lines = [",".join(table.keys())]
    lines += [",".join(map(repr, row)) for row in columns.tolist()]
    _atomic_write_text(path, "\n".join(lines) + "\n")
    return path


def energy_report(results: Results) -> dict[str, Any]:
    """Initial and final energies (J) and the energy balance error.

    ``balance_error = |E_total(end) - E_total(0)| / max(max_t KE, max_t IE, max_t |W_ext|, tiny)``
    with ``E_total = KE + IE + hourglass + contact - W_ext``: the LS-DYNA style energy ratio
    check (a conservative run keeps it at a few percent at most).  ``hourglass_ratio`` is the
    final hourglass energy over the largest internal energy (LS-DYNA's rule of thumb: < 0.1).
    With no history records every value is None.
    """
    keys = ("kinetic", "internal", "hourglass", "contact", "external_work")
    columns = dict(zip(keys, ENERGY_NAMES))
    h = results.history
    if results.n_records == 0:
        empty = {k: None for k in (*keys, "total")}
        return {
            "initial": dict(empty),
            "final": dict(empty),
            "balance_error": None,
            "reference_energy": None,
            "hourglass_ratio": None,
        }
    total = results.total_energy()
    initial = {k: float(h[c][0]) for k, c in columns.items()} | {"total": float(total[0])}
    final = {k: float(h[c][-1]) for k, c in columns.items()} | {"total": float(total[-1])}
    reference = max(
        float(np.max(h["kinetic_energy"])),
        float(np.max(h["internal_energy"])),
        float(np.max(np.abs(h["external_work"]))),
    )
    scale = max(reference, np.finfo(np.float64).tiny)
    max_internal = float(np.max(h["internal_energy"]))
    return {
        "initial": initial,
        "final": final,
        "balance_error": _finite(abs(final["total"] - initial["total"]) / scale),
        "reference_energy": reference,
        "hourglass_ratio": _finite(final["hourglass"] / max_internal) if max_internal > 0 else None,
    }


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def write_summary(
    results: Results,
    path: str | Path,
    effects: list[str],
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Write ``summary.json`` atomically and return its content.

    Run figures come from the ``/run`` attributes (None if the run did not write them);
    ``elements`` and ``nodes`` fall back to the mesh.  ``extra`` entries are merged last and
    may replace computed ones.  Keys and units: docs/outputs.md.
    """
    run = results.run
    summary: dict[str, Any] = {
        "title": results.title,
        "complete": results.complete,
        "end_time": (
            results.end_time if results.end_time is not None else _last(results.frame_times)
        ),
        "time_reached": (
            _last(results.history["time"]) if results.n_records else _last(results.frame_times)
        ),
        "wall_s": run.get("wall_s"),
        "cycles": run.get("cycles"),
        "dt_s": run.get("dt_s"),
        "dt_stable_s": run.get("dt_stable_s"),
        "elements": run.get("elements", results.n_elements),
        "nodes": run.get("nodes", results.n_nodes),
        "ranks": run.get("ranks"),
        "threads": run.get("threads"),
        "element_cycles_per_s": run.get("element_cycles_per_s"),
        "peak_memory_per_rank_mb": run.get("peak_memory_per_rank_mb"),
        "load_imbalance": run.get("load_imbalance"),
        "phase_s": {p: run.get(f"phase_{p}_s") for p in PHASE_NAMES},
        "contact_phase_s": {p: run.get(f"phase_contact_{p}_s") for p in CONTACT_PHASE_NAMES},
        "frames": results.n_frames,
        "history_records": results.n_records,
        "parts": list(results.part_names),
        "energy": energy_report(results),
        "effects": list(effects),
    }
    if extra:
        summary.update(extra)
    summary = _jsonable(summary)
    _atomic_write_text(Path(path), json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return summary


def _last(a: np.ndarray) -> float | None:
    return float(a[-1]) if a.shape[0] else None


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy to Python, Path to str, non-finite floats to None."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    value = _py(value)
    if isinstance(value, list):
        return [_jsonable(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _atomic_write_text(path: Path, text: str) -> None:
    """Write to a temporary file beside ``path``, then rename it over ``path``."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)  # mkstemp creates 0600
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
