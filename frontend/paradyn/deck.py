"""The ParaDyn deck (``deck.h5``, format version 1 of ``docs/formats.md``): model, writer, reader, validator.

:class:`Model` holds every array of the deck as numpy arrays with the deck's shapes (0-based indices),
the control values (:class:`Control`) and the names the frontend uses in its outputs.
:func:`write_deck` validates and writes atomically; :func:`read_deck` reads and validates;
:func:`validate_deck` only checks a file. Every problem raises :class:`DeckError` with one message
naming the file, the dataset, the offending entry and the fix.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

DECK_VERSION = 1
VERSION_ATTRIBUTE = "paradyn_deck_version"

ELASTIC = 1
J2_PLASTICITY = 2
HOURGLASS_VISCOUS = 1
HOURGLASS_STIFFNESS = 2
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")
# /control partition: how elements are given to MPI ranks (docs/formats.md); codes as the engine's
PARTITIONS = {"blocks": 1, "rcb": 2}
DEFAULT_PARTITION = "blocks"   # what the engine uses when the attribute is absent (docs/performance.md)


class DeckError(ValueError):
    """A deck (file or in-memory model) that breaks the format of docs/formats.md."""


@dataclass
class Control:
    """Attributes of the ``/control`` group; ``None`` leaves an optional attribute out (engine default)."""

    end_time: float
    output_interval: float
    history_interval: float | None = None
    time_step: float = 0.0
    time_step_safety: float = 0.9
    mass_damping: float = 0.0
    progress_interval: float = 0.5
    contact_sort_interval: float = 0.0
    checkpoint_interval: float = 0.0
    partition: str | None = None   # "blocks" or "rcb"; None leaves it to the engine (DEFAULT_PARTITION)

    REQUIRED = ("end_time", "output_interval")
    OPTIONAL = ("history_interval", "time_step", "time_step_safety", "mass_damping", "progress_interval",
                "contact_sort_interval", "checkpoint_interval")
    STRINGS = ("partition",)


def _empty_int() -> np.ndarray:
    return np.zeros(0, dtype=np.int32)


def _empty_float() -> np.ndarray:
    return np.zeros(0, dtype=np.float64)


@dataclass
class Model:
    """Everything a deck holds. Array shapes follow docs/formats.md; indices are 0-based.

    Optional node arrays left as ``None`` are filled with the format's defaults (zeros) when the
    coordinates are known; ``yield_stress``, ``tangent_modulus`` and ``hardening_mixing`` may stay
    ``None`` when no material uses model 2. Loads and tracked nodes default to none.
    """

    coordinates: np.ndarray                     # /nodes/coordinates (n_nodes, 3) m
    connectivity: np.ndarray                    # /elements/connectivity (n_elements, 4)
    element_part: np.ndarray                    # /elements/part (n_elements,)
    thickness: np.ndarray                       # /parts/thickness (n_parts,) m
    part_material: np.ndarray                   # /parts/material (n_parts,)
    material_model: np.ndarray                  # /materials/model (n_materials,) 1 elastic, 2 J2
    density: np.ndarray                         # /materials/density kg/m^3
    youngs_modulus: np.ndarray                  # /materials/youngs_modulus Pa
    poisson_ratio: np.ndarray                   # /materials/poisson_ratio
    control: Control
    initial_velocity: np.ndarray | None = None            # /nodes/initial_velocity (n_nodes, 3)
    initial_angular_velocity: np.ndarray | None = None    # /nodes/initial_angular_velocity (n_nodes, 3)
    fixed_dofs: np.ndarray | None = None                  # /nodes/fixed_dofs (n_nodes, 6) 0/1
    integration_points: np.ndarray | None = None          # /parts/integration_points, default 5
    hourglass_coefficient: np.ndarray | None = None       # /parts/hourglass_coefficient, default 0.1
    hourglass_form: np.ndarray | None = None              # /parts/hourglass_form, 1 viscous, 2 stiffness (default)
    yield_stress: np.ndarray | None = None                # /materials/yield_stress Pa
    tangent_modulus: np.ndarray | None = None             # /materials/tangent_modulus Pa
    hardening_mixing: np.ndarray | None = None            # /materials/hardening_mixing
    load_node: np.ndarray = field(default_factory=_empty_int)       # /loads/node
    load_dof: np.ndarray = field(default_factory=_empty_int)        # /loads/dof, 1..6
    load_value: np.ndarray = field(default_factory=_empty_float)    # /loads/value N or N m
    load_ramp_time: np.ndarray = field(default_factory=_empty_float)  # /loads/ramp_time s
    tracked_nodes: np.ndarray = field(default_factory=_empty_int)   # /output/tracked_nodes
    contact_pairs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int32))  # /contact/pairs
    contact_penalty_scale: np.ndarray = field(default_factory=_empty_float)     # /contact/penalty_scale
    contact_static_friction: np.ndarray = field(default_factory=_empty_float)   # /contact/static_friction
    contact_dynamic_friction: np.ndarray = field(default_factory=_empty_float)  # /contact/dynamic_friction
    contact_friction_decay: np.ndarray = field(default_factory=_empty_float)    # /contact/friction_decay s/m
    contact_passes: np.ndarray = field(default_factory=_empty_int)  # /contact/passes: 2 both, 1 alternate
    title: str = ""
    part_names: list[str] = field(default_factory=list)
    material_names: list[str] = field(default_factory=list)
    tracked_names: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.normalise()

    def normalise(self) -> None:
        """Turn array-likes into numpy arrays (ints to float64 for real fields) and fill defaults."""
        for spec in _DATASETS:
            value = getattr(self, spec.attribute)
            if value is not None:
                setattr(self, spec.attribute, _as_array(value, spec.kind))
        self._fill_defaults()

    def _fill_defaults(self) -> None:
        n_nodes = self.n_nodes
        if n_nodes is not None:
            if self.initial_velocity is None:
                self.initial_velocity = np.zeros((n_nodes, 3))
            if self.initial_angular_velocity is None:
                self.initial_angular_velocity = np.zeros((n_nodes, 3))
            if self.fixed_dofs is None:
                self.fixed_dofs = np.zeros((n_nodes, 6), dtype=np.int32)
        n_parts = self.n_parts
        if n_parts is not None:
            if self.integration_points is None:
                self.integration_points = np.full(n_parts, 5, dtype=np.int32)
            if self.hourglass_coefficient is None:
                self.hourglass_coefficient = np.full(n_parts, 0.1)
            if self.hourglass_form is None:
                self.hourglass_form = np.full(n_parts, HOURGLASS_STIFFNESS, dtype=np.int32)
        n_contacts = self.n_contacts
        for attribute, default in (("contact_penalty_scale", 0.1), ("contact_static_friction", 0.0),
                                   ("contact_dynamic_friction", 0.0), ("contact_friction_decay", 0.0),
                                   ("contact_passes", 2)):
            if np.size(getattr(self, attribute)) == 0 and n_contacts > 0:
                setattr(self, attribute, np.full(n_contacts, default,
                                                 dtype=np.int32 if attribute == "contact_passes" else float))

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
    def n_loads(self) -> int:
        return int(np.size(self.load_node))

    @property
    def n_tracked(self) -> int:
        return int(np.size(self.tracked_nodes))

    @property
    def n_contacts(self) -> int:
        pairs = np.asarray(self.contact_pairs)
        return int(pairs.shape[0]) if pairs.ndim == 2 else int(pairs.size)

    @property
    def uses_plasticity(self) -> bool:
        return bool(np.any(np.asarray(self.material_model) == J2_PLASTICITY))


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


# ----------------------------------------------------------------------------------------------
# the dataset table: model attribute, dataset path, kind, symbolic shape, required


@dataclass(frozen=True)
class _Dataset:
    attribute: str
    path: str
    kind: str                     # "int" or "float"
    shape: tuple[str | int, ...]  # symbolic dimensions
    required: bool


_DATASETS = (
    _Dataset("coordinates", "/nodes/coordinates", "float", ("n_nodes", 3), True),
    _Dataset("initial_velocity", "/nodes/initial_velocity", "float", ("n_nodes", 3), False),
    _Dataset("initial_angular_velocity", "/nodes/initial_angular_velocity", "float", ("n_nodes", 3), False),
    _Dataset("fixed_dofs", "/nodes/fixed_dofs", "int", ("n_nodes", 6), False),
    _Dataset("connectivity", "/elements/connectivity", "int", ("n_elements", 4), True),
    _Dataset("element_part", "/elements/part", "int", ("n_elements",), True),
    _Dataset("thickness", "/parts/thickness", "float", ("n_parts",), True),
    _Dataset("part_material", "/parts/material", "int", ("n_parts",), True),
    _Dataset("integration_points", "/parts/integration_points", "int", ("n_parts",), False),
    _Dataset("hourglass_coefficient", "/parts/hourglass_coefficient", "float", ("n_parts",), False),
    _Dataset("hourglass_form", "/parts/hourglass_form", "int", ("n_parts",), False),
    _Dataset("material_model", "/materials/model", "int", ("n_materials",), True),
    _Dataset("density", "/materials/density", "float", ("n_materials",), True),
    _Dataset("youngs_modulus", "/materials/youngs_modulus", "float", ("n_materials",), True),
    _Dataset("poisson_ratio", "/materials/poisson_ratio", "float", ("n_materials",), True),
    _Dataset("yield_stress", "/materials/yield_stress", "float", ("n_materials",), False),
    _Dataset("tangent_modulus", "/materials/tangent_modulus", "float", ("n_materials",), False),
    _Dataset("hardening_mixing", "/materials/hardening_mixing", "float", ("n_materials",), False),
    _Dataset("load_node", "/loads/node", "int", ("n_loads",), False),
    _Dataset("load_dof", "/loads/dof", "int", ("n_loads",), False),
    _Dataset("load_value", "/loads/value", "float", ("n_loads",), False),
    _Dataset("load_ramp_time", "/loads/ramp_time", "float", ("n_loads",), False),
    _Dataset("tracked_nodes", "/output/tracked_nodes", "int", ("n_tracked",), False),
    _Dataset("contact_pairs", "/contact/pairs", "int", ("n_contacts", 2), False),
    _Dataset("contact_penalty_scale", "/contact/penalty_scale", "float", ("n_contacts",), False),
    _Dataset("contact_static_friction", "/contact/static_friction", "float", ("n_contacts",), False),
    _Dataset("contact_dynamic_friction", "/contact/dynamic_friction", "float", ("n_contacts",), False),
    _Dataset("contact_friction_decay", "/contact/friction_decay", "float", ("n_contacts",), False),
    _Dataset("contact_passes", "/contact/passes", "int", ("n_contacts",), False),
)
_BY_ATTRIBUTE = {d.attribute: d for d in _DATASETS}
_PLASTICITY_FIELDS = ("yield_stress", "tangent_modulus", "hardening_mixing")
_LOAD_FIELDS = ("load_node", "load_dof", "load_value", "load_ramp_time")
_CONTACT_FIELDS = ("contact_pairs", "contact_penalty_scale", "contact_static_friction",
                   "contact_dynamic_friction", "contact_friction_decay", "contact_passes")
_NAME_ATTRIBUTES = (("part_names", "/parts", "n_parts"), ("material_names", "/materials", "n_materials"),
                    ("tracked_names", "/output", "n_tracked"))
_NAME_ATTRIBUTE_KEY = {"part_names": "names", "material_names": "names", "tracked_names": "tracked_names"}


# ----------------------------------------------------------------------------------------------
# validation


class _Checker:
    """Checks a model and raises DeckError with messages prefixed by the source (file or 'model')."""

    def __init__(self, model: Model, source: str) -> None:
        self.model = model
        self.source = source

    def fail(self, message: str) -> None:
        raise DeckError(f"{self.source}: {message}")

    def array(self, attribute: str) -> np.ndarray:
        return np.asarray(getattr(self.model, attribute))

    # -- structure ---------------------------------------------------------------------------

    def dtype(self, attribute: str) -> None:
        spec = _BY_ATTRIBUTE[attribute]
        kind = self.array(attribute).dtype.kind
        if spec.kind == "int" and kind not in "iu":
            self.fail(f"{spec.path} has dtype {self.array(attribute).dtype}, must be an integer type; "
                      f"write it with an integer dtype such as int32")
        if spec.kind == "float" and kind != "f":
            self.fail(f"{spec.path} has dtype {self.array(attribute).dtype}, must be floating point; "
                      f"write it with dtype float64")

    def shape(self, attribute: str, sizes: dict[str, int]) -> None:
        spec = _BY_ATTRIBUTE[attribute]
        actual = self.array(attribute).shape
        expected = tuple(sizes[d] if isinstance(d, str) else d for d in spec.shape)
        if actual != expected:
            symbolic = ", ".join(str(d) for d in spec.shape) + ("," if len(spec.shape) == 1 else "")
            self.fail(f"{spec.path} has shape {actual}, expected ({symbolic}) = {expected}; "
                      f"every array must have one row per {_row_meaning(spec.shape[0])}")

    def sizes(self) -> dict[str, int]:
        m = self.model
        for attribute, what, columns in (("coordinates", "node", 3), ("connectivity", "element", 4)):
            spec = _BY_ATTRIBUTE[attribute]
            a = self.array(attribute)
            if a.ndim != 2 or a.shape[1] != columns or a.shape[0] == 0:
                self.fail(f"{spec.path} has shape {a.shape}, expected (n_{what}s, {columns}) with at "
                          f"least one {what}")
        for attribute, what in (("thickness", "part"), ("material_model", "material")):
            spec = _BY_ATTRIBUTE[attribute]
            a = self.array(attribute)
            if a.ndim != 1 or a.shape[0] == 0:
                self.fail(f"{spec.path} has shape {a.shape}, expected (n_{what}s,) with at least "
                          f"one {what}")
        return {"n_nodes": m.n_nodes, "n_elements": m.n_elements, "n_parts": m.n_parts,
                "n_materials": m.n_materials, "n_loads": m.n_loads, "n_tracked": m.n_tracked, "n_contacts": m.n_contacts}

    # -- values ------------------------------------------------------------------------------

    def entries(self, attribute: str, bad: np.ndarray, rule: str, fix: str) -> None:
        """Fail on the first entry where ``bad`` is true, naming index, value and count."""
        if not np.any(bad):
            return
        spec = _BY_ATTRIBUTE[attribute]
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        value = self.array(attribute)[index]
        where = ", ".join(str(i) for i in index)
        more = int(np.count_nonzero(bad)) - 1
        extra = f" ({more} more entries too)" if more > 0 else ""
        self.fail(f"{spec.path}[{where}] = {_fmt(value)} {rule}{extra}; {fix}")

    def finite(self, attribute: str, fix: str) -> None:
        self.entries(attribute, ~np.isfinite(self.array(attribute)), "must be finite", fix)

    def index_range(self, attribute: str, upper: int, what: str) -> None:
        a = self.array(attribute)
        self.entries(attribute, (a < 0) | (a >= upper),
                     f"is out of range 0..{upper - 1}",
                     f"{what} indices are 0-based and must be below the number of {what}s ({upper})")


def _row_meaning(dimension: str | int) -> str:
    return {"n_nodes": "node", "n_elements": "element", "n_parts": "part", "n_materials": "material",
            "n_loads": "load", "n_tracked": "tracked node"}.get(str(dimension), str(dimension))


def _fmt(value: object) -> str:
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, np.ndarray):
        return np.array2string(value, precision=6)
    return str(value)


def validate_model(model: Model, source: str = "model") -> None:
    """Check a model against every rule of docs/formats.md; raise DeckError on the first problem."""
    model.normalise()
    check = _Checker(model, source)
    sizes = check.sizes()
    _check_presence(check)
    for spec in _DATASETS:
        if getattr(model, spec.attribute) is not None:
            check.dtype(spec.attribute)
            check.shape(spec.attribute, sizes)
    _check_nodes(check, sizes)
    _check_elements(check, sizes)
    _check_parts(check, sizes)
    _check_materials(check)
    _check_loads(check, sizes)
    _check_contacts(check, sizes)
    check.index_range("tracked_nodes", sizes["n_nodes"], "node")
    _check_names(check, sizes)
    _check_control(check)


def _check_presence(check: _Checker) -> None:
    model = check.model
    if model.uses_plasticity:
        for attribute in _PLASTICITY_FIELDS:
            if getattr(model, attribute) is None:
                first = int(np.flatnonzero(np.asarray(model.material_model) == J2_PLASTICITY)[0])
                check.fail(f"{_BY_ATTRIBUTE[attribute].path} is missing but /materials/model[{first}] = 2 "
                           f"(J2 plasticity); give yield_stress, tangent_modulus and hardening_mixing for "
                           f"every material")


def _check_nodes(check: _Checker, sizes: dict[str, int]) -> None:
    check.finite("coordinates", "give every node a finite position in metres")
    check.finite("initial_velocity", "give finite initial velocities in m/s")
    check.finite("initial_angular_velocity", "give finite initial angular velocities in rad/s")
    fixed = check.array("fixed_dofs")
    check.entries("fixed_dofs", (fixed != 0) & (fixed != 1), "must be 0 or 1",
                  "use 1 to fix a dof and 0 to leave it free")


def _check_elements(check: _Checker, sizes: dict[str, int]) -> None:
    check.index_range("connectivity", sizes["n_nodes"], "node")
    conn = np.sort(check.array("connectivity"), axis=1)
    repeated = np.any(conn[:, 1:] == conn[:, :-1], axis=1)
    if np.any(repeated):
        element = int(np.flatnonzero(repeated)[0])
        nodes = check.array("connectivity")[element].tolist()
        check.fail(f"/elements/connectivity[{element}] = {nodes} repeats a node; every quadrilateral "
                   f"needs four distinct nodes (remesh without collapsed elements)")
    used = np.zeros(sizes["n_nodes"], dtype=bool)
    used[check.array("connectivity").ravel()] = True
    if not np.all(used):
        unused = np.flatnonzero(~used)
        check.fail(f"/nodes/coordinates[{int(unused[0])}] belongs to no element ({unused.size} such nodes); "
                   f"a node without elements has no mass, remove unused nodes")
    check.index_range("element_part", sizes["n_parts"], "part")


def _check_parts(check: _Checker, sizes: dict[str, int]) -> None:
    t = check.array("thickness")
    check.entries("thickness", ~(np.isfinite(t) & (t > 0)), "must be > 0",
                  "set a positive shell thickness in metres")
    check.index_range("part_material", sizes["n_materials"], "material")
    ip = check.array("integration_points")
    check.entries("integration_points", (ip < 1) | (ip > 9), "must be between 1 and 9",
                  "choose 1 to 9 Gauss points through the thickness (5 is usual)")
    hg = check.array("hourglass_coefficient")
    check.entries("hourglass_coefficient", ~(np.isfinite(hg) & (hg >= 0)), "must be >= 0",
                  "use a small non-negative coefficient such as 0.1")
    form = check.array("hourglass_form")
    check.entries("hourglass_form", (form != HOURGLASS_VISCOUS) & (form != HOURGLASS_STIFFNESS),
                  "is unknown", "use 1 (viscous) or 2 (stiffness)")


def _check_materials(check: _Checker) -> None:
    model = check.array("material_model")
    check.entries("material_model", (model != ELASTIC) & (model != J2_PLASTICITY), "must be 1 or 2",
                  "use 1 for linear elastic or 2 for J2 plasticity")
    rho = check.array("density")
    check.entries("density", ~(np.isfinite(rho) & (rho > 0)), "must be > 0", "give the density in kg/m^3")
    e = check.array("youngs_modulus")
    check.entries("youngs_modulus", ~(np.isfinite(e) & (e > 0)), "must be > 0",
                  "give Young's modulus in Pa (200e9 for steel)")
    nu = check.array("poisson_ratio")
    check.entries("poisson_ratio", ~(np.isfinite(nu) & (nu > -1) & (nu < 0.5)),
                  "must satisfy -1 < nu < 0.5", "give a Poisson ratio such as 0.3")
    if not check.model.uses_plasticity:
        return
    plastic = model == J2_PLASTICITY
    sy = check.array("yield_stress")
    check.entries("yield_stress", plastic & ~(np.isfinite(sy) & (sy > 0)), "must be > 0 for a model 2 material",
                  "give the initial yield stress in Pa")
    et = check.array("tangent_modulus")
    check.entries("tangent_modulus", plastic & ~(np.isfinite(et) & (et >= 0) & (et < e)),
                  "must satisfy 0 <= Et < E for a model 2 material",
                  "give the plastic tangent modulus in Pa below Young's modulus (0 = perfectly plastic)")
    beta = check.array("hardening_mixing")
    check.entries("hardening_mixing", plastic & ~(np.isfinite(beta) & (beta >= 0) & (beta <= 1)),
                  "must be in [0, 1] for a model 2 material",
                  "use 1 for isotropic, 0 for kinematic hardening or a mix in between")


def _check_loads(check: _Checker, sizes: dict[str, int]) -> None:
    if sizes["n_loads"] == 0:
        return
    check.index_range("load_node", sizes["n_nodes"], "node")
    dof = check.array("load_dof")
    check.entries("load_dof", (dof < 1) | (dof > 6), "must be between 1 and 6",
                  "use 1..3 for a force along x, y, z and 4..6 for a moment about x, y, z")
    check.finite("load_value", "give the final load value in N or N m")
    ramp = check.array("load_ramp_time")
    check.entries("load_ramp_time", ~(np.isfinite(ramp) & (ramp >= 0)), "must be >= 0",
                  "give the ramp time in seconds (0 applies the load at once)")


def _check_contacts(check: _Checker, sizes: dict[str, int]) -> None:
    if sizes["n_contacts"] == 0:
        return
    check.index_range("contact_pairs", sizes["n_parts"], "part")
    pairs = check.array("contact_pairs")
    check.entries("contact_pairs", pairs[:, 0] == pairs[:, 1], "pairs a part with itself",
                  "name two different parts (self-contact is not modelled)")
    scale = check.array("contact_penalty_scale")
    check.entries("contact_penalty_scale", ~(np.isfinite(scale) & (scale > 0)), "must be > 0",
                  "use a penalty scale factor such as 0.1 (the default)")
    for name in ("contact_static_friction", "contact_dynamic_friction", "contact_friction_decay"):
        mu = check.array(name)
        check.entries(name, ~(np.isfinite(mu) & (mu >= 0)), "must be >= 0", "give a Coulomb coefficient >= 0")
    passes = check.array("contact_passes")
    check.entries("contact_passes", (passes != 1) & (passes != 2), "must be 1 or 2",
                  "use 2 (both bodies slave every step) or 1 (slave and master swap every step)")


def _check_names(check: _Checker, sizes: dict[str, int]) -> None:
    for attribute, group, size_key in _NAME_ATTRIBUTES:
        names = getattr(check.model, attribute)
        if names and len(names) != sizes[size_key]:
            key = _NAME_ATTRIBUTE_KEY[attribute]
            check.fail(f"attribute {key} on {group} has {len(names)} names but there are "
                       f"{sizes[size_key]} {_row_meaning(size_key)}s; give one name each")


def _check_control(check: _Checker) -> None:
    control = check.model.control
    rules: dict[str, tuple[Callable[[float], bool], str]] = {
        "end_time": (lambda v: v > 0, "must be > 0"),
        "output_interval": (lambda v: v > 0, "must be > 0"),
        "history_interval": (lambda v: v > 0, "must be > 0"),
        "time_step": (lambda v: v >= 0, "must be >= 0 (0 = automatic)"),
        "time_step_safety": (lambda v: 0 < v <= 1, "must be in (0, 1]"),
        "mass_damping": (lambda v: v >= 0, "must be >= 0"),
        "progress_interval": (lambda v: v > 0, "must be > 0"),
        "contact_sort_interval": (lambda v: v >= 0, "must be >= 0 cycles (0 = automatic)"),
        "checkpoint_interval": (lambda v: v >= 0, "must be >= 0 (0 = no checkpoints)"),
    }
    for name, (ok, rule) in rules.items():
        value = getattr(control, name)
        if value is None:
            if name in Control.REQUIRED:
                check.fail(f"/control attribute {name} is missing; set it in seconds (> 0)")
            continue
        try:
            number = float(value)
        except (TypeError, ValueError):
            check.fail(f"/control attribute {name} = {value!r} is not a number; give a real value")
        if not np.isfinite(number) or not ok(number):
            check.fail(f"/control attribute {name} = {_fmt(number)} {rule}; fix the [run] settings")
    if control.partition is not None and control.partition not in PARTITIONS:
        check.fail(f"/control attribute partition = {control.partition!r} is unknown; use "
                   f"{' or '.join(repr(p) for p in PARTITIONS)}, or leave it out for the default "
                   f"({DEFAULT_PARTITION!r})")


# ----------------------------------------------------------------------------------------------
# writing


def write_deck(model: Model, path: str | Path) -> Path:
    """Validate ``model`` and write it to ``path`` atomically (temporary file, then rename)."""
    path = Path(path)
    validate_model(model, source=f"{path} (not written)")
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(handle)
    try:
        with h5py.File(temporary, "w") as f:
            _write_contents(f, model)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return path


def _write_contents(f: h5py.File, model: Model) -> None:
    f.attrs[VERSION_ATTRIBUTE] = np.int32(DECK_VERSION)
    if model.title:
        f.attrs["title"] = model.title
    for spec in _DATASETS:
        value = getattr(model, spec.attribute)
        if value is None:
            continue
        if spec.attribute in _LOAD_FIELDS and model.n_loads == 0:
            continue
        if spec.attribute == "tracked_nodes" and model.n_tracked == 0:
            continue
        if spec.attribute in _CONTACT_FIELDS and model.n_contacts == 0:
            continue
        dtype = np.int32 if spec.kind == "int" else np.float64
        f.create_dataset(spec.path, data=np.ascontiguousarray(value, dtype=dtype))
    for attribute, group, _ in _NAME_ATTRIBUTES:
        names = getattr(model, attribute)
        if names:
            f.require_group(group).attrs[_NAME_ATTRIBUTE_KEY[attribute]] = np.array(
                [str(n) for n in names], dtype=h5py.string_dtype())
    control = f.require_group("/control")
    for name in Control.REQUIRED + Control.OPTIONAL:
        value = getattr(model.control, name)
        if value is not None:
            control.attrs[name] = np.float64(value)
    for name in Control.STRINGS:
        value = getattr(model.control, name)
        if value is not None:
            control.attrs[name] = str(value)


# ----------------------------------------------------------------------------------------------
# reading


def read_deck(path: str | Path) -> Model:
    """Read and validate a deck file; raise DeckError naming the dataset on any problem."""
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise DeckError(f"{source}: deck file not found; write it with paradyn.deck.write_deck")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise DeckError(f"{source}: not a readable HDF5 file ({exc}); regenerate the deck") from exc
    with f:
        _check_version(f, source)
        arrays = _read_arrays(f, source)
        names = _read_names(f)
        control = _read_control(f, source)
        title = _decode(f.attrs.get("title", ""))
    model = Model(control=control, title=title, **names, **arrays)
    validate_model(model, source=source)
    _fill_names(model)
    return model


def validate_deck(path: str | Path) -> None:
    """Check a deck file against docs/formats.md; raise DeckError naming the dataset on any problem."""
    read_deck(path)


def _check_version(f: h5py.File, source: str) -> None:
    if VERSION_ATTRIBUTE not in f.attrs:
        raise DeckError(f"{source}: root attribute {VERSION_ATTRIBUTE} is missing; this is not a "
                        f"ParaDyn deck, write it with paradyn.deck.write_deck")
    version = f.attrs[VERSION_ATTRIBUTE]
    if np.ndim(version) != 0 or np.asarray(version).dtype.kind not in "iu" or int(version) != DECK_VERSION:
        shown = version.item() if isinstance(version, np.generic) else version
        raise DeckError(f"{source}: root attribute {VERSION_ATTRIBUTE} = {shown!r}, this frontend "
                        f"reads version {DECK_VERSION} (an integer); regenerate the deck from its scene")


def _read_arrays(f: h5py.File, source: str) -> dict[str, np.ndarray | None]:
    arrays: dict[str, np.ndarray | None] = {}
    for spec in _DATASETS:
        item = f.get(spec.path)
        if item is None:
            if spec.required:
                raise DeckError(f"{source}: required dataset {spec.path} is missing; see docs/formats.md "
                                f"for the datasets of a deck")
            arrays[spec.attribute] = None
            continue
        if not isinstance(item, h5py.Dataset):
            raise DeckError(f"{source}: {spec.path} is a group, must be a dataset")
        kind = item.dtype.kind
        if (spec.kind == "int" and kind not in "iu") or (spec.kind == "float" and kind != "f"):
            wanted = "an integer type such as int32" if spec.kind == "int" else "floating point (float64)"
            raise DeckError(f"{source}: {spec.path} has dtype {item.dtype}, must be {wanted}; "
                            f"write it with that dtype")
        arrays[spec.attribute] = np.asarray(item[()])
    if "/loads" in f:
        missing = [s.path for s in _DATASETS if s.attribute in _LOAD_FIELDS and arrays[s.attribute] is None]
        if missing:
            raise DeckError(f"{source}: group /loads is present but {missing[0]} is missing; a load needs "
                            f"node, dof, value and ramp_time")
    if "/contact" in f and arrays["contact_pairs"] is None:
        raise DeckError(f"{source}: group /contact is present but /contact/pairs is missing; a contact "
                        f"pair names two parts")
    for attribute in _LOAD_FIELDS + _CONTACT_FIELDS + ("tracked_nodes",):
        if arrays[attribute] is None:
            del arrays[attribute]
    return arrays


def _decode(value: object) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace")
    return str(value)


def _read_names(f: h5py.File) -> dict[str, list[str]]:
    names: dict[str, list[str]] = {}
    for attribute, group, _ in _NAME_ATTRIBUTES:
        key = _NAME_ATTRIBUTE_KEY[attribute]
        if group in f and key in f[group].attrs:
            names[attribute] = [_decode(n) for n in np.atleast_1d(f[group].attrs[key])]
        else:
            names[attribute] = []
    return names


def _read_control(f: h5py.File, source: str) -> Control:
    if "/control" not in f:
        raise DeckError(f"{source}: group /control is missing; it carries end_time and output_interval")
    attrs = f["/control"].attrs
    values: dict[str, float | str | None] = {}
    for name in Control.REQUIRED + Control.OPTIONAL:
        if name not in attrs:
            if name in Control.REQUIRED:
                raise DeckError(f"{source}: /control attribute {name} is missing; set it in seconds (> 0)")
            continue
        raw = attrs[name]
        if np.ndim(raw) != 0 or np.asarray(raw).dtype.kind not in "iuf":
            raise DeckError(f"{source}: /control attribute {name} = {raw!r} must be a real scalar; "
                            f"write it as a float64 attribute")
        values[name] = float(raw)
    for name in Control.STRINGS:
        if name not in attrs:
            continue
        raw = attrs[name]
        if np.ndim(raw) != 0 or not isinstance(raw, (str, bytes)):
            shown = raw.item() if isinstance(raw, np.generic) else raw
            raise DeckError(f"{source}: /control attribute {name} = {shown!r} must be one string; "
                            f"write it as a str attribute")
        values[name] = _decode(raw)
    return Control(**values)  # type: ignore[arg-type]


def _fill_names(model: Model) -> None:
    """Names absent from a file get generic ones (part_0, material_0, node_<index>)."""
    if not model.part_names:
        model.part_names = [f"part_{i}" for i in range(model.n_parts or 0)]
    if not model.material_names:
        model.material_names = [f"material_{i}" for i in range(model.n_materials or 0)]
    if not model.tracked_names:
        model.tracked_names = [f"node_{int(n)}" for n in np.asarray(model.tracked_nodes)]
