"""Loads schema/deck.toml, control.toml, effects.toml and results.toml into plain Python structures for the writers.

Only the standard library: the generator runs before anything is installed. Each entry is
checked for the fields the writers need, so that a typo in the TOML fails here with its name
rather than as a strange generated file.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

DATASET_FIELDS = {"path", "python", "type", "shape", "required", "required_when", "checked_when", "default",
                  "lower", "upper", "lower_inclusive", "upper_inclusive", "upper_constant", "enum", "reference",
                  "units", "meaning", "scene", "fix", "fortran", "engine", "index"}
CONTROL_FIELDS = DATASET_FIELDS - {"path", "python", "shape", "reference", "checked_when", "required_when",
                                   "upper_constant", "fortran", "engine", "index"} | {"name", "default_from",
                                                                                      "default_divisor", "fortran_type"}


class SchemaError(ValueError):
    """schema/*.toml breaks the rules of its own header."""


@dataclass
class Entry:
    """One dataset or /control attribute, with the derived texts both validators print."""

    raw: dict[str, Any]
    rule: str = ""                      # bounds as words: "must be > 0", "must be in (0, 1]"
    enum_rule: str = ""                 # "must be 1 or 2 (1 = elastic, 2 = j2_plasticity)"
    defines_rows: bool = False          # first dataset with its row symbol

    def get(self, key: str, default: Any = None) -> Any:
        return self.raw.get(key, default)

    @property
    def name(self) -> str:
        return self.raw.get("path") or self.raw["name"]

    @property
    def required(self) -> bool:
        return bool(self.raw.get("required", False))

    @property
    def bounds(self) -> list[str]:
        return [b for b in ("lower", "upper") if b in self.raw]


@dataclass
class Schema:
    deck: dict[str, Any]
    sizes: dict[str, dict[str, Any]]
    conditions: dict[str, dict[str, Any]]
    enums: dict[str, dict[str, Any]]
    relations: dict[str, dict[str, Any]]
    datasets: list[Entry]
    control: list[Entry]
    name_attributes: list[dict[str, Any]]
    results: dict[str, Any]
    effects: list[dict[str, Any]] = field(default_factory=list)
    sources: list[str] = field(default_factory=list)

    def enum_codes(self, name: str) -> dict[str, int]:
        return {m["name"]: int(m["code"]) for m in self.enums[name]["members"]}

    def trait_members(self, enum: str, trait: str) -> list[str]:
        """The members of an enum that carry a trait (``traits = [...]`` on a member)."""
        return [m["name"] for m in self.enums[enum]["members"] if trait in m.get("traits", [])]

    def traits(self) -> list[tuple[str, str]]:
        """Every (enum, trait) pair the members name, in schema order: one predicate each."""
        found: list[tuple[str, str]] = []
        for name, enum in self.enums.items():
            for m in enum["members"]:
                found += [(name, t) for t in m.get("traits", []) if (name, t) not in found]
        return found

    def condition_codes(self, name: str) -> tuple[int, ...]:
        """Codes a dataset condition selects (empty for a group condition): the member it
        ``equals``, or every member that ``has_trait``."""
        condition = self.conditions[name]
        if "equals" not in condition and "has_trait" not in condition:
            return ()
        dataset = next(d for d in self.datasets if d.name == condition["dataset"])
        codes = self.enum_codes(dataset.get("enum"))
        if "equals" in condition:
            return (codes[condition["equals"]],)
        return tuple(codes[m] for m in self.trait_members(dataset.get("enum"), condition["has_trait"]))

    def rules(self) -> list[tuple[str, str, str]]:
        """Every rule a damaged deck can break: (what, name, rule), what in version, dataset,
        control, relation. Both validators must refuse a deck that breaks any one of them."""
        found = [("version", self.deck["version_attribute"], r) for r in ("missing", "class", "value")]
        for d in self.datasets:
            kinds = ["missing"] if d.required else (["required_when"] if d.get("required_when") else [])
            kinds += ["class", "shape"]
            sizes = self.sizes[d.get("shape")[0]]
            kinds += (["empty"] if sizes["min_rows"] > 0 else []) if d.defines_rows else ["rows"]
            kinds += d.bounds + (["enum"] if d.get("enum") else []) + (["reference"] if d.get("reference") else [])
            kinds += ["finite"] if d.get("type") == "float" else []
            found += [("dataset", d.name, k) for k in kinds]
        for a in self.control:
            kinds = (["missing"] if a.required else []) + ["class"] + a.bounds
            kinds += (["enum"] if a.get("enum") else []) + (["finite"] if a.get("type") == "float" else [])
            found += [("control", a.name, k) for k in kinds]
        found += [("relation", r["path"], name) for name, r in self.relations.items()]
        return found


def number_text(value: float | int) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def bound_rule(entry: Entry) -> str:
    lower, upper = entry.get("lower"), entry.get("upper")
    low_in, up_in = entry.get("lower_inclusive", True), entry.get("upper_inclusive", True)
    if lower is None and upper is None:
        return ""
    if upper is None:
        return f"must be {'>=' if low_in else '>'} {number_text(lower)}"
    if lower is None:
        return f"must be {'<=' if up_in else '<'} {number_text(upper)}"
    if entry.get("type") == "int" and low_in and up_in:
        return f"must be between {lower} and {upper}"
    return (f"must be in {'[' if low_in else '('}{number_text(lower)}, {number_text(upper)}"
            f"{']' if up_in else ')'}")


def _enum_rule(schema_enums: dict[str, Any], entry: Entry) -> str:
    members = schema_enums[entry.get("enum")]["members"]
    if entry.get("type") == "string":
        return "must be " + " or ".join(f'"{m["name"]}"' for m in members)
    codes = " or ".join(str(m["code"]) for m in members)
    named = ", ".join(f"{m['code']} = {m['name']}" for m in members)
    return f"must be {codes} ({named})"


def _check(entry: Entry, allowed: set[str], schema: Schema, kind: str) -> None:
    unknown = set(entry.raw) - allowed
    if unknown:
        raise SchemaError(f"{kind} {entry.name}: unknown fields {sorted(unknown)}")
    for key in ("type", "meaning", "scene", "fix"):
        if key not in entry.raw:
            raise SchemaError(f"{kind} {entry.name}: field {key} is missing")
    if entry.get("type") not in ("int", "float", "string"):
        raise SchemaError(f"{kind} {entry.name}: type must be int, float or string")
    for key in ("required_when", "checked_when"):
        if entry.get(key) is not None and entry.get(key) not in schema.conditions:
            raise SchemaError(f"{kind} {entry.name}: {key} names no [conditions] entry")
    if entry.get("enum") is not None and entry.get("enum") not in schema.enums:
        raise SchemaError(f"{kind} {entry.name}: enum names no [enums] entry")
    references = {s["entity"] for s in schema.sizes.values()}
    if entry.get("reference") is not None and entry.get("reference") not in references:
        raise SchemaError(f"{kind} {entry.name}: reference must be one of {sorted(references)}")


def _normalise_bounds(entry: Entry) -> None:
    """``lower = { value = 0.0, inclusive = false }`` becomes lower = 0.0, lower_inclusive = false;
    a plain number is an inclusive bound. Units default to "-"."""
    entry.raw.setdefault("units", "-")
    for side in ("lower", "upper"):
        bound = entry.raw.get(side)
        if isinstance(bound, dict):
            if set(bound) != {"value", "inclusive"}:
                raise SchemaError(f"{entry.name}: {side} takes a number or {{ value = ..., inclusive = ... }}")
            entry.raw[side], entry.raw[f"{side}_inclusive"] = bound["value"], bool(bound["inclusive"])


def load(root: Path) -> Schema:
    deck_path, results_path = root / "schema" / "deck.toml", root / "schema" / "results.toml"
    deck = tomllib.loads(deck_path.read_text(encoding="utf-8"))
    deck["control"] = tomllib.loads((root / "schema" / "control.toml").read_text(encoding="utf-8"))["control"]
    results = tomllib.loads(results_path.read_text(encoding="utf-8"))
    schema = Schema(deck=deck["deck"], sizes=deck["sizes"], conditions=deck["conditions"], enums=deck["enums"],
                    relations=deck["relations"], datasets=[Entry(d) for d in deck["dataset"]],
                    control=[Entry(a) for a in deck["control"]], name_attributes=deck["deck"]["name_attributes"],
                    results=results, effects=_effects(root),
                    sources=["schema/deck.toml", "schema/control.toml", "schema/effects.toml", "schema/results.toml"])
    schema.control += [_switch_attribute(e) for e in schema.effects if e.get("switch")]
    for entry in schema.datasets + schema.control:
        _normalise_bounds(entry)
    seen_rows: set[str] = set()
    for d in schema.datasets:
        _check(d, DATASET_FIELDS, schema, "dataset")
        symbol = d.get("shape")[0]
        if symbol not in schema.sizes:
            raise SchemaError(f"dataset {d.name}: row symbol {symbol} is not in [sizes]")
        d.defines_rows = symbol not in seen_rows
        seen_rows.add(symbol)
        if d.defines_rows and not (d.required or d.get("required_when") or schema.sizes[symbol]["min_rows"] == 0):
            raise SchemaError(f"dataset {d.name} defines {symbol}, so it must be required or required_when")
    for a in schema.control:
        _check(a, CONTROL_FIELDS, schema, "control attribute")
    for entry in schema.datasets + schema.control:
        entry.rule = bound_rule(entry)
        entry.enum_rule = _enum_rule(schema.enums, entry) if entry.get("enum") else ""
    for name, relation in schema.relations.items():
        if relation["path"] not in {d.name for d in schema.datasets}:
            raise SchemaError(f"relation {name}: path {relation['path']} is not a dataset")
    return schema


EFFECT_FIELDS = {"name", "stage", "switch", "timed_with", "declared_by", "rows", "meaning"}
EFFECT_STAGES = ("loads", "velocities", "constraints", "elements", "contact")


def _effects(root: Path) -> list[dict[str, Any]]:
    """schema/effects.toml's effects, checked: known fields, a stage, timed_with naming an earlier
    effect that is timed itself."""
    effects = tomllib.loads((root / "schema" / "effects.toml").read_text(encoding="utf-8"))["effect"]
    sizes = tomllib.loads((root / "schema" / "deck.toml").read_text(encoding="utf-8"))["sizes"]
    names: list[str] = []
    for e in effects:
        unknown = set(e) - EFFECT_FIELDS
        if unknown or not {"name", "stage", "declared_by", "meaning"} <= set(e):
            raise SchemaError(f"effect {e.get('name')}: unknown fields {sorted(unknown)} or a field missing")
        if e["stage"] not in EFFECT_STAGES:
            raise SchemaError(f"effect {e['name']}: stage must be one of {EFFECT_STAGES}")
        owners = e.get("timed_with", [])
        e["timed_with"] = owners = [owners] if isinstance(owners, str) else list(owners)
        if len(owners) > 2 or any(o not in names or next(x for x in effects if x["name"] == o)["timed_with"]
                                  for o in owners):
            raise SchemaError(f"effect {e['name']}: timed_with must name one or two earlier effects timed by "
                              "themselves")
        if e.get("rows") is not None and e["rows"] not in sizes:
            raise SchemaError(f"effect {e['name']}: rows must name a row symbol of schema/deck.toml [sizes]")
        names.append(e["name"])
    return effects


def _switch_attribute(effect: dict[str, Any]) -> Entry:
    """The /control attribute that switches an effect off: effect_<switch> = "on" | "off"."""
    return Entry({"name": f"effect_{effect['switch']}", "type": "string", "default": "on", "enum": "switch",
                  "units": "-", "meaning": f"\"off\" switches off {effect['name']}: {effect['meaning']}",
                  "scene": f"[effects] {effect['switch']}",
                  "fix": 'use "on" or "off" (the scene\'s [effects] table takes true or false)'})
