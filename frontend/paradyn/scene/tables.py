"""Typed access to a scene's TOML tables: the reader behind every message of a scene problem.

``_Reader`` checks a table's keys and reads numbers, integers, strings and vectors with their
bounds; each problem becomes a :class:`SceneError` that names the scene file, the table and the key.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from paradyn.arguments import did_you_mean

from .specs import SceneError

_REQUIRED = object()


# ----------------------------------------------------------------------------------------------
# reading helpers


class _Reader:
    """Typed access to TOML tables with messages that name the scene file, the table and the key."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, message: str) -> SceneError:
        return SceneError(f"{self.path}: {message}")

    def keys(self, table: Mapping[str, Any], label: str, allowed: Iterable[str]) -> None:
        allowed = list(allowed)
        for key in table:
            if key not in allowed:
                raise self.error(f"unknown key '{key}' in {label}; {did_you_mean(key, allowed)}allowed keys are: "
                                 f"{', '.join(allowed)}")

    def table(self, parent: Mapping[str, Any], key: str, label: str, required: bool = True) -> dict[str, Any]:
        value = parent.get(key)
        if value is None:
            if required:
                raise self.error(f"missing required table [{key}] in {label}")
            return {}
        if not isinstance(value, dict):
            raise self.error(f"'{key}' in {label} must be a table, written [{key}] (got {_kind(value)})")
        return value

    def tables(self, parent: Mapping[str, Any], key: str) -> list[dict[str, Any]]:
        value = parent.get(key, [])
        if isinstance(value, dict):
            raise self.error(f"'{key}' must be an array of tables: write [[{key}]] instead of [{key}]")
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.error(f"'{key}' must be an array of tables written [[{key}]]")
        return value

    def raw(self, table: Mapping[str, Any], key: str, label: str, default: Any) -> Any:
        if key in table:
            return table[key]
        if default is _REQUIRED:
            raise self.error(f"missing required key '{key}' in {label}")
        return default

    def number(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               minimum: float | None = None, positive: bool = False) -> float:
        value = self.raw(table, key, label, default)
        if value is None:
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(f"'{key}' in {label} must be a finite number, got {value!r}")
        if positive and value <= 0:
            raise self.error(f"'{key}' in {label} must be > 0, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.error(f"'{key}' in {label} must be >= {minimum}, got {value!r}")
        return float(value)

    def integer(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
                minimum: int = 1, maximum: int | None = None) -> int:
        value = self.raw(table, key, label, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"'{key}' in {label} must be an integer, got {value!r}")
        if value < minimum or (maximum is not None and value > maximum):
            bound = f"between {minimum} and {maximum}" if maximum is not None else f">= {minimum}"
            raise self.error(f"'{key}' in {label} must be {bound}, got {value}")
        return value

    def string(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               choices: Iterable[str] | None = None) -> str:
        value = self.raw(table, key, label, default)
        if not isinstance(value, str) or (not value and default is _REQUIRED):
            raise self.error(f"'{key}' in {label} must be a non-empty string, got {value!r}")
        if choices is not None and value not in choices:
            choices = list(choices)
            raise self.error(f"'{key}' = '{value}' in {label} is not one of: {', '.join(choices)}; "
                             f"{did_you_mean(value, choices)}".rstrip("; ").rstrip())
        return value

    def flag(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED) -> bool:
        value = self.raw(table, key, label, default)
        if not isinstance(value, bool):
            raise self.error(f"'{key}' in {label} must be true or false, got {value!r}")
        return value

    def vector(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               length: int = 3) -> tuple[float, ...]:
        value = self.raw(table, key, label, default)
        if (not isinstance(value, (list, tuple)) or len(value) != length
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                       for v in value)):
            raise self.error(f"'{key}' in {label} must be a list of {length} finite numbers, got {value!r}")
        return tuple(float(v) for v in value)

    def int_pair(self, table: Mapping[str, Any], key: str, label: str) -> tuple[int, int]:
        value = self.raw(table, key, label, _REQUIRED)
        if (not isinstance(value, list) or len(value) != 2
                or any(isinstance(v, bool) or not isinstance(v, int) or v < 1 for v in value)):
            raise self.error(f"'{key}' in {label} must be two positive integers [nx, ny], got {value!r}")
        return (value[0], value[1])

    def unique(self, names: list[str], kind: str) -> None:
        """Refuse two entries of ``[[kind]]`` with one name."""
        seen: set[str] = set()
        for name in names:
            if name in seen:
                raise self.error(f"two [[{kind}]] entries are named '{name}'; names must be unique")
            seen.add(name)


def _kind(value: Any) -> str:
    return {list: "an array", dict: "a table", str: "a string"}.get(type(value), type(value).__name__)


def read_life(r: _Reader, t: dict[str, Any], label: str, what: str, spec: Any) -> tuple[float, float]:
    """A contact's or a motion's birth_time and death_time (s), the death after the birth."""
    birth = r.number(t, "birth_time", label, default=spec.birth_time, minimum=0.0)
    death = r.number(t, "death_time", label, default=spec.death_time, positive=True)
    if death <= birth:
        raise r.error(f"'death_time' in {label} ({death:g} s) must come after 'birth_time' ({birth:g} s): the "
                      f"{what} would never act; remove the {what} or move its times")
    return birth, death
