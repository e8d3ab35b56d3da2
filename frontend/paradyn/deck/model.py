"""The deck model: every array of ``deck.h5`` as numpy arrays, and the ``/control`` values.

:class:`Model` holds the deck's arrays with the deck's shapes (0-based indices), the control values
(:class:`Control`) and the names the frontend uses in its outputs; missing optional arrays get the
schema's defaults. Writing and reading are in :mod:`paradyn.deck.files`,
validating in :mod:`paradyn.deck.validation`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from paradyn._schema import CONTROL, DATASETS, EFFECT_SWITCHES, ENUM_TRAITS, ENUMS
from paradyn.deck.fields import DeckFields

CONTROL_BY_NAME = {a.name: a for a in CONTROL}
DATASET_BY_ATTRIBUTE = {d.python: d for d in DATASETS}

ELASTIC = ENUMS["material_model"]["elastic"]
J2_PLASTICITY = ENUMS["material_model"]["j2_plasticity"]
HOURGLASS_VISCOUS = ENUMS["hourglass_form"]["viscous"]
HOURGLASS_STIFFNESS = ENUMS["hourglass_form"]["stiffness"]
# /control partition: how elements are given to MPI ranks (docs/formats.md); codes as the engine's
PARTITIONS = dict(ENUMS["partition"])
DEFAULT_PARTITION = str(CONTROL_BY_NAME["partition"].default)   # what the engine uses when the attribute is absent
# /control effect_<switch> = "on" | "off": the scene's [effects] switches (schema/effects.toml)
SWITCH_ATTRIBUTES = {f"effect_{switch}": switch for switch in EFFECT_SWITCHES}


def trait_codes(enum: str, trait: str) -> list[int]:
    """The codes of the members of ``enum`` that carry ``trait`` (schema/deck.toml ``traits``)."""
    return [ENUMS[enum][name] for name in ENUM_TRAITS[enum][trait]]


def control_default(name: str) -> float | str | None:
    """The deck's default of a /control attribute (None where it has none or derives it)."""
    return CONTROL_BY_NAME[name].default


def _number_default(name: str) -> float:
    value = control_default(name)
    if not isinstance(value, (int, float)):
        raise TypeError(f"schema/deck.toml gives /control attribute {name} no numeric default")
    return float(value)


@dataclass
class Control:
    """Attributes of the ``/control`` group; ``None`` leaves an optional attribute out (engine default)."""

    end_time: float
    output_interval: float
    history_interval: float | None = None   # None: the engine uses output_interval / 10
    time_step: float = _number_default("time_step")
    time_step_safety: float = _number_default("time_step_safety")
    mass_damping: float = _number_default("mass_damping")
    progress_interval: float = _number_default("progress_interval")
    contact_sort_interval: float = _number_default("contact_sort_interval")
    checkpoint_interval: float = _number_default("checkpoint_interval")
    partition: str | None = None   # "blocks" or "rcb"; None leaves it to the engine (DEFAULT_PARTITION)
    contact_gather: str | None = None   # "near" or "all"; None leaves it to the engine ("near")
    precision: str | None = None   # "double" or "mixed" (the engine that runs it); None: double, attribute left out
    # [effects] switches, switch name -> "on" or "off" (/control effect_<switch>); absent = "on"
    effect_switches: dict[str, str] = field(default_factory=dict)
    gravity_x: float = _number_default("gravity_x")   # body acceleration m/s^2 (scene [run] gravity)
    gravity_y: float = _number_default("gravity_y")
    gravity_z: float = _number_default("gravity_z")
    energy_error_limit: float = _number_default("energy_error_limit")   # stop past this balance error, 0 = never
    time_step_floor: float = _number_default("time_step_floor")   # stop below this fraction of the first step
    contact_travel_limit: float = _number_default("contact_travel_limit")   # most travel per step / wall, 0 = off
    contact_closing_limit: float = _number_default("contact_closing_limit")   # near pairs' closing per step / wall
    mass_scaling_step: float = _number_default("mass_scaling_step")   # least step wanted (s), 0 = no mass scaling
    mass_scaling_limit: float = _number_default("mass_scaling_limit")   # most added mass, fraction of the model's

    REQUIRED = tuple(a.name for a in CONTROL if a.required)
    OPTIONAL = tuple(a.name for a in CONTROL if not a.required and a.type == "float")
    STRINGS = tuple(a.name for a in CONTROL if a.type == "string" and a.name not in SWITCH_ATTRIBUTES)

    def value(self, name: str) -> float | str | None:
        """The value of /control attribute ``name`` (an effect switch from ``effect_switches``)."""
        if name in SWITCH_ATTRIBUTES:
            return self.effect_switches.get(SWITCH_ATTRIBUTES[name])
        return getattr(self, name)


