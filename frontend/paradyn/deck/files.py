"""The deck file (``deck.h5``, format version 1 of ``docs/formats.md``): writing, reading and checking it.

:func:`write_deck` validates and writes atomically; :func:`read_deck` reads and validates;
:func:`read_deck_arrays` reads a few arrays; :func:`validate_deck` only checks a file. Every problem
raises :class:`~paradyn.deck.DeckError` with one message naming the file, the dataset, the offending
entry and the fix. The public names are :mod:`paradyn.deck`'s.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from paradyn._schema import (
    CONDITIONS,
    DATASETS,
    DECK_VERSION,
    NAME_ATTRIBUTES,
    SIZES,
    TITLE_ATTRIBUTE,
    VERSION_ATTRIBUTE,
    DatasetSpec,
)

from .items import deck_items
from .model import CONTROL_BY_NAME, DATASET_BY_ATTRIBUTE, SWITCH_ATTRIBUTES, Control, Model
from .validation import DeckError, validate_model

if TYPE_CHECKING:
    import h5py

# ----------------------------------------------------------------------------------------------
# writing


def write_deck(model: Model, path: str | Path) -> Path:
    """Validate ``model`` and write it to ``path`` atomically (temporary file, then rename).

    The file is made in memory (HDF5's core driver) and written to disk in one piece with plain
    file writes: a disk that fills then raises one OSError (``cannot write PATH (No space left on
    device)``) and leaves neither the deck nor the temporary file, where HDF5 writing to a full
    disk itself crashed the process (issue 34)."""
    path = Path(path)
    import h5py  # where a file is opened

    validate_model(model, source=f"{path} (not written)")
    with h5py.File(f"{path.name}.in-memory", "w", driver="core", backing_store=False) as f:
        _write_contents(f, model)
        f.flush()
        image = f.id.get_file_image()
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(image)
        os.replace(temporary, path)
    except OSError as error:
        Path(temporary).unlink(missing_ok=True)
        raise OSError(error.errno, f"cannot write {path} ({error.strerror or error})", str(path)) from error
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


def _write_contents(f: h5py.File, model: Model) -> None:
    import h5py

    for item in deck_items(model):
        if item[0] == "dataset":
            f.create_dataset(item[1], data=item[2])
        else:
            _, group, name, value = item
            if isinstance(value, tuple):
                value = np.array(value, dtype=h5py.string_dtype())
            f.require_group(group).attrs[name] = value


# ----------------------------------------------------------------------------------------------
# reading


def read_deck(path: str | Path) -> Model:
    """Read and validate a deck file; raise DeckError naming the dataset on any problem."""
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise DeckError(f"{source}: deck file not found; write it with paradyn.deck.write_deck")
    import h5py

    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise DeckError(f"{source}: not a readable HDF5 file ({exc}); regenerate the deck") from exc
    with f:
        _check_version(f, source)
        arrays = _read_arrays(f, source)
        names = _read_names(f)
        control = _read_control(f, source)
        title = _decode(f.attrs.get(TITLE_ATTRIBUTE, ""))
    model = Model(control=control, title=title, **names, **arrays)
    validate_model(model, source=source)
    _fill_names(model)
    return model


def read_deck_arrays(path: str | Path, names: tuple[str, ...]) -> dict[str, np.ndarray | None]:
    """Some datasets of a deck a run already used (so already checked), by their Python names
    (``thickness``, ``contact_pairs``...; None where absent): the post-processing's few numbers
    from the deck without reading and validating all of it again."""
    import h5py

    paths = {spec.python: spec.path for spec in DATASETS}
    with h5py.File(path, "r") as f:
        return {name: (f[paths[name]][()] if paths[name] in f else None) for name in names}


def validate_deck(path: str | Path) -> None:
    """Check a deck file against docs/formats.md; raise DeckError naming the dataset on any problem."""
    read_deck(path)


def _check_version(f: h5py.File, source: str) -> None:
    if VERSION_ATTRIBUTE not in f.attrs:
        raise DeckError(f"{source}: root attribute {VERSION_ATTRIBUTE} is missing; this is not a "
                        f"ParaDyn deck, write it with paradyn.deck.write_deck")
    version = f.attrs[VERSION_ATTRIBUTE]
    if np.ndim(version) != 0 or np.asarray(version).dtype.kind not in "iu" or int(version) != DECK_VERSION:
        shown = version.item() if isinstance(version, np.generic) else version
        raise DeckError(f"{source}: root attribute {VERSION_ATTRIBUTE} = {shown!r}, this frontend "
                        f"reads version {DECK_VERSION} (an integer); regenerate the deck from its scene")


def _read_arrays(f: h5py.File, source: str) -> dict[str, np.ndarray | None]:
    import h5py

    arrays: dict[str, np.ndarray | None] = {}
    for spec in DATASETS:
        item = f.get(spec.path)
        if item is None:
            group = CONDITIONS[spec.required_when].group if spec.required_when else None
            if spec.required or (group is not None and group in f):
                why = f" (required since the group {group} exists)" if group else ""
                raise DeckError(f"{source}: required dataset {spec.path} is missing{why}; see docs/formats.md "
                                f"for the datasets of a deck")
            arrays[spec.python] = None
            continue
        if not isinstance(item, h5py.Dataset):
            raise DeckError(f"{source}: {spec.path} is a group, must be a dataset")
        kind = item.dtype.kind
        if (spec.type == "int" and kind not in "iu") or (spec.type == "float" and kind != "f"):
            wanted = "an integer type such as int32" if spec.type == "int" else "floating point (float64)"
            raise DeckError(f"{source}: {spec.path} has dtype {item.dtype}, must be {wanted}; "
                            f"write it with that dtype")
        arrays[spec.python] = np.asarray(item[()])
    # absent arrays of an optional group without a default (loads, tracked nodes, contact pairs)
    # keep the model's empty arrays; the others stay None and get the schema's default
    return {k: v for k, v in arrays.items() if v is not None or not _empty_by_default(DATASET_BY_ATTRIBUTE[k])}


def _empty_by_default(spec: DatasetSpec) -> bool:
    return spec.default is None and SIZES[spec.shape[0]].min_rows == 0


def _decode(value: object) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    return str(value)


def _read_names(f: h5py.File) -> dict[str, list[str]]:
    names: dict[str, list[str]] = {}
    for spec in NAME_ATTRIBUTES:
        if spec.group in f and spec.name in f[spec.group].attrs:
            names[spec.python] = [_decode(n) for n in np.atleast_1d(f[spec.group].attrs[spec.name])]
        else:
            names[spec.python] = []
    return names


def _read_control(f: h5py.File, source: str) -> Control:
    if "/control" not in f:
        raise DeckError(f"{source}: group /control is missing; it carries end_time and output_interval")
    attrs = f["/control"].attrs
    values: dict[str, float | str | None] = {}
    for name in Control.REQUIRED + Control.OPTIONAL:
        if name not in attrs:
            if name in Control.REQUIRED:
                raise DeckError(f"{source}: /control attribute {name} is missing; {CONTROL_BY_NAME[name].fix}")
            continue
        raw = attrs[name]
        if np.ndim(raw) != 0 or np.asarray(raw).dtype.kind not in "iuf":
            raise DeckError(f"{source}: /control attribute {name} = {raw!r} must be a real scalar; "
                            f"write it as a float64 attribute")
        values[name] = float(raw)
    switches: dict[str, str] = {}
    for name in Control.STRINGS + tuple(SWITCH_ATTRIBUTES):
        if name not in attrs:
            continue
        raw = attrs[name]
        if np.ndim(raw) != 0 or not isinstance(raw, (str, bytes)):
            shown = raw.item() if isinstance(raw, np.generic) else raw
            raise DeckError(f"{source}: /control attribute {name} = {shown!r} must be one string; "
                            f"write it as a str attribute")
        if name in SWITCH_ATTRIBUTES:
            switches[SWITCH_ATTRIBUTES[name]] = _decode(raw)
        else:
            values[name] = _decode(raw)
    return Control(**values, effect_switches=switches)  # type: ignore[arg-type]


def _fill_names(model: Model) -> None:
    """Names absent from a file get generic ones (part_0, material_0, node_<index>)."""
    if not model.part_names:
        model.part_names = [f"part_{i}" for i in range(model.n_parts or 0)]
    if not model.material_names:
        model.material_names = [f"material_{i}" for i in range(model.n_materials or 0)]
    if not model.tracked_names:
        model.tracked_names = [f"node_{int(n)}" for n in np.asarray(model.tracked_nodes)]
