"""The text of a scene file from its tables: what :meth:`paradyn.Scene.to_toml` writes.

The tables hold only what a scene file holds (strings, booleans, integers, finite floats, lists,
``[run]``-like tables and arrays of tables with one level of sub-table, ``[part.geometry]``), so
a writer of that subset of TOML is enough: floats are written with ``repr`` (the shortest text that
reads back to the same double) and strings as JSON strings, whose escapes TOML shares.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any


def scene_toml(tables: Mapping[str, Any]) -> str:
    """TOML text that ``tomllib.loads`` reads back to ``tables``.

    Examples
    --------
    >>> print(scene_toml({"title": "plate", "run": {"end_time": 1e-4},
    ...                   "part": [{"name": "p", "geometry": {"kind": "plate", "size": [0.1, 0.1]}}]}))
    title = "plate"
    <BLANKLINE>
    [run]
    end_time = 0.0001
    <BLANKLINE>
    [[part]]
    name = "p"
    [part.geometry]
    kind = "plate"
    size = [0.1, 0.1]
    <BLANKLINE>
    """
    lines = [f"{key} = {toml_value(value)}" for key, value in tables.items() if not _is_table(value)]
    for key, value in tables.items():
        if isinstance(value, Mapping):
            lines += ["", *_table(f"[{key}]", key, value)]
        elif _is_table(value):
            for entry in value:
                lines += ["", *_table(f"[[{key}]]", key, entry)]
    return "\n".join(lines) + "\n"


def toml_value(value: Any) -> str:
    """One TOML value: a boolean, number, string or (nested) array."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} ({type(value).__name__}) in a scene file")


def _is_table(value: Any) -> bool:
    return isinstance(value, Mapping) or (isinstance(value, list) and bool(value)
                                          and all(isinstance(v, Mapping) for v in value))


def _table(header: str, key: str, table: Mapping[str, Any]) -> list[str]:
    lines = [header] + [f"{k} = {toml_value(v)}" for k, v in table.items() if not isinstance(v, Mapping)]
    for sub, value in table.items():
        if isinstance(value, Mapping):
            lines += [f"[{key}.{sub}]"] + [f"{k} = {toml_value(v)}" for k, v in value.items()]
    return lines
