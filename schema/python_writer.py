"""Writes frontend/paradyn/_schema.py: the deck and results tables as named tuples (immutable records
that cost a sixth of a frozen dataclass to define when the module loads: docs/performance.md)."""

from __future__ import annotations

from typing import Any

from schema_model import Entry, Schema

CLASSES = '''

class Bound(NamedTuple):
    """A bound on every entry; ``inclusive`` allows the bound itself."""

    value: float
    inclusive: bool


class DatasetSpec(NamedTuple):
    """One deck dataset (schema/deck.toml explains every field)."""

    path: str
    python: str                       # attribute of paradyn.deck.Model
    type: str                         # "int" or "float"
    shape: tuple[str | int, ...]      # row symbol first, then column count
    required: bool
    required_when: str | None         # key of CONDITIONS
    checked_when: str | None          # key of CONDITIONS: values checked only on those rows
    default: float | int | None
    lower: Bound | None
    upper: Bound | None
    rule: str                         # the bounds in words, for messages
    enum: str | None                  # key of ENUMS
    enum_rule: str
    reference: str | None             # entity the entries index: node, part, material
    defines_rows: bool                # first dataset of its row symbol: its rows define the count
    units: str
    meaning: str
    scene: str
    fix: str


class AttributeSpec(NamedTuple):
    """One attribute of /control (schema/deck.toml explains every field)."""

    name: str
    type: str                         # "float" (any number) or "string"
    required: bool
    default: float | str | None
    default_from: str | None          # default = that attribute / default_divisor
    default_divisor: float | None
    lower: Bound | None
    upper: Bound | None
    rule: str
    enum: str | None
    enum_rule: str
    units: str
    meaning: str
    scene: str
    fix: str


class SizeSpec(NamedTuple):
    symbol: str
    entity: str
    min_rows: int
    scene_table: str | None           # the scene's [[table]] whose entries are these rows (paradyn.scene.row_tables)


class ConditionSpec(NamedTuple):
    """A group that exists, or a dataset with an entry equal to one of some enum members' codes."""

    name: str
    group: str | None
    dataset: str | None
    codes: tuple[int, ...]            # the codes it selects (empty for a group condition)
    meaning: str
    rows: str                         # words for the rows it selects, for messages


class RelationSpec(NamedTuple):
    """A hand-checked relation between fields; ``path`` is what its messages name."""

    name: str
    path: str
    meaning: str


class NameAttributeSpec(NamedTuple):
    group: str
    name: str
    python: str
    one_per: str
'''


def _call(name: str, fields: list[tuple[str, Any]], indent: str = "    ", positional: bool = False) -> str:
    """``Name(a=1, b='x', ...)`` (or ``Name(1, 'x', ...)``) packed into lines of at most 116 characters."""
    inner = indent + "    "
    lines, line = [], inner
    for key, value in fields:
        prefix = "" if positional else f"{key}="
        item = f"{prefix}{value!r},"
        if len(inner) + len(item) > 116 and isinstance(value, str):
            # a long text: adjacent literals in parentheses, one per line
            if line.strip():
                lines.append(line.rstrip())
            lines.append(f"{inner}{prefix}(")
            lines.extend(f"{inner}    {chunk!r}" for chunk in _chunks(value, 116 - len(inner) - 8))
            line = f"{inner}), "
            continue
        if len(line) + len(item) + 1 > 116 and line.strip():
            lines.append(line.rstrip())
            line = inner
        line += item + " "
    lines.append(line.rstrip())
    return f"{indent}{name}(\n" + "\n".join(lines) + f"\n{indent}),"


def _chunks(text: str, width: int) -> list[str]:
    """text cut after spaces into pieces of at most width characters (they join back to text)."""
    pieces, current = [], ""
    for word in text.split(" "):
        candidate = f"{current} {word}" if current else word
        if len(candidate) > width and current:
            pieces.append(current + " ")
            current = word
        else:
            current = candidate
    pieces.append(current)
    return pieces


class _Literal:
    def __init__(self, text: str) -> None:
        self.text = text

    def __repr__(self) -> str:
        return self.text


def _bound(entry: Entry, which: str) -> _Literal | None:
    if which not in entry.raw:
        return None
    return _Literal(f"Bound({entry.raw[which]!r}, {bool(entry.get(which + '_inclusive', True))!r})")


def _mapping_lines(key: str, mapping: dict[str, Any]) -> list[str]:
    """``    'key': {...},`` on one line, or with one item a line where that is too long for ruff."""
    line = f"    {key!r}: {mapping!r},"
    if len(line) <= 116:
        return [line]
    return [f"    {key!r}: {{", *[f"        {k!r}: {v!r}," for k, v in mapping.items()], "    },"]


