"""Writes fortran/src/model/deck_fields.f90: one field of the engine's deck per dataset and /control
attribute of the schema, and the two routines that store them as the reader reads them.

A dataset's field is named by its ``fortran`` key, else by its ``python`` name; ``engine = false``
keeps a dataset out (the frontend's ids). Shape (rows,) gives a rank-1 field, (rows, c) a (c, rows)
one; int datasets are integer, indices made 1-based where the dataset has a ``reference`` or
``index = true``. Every row symbol gets its count ``n_<symbol>``, set by the dataset that defines
its rows (store_dataset hands each dataset to the routine of its part of the schema's datasets, so
that no routine grows with the schema). A /control attribute is real(wp), an integer where it names
an enum member (its code) or ``fortran_type = "integer"``; the effect switches fill ``effect_on``.
"""

from __future__ import annotations

from fortran_writer import LINE, identifier, real
from schema_model import Entry, Schema

# datasets per store routine: at most 3 lines each, so a routine stays under the 120 lines of
# tests/test_code_size.py however many datasets the schema gains
STORE_PART = 32


def field_name(d: Entry) -> str:
    return d.get("fortran") or d.get("python")


def engine_datasets(schema: Schema) -> list[Entry]:
    return [d for d in schema.datasets if d.get("engine", True)]


def _is_switch(a: Entry) -> bool:
    return a.name.startswith("effect_") and a.get("enum") == "switch"


def _integer(a: Entry) -> bool:
    return a.get("type") == "string" or a.get("fortran_type") == "integer"


def _declaration(d: Entry) -> str:
    kind = "integer" if d.get("type") == "int" else "real(wp)"
    rank = "(:, :)" if len(d.get("shape")) > 1 else "(:)"
    columns = f"{d.get('shape')[1]}, " if len(d.get("shape")) > 1 else ""
    line = f"    {kind}, allocatable :: {field_name(d)}{rank}"
    note = f"   !< {d.name} ({columns}{d.get('shape')[0]}) {d.get('units')}"
    return line + note if len(line + note) <= LINE else line


def _control_declaration(schema: Schema, a: Entry) -> str:
    default = a.get("default")
    if isinstance(default, str):
        default = schema.enum_codes(a.get("enum"))[default]
    if _integer(a):
        line = f"    integer :: {a.name} = {int(default or 0)}"
    else:
        line = f"    real(wp) :: {a.name} = {real(default)}"
    note = f"   !< /control {a.name}" + (f" ({a.get('units')})" if a.get("units", "-") != "-" else "")
    return line + note if len(line + note) <= LINE else line


def _store_case(d: Entry) -> list[str]:
    name = field_name(d)
    matrix = len(d.get("shape")) > 1
    if d.get("type") == "int":
        value = "indices" if matrix else "indices(1, :)"
        if d.get("index"):
            value += " + 1"
    else:
        value = "values" if matrix else "values(1, :)"
    lines = [f"    case (dataset_{identifier(d.name)})", f"      d%{name} = {value}"]
    if d.defines_rows:
        lines.append(f"      d%n_{d.get('shape')[0][2:]} = size(values, 2)")
    return lines


