"""Reading LS-DYNA keyword files (``.k``, ``.key``, ``.dyn``) into keyword blocks and typed fields.

This module knows the file format, not the meaning of the cards (that is
:mod:`paradyn.keyword.scene`): it follows ``*INCLUDE`` files, drops ``$`` comments, collects
``*PARAMETER`` values, and splits the rest into :class:`Block` objects, one per keyword with its
data lines. :func:`fields` then reads one data line against a card layout, in fixed columns
(10-character fields, or the widths the layout gives), in long format (keyword suffix ``+`` or
``*KEYWORD LONG=Y``: every field at least 20 characters) or in free format (fields separated by
commas), substituting ``&name`` parameters. Every problem is a :class:`KeywordError` naming the
file, the line and the field. docs/keyword.md lists what is read.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

FIELD_WIDTH = 10        # a standard field
LONG_WIDTH = 20         # the least width of a field in long format
Value = int | float | str | None


class KeywordError(ValueError):
    """A keyword file that cannot be read; the message starts with ``file:line``."""


@dataclass(frozen=True)
class Line:
    """One data line of a keyword file, with where it came from."""

    text: str
    path: Path
    number: int

    @property
    def where(self) -> str:
        return f"{self.path}:{self.number}"


@dataclass
class Block:
    """A keyword and its data lines: ``name`` is upper case, without ``*`` and format suffix."""

    name: str
    path: Path
    number: int
    lines: list[Line] = field(default_factory=list)
    long: bool = False

    @property
    def where(self) -> str:
        return f"{self.path}:{self.number}"


@dataclass(frozen=True)
class Field:
    """A field of a card layout: name (as the LS-DYNA manual spells it), kind, width, default."""

    name: str
    kind: str = "float"            # "int", "float" or "text"
    default: Value = None
    width: int = FIELD_WIDTH


def layout(names: str, kind: str = "float", **defaults: Value) -> tuple[Field, ...]:
    """A card of 10-character fields named in ``names`` (space separated), all of ``kind``, with
    defaults by name (``None`` when not given). An ``int:`` or ``text:`` prefix on a name overrides
    ``kind`` for that field."""
    cards = []
    for name in names.split():
        own_kind, _, bare = name.rpartition(":")
        cards.append(Field(bare, own_kind or kind, defaults.get(bare.lower())))
    return tuple(cards)


@dataclass
class KeywordFile:
    """A keyword file with its includes read: the blocks in order, the parameters and the title."""

    path: Path
    blocks: list[Block]
    parameters: dict[str, float | int | str]
    title: str = ""
    warnings: list[str] = field(default_factory=list)


def read_keyword_file(path: str | Path) -> KeywordFile:
    """Read ``path`` and the files it includes into keyword blocks.

    ``*INCLUDE`` names a file relative to the folder of the file that includes it (or an absolute
    path); its blocks take its place. ``*PARAMETER`` values are collected in reading order, so a
    parameter must be defined before the line that uses it. ``*TITLE`` gives the title, ``*END``
    ends a file, ``*KEYWORD LONG=Y`` makes long format the default.
    """
    path = Path(path)
    if not path.is_file():
        raise KeywordError(f"{path}: keyword file not found; check the path")
    deck = KeywordFile(path=path, blocks=[], parameters={})
    _read_into(deck, path.resolve(), stack=(), long=False)
    return deck


def _read_into(deck: KeywordFile, path: Path, stack: tuple[Path, ...], long: bool) -> bool:
    """Append the blocks of ``path`` to ``deck``; return the long-format default after it."""
    if path in stack:
        chain = " -> ".join(str(p) for p in (*stack, path))
        raise KeywordError(f"{stack[-1]}: *INCLUDE makes a cycle ({chain}); remove the include")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        where = f"{stack[-1]}: *INCLUDE" if stack else f"{path}"
        raise KeywordError(f"{where}: cannot read {path} ({exc.strerror}); check the path") from exc
    for block in _blocks_of(path, text.splitlines(), long):
        if block.name == "END":
            break
        if block.name == "KEYWORD":
            long = long or block.long
        elif block.name == "INCLUDE":
            for included in _include_paths(block):
                long = _read_into(deck, included, (*stack, path), long)
        elif block.name == "PARAMETER":
            _read_parameters(deck, block)
        elif block.name == "TITLE":
            deck.title = block.lines[0].text.strip() if block.lines else ""
        elif block.name != "COMMENT":
            deck.blocks.append(block)
    return long


_KEYWORD_NAME = re.compile(r"\*([A-Za-z0-9_]+)\s*([+\-%]?)")


def _blocks_of(path: Path, lines: list[str], long: bool) -> list[Block]:
    blocks: list[Block] = []
    for number, raw in enumerate(lines, start=1):
        text = raw.rstrip("\r\n")
        if text.startswith("$"):
            continue
        if text.startswith("*"):
            match = _KEYWORD_NAME.match(text)
            if match is None:
                raise KeywordError(f"{path}:{number}: '{text.strip()}' is not a keyword line; a keyword "
                                   f"is '*' followed by its name, as *NODE")
            name, suffix = match.group(1).upper(), match.group(2)
            if suffix == "%":
                raise KeywordError(f"{path}:{number}: *{name}% (the i10 format) is not read; write the "
                                   f"keyword in standard, long (+) or free (comma) format")
            if name == "KEYWORD" and re.search(r"LONG\s*=\s*[YS]", text.upper()):
                long = True    # long format from here on, in this file and the files it includes
            is_long = suffix == "+" or (long and suffix != "-")
            blocks.append(Block(name=name, path=path, number=number, long=is_long))
        elif blocks:
            blocks[-1].lines.append(Line(text=text, path=path, number=number))
        elif text.strip():
            raise KeywordError(f"{path}:{number}: data before the first keyword; start the file with "
                               f"*KEYWORD")
    return blocks


def _include_paths(block: Block) -> list[Path]:
    """The files one ``*INCLUDE`` names: one per line, a line ending in `` +`` continues on the next."""
    names: list[str] = []
    pending = ""
    for line in block.lines:
        text = line.text.rstrip()
        if not text.strip() and not pending:
            continue
        if text.endswith(" +"):
            pending += text[:-2].strip()
            continue
        names.append(pending + text.strip())
        pending = ""
    if not names:
        raise KeywordError(f"{block.where}: *INCLUDE names no file; give the file name on the next line")
    return [(block.path.parent / name).resolve() for name in names]


def _read_parameters(deck: KeywordFile, block: Block) -> None:
    """``*PARAMETER``: pairs of (type letter R/I/C with the name, value), four pairs a line."""
    pairs = tuple(Field(f"{key}{i}", kind) for i in range(1, 5) for key, kind in (("PRMR", "text"), ("VAL", "text")))
    for line in block.lines:
        if not line.text.strip():
            continue
        values = fields(line, pairs, long=block.long, parameters=deck.parameters, keyword="PARAMETER")
        for i in range(1, 5):
            label, raw = values[f"PRMR{i}"], values[f"VAL{i}"]
            if not label:
                continue
            kind, name = str(label)[0].upper(), str(label)[1:].strip()
            if kind not in "RIC" or not name:
                raise KeywordError(f"{line.where}: *PARAMETER field PRMR{i} = '{label}' must be a type letter "
                                   f"R, I or C followed by the name, as 'R rho'")
            deck.parameters[name.upper()] = _parameter_value(line, f"VAL{i}", kind, str(raw or ""))


def _parameter_value(line: Line, label: str, kind: str, raw: str) -> float | int | str:
    if kind == "C":
        return raw
    return _number(line, "PARAMETER", label, raw, "int" if kind == "I" else "float")


# ----------------------------------------------------------------------------------------------
# fields of a data line


def fields(line: Line, card: Sequence[Field], *, long: bool, parameters: dict[str, float | int | str],
           keyword: str) -> dict[str, Value]:
    """The values of one data line read against ``card``; a blank field takes the field's default.

    A line holding a comma is free format: its comma-separated entries are the fields in order.
    Otherwise the fields are fixed columns of the card's widths (at least 20 characters each in
    long format). ``&name`` (or ``-&name``) stands for a ``*PARAMETER``.
    """
    if "," in line.text:
        raw = [entry.strip() for entry in line.text.split(",")]
        if len(raw) > len(card) and any(raw[len(card):]):
            raise KeywordError(f"{line.where}: *{keyword} takes {len(card)} fields on this card, the line "
                               f"has {len(raw)}; remove the extra entries")
    else:
        text = line.text
        raw = [text[start:end].strip() for start, end in _columns(tuple(card), long)]
    values: dict[str, Value] = {}
    for spec, text in zip(card, raw + [""] * (len(card) - len(raw)), strict=True):
        values[spec.name] = _value(line, keyword, spec, text, parameters)
    return values


@functools.lru_cache(maxsize=256)
def _columns(card: tuple[Field, ...], long: bool) -> tuple[tuple[int, int], ...]:
    """The (start, end) columns of the card's fields, standard or long."""
    spans, start = [], 0
    for spec in card:
        width = max(spec.width, LONG_WIDTH) if long else spec.width
        spans.append((start, start + width))
        start += width
    return tuple(spans)