def _dataset(d: Entry) -> str:
    return _call("DatasetSpec", [
        ("path", d.name), ("python", d.get("python")), ("type", d.get("type")), ("shape", tuple(d.get("shape"))),
        ("required", d.required), ("required_when", d.get("required_when")),
        ("checked_when", d.get("checked_when")), ("default", d.get("default")), ("lower", _bound(d, "lower")),
        ("upper", _bound(d, "upper")), ("rule", d.rule), ("enum", d.get("enum")), ("enum_rule", d.enum_rule),
        ("reference", d.get("reference")), ("defines_rows", d.defines_rows), ("units", d.get("units")),
        ("meaning", d.get("meaning")), ("scene", d.get("scene")), ("fix", d.get("fix"))], positional=True)


def _attribute(a: Entry) -> str:
    return _call("AttributeSpec", [
        ("name", a.name), ("type", a.get("type")), ("required", a.required), ("default", a.get("default")),
        ("default_from", a.get("default_from")), ("default_divisor", a.get("default_divisor")),
        ("lower", _bound(a, "lower")), ("upper", _bound(a, "upper")), ("rule", a.rule), ("enum", a.get("enum")),
        ("enum_rule", a.enum_rule), ("units", a.get("units")), ("meaning", a.get("meaning")),
        ("scene", a.get("scene")), ("fix", a.get("fix"))], positional=True)


def _names(constant: str, names: list[str]) -> str:
    """``CONSTANT = ('a', 'b', ...)`` wrapped at 116 characters."""
    line = f"{constant} = {tuple(names)!r}"
    if len(line) <= 116:
        return line
    lines, current = [f"{constant} = ("], "   "
    for name in names:
        if len(current) + len(repr(name)) + 2 > 116:
            lines.append(current.rstrip())
            current = "   "
        current += f" {name!r},"
    return "\n".join([*lines, current.rstrip(), ")"])


def write(schema: Schema, header: str) -> str:
    deck, results = schema.deck, schema.results
    out = [f'"""{header}\n\nThe deck and results formats of docs/formats.md as Python tables; '
           'paradyn.deck validates\nwith them and paradyn.scene takes its defaults from them.\n"""',
           "", "from __future__ import annotations", "", "from typing import NamedTuple", CLASSES, ""]
    out += [f"DECK_VERSION = {deck['version']!r}", f"VERSION_ATTRIBUTE = {deck['version_attribute']!r}",
            f"TITLE_ATTRIBUTE = {deck['title_attribute']!r}", f"DOF_NAMES = {tuple(deck['dof_names'])!r}",
            _names("RESTART_MAY_CHANGE", deck["restart_may_change"]), ""]
    out.append("ENUMS: dict[str, dict[str, int]] = {")
    for name in schema.enums:
        out += _mapping_lines(name, schema.enum_codes(name))
    out += ["}", "", "# The members of an enum that carry a trait (schema/deck.toml traits): ask a trait, not a name",
            "ENUM_TRAITS: dict[str, dict[str, tuple[str, ...]]] = {"]
    for enum in dict.fromkeys(e for e, _ in schema.traits()):
        traits = {t: tuple(schema.trait_members(enum, t)) for e, t in schema.traits() if e == enum}
        out += _mapping_lines(enum, traits)
    out += ["}", "", "SIZES: dict[str, SizeSpec] = {"]
    out += [f"    {k!r}: SizeSpec({k!r}, {v['entity']!r}, {v['min_rows']!r}, {v.get('scene_table')!r}),"
            for k, v in schema.sizes.items()]
    out += ["}", "", "CONDITIONS: dict[str, ConditionSpec] = {"]
    for name, c in schema.conditions.items():
        out.append(_call("ConditionSpec", [("name", name), ("group", c.get("group")), ("dataset", c.get("dataset")),
                                           ("codes", schema.condition_codes(name)), ("meaning", c["meaning"]),
                                           ("rows", c.get("rows", ""))])
                   .replace("    ConditionSpec(", f"    {name!r}: ConditionSpec(", 1))
    out += ["}", "", "RELATIONS: dict[str, RelationSpec] = {"]
    out += [_call("RelationSpec", [("name", k), ("path", v["path"]), ("meaning", v["meaning"])], positional=True)
            .replace("    RelationSpec(", f"    {k!r}: RelationSpec(", 1) for k, v in schema.relations.items()]
    out += ["}", "", "# fields in the order of DatasetSpec and AttributeSpec above",
            "DATASETS: tuple[DatasetSpec, ...] = ("] + [_dataset(d) for d in schema.datasets] + [")", ""]
    out += ["CONTROL: tuple[AttributeSpec, ...] = ("] + [_attribute(a) for a in schema.control] + [")", ""]
    out += ["NAME_ATTRIBUTES: tuple[NameAttributeSpec, ...] = ("]
    out += [f"    NameAttributeSpec({n['group']!r}, {n['name']!r}, {n['python']!r}, {n['one_per']!r}),"
            for n in schema.name_attributes]
    out += [")", "", "# Every rule of the deck, by (what, name); tests/test_schema_damage.py breaks each one.",
            "RULES: dict[tuple[str, str], tuple[str, ...]] = {"]
    grouped: dict[tuple[str, str], list[str]] = {}
    for what, name, rule in schema.rules():
        grouped.setdefault((what, name), []).append(rule)
    out += [f"    {key!r}:\n        {tuple(rules)!r}," if len(f"    {key!r}: {tuple(rules)!r},") > 116
            else f"    {key!r}: {tuple(rules)!r}," for key, rules in grouped.items()]
    out += ["}", ""]
    out += ["# The results file and the engine's output", ""]
    out += [f"RESULTS_VERSION = {results['results']['version']!r}",
            f"RESULTS_VERSION_ATTRIBUTE = {results['results']['version_attribute']!r}",
            _names("MESH_DATASETS", [m["path"] for m in results["mesh"]]),
            _names("FRAME_FIELDS", [f["name"] for f in results["frame"]]),
            _names("HISTORY_NAMES", [h["name"] for h in results["history"]]),
            _names("ENERGY_NAMES", [h["name"] for h in results["history"]
                                    if h.get("units") == "J" and list(h["shape"]) == ["n_records"]]),
            "HISTORY_UNITS: dict[str, str] = {",
            *[f"    {h['name']!r}: {h['units']!r}," for h in results["history"]],
            "}",
            _names("RUN_ATTRIBUTES", [n for r in results["run"] for n in r["names"]]),
            _names("PHASES", results["phases"]["names"]),
            _names("CONTACT_PHASES", results["phases"]["contact_parts"]),
            "", "# The effects of a step (schema/effects.toml), in the order of the step",
            _names("EFFECTS", [e["name"] for e in schema.effects]),
            "EFFECT_SWITCHES: dict[str, str] = {",
            *[f"    {e['switch']!r}: {e['name']!r}," for e in schema.effects if e.get("switch")],
            "}",
            "EFFECT_TIMED_WITH: dict[str, tuple[str, ...]] = {",
            *[f"    {e['name']!r}: {tuple(e['timed_with'])!r}," for e in schema.effects if e["timed_with"]],
            "}", "",
            "PROGRESS_KINDS: dict[str, tuple[str, ...]] = {"]
    for p in results["progress"]:   # one line per kind, the keys on a second where the line would pass 120
        line = f"    {p['kind']!r}: {tuple(p['keys'])!r},"
        out += [line] if len(line) <= 120 else [f"    {p['kind']!r}:", f"        {tuple(p['keys'])!r},"]
    out += ["}", ""]
    out += [f"STATUS_{s['name'].upper()} = {s['code']}" for s in results["exit_status"]]
    out += ["EXIT_STATUSES: dict[int, str] = {"]
    out += [f"    {s['code']}: {s['name']!r}," for s in results["exit_status"]]
    out += ["}", ""]
    return "\n".join(out)