def write(schema: Schema, header: list[str]) -> str:
    datasets = engine_datasets(schema)
    attributes = [a for a in schema.control if not _is_switch(a)]
    ids = [f"dataset_{identifier(d.name)}" for d in datasets] + [f"control_{a.name}" for a in attributes]
    out = [f"!> {h}" for h in header]
    out += ["module deck_fields", "  use paradyn_kinds, only: wp"]
    uses = ["class_int", "size_none", "deck_datasets", "n_effects", "effect_switch", "switch_off", *ids,
            *[f"effect_{e['name']}" for e in schema.effects if e.get("rows")]]
    line = "  use paradyn_schema, only: "
    for k, name in enumerate(uses):
        piece = name + (", " if k < len(uses) - 1 else "")
        if len(line) + len(piece) > LINE:
            out.append(line.rstrip() + " &")
            line = "                            "
        line += piece
    out += [line, "  implicit none", "  private",
            "  public :: deck_fields_t, store_dataset, store_control, declare_by_rows, drop_rows", ""]
    out += ["  !> The deck's tables as the schema declares them: every engine dataset and /control attribute.",
            "  type :: deck_fields_t"]
    symbols = [s[2:] for s in schema.sizes]
    out += [f"    integer :: n_{s} = 0" for s in symbols]
    out += [_declaration(d) for d in datasets]
    out += [_control_declaration(schema, a) for a in attributes]
    out += ["    logical :: effect_on(n_effects) = .true.   !< false: the scene switched the effect off",
            "  end type deck_fields_t", "", "contains", ""]
    out += ["  !> Puts dataset id, as read ((max(columns, 1), rows), 0-based indices), into its field;",
            "  !> indices become 1-based. A dataset the engine does not keep (engine = false) is ignored.",
            "  subroutine store_dataset(d, id, values)",
            "    class(deck_fields_t), intent(inout) :: d", "    integer, intent(in) :: id",
            "    real(wp), intent(in) :: values(:, :)", "    integer, allocatable :: indices(:, :)",
            "    if (deck_datasets(id)%class == class_int) then   ! checked: every entry is a small whole number",
            "      allocate (indices(size(values, 1), size(values, 2)))", "      indices = nint(values)",
            "      if (deck_datasets(id)%reference /= size_none) indices = indices + 1", "    end if",
            "    select case (id)   ! ids in schema order: each part of the datasets has its routine"]
    parts = [datasets[k:k + STORE_PART] for k in range(0, len(datasets), STORE_PART)]
    for k, part in enumerate(parts, start=1):
        out += [f"    case (dataset_{identifier(part[0].name)}:dataset_{identifier(part[-1].name)})",
                f"      call store_datasets_{k}(d, id, values, indices)"]
    out += ["    end select", "  end subroutine store_dataset", ""]
    for k, part in enumerate(parts, start=1):
        out += [f"  !> store_dataset for the datasets {part[0].name} to {part[-1].name}.",
                f"  subroutine store_datasets_{k}(d, id, values, indices)",
                "    class(deck_fields_t), intent(inout) :: d", "    integer, intent(in) :: id",
                "    real(wp), intent(in) :: values(:, :)", "    integer, allocatable, intent(in) :: indices(:, :)",
                "    select case (id)"]
        for d in part:
            out += _store_case(d)
        out += ["    end select", f"  end subroutine store_datasets_{k}", ""]
    out += ["  !> Puts /control attribute id into its field (a string attribute arrives as its enum code).",
            "  subroutine store_control(d, id, value)", "    class(deck_fields_t), intent(inout) :: d",
            "    integer, intent(in) :: id", "    real(wp), intent(in) :: value", "    select case (id)"]
    for a in attributes:
        value = "nint(value)" if _integer(a) else "value"
        out += [f"    case (control_{a.name})", f"      d%{a.name} = {value}"]
    out += ["    case default   ! an effect's switch (schema/effects.toml)",
            "      where (effect_switch == id) d%effect_on = nint(value) /= switch_off",
            "    end select", "  end subroutine store_control", ""]
    out += _effect_rows(schema)
    out += ["end module deck_fields", ""]
    return "\n".join(out)


def _effect_rows(schema: Schema) -> list[str]:
    """The effects declared by the rows of their table (schema/effects.toml ``rows``)."""
    by_rows = [(e["name"], e["rows"]) for e in schema.effects if e.get("rows")]
    out = ["  !> Marks the effects that the deck declares by rows of their tables (schema/effects.toml rows).",
           "  pure subroutine declare_by_rows(d, declared)", "    class(deck_fields_t), intent(in) :: d",
           "    logical, intent(inout) :: declared(n_effects)"]
    out += [f"    declared(effect_{name}) = d%{rows} > 0" for name, rows in by_rows]
    out += ["  end subroutine declare_by_rows", "",
            "  !> Drops the rows of the effects declared by rows that are switched off (off(id)).",
            "  pure subroutine drop_rows(d, off)", "    class(deck_fields_t), intent(inout) :: d",
            "    logical, intent(in) :: off(n_effects)"]
    out += [f"    if (off(effect_{name})) d%{rows} = 0" for name, rows in by_rows]
    out += ["  end subroutine drop_rows", ""]
    return out
