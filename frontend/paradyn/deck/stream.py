"""What a deck file holds, item by item, and the same items as the stream the engine writes into
``deck.h5`` itself (docs/formats.md, "Deck stream").

:func:`deck_items` is the one list of a model's datasets and attributes, in the schema's order:
:func:`paradyn.deck.write_deck` writes it with h5py, and :func:`encode` turns it into the stream
that a waiting engine (``paradyn-engine --await-deck``) reads from its standard input. A run sends
the stream, so ``paradyn-run`` loads h5py only while the engine runs: 20 ms of its fixed cost
(docs/performance.md, "Fixed costs"). This module loads no h5py.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from paradyn._schema import DATASETS, DECK_VERSION, NAME_ATTRIBUTES, TITLE_ATTRIBUTE, VERSION_ATTRIBUTE

from .model import SWITCH_ATTRIBUTES, Control, Model

STREAM_HEADER = b"paradyn-deck-stream 1\n"
# an item: ("dataset", path, array) or ("attribute", object path, name, value); a value is an
# np.int32 or np.float64 scalar, a str, or a tuple of str
Item = tuple


def deck_items(model: Model) -> Iterator[Item]:
    """The datasets (int32 or float64, C order) and attributes of ``model``'s deck, in file order.
    Empty optional groups (no loads, tracked nodes or contacts) are left out."""
    yield ("attribute", "/", VERSION_ATTRIBUTE, np.int32(DECK_VERSION))
    if model.title:
        yield ("attribute", "/", TITLE_ATTRIBUTE, str(model.title))
    for spec in DATASETS:
        value = getattr(model, spec.python)
        if value is None or getattr(model, spec.shape[0]) == 0:
            continue
        dtype = "<i4" if spec.type == "int" else "<f8"
        yield ("dataset", spec.path, np.ascontiguousarray(value, dtype=dtype))
    for name_spec in NAME_ATTRIBUTES:
        names = getattr(model, name_spec.python)
        if names:
            yield ("attribute", name_spec.group, name_spec.name, tuple(str(n) for n in names))
    for name in Control.REQUIRED + Control.OPTIONAL:
        value = getattr(model.control, name)
        if value is not None:
            yield ("attribute", "/control", name, np.float64(value))
    for name in Control.STRINGS + tuple(SWITCH_ATTRIBUTES):
        value = model.control.value(name)
        if value is not None:
            yield ("attribute", "/control", name, str(value))


def encode(model: Model) -> Iterator[bytes | memoryview]:
    """The deck of ``model`` as the engine's standard input reads it after the line ``deck``:
    a header line, then per item a line naming it and its bytes (little-endian numbers; each
    string as a line with its length in bytes, then its UTF-8 bytes), then ``end``."""
    yield STREAM_HEADER
    for item in deck_items(model):
        if item[0] == "dataset":
            _, path, array = item
            yield f"dataset {path} {_kind(array)} {array.ndim} {' '.join(map(str, array.shape))}\n".encode()
            yield array.data.cast("B")   # the array's own bytes (C order), not a copy
        else:
            _, group, name, value = item
            yield from _attribute(group, name, value)
    yield b"end\n"


def _attribute(group: str, name: str, value: object) -> Iterator[bytes | memoryview]:
    if isinstance(value, (str, tuple)):
        strings = (value,) if isinstance(value, str) else value
        yield f"attribute {group} {name} string {0 if isinstance(value, str) else len(strings)}\n".encode()
        for text in strings:   # no NUL: validate_model refuses one
            data = text.encode("utf-8")
            yield b"%d\n" % len(data) + data
    else:
        array = np.asarray(value)
        yield f"attribute {group} {name} {_kind(array)} 0\n".encode()
        yield array.astype(array.dtype.newbyteorder("<")).tobytes()


def _kind(array: np.ndarray) -> str:
    return "int32" if array.dtype.kind == "i" else "float64"
