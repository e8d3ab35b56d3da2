"""The ParaDyn deck (``deck.h5``, format version 1 of ``docs/formats.md``): model, writer, reader, validator.

:class:`Model` holds every array of the deck as numpy arrays with the deck's shapes (0-based indices),
the control values (:class:`Control`) and the names the frontend uses in its outputs.
:func:`write_deck` validates and writes atomically; :func:`read_deck` reads and validates;
:func:`validate_deck` only checks a file. Every problem raises :class:`DeckError` with one message
naming the file, the dataset, the offending entry and the fix.

The datasets, attributes, defaults and rules come from the schema (``schema/deck.toml``, generated
into :mod:`paradyn._schema`); the engine checks the same tables. The work is split by job: the
model in :mod:`paradyn.deck.model`, its checks in :mod:`paradyn.deck.validation`, the file in
:mod:`paradyn.deck.files`, the items in file order in :mod:`paradyn.deck.items`, the field per
dataset in :mod:`paradyn.deck.fields` (generated). The deck imports nothing of the frontend but the schema's
tables: the scene, the keyword reader, the runs and the results build on it.
"""

from __future__ import annotations

from paradyn._schema import DATASETS, DECK_VERSION, DOF_NAMES, VERSION_ATTRIBUTE

from .files import read_deck, read_deck_arrays, validate_deck, write_deck
from .model import (
    DEFAULT_PARTITION,
    ELASTIC,
    HOURGLASS_STIFFNESS,
    HOURGLASS_VISCOUS,
    J2_PLASTICITY,
    PARTITIONS,
    SWITCH_ATTRIBUTES,
    Control,
    Model,
    control_default,
)
from .validation import DeckError, material_curve_fault, validate_model

__all__ = [
    "DATASETS",
    "DECK_VERSION",
    "DEFAULT_PARTITION",
    "DOF_NAMES",
    "ELASTIC",
    "HOURGLASS_STIFFNESS",
    "HOURGLASS_VISCOUS",
    "J2_PLASTICITY",
    "PARTITIONS",
    "SWITCH_ATTRIBUTES",
    "VERSION_ATTRIBUTE",
    "Control",
    "DeckError",
    "Model",
    "control_default",
    "material_curve_fault",
    "read_deck",
    "read_deck_arrays",
    "validate_deck",
    "validate_model",
    "write_deck",
]
