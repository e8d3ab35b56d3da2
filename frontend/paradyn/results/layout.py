"""The layout of ``results.h5`` (docs/formats.md, version 1) and the checks made when opening one.

Everything here works on an open ``h5py.File`` and raises :class:`ResultsError` with a message
that names the file, the dataset and what to do. :mod:`paradyn.results.reading` builds the
:class:`~paradyn.results.reading.Results` object from these pieces.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from paradyn._schema import ENERGY_NAMES, FRAME_FIELDS

if TYPE_CHECKING:
    from collections.abc import Mapping

    import h5py

    # an open file, or some of its datasets by full path (_opened_datasets): what ``in`` and ``[]`` need
    Datasets = h5py.Group | Mapping[str, h5py.Dataset]

SUPPORTED_RESULTS_VERSIONS = (1,)

TRACKED_COMPONENTS = ("dx", "dy", "dz", "vx", "vy", "vz")
# the frame fields of schema/results.toml, under the names Results gives them (element_ dropped)
FRAME_DATASETS = {name.removeprefix("element_"): f"/frames/{name}" for name in FRAME_FIELDS if name != "time"}
# frame fields a file written before them lacks (read as zeros there); every other one is required
LATER_FRAME_FIELDS = ("acceleration", "nodal_contact_force", "layer_stress", "membrane_strain",
                      "internal_energy_density", "surface_strain", "thickness")


@dataclass(frozen=True)
class FrameArrays:
    """The fields of one frame (SI units; docs/outputs.md): ``displacement``, ``velocity``,
    ``acceleration`` and ``nodal_contact_force`` (n_nodes, 3); ``membrane_stress`` and
    ``membrane_strain`` (n_elements, 3); ``layer_stress`` (n_elements, 3 layers: bottom, middle,
    top, 5 components: sxx, syy, sxy, sxz, syz); ``surface_strain`` (n_elements, 2 surfaces: bottom,
    top, 3 components: exx, eyy, exy); ``von_mises``, ``plastic_strain``,
    ``internal_energy_density`` and ``thickness`` (the current shell thickness) (n_elements,)."""

    index: int
    time: float
    displacement: np.ndarray
    velocity: np.ndarray
    membrane_stress: np.ndarray
    von_mises: np.ndarray
    plastic_strain: np.ndarray
    acceleration: np.ndarray
    nodal_contact_force: np.ndarray
    layer_stress: np.ndarray
    membrane_strain: np.ndarray
    internal_energy_density: np.ndarray
    surface_strain: np.ndarray
    thickness: np.ndarray


class ResultsError(ValueError):
    """A results (or deck) file cannot be read as ParaDyn results."""


class IncompleteResultsError(ResultsError):
    """The results file has ``complete = 0``: the run did not finish."""


def open_results(path: Path) -> h5py.File:
    """Open ``path`` for reading; raise ResultsError saying why it cannot be opened."""
    import h5py  # where a file is opened

    try:
        return h5py.File(path, "r")
    except OSError as exc:
        raise ResultsError(_open_error(path, exc)) from exc


def _open_error(path: Path, exc: OSError) -> str:
    text = str(exc)
    if "truncated" in text.lower():   # checked first: HDF5 may also mention the lock it could not take
        return (
            f"{path} is truncated: it ends before the data it declares (a copy or a disk that stopped "
            f"while writing it); copy it again from the run, or rerun with --restart from its checkpoint ({text})"
        )
    if "lock" in text.lower():
        return (
            f"{path} is locked, probably by an engine that is still writing it; wait for the "
            f"run to finish, or set HDF5_USE_FILE_LOCKING=FALSE to read it anyway ({text})"
        )
    return f"{path} is not a ParaDyn results file: it cannot be opened as HDF5 ({text})"


def check_header(h5: h5py.File, path: Path, allow_incomplete: bool) -> tuple[int, bool]:
    """(version, complete) of a results file; raise if it is not one, or is incomplete and
    ``allow_incomplete`` is False."""
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


def read_mesh(h5: h5py.File, path: Path) -> dict[str, np.ndarray]:
    """``coordinates`` (float64), ``connectivity`` and ``part`` (int64) of ``/mesh``, checked."""
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
    h5: Datasets, names: dict[str, str], complete: bool, path: Path, group: str
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


def frame_tails(n_nodes: int, n_elements: int) -> dict[str, tuple[int, ...]]:
    """The shape of one frame of every frame field."""
    return {
        "displacement": (n_nodes, 3),
        "velocity": (n_nodes, 3),
        "membrane_stress": (n_elements, 3),
        "von_mises": (n_elements,),
        "plastic_strain": (n_elements,),
        "acceleration": (n_nodes, 3),
        "nodal_contact_force": (n_nodes, 3),
        "layer_stress": (n_elements, 3, 5),
        "membrane_strain": (n_elements, 3),
        "internal_energy_density": (n_elements,),
        "surface_strain": (n_elements, 2, 3),
        "thickness": (n_elements,),
    }


def read_frame_layout(
    h5: h5py.File, path: Path, complete: bool, n_nodes: int, n_elements: int
) -> np.ndarray:
    """Check the ``/frames`` datasets (presence, shapes, lengths) without reading the fields;
    return the times of the whole frames (an incomplete file may hold the time ahead of the
    fields: only frames written completely count)."""
    names = {"time": "/frames/time", **FRAME_DATASETS}
    data = _opened_datasets(h5, "/frames")
    if complete:
        for name, ds in names.items():
            if name not in LATER_FRAME_FIELDS:
                _ensure(data, ds, path)
    present = {name: ds for name, ds in names.items() if name not in LATER_FRAME_FIELDS or ds in data}
    n = _available_rows(data, present, complete, path, "/frames")
    for name, tail in frame_tails(n_nodes, n_elements).items():
        ds = FRAME_DATASETS[name]
        if ds in data and n > 0 and data[ds].shape[1:] != tail:
            raise ResultsError(_shape_error(path, ds, data[ds].shape, tail))
    return read_rows(data, "/frames/time", n, (), path)


def read_history(h5: h5py.File, path: Path, complete: bool) -> dict[str, np.ndarray]:
    """Every ``/history`` dataset as float64, cut to the records written in all of them."""
    energy = {name: f"/history/{name}" for name in ("time", *ENERGY_NAMES)}
    tracked = {
        "tracked_displacement": "/history/tracked_displacement",
        "tracked_velocity": "/history/tracked_velocity",
    }
    data = _opened_datasets(h5, "/history")
    if complete:
        for ds in energy.values():
            _ensure(data, ds, path)
    present_tracked = {k: v for k, v in tracked.items() if v in data}
    n = _available_rows(data, {**energy, **present_tracked}, complete, path, "/history")
    out = {name: read_rows(data, ds, n, (), path) for name, ds in energy.items()}
    # deepest contact penetration (m); zeros for files written before the engine had contact
    out["contact_penetration"] = read_rows(data, "/history/contact_penetration", n, (), path)
    # the step from each record on and the element that sets it (docs/theory.md); files written
    # before the step followed the mesh have neither: dt reads as NaN and the element as -1
    for name in ("dt", "dt_stable"):
        out[name] = (read_rows(data, f"/history/{name}", n, (), path) if f"/history/{name}" in data
                     else np.full(n, np.nan))
    out["dt_element"] = (read_rows(data, "/history/dt_element", n, (), path) if "/history/dt_element" in data
                         else np.full(n, -1.0))
    n_tracked = data[tracked["tracked_displacement"]].shape[1] if present_tracked else 0
    for name, ds in tracked.items():
        out[name] = read_rows(data, ds, n, (n_tracked, 3), path)
    # per part (n_records, n_parts), per contact definition (n_records, n_contacts, 3) and per rigid
    # wall (n_records, n_walls, 3); files written before the engine had them read as no columns
    for name, tail in (("part_kinetic_energy", ()), ("part_internal_energy", ()), ("part_hourglass_energy", ()),
                       ("part_plastic_work", ()), ("contact_force", (3,)), ("rigid_wall_force", (3,))):
        width = data[f"/history/{name}"].shape[1] if f"/history/{name}" in data else 0
        out[name] = read_rows(data, f"/history/{name}", n, (width, *tail), path) if width else np.zeros((n, 0, *tail))
    # the supports' resultant force and its moment about the origin (n_records, 3); zeros in files
    # written before them
    for name in ("reaction_force", "reaction_moment"):
        out[name] = read_rows(data, f"/history/{name}", n, (3,), path)
    return out


def _opened_datasets(h5: h5py.File, group: str) -> Datasets:
    """Every dataset of ``group``, opened once, by its full path: h5py looks a path up anew at
    each ``in`` and ``[]`` (20 to 40 us each), which was most of reading a short history."""
    import h5py

    if group not in h5:
        return {}
    return {f"{group}/{name}": item for name, item in h5[group].items() if isinstance(item, h5py.Dataset)}


def _ensure(h5: Datasets, name: str, path: Path) -> None:
    if name not in h5:
        raise ResultsError(
            f"{path} says the run is complete but dataset {name} is missing; the file is "
            f"damaged or was written by another program (see docs/formats.md)"
        )


def _shape_error(path: Path, name: str, shape: tuple[int, ...], tail: tuple[int, ...]) -> str:
    expected = "(n,)" if not tail else f"(n, {', '.join(map(str, tail))})"
    return f"{path}: dataset {name} has shape {shape}, expected {expected} (see docs/formats.md)"


def read_rows(h5: Datasets, name: str, n: int, tail: tuple[int, ...], path: Path) -> np.ndarray:
    """The first ``n`` rows of dataset ``name`` as float64 (zeros when it is absent)."""
    if name not in h5 or n == 0:
        return np.zeros((n, *tail), dtype=np.float64)
    data = np.asarray(h5[name][:n], dtype=np.float64)
    if data.shape[1:] != tail:
        raise ResultsError(_shape_error(path, name, h5[name].shape, tail))
    return data


def read_run(h5: h5py.File) -> dict[str, Any]:
    """The ``/run`` attributes as plain Python values (empty before the engine wrote them)."""
    if "run" not in h5:
        return {}
    return {str(k): to_python(v) for k, v in h5["run"].attrs.items()}


def to_python(value: Any) -> Any:
    """numpy scalars, bytes and small arrays to plain Python values (for JSON)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    if isinstance(value, np.ndarray):
        if value.size == 1:
            return to_python(value.reshape(-1)[0])
        return [to_python(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def strings(value: Any, one: bool = False) -> list[str]:
    """h5py string attribute (str, bytes, or an array of either) to a list of str."""
    if value is None:
        return []
    if isinstance(value, (str, bytes, np.str_, np.bytes_)):
        items = [value]
    else:
        items = list(np.asarray(value).reshape(-1))
    out = [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in items]
    return out[:1] if one else out


def read_frame_row(h5: h5py.File, name: str, k: int, tail: tuple[int, ...]) -> np.ndarray:
    """Row ``k`` of frame field ``name`` as float64 (zeros when the dataset is absent)."""
    return read_frame_rows(h5, name, k, k + 1, tail)[0]


def read_frame_rows(h5: h5py.File, name: str, first: int, last: int, tail: tuple[int, ...]) -> np.ndarray:
    """Rows ``first:last`` of frame field ``name`` as float64 (zeros when the dataset is absent;
    the thickness of a file written before it: /mesh/thickness, which the engine kept then)."""
    ds = FRAME_DATASETS[name]
    if ds not in h5:
        if name == "thickness" and "/mesh/thickness" in h5:
            return np.tile(np.asarray(h5["/mesh/thickness"][()], dtype=np.float64), (last - first, 1))
        return np.zeros((last - first, *tail), dtype=np.float64)
    return np.asarray(h5[ds][first:last], dtype=np.float64)