@dataclass(kw_only=True)
class Model(DeckFields):
    """Everything a deck holds: the datasets (:class:`paradyn.deck.fields.DeckFields`, one field
    per dataset of the schema, generated), the ``/control`` values and the names of things.
    Array shapes follow docs/formats.md; indices are 0-based.

    Optional node arrays left as ``None`` are filled with the format's defaults (zeros) when the
    coordinates are known; the plastic materials' data (``yield_stress``, ...) may stay ``None``
    when no material is plastic. The optional tables (loads, contacts, walls, ...) default to none.
    """

    control: Control
    title: str = ""
    part_names: list[str] = field(default_factory=list)
    material_names: list[str] = field(default_factory=list)
    tracked_names: list[str] = field(default_factory=list)
    #: the arrays _fill_defaults made, by name: filled again when their table has grown since
    _defaulted: dict[str, np.ndarray] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.normalise()

    def normalise(self) -> None:
        """Turn array-likes into numpy arrays (ints to float64 for real fields) and fill defaults."""
        for spec in DATASETS:
            value = getattr(self, spec.python)
            if value is not None:
                setattr(self, spec.python, _as_array(value, spec.type))
        self._fill_defaults()

    def _fill_defaults(self) -> None:
        """Absent optional arrays get the schema's default once their row count is known (one this
        made before its table grew, as a model built empty and filled later has, is made again;
        an array given with the wrong rows stays, for validation to refuse).

        Arrays required under a condition (the J2 data) stay ``None`` so that validation can
        tell whether they were given."""
        for spec in DATASETS:
            if spec.required or spec.default is None or spec.required_when is not None:
                continue
            rows = getattr(self, spec.shape[0])
            value = getattr(self, spec.python)
            grown = value is not None and rows is not None and len(value) != rows
            if grown and value is self._defaulted.get(spec.python):
                value = None
            if rows is not None and value is None:
                dtype = np.int32 if spec.type == "int" else np.float64
                filled = np.full((rows, *spec.shape[1:]), spec.default, dtype=dtype)
                setattr(self, spec.python, filled)
                self._defaulted[spec.python] = filled

    @property
    def n_nodes(self) -> int | None:
        c = self.coordinates
        return int(c.shape[0]) if c.ndim == 2 else None

    @property
    def n_elements(self) -> int | None:
        c = self.connectivity
        return int(c.shape[0]) if c.ndim >= 1 else None

    @property
    def n_parts(self) -> int | None:
        t = self.thickness
        return int(t.shape[0]) if t.ndim == 1 else None

    @property
    def n_materials(self) -> int | None:
        m = self.material_model
        return int(m.shape[0]) if m.ndim == 1 else None

    @property
    def gravity(self) -> tuple[float, float, float]:
        c = self.control
        return (float(c.gravity_x), float(c.gravity_y), float(c.gravity_z))

    @property
    def uses_plasticity(self) -> bool:
        return bool(np.any(np.isin(np.asarray(self.material_model), trait_codes("material_model", "plastic"))))


def _as_array(value: object, kind: str) -> np.ndarray:
    """numpy array; integers and booleans become float64 for real fields, booleans int32 for integer ones.

    Floats are never rounded into integer fields: validation rejects them instead.
    """
    array = np.asarray(value)
    if kind == "float" and array.dtype.kind in "biu":
        return array.astype(np.float64)
    if kind == "int" and array.dtype.kind == "b":
        return array.astype(np.int32)
    return array
