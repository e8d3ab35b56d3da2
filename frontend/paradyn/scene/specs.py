"""The scene's data types: what :func:`paradyn.scene.load_scene` returns and :func:`paradyn.scene.build_model` reads.

:class:`Scene` holds the run settings (:data:`RunSettings`, the deck's :class:`deck.Control`), the
materials, the parts with their geometry specs, and the fixes, loads, tracked points, contacts, rigid
walls, load curves, pressures and prescribed velocities; where a key fills a deck dataset its
default is the deck's (schema/deck.toml). :class:`SceneError` is the error of every scene problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from paradyn import _schema, deck
from paradyn.mesh import files as mesh_files
from paradyn.mesh import geometry


class SceneError(ValueError):
    """A scene file that cannot be turned into a model; the message names the file, table and key."""


MATERIAL_MODELS = dict(_schema.ENUMS["material_model"])
HOURGLASS_FORMS = dict(_schema.ENUMS["hourglass_form"])
SHELL_ELEMENTS = dict(_schema.ENUMS["shell_element"])
ROTARY_INERTIAS = dict(_schema.ENUMS["rotary_inertia"])
DOF_GROUPS = {
    "all": deck.DOF_NAMES,
    "translations": deck.DOF_NAMES[:3],
    "rotations": deck.DOF_NAMES[3:],
}
# Where a scene key fills a deck dataset, its default is the deck's (schema/deck.toml); the [run]
# defaults are those of deck.Control, which come from the same schema.
_DECK_DEFAULT = {d.path: d.default for d in _schema.DATASETS}


def _enum_name(enum: str, code: object) -> str:
    """The scene's name of an enum code (the scene says "stiffness" where the deck holds 2)."""
    return next(name for name, value in _schema.ENUMS[enum].items() if value == code)

# ----------------------------------------------------------------------------------------------
# scene dataclasses


# The [run] table maps one to one onto the deck's /control attributes.
RunSettings = deck.Control


@dataclass
class MaterialSpec:
    name: str
    model: str                      # a member of the schema's material_model: "elastic", "j2_plasticity", ...
    density: float
    youngs_modulus: float
    poisson_ratio: float
    yield_stress: float = _DECK_DEFAULT["/materials/yield_stress"]          # j2 only
    tangent_modulus: float = _DECK_DEFAULT["/materials/tangent_modulus"]    # j2 only
    hardening_mixing: float = _DECK_DEFAULT["/materials/hardening_mixing"]  # j2 only
    # the other /materials datasets a model uses (schema/deck.toml), by their python names (a
    # curve's: the [[curve]]'s name, None for none)
    extra: dict[str, float | str | None] = field(default_factory=dict)

    @property
    def model_code(self) -> int:
        return MATERIAL_MODELS[self.model]


@dataclass
class CylinderGeometry:
    radius: float
    length: float
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    center: tuple[float, float, float] = (0.0, 0.0, 0.0)
    elements_around: int = 16
    elements_along: int = 32

    def mesh(self) -> geometry.Mesh:
        return geometry.cylinder(self.radius, self.length, self.axis, self.center,
                                 self.elements_around, self.elements_along)


@dataclass
class PlateGeometry:
    size: tuple[float, float]
    elements: tuple[int, int]
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    u_axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    v_axis: tuple[float, float, float] = (0.0, 1.0, 0.0)

    def mesh(self) -> geometry.Mesh:
        return geometry.plate(self.size, self.elements, self.origin, self.u_axis, self.v_axis)


@dataclass
class FileGeometry:
    path: Path  # absolute (resolved against the scene file's folder)
    group: str | None = None   # a physical group or cell set of the file; None: every quadrilateral

    def mesh(self) -> geometry.Mesh:
        return mesh_files.load_mesh(self.path, self.group)


Geometry = CylinderGeometry | PlateGeometry | FileGeometry


@dataclass
class PartSpec:
    name: str
    material: str
    thickness: float
    geometry: Geometry
    integration_points: int = _DECK_DEFAULT["/parts/integration_points"]
    hourglass_coefficient: float = _DECK_DEFAULT["/parts/hourglass_coefficient"]
    hourglass_form: str = _enum_name("hourglass_form", _DECK_DEFAULT["/parts/hourglass_form"])
    warping_correction: bool = bool(_DECK_DEFAULT["/parts/warping_correction"])
    # the quadrilaterals' formulation: "blt" (one point, hourglass control) or "full" (2 x 2 points)
    element: str = _enum_name("shell_element", _DECK_DEFAULT["/parts/shell_element"])
    # the nodal rotary inertia of its shells: "scaled" m (t^2 + A) / 4 or "radioss" m (t^2 + A) / 12
    rotary_inertia: str = _enum_name("rotary_inertia", _DECK_DEFAULT["/parts/rotary_inertia"])
    # the element's forces use its current thickness (LS-DYNA ISTUPD = 1); one-point quadrilaterals only
    thickness_update: bool = bool(_DECK_DEFAULT["/parts/thickness_update"])
    initial_velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    # "truss": 2-node bars (elements N1 N2 N2 N2) of cross-section area cross_section_area (m^2)
    element_kind: str = _enum_name("element_kind", _DECK_DEFAULT["/parts/element_kind"])
    cross_section_area: float = 0.0


