"""Fields whose 0.0 means LS-DYNA's default (docs/keyword.md, "0.0 means the default").

LS-DYNA's manual gives many fields a default that applies both when the field is blank and when it
holds 0 (``SLSFAC``: "EQ.0.0: default set to 0.1"); decks written by pre-processors put the 0 in
(``SFS 0.000``). :data:`ZERO_MEANS_DEFAULT` is the one table of those fields: the card reader
(:meth:`paradyn.keyword.cards._Reading.card`) replaces a 0 in them by the default before anything
else looks at the value, so a 0 that means the default is read as the default and is not warned.
A field not listed keeps its 0 (a zero friction, a zero offset).
"""

from __future__ import annotations

from dataclasses import dataclass

from .reader import Value


@dataclass(frozen=True)
class ZeroDefault:
    """A field of a keyword whose 0 stands for ``default``."""

    keyword: str      # the keyword as the table names it: a keyword and its options (CONTACT covers *CONTACT_...)
    field: str
    default: Value


ZERO_MEANS_DEFAULT: tuple[ZeroDefault, ...] = (
    ZeroDefault("CONTROL_CONTACT", "SLSFAC", 0.1),
    ZeroDefault("CONTROL_CONTACT", "ISLCHK", 1),
    ZeroDefault("CONTROL_CONTACT", "PENOPT", 1),
    ZeroDefault("CONTROL_CONTACT", "ORIEN", 1),
    ZeroDefault("CONTROL_CONTACT", "RWKSF", 1.0),
    ZeroDefault("CONTROL_CONTACT", "XPENE", 4.0),
    ZeroDefault("CONTACT", "DT", 1e20),
    ZeroDefault("CONTACT", "SFS", 1.0),
    ZeroDefault("CONTACT", "SFM", 1.0),
    ZeroDefault("CONTACT", "SFST", 1.0),
    ZeroDefault("CONTACT", "SFMT", 1.0),
    ZeroDefault("CONTACT", "FSF", 1.0),
    ZeroDefault("CONTACT", "VSF", 1.0),
    ZeroDefault("CONTACT", "SOFSCL", 0.1),
    ZeroDefault("CONTACT", "MAXPAR", 1.025),
    ZeroDefault("CONTACT", "SBOPT", 2),
    ZeroDefault("CONTACT", "DEPTH", 2),
    ZeroDefault("CONTACT", "FRCFRQ", 1),
    ZeroDefault("CONTACT", "IGAP", 1),
    ZeroDefault("SECTION_SHELL", "ELFORM", 2),
    ZeroDefault("SECTION_SHELL", "SHRF", 1.0),
    ZeroDefault("SECTION_SHELL", "NIP", 2),
    ZeroDefault("SECTION_SHELL", "PROPT", 1.0),
    ZeroDefault("SECTION_SHELL", "SETYP", 1),
    ZeroDefault("HOURGLASS", "IHQ", 1),
    ZeroDefault("HOURGLASS", "QM", 0.1),
    ZeroDefault("HOURGLASS", "Q1", 1.5),
    ZeroDefault("HOURGLASS", "Q2", 0.06),
    ZeroDefault("HOURGLASS", "QB/VDC", 0.1),
    ZeroDefault("HOURGLASS", "QW", 0.1),
    ZeroDefault("CONTROL_HOURGLASS", "IHQ", 1),
    ZeroDefault("CONTROL_HOURGLASS", "QH", 0.1),
    ZeroDefault("CONTROL_TIMESTEP", "TSSFAC", 0.9),
    ZeroDefault("CONTROL_TERMINATION", "ENDMAS", 1e8),
    ZeroDefault("DEFINE_CURVE", "SFA", 1.0),
    ZeroDefault("DEFINE_CURVE", "SFO", 1.0),
    ZeroDefault("BOUNDARY_PRESCRIBED_MOTION", "DEATH", 1e28),
    ZeroDefault("PART_CONTACT", "SFT", 1.0),
    ZeroDefault("PART_CONTACT", "SSF", 1.0),
)

# keywords by the table's name, longest first, so that CONTROL_CONTACT is not taken for CONTACT
_FAMILIES = sorted({z.keyword for z in ZERO_MEANS_DEFAULT}, key=len, reverse=True)
_BY_FAMILY: dict[str, dict[str, Value]] = {}
for _zero in ZERO_MEANS_DEFAULT:
    _BY_FAMILY.setdefault(_zero.keyword, {})[_zero.field] = _zero.default


def family(keyword: str) -> str | None:
    """The table's name for a keyword (``CONTACT_AUTOMATIC_SINGLE_SURFACE_ID`` -> ``CONTACT``), or None."""
    for name in _FAMILIES:
        if keyword == name or keyword.startswith(name + "_"):
            return name
    return None


def zero_defaults(keyword: str) -> dict[str, Value]:
    """The fields of ``keyword`` whose 0 means the default, with the defaults."""
    name = family(keyword)
    return _BY_FAMILY.get(name, {}) if name else {}


def apply_zero_defaults(keyword: str, values: dict[str, Value]) -> None:
    """Replace, in one card's ``values``, each 0 that means the default by the default."""
    for name, default in zero_defaults(keyword).items():
        if name in values and values[name] == 0:
            values[name] = default
