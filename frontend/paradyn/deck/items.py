"""What a deck file holds, item by item: :func:`deck_items` is the one list of a model's datasets
and attributes, in the schema's order, that :func:`paradyn.deck.write_deck` writes with h5py."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from paradyn._schema import DATASETS, DECK_VERSION, NAME_ATTRIBUTES, TITLE_ATTRIBUTE, VERSION_ATTRIBUTE

from .model import SWITCH_ATTRIBUTES, Control, Model

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