def _value(line: Line, keyword: str, spec: Field, text: str, parameters: dict[str, float | int | str]) -> Value:
    if not text:
        return spec.default
    if "&" in text:
        return _substitute(line, keyword, spec, text, parameters)
    if spec.kind == "text":
        return text
    return _number(line, keyword, spec.name, text, spec.kind)


def _substitute(line: Line, keyword: str, spec: Field, text: str,
                parameters: dict[str, float | int | str]) -> Value:
    negative = text.startswith("-")
    name = text.lstrip("-").lstrip("&").strip().upper()
    if not text.lstrip("-").startswith("&") or name not in parameters:
        known = ", ".join(sorted(parameters)) or "none"
        raise KeywordError(f"{line.where}: *{keyword} field {spec.name} = '{text}' names no parameter defined "
                           f"before it (defined: {known}); define it with *PARAMETER first")
    value = parameters[name]
    if spec.kind == "text":
        return str(value)
    number = _number(line, keyword, spec.name, str(value), spec.kind) if isinstance(value, str) else value
    if spec.kind == "int" and float(number) != int(number):
        raise KeywordError(f"{line.where}: *{keyword} field {spec.name}: parameter &{name} = {number} is not "
                           f"a whole number; this field takes an integer")
    number = int(number) if spec.kind == "int" else float(number)
    return -number if negative else number


_FORTRAN_EXPONENT = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+))([dD]|(?<=\d)(?=[+-]\d))([+-]?\d+)$")


def _number(line: Line, keyword: str, name: str, text: str, kind: str) -> int | float:
    """An integer or a real as Fortran reads it (``1.5e3``, ``1.5d3``, ``1.5+3``); anything else is an error."""
    if kind == "int":
        try:
            return int(text)
        except ValueError:
            pass
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if math.isfinite(value) and value == int(value) and abs(value) < 2**53:
            return int(value)
        raise KeywordError(f"{line.where}: *{keyword} field {name} = '{text}' is not an integer; write a "
                           f"whole number")
    fortran = _FORTRAN_EXPONENT.match(text)
    candidate = f"{fortran.group(1)}e{fortran.group(3)}" if fortran else text
    try:
        value = float(candidate)
    except ValueError:
        value = math.nan
        finite = False
    else:
        finite = math.isfinite(value)
    if not finite or "_" in candidate:
        raise KeywordError(f"{line.where}: *{keyword} field {name} = '{text}' is not a finite number; write "
                           f"a number such as 7.86e3")
    return value
