"""Writes fortran/src/core/paradyn_schema.f90: named constants and the spec tables of the deck."""

from __future__ import annotations

from schema_model import Entry, Schema

LINE = 110   # well under Fortran's 132, continuation marks included


def identifier(path: str) -> str:
    return path.strip("/").replace("/", "_")


def text(value: str) -> str:
    """A Fortran string literal; a long one as a concatenation of pieces on continuation lines
    (each of at most 100 characters, never splitting a doubled quote)."""
    quoted = value.replace("'", "''")
    pieces, start = [], 0
    while len(quoted) - start > 116:
        end = start + 100
        if quoted[start:end].count("'") % 2:   # the cut would split a doubled quote
            end -= 1
        pieces.append(quoted[start:end])
        start = end
    pieces.append(quoted[start:])
    return " // &\n          ".join("'" + p + "'" for p in pieces)


def real(value: float | int | None) -> str:
    return f"{float(value or 0.0)!r}_wp"


def logical(value: bool) -> str:
    return ".true." if value else ".false."


def _pack(head: str, items: list[str], indent: str, tail: str = "") -> list[str]:
    """``head item, item, ... tail`` wrapped into continuation lines."""
    lines, line = [], indent + head
    for k, item in enumerate(items):
        piece = item + (", " if k < len(items) - 1 else "")
        if len(line) + len(piece) > LINE:
            lines.append(line.rstrip() + " &")
            line = indent + "    "
        line += piece
    lines.append(line + tail)
    return lines


def _char_len(values: list[str]) -> int:
    return max(8, max(len(v) for v in values))


def _ids(prefix: str, names: list[str]) -> list[str]:
    return [f"  integer, parameter :: {prefix}{n} = {k}" for k, n in enumerate(names, start=1)]


