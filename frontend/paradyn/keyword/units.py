"""Units of an LS-DYNA keyword deck: LS-DYNA has none, ParaDyn is SI (docs/keyword.md, Units).

A deck states its units with ``*CONTROL_UNITS`` (LENGTH, TIME, MASS), or the caller names a
system (``units="mm-t-s"``); without either the numbers are taken as SI and a warning says so.
:class:`Units` holds the factors that turn the deck's length, time and mass into metres, seconds
and kilograms; every other quantity follows from them.
"""

from __future__ import annotations

from dataclasses import dataclass

LENGTHS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2}
TIMES = {"sec": 1.0, "s": 1.0, "ms": 1e-3, "micro_s": 1e-6}
MASSES = {"kg": 1.0, "g": 1e-3, "mtrc_ton": 1e3, "t": 1e3}
SYSTEMS = {                        # name -> (length, time, mass) as *CONTROL_UNITS spells them
    "SI": ("m", "sec", "kg"),
    "mm-t-s": ("mm", "sec", "mtrc_ton"),     # N, MPa
    "mm-kg-ms": ("mm", "ms", "kg"),          # kN, GPa
    "mm-g-ms": ("mm", "ms", "g"),            # N, MPa
}
_FORCE_NAMES = {"SI": "N, Pa", "mm-t-s": "N, MPa", "mm-kg-ms": "kN, GPa", "mm-g-ms": "N, MPa"}


class UnitsError(ValueError):
    """A unit name ParaDyn does not convert."""


@dataclass(frozen=True)
class Units:
    """Factors from the deck's units to SI: a deck length times ``length`` is metres, and so on."""

    length_name: str
    time_name: str
    mass_name: str

    @classmethod
    def named(cls, system: str) -> Units:
        if system not in SYSTEMS:
            raise UnitsError(f"units = '{system}' is unknown; use one of {', '.join(SYSTEMS)}")
        return cls(*SYSTEMS[system])

    @classmethod
    def of(cls, length: str, time: str, mass: str) -> Units:
        for value, table, what in ((length, LENGTHS, "LENGTH"), (time, TIMES, "TIME"), (mass, MASSES, "MASS")):
            if value.lower() not in table:
                raise UnitsError(f"*CONTROL_UNITS {what} = '{value}' is not converted; use one of "
                                 f"{', '.join(table)}")
        return cls(length.lower(), time.lower(), mass.lower())

    @property
    def length(self) -> float:
        return LENGTHS[self.length_name]

    @property
    def time(self) -> float:
        return TIMES[self.time_name]

    @property
    def mass(self) -> float:
        return MASSES[self.mass_name]

    @property
    def velocity(self) -> float:
        return self.length / self.time

    @property
    def density(self) -> float:
        return self.mass / self.length**3

    @property
    def force(self) -> float:
        return self.mass * self.length / self.time**2

    @property
    def stress(self) -> float:
        return self.mass / (self.length * self.time**2)

    @property
    def system(self) -> str | None:
        """The system's name when the units are one of :data:`SYSTEMS` (``None`` otherwise)."""
        own = (self.length_name, "sec" if self.time_name == "s" else self.time_name,
               "mtrc_ton" if self.mass_name == "t" else self.mass_name)
        return next((name for name, units in SYSTEMS.items() if units == own), None)

    def describe(self) -> str:
        system = self.system
        base = f"length {self.length_name}, time {self.time_name}, mass {self.mass_name}"
        return f"{system} ({base}; {_FORCE_NAMES[system]})" if system else base