def _field_default(schema: Schema, d: Entry) -> str:
    """A dataset's default in the deck model: required ones have none; the datasets of an optional
    table (those that define its rows or are required when its group exists) start empty; the rest
    are None (filled from the schema's default once their rows are known, or left out)."""
    if d.required:
        return ""
    condition = schema.conditions.get(d.get("required_when") or "", {})
    if "group" in condition or d.defines_rows:
        columns = d.get("shape")[1:]
        dtype = "np.int32" if d.get("type") == "int" else "np.float64"
        shape = f"(0, {columns[0]})" if columns else "0"
        return f" = field(default_factory=lambda: np.zeros({shape}, dtype={dtype}))"
    return " = None"


def write_fields(schema: Schema, header: str) -> str:
    """paradyn/deck/fields.py: one dataclass field per dataset and a row count per row symbol."""
    out = [f'"""{header}\n\nThe deck model\'s arrays, one field per dataset of schema/deck.toml (its ``python``\n'
           'name), and the row count of every row symbol. :class:`paradyn.deck.Model` extends it."""', "",
           "from __future__ import annotations", "", "from dataclasses import dataclass, field", "",
           "import numpy as np", "", "", "@dataclass(kw_only=True)", "class DeckFields:",
           '    """The datasets of a deck (shapes as docs/formats.md, indices 0-based)."""', ""]
    for d in sorted(schema.datasets, key=lambda d: not d.required):
        default = _field_default(schema, d)
        kind = "np.ndarray | None" if default == " = None" else "np.ndarray"
        line = f"    {d.get('python')}: {kind}{default}"
        note = f"   # {d.name} {tuple(d.get('shape'))} {d.get('units')}".replace("'", "")
        out.append(line + note if len(line + note) <= 120 else line)
    required = {d.get("shape")[0] for d in schema.datasets if d.defines_rows and d.required}
    for symbol in schema.sizes:
        if symbol in required:
            continue   # the model's own properties (None while the array is not yet a table)
        first = next(d for d in schema.datasets if d.get("shape")[0] == symbol)
        out += ["", "    @property", f"    def {symbol}(self) -> int:",
                f'        """Rows of {first.name}."""',
                f"        return _rows(self.{first.get('python')}, {len(first.get('shape'))})"]
    out += ["", "", "def _rows(value: object, rank: int) -> int:",
            '    """Rows of a table: its first dimension, or its size when it is not yet a table of that rank."""',
            "    a = np.asarray(value)", "    return int(a.shape[0]) if a.ndim == rank else int(a.size)", ""]
    return "\n".join(out)