class _Writer:
    def __init__(self, schema: Schema) -> None:
        self.s = schema
        self.public: list[str] = []
        self.body: list[str] = []

    def constant(self, name: str, value: str, kind: str = "integer", comment: str = "") -> None:
        self.public.append(name)
        note = f"   !< {comment}" if comment else ""
        self.body.append(f"  {kind}, parameter :: {name} = {value}{note}"[:LINE + 4].rstrip())

    def enums(self) -> None:
        self.body.append("")
        self.body.append("  ! enum members (schema/deck.toml [enums]): the codes the deck holds")
        for enum in self.s.enums.values():
            for m in enum["members"]:
                self.constant(f"{enum['fortran_prefix']}_{m['name']}", str(m["code"]), comment=m["meaning"][:70])
        for d in self.s.datasets + self.s.control:
            if d.get("upper_constant"):
                self.constant(d.get("upper_constant"), str(d.get("upper")), comment=f"upper bound of {d.name}")

    def statuses(self) -> None:
        self.body.append("")
        self.body.append("  ! exit statuses of paradyn-engine (schema/results.toml)")
        for s in self.s.results["exit_status"]:
            self.constant(f"status_{s['name']}", str(s["code"]), comment=s["meaning"][:80])

    def results_names(self) -> None:
        """The results file's frame fields and the scalar histories (shape (n_records,), time
        excluded) by name and by id, in schema order: the results writer's datasets."""
        frames = [f["name"] for f in self.s.results["frame"]]
        scalars = [h["name"] for h in self.s.results["history"]
                   if h["name"] != "time" and list(h["shape"]) == ["n_records"]]
        self.body += ["", "  ! results datasets (schema/results.toml): frame fields, scalar histories by id"]
        self.constant("n_frame_fields", str(len(frames)))
        self.constant("n_history_scalars", str(len(scalars)))
        for k, name in enumerate(scalars, start=1):
            self.constant(f"history_{name}", str(k))
        self.public += ["frame_field_names", "history_scalar_names"]
        n_frame, n_scalar = _char_len(frames), _char_len(scalars)
        self.body += _pack(f"  character(len={n_frame}), parameter :: frame_field_names(n_frame_fields) = "
                           f"[character(len={n_frame}) :: ", [text(n) for n in frames], "", "]")
        self.body += _pack(f"  character(len={n_scalar}), parameter :: history_scalar_names(n_history_scalars) = "
                           f"[character(len={n_scalar}) :: ", [text(n) for n in scalars], "", "]")

    def ids(self) -> None:
        s = self.s
        self.body += ["", "  ! classes, row symbols, conditions, enums, datasets and /control attributes by id"]
        for k, name in enumerate(("int", "float", "string"), start=1):
            self.constant(f"class_{name}", str(k))
        self.constant("size_none", "0")
        for k, name in enumerate(s.sizes, start=1):
            self.constant(f"size_{name}", str(k))
        self.constant("n_sizes", str(len(s.sizes)))
        self.constant("condition_none", "0")
        for k, name in enumerate(s.conditions, start=1):
            self.constant(f"condition_{name}", str(k))
        self.constant("n_conditions", str(len(s.conditions)))
        self.constant("enum_none", "0")
        for k, name in enumerate(s.enums, start=1):
            self.constant(f"enum_{name}", str(k))
        self.constant("n_enums", str(len(s.enums)))
        for k, d in enumerate(s.datasets, start=1):
            self.constant(f"dataset_{identifier(d.name)}", str(k))
        self.constant("n_deck_datasets", str(len(s.datasets)))
        for k, a in enumerate(s.control, start=1):
            self.constant(f"control_{a.name}", str(k))
        self.constant("n_control_attributes", str(len(s.control)))
        self.public.append("control_restart_may_change")
        self.body += _pack("  logical, parameter :: control_restart_may_change(n_control_attributes) = [",
                           [logical(a.name in s.deck["restart_may_change"]) for a in s.control], "", "]")
        self.constant("max_enum_members", str(max(len(e["members"]) for e in s.enums.values())))

    def effects(self) -> None:
        """The effects of a step by id (schema/effects.toml): names, the effect whose timer each is
        part of (0: its own), and the /control switch attribute that turns it off (0: none)."""
        effects = self.s.effects
        names = [e["name"] for e in effects]
        self.body += ["", "  ! effects of a step (schema/effects.toml), in the order of the step"]
        self.constant("n_effects", str(len(effects)))
        for k, name in enumerate(names, start=1):
            self.constant(f"effect_{name}", str(k))
        self.public += ["effect_names", "effect_timed_with", "effect_also_timed_with", "effect_switch"]
        n_name = _char_len(names)
        self.body += _pack(f"  character(len={n_name}), parameter :: effect_names(n_effects) = "
                           f"[character(len={n_name}) :: ", [text(n) for n in names], "", "]")
        owners = [e["timed_with"] + [""] * (2 - len(e["timed_with"])) for e in effects]
        self.body += _pack("  integer, parameter :: effect_timed_with(n_effects) = [",
                           [f"effect_{o[0]}" if o[0] else "0" for o in owners], "", "]")
        self.body += _pack("  integer, parameter :: effect_also_timed_with(n_effects) = [",
                           [f"effect_{o[1]}" if o[1] else "0" for o in owners], "", "]")
        self.body += _pack("  integer, parameter :: effect_switch(n_effects) = [",
                           [f"control_effect_{e['switch']}" if e.get("switch") else "0" for e in effects], "", "]")

    def size_tables(self) -> None:
        s = self.s
        entities = [v["entity"] for v in s.sizes.values()]
        self.public += ["size_symbol", "size_entity", "size_min_rows"]
        n_symbol, n_entity = _char_len(list(s.sizes)), _char_len(entities)
        self.body += ["", *_pack(f"  character(len={n_symbol}), parameter :: size_symbol(n_sizes) = "
                                    f"[character(len={n_symbol}) :: ", [text(n) for n in s.sizes], "", "]")]
        self.body += _pack(f"  character(len={n_entity}), parameter :: size_entity(n_sizes) = "
                           f"[character(len={n_entity}) :: ", [text(e) for e in entities], "", "]")
        self.body += _pack("  integer, parameter :: size_min_rows(n_sizes) = [",
                           [str(v["min_rows"]) for v in s.sizes.values()], "", "]")

    def entry_texts(self) -> dict[str, int]:
        entries = self.s.datasets + self.s.control
        names = [m["name"] for e in self.s.enums.values() for m in e["members"]]
        return {"path": _char_len([d.name for d in self.s.datasets]),
                "name": _char_len([a.name for a in self.s.control]),
                "rule": _char_len([e.rule for e in entries]), "enum_rule": _char_len([e.enum_rule for e in entries]),
                "fix": _char_len([e.get("fix") for e in entries]), "member": _char_len(names),
                "group": _char_len([c.get("group", "") for c in self.s.conditions.values()]),
                "rows": _char_len([c.get("rows", "") for c in self.s.conditions.values()])}

    def types(self, n: dict[str, int]) -> None:
        self.public += ["enum_spec_t", "condition_spec_t", "dataset_spec_t", "attribute_spec_t"]
        self.body += ["", "  !> Members of an enum: codes and the names a scene or a string attribute uses.",
                      "  type :: enum_spec_t", "    integer :: n_members",
                      "    integer :: codes(max_enum_members)",
                      f"    character(len={n['member']}) :: names(max_enum_members)", "  end type enum_spec_t",
                      "", "  !> A group that exists (group), or a dataset with an entry equal to one of codes.",
                      "  type :: condition_spec_t", f"    character(len={n['group']}) :: group",
                      "    integer :: dataset                  !< dataset id, 0 for a group condition",
                      "    integer :: n_codes                  !< the codes it selects: codes(1:n_codes)",
                      "    integer :: codes(max_enum_members)",
                      f"    character(len={n['rows']}) :: rows   !< the rows it selects, in words",
                      "  end type condition_spec_t", "",
                      "  !> One deck dataset (schema/deck.toml explains every field).",
                      "  type :: dataset_spec_t", f"    character(len={n['path']}) :: path",
                      "    integer :: class                    !< class_int or class_float",
                      "    integer :: columns                  !< 0: shape (rows,); c > 0: shape (rows, c)",
                      "    integer :: row_symbol               !< size_n_nodes, ...",
                      "    logical :: defines_rows             !< first dataset of its row symbol",
                      "    logical :: required",
                      "    integer :: required_when            !< condition id, condition_none",
                      "    integer :: checked_when             !< condition id: values checked on those rows only",
                      "    real(wp) :: default                 !< every entry of an absent optional dataset",
                      "    logical :: has_lower, lower_inclusive, has_upper, upper_inclusive",
                      "    real(wp) :: lower, upper", "    integer :: enum                     !< enum id, enum_none",
                      "    integer :: n_codes                  !< the enum's codes: codes(1:n_codes)",
                      "    integer :: codes(max_enum_members)",
                      "    integer :: reference                !< size id of the entity indexed, size_none",
                      f"    character(len={n['rule']}) :: rule", f"    character(len={n['enum_rule']}) :: enum_rule",
                      f"    character(len={n['fix']}) :: fix", "  end type dataset_spec_t", "",
                      "  !> One attribute of /control; a string attribute holds an enum member's name.",
                      "  type :: attribute_spec_t", f"    character(len={n['name']}) :: name",
                      "    integer :: class                    !< class_float (any number) or class_string",
                      "    logical :: required",
                      "    real(wp) :: default                 !< for a string: the default member's code",
                      "    integer :: default_from             !< control id: default = that / default_divisor",
                      "    real(wp) :: default_divisor",
                      "    logical :: has_lower, lower_inclusive, has_upper, upper_inclusive",
                      "    real(wp) :: lower, upper", "    integer :: enum",
                      f"    character(len={n['rule']}) :: rule", f"    character(len={n['enum_rule']}) :: enum_rule",
                      f"    character(len={n['fix']}) :: fix", "  end type attribute_spec_t"]

    def bounds(self, e: Entry) -> list[str]:
        return [logical("lower" in e.raw), logical(e.get("lower_inclusive", True)), logical("upper" in e.raw),
                logical(e.get("upper_inclusive", True)), real(e.get("lower")), real(e.get("upper"))]

    def codes(self, e: Entry) -> list[str]:
        """n_codes and the padded code list of an entry's enum (none: 0 and zeros)."""
        width = max(len(x["members"]) for x in self.s.enums.values())
        codes = list(self.s.enum_codes(e.get("enum")).values()) if e.get("enum") else []
        return [str(len(codes)), "[" + ", ".join(str(c) for c in codes + [0] * (width - len(codes))) + "]"]

    def tables(self) -> None:
        s = self.s
        self.public += ["deck_enums", "deck_conditions", "deck_datasets", "control_attributes"]
        rows = []
        for e in s.enums.values():
            members = e["members"] + [{"code": 0, "name": ""}] * (int(max(len(x["members"]) for x in s.enums.values()))
                                                                  - len(e["members"]))
            names = [text(m["name"]) for m in members]   # separate items: the list may wrap between names
            names[0] = f"[character(len={self.n['member']}) :: " + names[0]
            names[-1] += "]"
            rows.append(_pack("enum_spec_t(", [str(len(e["members"])), "[" + ", ".join(str(m["code"]) for m in members)
                                               + "]", *names], "    ", ")"))
        self._array("type(enum_spec_t)", "deck_enums(n_enums)", rows)
        ids = {d.name: k for k, d in enumerate(s.datasets, start=1)}
        width = max(len(x["members"]) for x in s.enums.values())
        rows = []
        for name, c in s.conditions.items():
            codes = list(s.condition_codes(name))
            padded = "[" + ", ".join(str(k) for k in codes + [0] * (width - len(codes))) + "]"
            rows.append(_pack("condition_spec_t(", [text(c.get("group", "")), str(ids.get(c.get("dataset"), 0)),
                                                    str(len(codes)), padded, text(c.get("rows", ""))], "    ", ")"))
        self._array("type(condition_spec_t)", "deck_conditions(n_conditions)", rows)
        references = {v["entity"]: f"size_{k}" for k, v in s.sizes.items()}
        rows = []
        for d in s.datasets:
            shape = d.get("shape")
            items = [text(d.name), f"class_{d.get('type')}", str(shape[1] if len(shape) > 1 else 0),
                     f"size_{shape[0]}", logical(d.defines_rows), logical(d.required),
                     f"condition_{d.get('required_when') or 'none'}", f"condition_{d.get('checked_when') or 'none'}",
                     real(d.get("default")), *self.bounds(d), f"enum_{d.get('enum') or 'none'}",
                     *self.codes(d), references.get(d.get("reference"), "size_none"),
                     text(d.rule), text(d.enum_rule), text(d.get("fix"))]
            rows.append(_pack("dataset_spec_t(", items, "    ", ")"))
        self._array("type(dataset_spec_t)", "deck_datasets(n_deck_datasets)", rows)
        rows = []
        for a in s.control:
            default = a.get("default")
            if isinstance(default, str):
                default = s.enum_codes(a.get("enum"))[default]
            items = [text(a.name), f"class_{a.get('type')}", logical(a.required), real(default),
                     f"control_{a.get('default_from')}" if a.get("default_from") else "0",
                     real(a.get("default_divisor")), *self.bounds(a),
                     f"enum_{a.get('enum') or 'none'}", text(a.rule), text(a.enum_rule), text(a.get("fix"))]
            rows.append(_pack("attribute_spec_t(", items, "    ", ")"))
        self._array("type(attribute_spec_t)", "control_attributes(n_control_attributes)", rows)

    def _array(self, kind: str, name: str, rows: list[list[str]]) -> None:
        self.body += ["", f"  {kind}, parameter :: {name} = [ &"]
        for k, row in enumerate(rows):
            last = k == len(rows) - 1
            self.body += [*row[:-1], row[-1] + (" ]" if last else ", &")]

    def write(self, header: list[str]) -> str:
        s = self.s
        self.n = self.entry_texts()
        self.constant("deck_version", str(s.deck["version"]))
        self.constant("deck_version_attribute", text(s.deck["version_attribute"]), "character(len=*)")
        self.enums()
        self.statuses()
        self.results_names()
        self.ids()
        self.effects()
        self.size_tables()
        self.types(self.n)
        self.tables()
        self.public += ["enum_name", "enum_code"]
        predicates = self.trait_predicates()
        publics = _pack("public :: ", self.public, "  ")
        lines = [f"!> {h}" for h in header] + [
            "module paradyn_schema", "  use paradyn_kinds, only: wp", "  implicit none", "  private"]
        return "\n".join([*lines, *publics, *self.body, _ENUM_LOOKUPS, *predicates, "",
                          "end module paradyn_schema", ""])

    def trait_predicates(self) -> list[str]:
        """One elemental predicate per (enum, trait): ``<prefix>_is_<trait>(code)``, true for the
        members that carry the trait, so that no code outside a family compares its codes."""
        out: list[str] = []
        for enum, trait in self.s.traits():
            name = f"{self.s.enums[enum]['fortran_prefix']}_is_{trait}"
            codes = self.s.enum_codes(enum)
            members = self.s.trait_members(enum, trait)
            self.public.append(name)
            out += ["", f"  !> Whether a code of enum {enum} has the trait {trait}:", f"  !> {', '.join(members)}",
                    f"  elemental logical function {name}(code) result(has)", "    integer, intent(in) :: code",
                    f"    has = any(code == [{', '.join(str(codes[m]) for m in members)}])",
                    f"  end function {name}"]
        return out


# The two lookups between an enum's codes and names, the same for every enum
_ENUM_LOOKUPS = '''
contains

  !> The name of code `code` in enum `enum` (deck_enums), '' for an unknown code.
  pure function enum_name(enum, code) result(name)
    integer, intent(in) :: enum, code
    character(len=:), allocatable :: name
    integer :: k
    name = ''
    do k = 1, deck_enums(enum)%n_members
      if (deck_enums(enum)%codes(k) == code) name = trim(deck_enums(enum)%names(k))
    end do
  end function enum_name

  !> The code of name `name` in enum `enum` (deck_enums), -1 for an unknown name.
  pure integer function enum_code(enum, name) result(code)
    integer, intent(in) :: enum
    character(len=*), intent(in) :: name
    integer :: k
    code = -1
    do k = 1, deck_enums(enum)%n_members
      if (name == trim(deck_enums(enum)%names(k))) code = deck_enums(enum)%codes(k)
    end do
  end function enum_code'''


def write(schema: Schema, header: list[str]) -> str:
    return _Writer(schema).write(header)
