"""The tables of docs/formats.md, as Markdown."""

from __future__ import annotations

from schema_model import Entry, Schema, number_text


def _shape(shape: list[str | int]) -> str:
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def _enum_words(schema: Schema, entry: Entry) -> str:
    members = schema.enums[entry.get("enum")]["members"]
    if entry.get("type") == "string":
        return "; ".join(f'`"{m["name"]}"`: {m["meaning"]}' for m in members)
    return "; ".join(f"{m['code']} = {m['name']} ({m['meaning']})" for m in members)


def _status(schema: Schema, entry: Entry) -> str:
    if entry.required:
        return "required"
    if entry.get("required_when"):
        return f"required when {schema.conditions[entry.get('required_when')]['meaning']}"
    if entry.get("default_from"):
        return f"optional, default {entry.get('default_from')} / {number_text(entry.get('default_divisor'))}"
    if entry.get("default") is not None:
        default = entry.get("default")
        return f"optional, default {default!r}" if isinstance(default, str) else f"optional, default {default}"
    return "optional"


def _rules(schema: Schema, entry: Entry) -> str:
    words = []
    if entry.rule:
        where = entry.get("checked_when")
        words.append(entry.rule + (f" {schema.conditions[where]['rows']}" if where else ""))
    if entry.get("enum"):
        words.append(_enum_words(schema, entry))
    if entry.get("reference"):
        none = "-1 (none) or " if entry.get("lower") == -1 else ""
        words.append(f"{none}{entry.get('reference')} index, 0 <= i < number of {entry.get('reference')}s")
    if entry.get("type") == "float":
        words.append("finite")
    return "; ".join(words)


def _row(cells: list[str]) -> str:
    return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"


def deck_datasets(schema: Schema) -> str:
    lines = [_row(["dataset", "dtype", "shape", "units", "presence", "values", "meaning", "scene"]),
             "|---|---|---|---|---|---|---|---|"]
    for d in schema.datasets:
        dtype = "integer" if d.get("type") == "int" else "float"
        lines.append(_row([f"`{d.name}`", dtype, _shape(d.get("shape")), d.get("units"), _status(schema, d),
                           _rules(schema, d), d.get("meaning"), d.get("scene")]))
    return "\n".join(lines) + "\n"


def control_attributes(schema: Schema) -> str:
    lines = [_row(["attribute", "type", "units", "presence", "values", "meaning", "scene"]),
             "|---|---|---|---|---|---|---|"]
    for a in schema.control:
        kind = "string" if a.get("type") == "string" else "number"
        lines.append(_row([f"`{a.name}`", kind, a.get("units"), _status(schema, a), _rules(schema, a),
                           a.get("meaning"), a.get("scene")]))
    return "\n".join(lines) + "\n"


def results_datasets(schema: Schema) -> str:
    r = schema.results
    lines = [_row(["dataset", "dtype", "shape", "units", "meaning"]), "|---|---|---|---|---|"]
    entries = [(m["path"], m) for m in r["mesh"]] + [(f"/frames/{f['name']}", f) for f in r["frame"]]
    entries += [(f"/history/{h['name']}", h) for h in r["history"]]
    for path, e in entries:
        lines.append(_row([f"`{path}`", e["type"], _shape(e["shape"]), e["units"], e["meaning"]]))
    return "\n".join(lines) + "\n"


def run_attributes(schema: Schema) -> str:
    lines = [_row(["attribute", "meaning"]), "|---|---|"]
    for r in schema.results["run"]:
        lines.append(_row([", ".join(f"`{n}`" for n in r["names"]), r["meaning"]]))
    return "\n".join(lines) + "\n"


def exit_statuses(schema: Schema) -> str:
    lines = [_row(["status", "name", "meaning"]), "|---|---|---|"]
    for s in schema.results["exit_status"]:
        lines.append(_row([str(s["code"]), f"`{s['name']}`", s["meaning"]]))
    return "\n".join(lines) + "\n"


def relations(schema: Schema) -> str:
    lines = [_row(["relation", "named in the message", "rule"]), "|---|---|---|"]
    for name, r in schema.relations.items():
        lines.append(_row([f"`{name}`", f"`{r['path']}`", r["meaning"]]))
    return "\n".join(lines) + "\n"


def effects(schema: Schema) -> str:
    lines = [_row(["effect", "stage", "declared by", "switch ([effects])", "timed with", "meaning"]),
             "|---|---|---|---|---|---|"]
    for e in schema.effects:
        switch = f"`{e['switch']}`" if e.get("switch") else "-"
        timed = " or ".join(e["timed_with"]) or "itself"
        lines.append(_row([f"`{e['name']}`", e["stage"], e["declared_by"], switch, timed, e["meaning"]]))
    return "\n".join(lines) + "\n"


def tables(schema: Schema) -> dict[str, str]:
    return {"effects": effects(schema), "deck-datasets": deck_datasets(schema), "deck-relations": relations(schema),
            "control-attributes": control_attributes(schema),
            "results-datasets": results_datasets(schema), "run-attributes": run_attributes(schema),
            "exit-statuses": exit_statuses(schema)}