@dataclass
class FixSpec:
    part: str
    box: tuple[tuple[float, float, float], tuple[float, float, float]]
    dofs: tuple[str, ...] = deck.DOF_NAMES


@dataclass
class LoadSpec:
    part: str
    point: tuple[float, float, float]
    dof: str
    value: float
    ramp_time: float = 0.0


@dataclass
class TrackSpec:
    name: str
    part: str
    point: tuple[float, float, float]


# the deck's kinds with edge checks, as the scene's kind with edges = true
EDGE_KINDS = {"edge_to_edge": "node_to_segment", "single_surface_edges": "single_surface"}


@dataclass
class WeldSpec:
    """A spot weld (docs/scene.md, [[weld]]): the nodes of two parts nearest ``point`` move as one
    small rigid body until its failure (docs/theory.md, "Weld failure")."""

    parts: tuple[str, str]
    point: tuple[float, float, float]
    strength: tuple[float, float] = (0.0, 0.0)    # SN, SS (N); 0: no failure in that mode
    exponent: tuple[float, float] = (2.0, 2.0)    # N, M
    failure_time: float = 1e20                    # s


@dataclass
class ContactSpec:
    """Parts that may touch (docs/scene.md, [[contact]]): two different parts for a node_to_segment
    pair; for a single_surface contact the parts that form one surface, every part when empty.
    ``edges``: the element edges of the surfaces are also checked against each other's edges."""

    parts: tuple[str, ...]
    penalty_scale: float = _DECK_DEFAULT["/contact/penalty_scale"]
    soft_constraint: float = _DECK_DEFAULT["/contact/soft_constraint"]   # 0 off; LS-DYNA SOFT = 1's SOFSCL
    # scale on the contact thickness of the first and the second part (LS-DYNA SFST, SFMT)
    thickness_scale: tuple[float, float] = (_DECK_DEFAULT["/contact/thickness_scale"],) * 2
    static_friction: float = _DECK_DEFAULT["/contact/static_friction"]
    dynamic_friction: float = _DECK_DEFAULT["/contact/dynamic_friction"]
    friction_decay: float = _DECK_DEFAULT["/contact/friction_decay"]
    symmetric: bool = _DECK_DEFAULT["/contact/passes"] == _schema.ENUMS["contact_passes"]["both"]
    kind: str = _enum_name("contact_kind", _DECK_DEFAULT["/contact/kind"])
    initial_penetration: str = _enum_name("initial_penetration", _DECK_DEFAULT["/contact/initial_penetration"])
    birth_time: float = _DECK_DEFAULT["/contact/birth_time"]
    death_time: float = _DECK_DEFAULT["/contact/death_time"]
    edges: bool = False   # also element edges against edges (deck kinds edge_to_edge, single_surface_edges)
    normal_failure_stress: float = _DECK_DEFAULT["/contact/normal_failure_stress"]   # tiebreak NFLS (Pa)
    shear_failure_stress: float = _DECK_DEFAULT["/contact/shear_failure_stress"]     # tiebreak SFLS (Pa)
    FAILURE_KEYS = ("normal_failure_stress", "shear_failure_stress")   # (a class constant: no field)


@dataclass
class CurveSpec:
    """A load curve: piecewise linear, first value before the first time, last value after the last."""

    name: str
    time: tuple[float, ...]
    value: tuple[float, ...]


@dataclass
class PressureSpec:
    part: str
    value: float                    # Pa; positive pushes along the element normal
    curve: str | None = None        # None: a constant factor 1


@dataclass
class PrescribeSpec:
    part: str
    box: tuple[tuple[float, float, float], tuple[float, float, float]]
    dof: str
    value: float                    # m/s or rad/s
    curve: str | None = None        # None: a constant factor 1
    birth_time: float = _DECK_DEFAULT["/prescribed/birth_time"]   # s: free before it
    death_time: float = _DECK_DEFAULT["/prescribed/death_time"]   # s: free after it


@dataclass
class Scene:
    path: Path
    title: str
    run: RunSettings
    materials: list[MaterialSpec]
    parts: list[PartSpec]
    fixes: list[FixSpec] = field(default_factory=list)
    loads: list[LoadSpec] = field(default_factory=list)
    tracks: list[TrackSpec] = field(default_factory=list)
    contacts: list[ContactSpec] = field(default_factory=list)
    curves: list[CurveSpec] = field(default_factory=list)
    pressures: list[PressureSpec] = field(default_factory=list)
    prescribed: list[PrescribeSpec] = field(default_factory=list)
    welds: list[WeldSpec] = field(default_factory=list)
    # the row tables (paradyn.scene.row_tables: [[rigid_wall]], ...), table -> its entries as read
    rows: dict[str, list[dict[str, Any]]] = field(default_factory=dict)

    def part(self, name: str) -> PartSpec:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(name)
