"""The text of a scene file from its tables: what :meth:`paradyn.Scene.to_toml` writes.

Written by ``tomli_w``, the writer that pairs with the reader (``tomllib``): every document the
reader accepts is written back to text that reads to the same tables, whatever its keys (a
``[study.reference_values]`` key with ``@``, dotted or quoted keys), strings (control characters)
and nesting (``[[study.runs]]``, tables in arrays of tables). ``tests/test_scene_toml.py`` checks
that with hypothesis over the documents the reader accepts.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import tomli_w


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
    <BLANKLINE>
    [part.geometry]
    kind = "plate"
    size = [
        0.1,
        0.1,
    ]
    <BLANKLINE>
    """
    try:
        return tomli_w.dumps(_plain(tables))
    except TypeError as exc:
        raise TypeError(f"cannot write this value in a scene file: {exc}") from exc


def _plain(value: Any) -> Any:
    """Tuples as lists, mappings as dicts (what the writer takes and the reader gives)."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value
