"""Scene tables whose entries are rows of one deck table, driven by the schema alone.

A row symbol of schema/deck.toml with ``scene_table = "NAME"`` makes ``[[NAME]]`` a scene table:
its keys are the datasets of those rows (each dataset's ``scene = "[[NAME]] key"``), read with
their type, shape, bounds and default, and written one row per entry into the deck model. A key
of an enum dataset takes a member's name; a key of a dataset that references parts, materials or
curves takes the name of one (an absent curve is the constant factor 1). So a new table of this
kind is its datasets in the schema and nothing in Python: the reader, ``paradyn.Scene.add``,
the scene file writer and the deck model all follow.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from paradyn._schema import DATASETS, ENUMS, SIZES, DatasetSpec
from paradyn.arguments import did_you_mean
from paradyn.deck.validation import within_bounds

from .specs import SceneError
from .tables import _REQUIRED, _Reader

if TYPE_CHECKING:
    from paradyn.deck import Model

    from .specs import Scene

# what a reference key names in the scene: the array of tables whose entry names give its index
_NAMED_BY = {"part": "parts", "material": "materials", "curve": "curves"}


@dataclass(frozen=True)
class RowKey:
    """One key of a row table: the dataset it fills."""

    name: str
    spec: DatasetSpec

    @property
    def required(self) -> bool:
        return key_required(self.spec)


def key_required(spec: DatasetSpec) -> bool:
    """Whether a scene must give the key of ``spec``: it has no default that its own bounds accept
    (an absent curve is the constant factor 1)."""
    if spec.reference == "curve":
        return False
    return spec.default is None or not within_bounds(np.asarray(float(spec.default)), spec)


def _tables() -> dict[str, tuple[RowKey, ...]]:
    tables: dict[str, tuple[RowKey, ...]] = {}
    for size in SIZES.values():
        if size.scene_table is None:
            continue
        prefix = f"[[{size.scene_table}]] "
        keys = [RowKey(d.scene[len(prefix):], d) for d in DATASETS
                if d.shape[0] == size.symbol and d.scene.startswith(prefix)]
        tables[size.scene_table] = tuple(keys)
    return tables


ROW_TABLES: dict[str, tuple[RowKey, ...]] = _tables()


def parse_row(r: _Reader, table: Mapping[str, Any], name: str, index: int) -> dict[str, Any]:
    """Entry ``index`` of ``[[name]]`` checked key by key against its datasets; the values as read
    (names for enums and references, tuples for vectors), absent keys at their default."""
    label = f"[[{name}]] #{index + 1}"
    keys = ROW_TABLES[name]
    r.keys(table, label, [k.name for k in keys])
    return {k.name: read_key(r, table, k.name, k.spec, label) for k in keys}


def read_key(r: _Reader, table: Mapping[str, Any], key: str, spec: DatasetSpec, label: str) -> Any:
    """The value of ``key`` of a scene table as the dataset ``spec`` holds it: its type and shape,
    its bounds (the schema's rule and fix in the message), its default where the key is absent."""
    default = _REQUIRED if key_required(spec) else _scene_default(spec)
    if spec.enum is not None:
        return r.string(table, key, label, default=default, choices=list(ENUMS[spec.enum]))
    if spec.reference in _NAMED_BY:   # a name; an absent optional one is None (a curve: the constant 1)
        return r.string(table, key, label) if key in table or default is _REQUIRED else default
    if len(spec.shape) > 1:
        value = r.vector(table, key, label, default=default, length=int(spec.shape[1]))
    elif spec.type == "int":
        value = r.integer(table, key, label, default=default, minimum=-(2**31))
    else:
        value = r.number(table, key, label, default=default)
    if not np.all(within_bounds(np.asarray(value, dtype=float), spec)):
        raise r.error(f"'{key}' in {label} = {value!r} {spec.rule}; {spec.fix}")
    return value


def _scene_default(spec: DatasetSpec) -> Any:
    if spec.enum is not None:
        return next(name for name, code in ENUMS[spec.enum].items() if code == spec.default)
    if spec.reference in _NAMED_BY:
        return None
    if len(spec.shape) > 1:
        return (spec.default,) * int(spec.shape[1])
    return spec.default


def parse_rows(r: _Reader, data: Mapping[str, Any]) -> dict[str, list[dict[str, Any]]]:
    """Every row table of a scene's tables (empty lists for those it does not have)."""
    return {name: [parse_row(r, t, name, i) for i, t in enumerate(r.tables(data, name))] for name in ROW_TABLES}


def check_row_references(r: _Reader, scene: Scene) -> None:
    """Every part, material and curve a row names is defined in the scene."""
    for name, rows in scene.rows.items():
        for index, row in enumerate(rows):
            for key in ROW_TABLES[name]:
                kind = key.spec.reference
                if kind not in _NAMED_BY or row[key.name] is None:
                    continue
                names = [entry.name for entry in getattr(scene, _NAMED_BY[kind])]
                if row[key.name] not in names:
                    raise r.error(f"'{key.name}' = '{row[key.name]}' in [[{name}]] #{index + 1} names no "
                                  f"[[{kind}]]; {did_you_mean(row[key.name], names)}defined: "
                                  f"{', '.join(names) or 'none'}")


def needs_constant_curve(scene: Scene) -> bool:
    """Whether a row leaves a curve key out (the deck then needs the constant curve)."""
    return any(key.spec.reference == "curve" and row[key.name] is None
               for name, rows in scene.rows.items() for row in rows for key in ROW_TABLES[name])


def rows_to_model(scene: Scene, model: Model, constant_curve: int) -> None:
    """The deck arrays of every row table: one row per entry, names turned into 0-based indices
    and enum members into codes (``constant_curve``: the curve an absent curve key means)."""
    index = {kind: {entry.name: i for i, entry in enumerate(getattr(scene, attribute))}
             for kind, attribute in _NAMED_BY.items()}
    for name, keys in ROW_TABLES.items():
        rows = scene.rows.get(name, [])
        for key in keys:
            spec = key.spec
            values = [_deck_value(row[key.name], spec, index, constant_curve) for row in rows]
            dtype = np.int32 if spec.type == "int" else np.float64
            setattr(model, spec.python, np.array(values, dtype=dtype).reshape(len(rows), *spec.shape[1:]))


def _deck_value(value: Any, spec: DatasetSpec, index: dict[str, dict[str, int]], constant_curve: int) -> Any:
    if spec.enum is not None:
        return ENUMS[spec.enum][value]
    if spec.reference == "curve" and value is None:
        return constant_curve
    if spec.reference in _NAMED_BY:
        return index[spec.reference][value]
    return value


def scene_words(message: str) -> str:
    """A deck message with every row-table entry it names also named as the scene names it
    (``/rigid_walls/normal[0]`` gains ``([[rigid_wall]] #1 'normal')``)."""
    for name, keys in ROW_TABLES.items():
        for key in keys:
            message = re.sub(re.escape(key.spec.path) + r"\[(\d+)\]",
                             lambda m, n=name, k=key.name: f"{m.group(0)} ([[{n}]] #{int(m.group(1)) + 1} '{k}')",
                             message)
    return message


__all__ = [
    "ROW_TABLES",
    "RowKey",
    "SceneError",
    "check_row_references",
    "key_required",
    "needs_constant_curve",
    "parse_row",
    "parse_rows",
    "read_key",
    "rows_to_model",
    "scene_words",
]
