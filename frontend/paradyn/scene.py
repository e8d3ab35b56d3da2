"""Scenes: the user's TOML description of a ParaDyn run (see docs/scene.md), turned into a deck model.

``load_scene(path)`` parses and checks the file (unknown keys, missing keys, types, ranges) and
returns a :class:`Scene`; ``build_model(scene)`` meshes the parts and returns a :class:`deck.Model`.
Every problem raises :class:`SceneError` with a message that starts with the scene file path.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from paradyn import _schema, deck, geometry

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]


class SceneError(ValueError):
    """A scene file that cannot be turned into a model; the message names the file, table and key."""


MATERIAL_MODELS = dict(_schema.ENUMS["material_model"])
HOURGLASS_FORMS = dict(_schema.ENUMS["hourglass_form"])
DOF_GROUPS = {
    "all": deck.DOF_NAMES,
    "translations": deck.DOF_NAMES[:3],
    "rotations": deck.DOF_NAMES[3:],
}
_REQUIRED = object()
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
    model: str                      # "elastic" or "j2_plasticity"
    density: float
    youngs_modulus: float
    poisson_ratio: float
    yield_stress: float = _DECK_DEFAULT["/materials/yield_stress"]          # j2 only
    tangent_modulus: float = _DECK_DEFAULT["/materials/tangent_modulus"]    # j2 only
    hardening_mixing: float = _DECK_DEFAULT["/materials/hardening_mixing"]  # j2 only

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

    def mesh(self) -> geometry.Mesh:
        return geometry.load_mesh(self.path)


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
    initial_velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)


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


@dataclass
class ContactSpec:
    parts: tuple[str, str]
    penalty_scale: float = _DECK_DEFAULT["/contact/penalty_scale"]
    static_friction: float = _DECK_DEFAULT["/contact/static_friction"]
    dynamic_friction: float = _DECK_DEFAULT["/contact/dynamic_friction"]
    friction_decay: float = _DECK_DEFAULT["/contact/friction_decay"]
    symmetric: bool = _DECK_DEFAULT["/contact/passes"] == _schema.ENUMS["contact_passes"]["both"]
    kind: str = _enum_name("contact_kind", _DECK_DEFAULT["/contact/kind"])


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

    def part(self, name: str) -> PartSpec:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(name)


# ----------------------------------------------------------------------------------------------
# reading helpers


class _Reader:
    """Typed access to TOML tables with messages that name the scene file, the table and the key."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, message: str) -> SceneError:
        return SceneError(f"{self.path}: {message}")

    def keys(self, table: Mapping[str, Any], label: str, allowed: Iterable[str]) -> None:
        allowed = list(allowed)
        for key in table:
            if key not in allowed:
                raise self.error(f"unknown key '{key}' in {label}; allowed keys are: {', '.join(allowed)}")

    def table(self, parent: Mapping[str, Any], key: str, label: str, required: bool = True) -> dict[str, Any]:
        value = parent.get(key)
        if value is None:
            if required:
                raise self.error(f"missing required table [{key}] in {label}")
            return {}
        if not isinstance(value, dict):
            raise self.error(f"'{key}' in {label} must be a table, written [{key}] (got {_kind(value)})")
        return value

    def tables(self, parent: Mapping[str, Any], key: str) -> list[dict[str, Any]]:
        value = parent.get(key, [])
        if isinstance(value, dict):
            raise self.error(f"'{key}' must be an array of tables: write [[{key}]] instead of [{key}]")
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            raise self.error(f"'{key}' must be an array of tables written [[{key}]]")
        return value

    def raw(self, table: Mapping[str, Any], key: str, label: str, default: Any) -> Any:
        if key in table:
            return table[key]
        if default is _REQUIRED:
            raise self.error(f"missing required key '{key}' in {label}")
        return default

    def number(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               minimum: float | None = None, positive: bool = False) -> float:
        value = self.raw(table, key, label, default)
        if value is None:
            return value
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.error(f"'{key}' in {label} must be a finite number, got {value!r}")
        if positive and value <= 0:
            raise self.error(f"'{key}' in {label} must be > 0, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.error(f"'{key}' in {label} must be >= {minimum}, got {value!r}")
        return float(value)

    def integer(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
                minimum: int = 1, maximum: int | None = None) -> int:
        value = self.raw(table, key, label, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"'{key}' in {label} must be an integer, got {value!r}")
        if value < minimum or (maximum is not None and value > maximum):
            bound = f"between {minimum} and {maximum}" if maximum is not None else f">= {minimum}"
            raise self.error(f"'{key}' in {label} must be {bound}, got {value}")
        return value

    def string(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               choices: Iterable[str] | None = None) -> str:
        value = self.raw(table, key, label, default)
        if not isinstance(value, str) or (not value and default is _REQUIRED):
            raise self.error(f"'{key}' in {label} must be a non-empty string, got {value!r}")
        if choices is not None and value not in choices:
            raise self.error(f"'{key}' = '{value}' in {label} is not one of: {', '.join(choices)}")
        return value

    def vector(self, table: Mapping[str, Any], key: str, label: str, default: Any = _REQUIRED,
               length: int = 3) -> tuple[float, ...]:
        value = self.raw(table, key, label, default)
        if (not isinstance(value, (list, tuple)) or len(value) != length
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                       for v in value)):
            raise self.error(f"'{key}' in {label} must be a list of {length} finite numbers, got {value!r}")
        return tuple(float(v) for v in value)

    def int_pair(self, table: Mapping[str, Any], key: str, label: str) -> tuple[int, int]:
        value = self.raw(table, key, label, _REQUIRED)
        if (not isinstance(value, list) or len(value) != 2
                or any(isinstance(v, bool) or not isinstance(v, int) or v < 1 for v in value)):
            raise self.error(f"'{key}' in {label} must be two positive integers [nx, ny], got {value!r}")
        return (value[0], value[1])


def _kind(value: Any) -> str:
    return {list: "an array", dict: "a table", str: "a string"}.get(type(value), type(value).__name__)


def _label(kind: str, index: int, table: Mapping[str, Any]) -> str:
    name = table.get("name")
    suffix = f" '{name}'" if isinstance(name, str) else ""
    return f"[[{kind}]] #{index + 1}{suffix}"


# ----------------------------------------------------------------------------------------------
# parsing


_TOP_KEYS = ("title", "run", "material", "part", "fix", "load", "track", "contact")
_RUN_KEYS = ("end_time", "output_interval", "history_interval", "time_step", "time_step_safety",
             "mass_damping", "progress_interval", "contact_sort_interval", "checkpoint_interval", "partition",
             "contact_gather")
_MATERIAL_KEYS = ("name", "model", "density", "youngs_modulus", "poisson_ratio", "yield_stress",
                  "tangent_modulus", "hardening_mixing")
_J2_KEYS = ("yield_stress", "tangent_modulus", "hardening_mixing")
_PART_KEYS = ("name", "material", "thickness", "integration_points", "hourglass_coefficient",
              "hourglass_form", "initial_velocity", "geometry")
_GEOMETRY_KEYS = {
    "cylinder": ("kind", "radius", "length", "axis", "center", "elements_around", "elements_along"),
    "plate": ("kind", "size", "elements", "origin", "u_axis", "v_axis"),
    "file": ("kind", "path"),
}
_FIX_KEYS = ("part", "box", "dofs")
_LOAD_KEYS = ("part", "point", "dof", "value", "ramp_time")
_TRACK_KEYS = ("name", "part", "point")
_CONTACT_KEYS = ("parts", "kind", "penalty_scale", "static_friction", "dynamic_friction", "friction_decay",
                 "symmetric")


def load_scene(path: str | Path) -> Scene:
    """Parse and check a scene file; raise SceneError naming the file, table and key on any problem."""
    path = Path(path)
    reader = _Reader(path)
    data = _parse_toml(path)
    reader.keys(data, "the top level of the scene", _TOP_KEYS)
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise reader.error(f"'title' must be a string, got {title!r}")
    run = _parse_run(reader, reader.table(data, "run", "the scene"))
    materials = [_parse_material(reader, t, i) for i, t in enumerate(reader.tables(data, "material"))]
    parts = [_parse_part(reader, t, i) for i, t in enumerate(reader.tables(data, "part"))]
    fixes = [_parse_fix(reader, t, i) for i, t in enumerate(reader.tables(data, "fix"))]
    loads = [_parse_load(reader, t, i) for i, t in enumerate(reader.tables(data, "load"))]
    tracks = [_parse_track(reader, t, i) for i, t in enumerate(reader.tables(data, "track"))]
    contacts = [_parse_contact(reader, t, i) for i, t in enumerate(reader.tables(data, "contact"))]
    scene = Scene(path=path, title=title, run=run, materials=materials, parts=parts,
                  fixes=fixes, loads=loads, tracks=tracks, contacts=contacts)
    _check_references(reader, scene)
    return scene


def _parse_toml(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise SceneError(f"{path}: scene file not found; check the path") from exc
    except OSError as exc:
        raise SceneError(f"{path}: cannot read the scene file ({exc})") from exc
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML ({exc}); fix the syntax at that line") from exc


def _parse_run(r: _Reader, t: dict[str, Any]) -> RunSettings:
    label = "[run]"
    r.keys(t, label, _RUN_KEYS)
    run = RunSettings(
        end_time=r.number(t, "end_time", label, positive=True),
        output_interval=r.number(t, "output_interval", label, positive=True),
        history_interval=r.number(t, "history_interval", label, default=None, positive=True),
        time_step=r.number(t, "time_step", label, default=RunSettings.time_step, minimum=0.0),
        time_step_safety=r.number(t, "time_step_safety", label, default=RunSettings.time_step_safety,
                                  positive=True),
        mass_damping=r.number(t, "mass_damping", label, default=RunSettings.mass_damping, minimum=0.0),
        progress_interval=r.number(t, "progress_interval", label, default=RunSettings.progress_interval,
                                   positive=True),
        contact_sort_interval=r.integer(t, "contact_sort_interval", label,
                                        default=int(RunSettings.contact_sort_interval), minimum=0),
        checkpoint_interval=r.number(t, "checkpoint_interval", label, default=RunSettings.checkpoint_interval,
                                     minimum=0.0),
        partition=(r.string(t, "partition", label, choices=tuple(deck.PARTITIONS)) if "partition" in t
                   else None),
        contact_gather=(r.string(t, "contact_gather", label, choices=tuple(_schema.ENUMS["contact_gather"]))
                        if "contact_gather" in t else None),
    )
    if run.time_step_safety > 1.0:
        raise r.error(f"'time_step_safety' in {label} must be in (0, 1], got {run.time_step_safety}")
    return run


def _parse_material(r: _Reader, t: dict[str, Any], index: int) -> MaterialSpec:
    label = _label("material", index, t)
    r.keys(t, label, _MATERIAL_KEYS)
    model = r.string(t, "model", label, choices=tuple(MATERIAL_MODELS))
    if model == "elastic":
        extra = [k for k in _J2_KEYS if k in t]
        if extra:
            raise r.error(f"'{extra[0]}' in {label} only applies to model = \"j2_plasticity\"; remove it "
                          f"or change the model")
    material = MaterialSpec(
        name=r.string(t, "name", label),
        model=model,
        density=r.number(t, "density", label, positive=True),
        youngs_modulus=r.number(t, "youngs_modulus", label, positive=True),
        poisson_ratio=r.number(t, "poisson_ratio", label),
    )
    if not -1.0 < material.poisson_ratio < 0.5:
        raise r.error(f"'poisson_ratio' in {label} must satisfy -1 < nu < 0.5, got {material.poisson_ratio}")
    if model == "j2_plasticity":
        material.yield_stress = r.number(t, "yield_stress", label, positive=True)
        material.tangent_modulus = r.number(t, "tangent_modulus", label, default=MaterialSpec.tangent_modulus,
                                            minimum=0.0)
        material.hardening_mixing = r.number(t, "hardening_mixing", label, default=MaterialSpec.hardening_mixing,
                                             minimum=0.0)
        if material.tangent_modulus >= material.youngs_modulus:
            raise r.error(f"'tangent_modulus' in {label} must be below youngs_modulus "
                          f"({material.youngs_modulus:g} Pa), got {material.tangent_modulus:g}")
        if material.hardening_mixing > 1.0:
            raise r.error(f"'hardening_mixing' in {label} must be in [0, 1] (1 isotropic, 0 kinematic), "
                          f"got {material.hardening_mixing}")
    return material


def _parse_part(r: _Reader, t: dict[str, Any], index: int) -> PartSpec:
    label = _label("part", index, t)
    r.keys(t, label, _PART_KEYS)
    name = r.string(t, "name", label)
    return PartSpec(
        name=name,
        material=r.string(t, "material", label),
        thickness=r.number(t, "thickness", label, positive=True),
        geometry=_parse_geometry(r, r.table(t, "geometry", label), f"[part.geometry] of part '{name}'"),
        integration_points=r.integer(t, "integration_points", label, default=PartSpec.integration_points,
                                     minimum=1, maximum=9),
        hourglass_coefficient=r.number(t, "hourglass_coefficient", label, default=PartSpec.hourglass_coefficient,
                                       minimum=0.0),
        hourglass_form=r.string(t, "hourglass_form", label, default=PartSpec.hourglass_form,
                                choices=tuple(HOURGLASS_FORMS)),
        initial_velocity=r.vector(t, "initial_velocity", label, default=(0.0, 0.0, 0.0)),
    )


def _parse_geometry(r: _Reader, t: dict[str, Any], label: str) -> Geometry:
    kind = r.string(t, "kind", label, choices=tuple(_GEOMETRY_KEYS))
    r.keys(t, f"{label} (kind = \"{kind}\")", _GEOMETRY_KEYS[kind])
    if kind == "cylinder":
        around = r.integer(t, "elements_around", label, default=16, minimum=4)
        if around % 4:
            raise r.error(f"'elements_around' in {label} must be a multiple of 4, got {around}")
        return CylinderGeometry(
            radius=r.number(t, "radius", label, positive=True),
            length=r.number(t, "length", label, positive=True),
            axis=r.vector(t, "axis", label, default=(1.0, 0.0, 0.0)),
            center=r.vector(t, "center", label, default=(0.0, 0.0, 0.0)),
            elements_around=around,
            elements_along=r.integer(t, "elements_along", label, default=32),
        )
    if kind == "plate":
        size = r.vector(t, "size", label, length=2)
        if min(size) <= 0:
            raise r.error(f"'size' in {label} must be two positive lengths [lx, ly], got {list(size)}")
        return PlateGeometry(
            size=(size[0], size[1]),
            elements=r.int_pair(t, "elements", label),
            origin=r.vector(t, "origin", label, default=(0.0, 0.0, 0.0)),
            u_axis=r.vector(t, "u_axis", label, default=(1.0, 0.0, 0.0)),
            v_axis=r.vector(t, "v_axis", label, default=(0.0, 1.0, 0.0)),
        )
    file = (r.path.parent / r.string(t, "path", label)).resolve()
    if not file.is_file():
        raise r.error(f"'path' in {label}: mesh file {file} not found; paths are relative to the "
                      f"scene file's folder")
    return FileGeometry(path=file)


def _parse_dofs(r: _Reader, t: dict[str, Any], label: str) -> tuple[str, ...]:
    value = r.raw(t, "dofs", label, ["all"])
    items = [value] if isinstance(value, str) else value
    allowed = deck.DOF_NAMES + tuple(DOF_GROUPS)
    if not isinstance(items, list) or not items or not all(isinstance(v, str) for v in items):
        raise r.error(f"'dofs' in {label} must be a list of dof names from: {', '.join(allowed)}")
    chosen: set[str] = set()
    for item in items:
        if item not in allowed:
            raise r.error(f"'dofs' in {label} contains '{item}', which is not one of: {', '.join(allowed)}")
        chosen.update(DOF_GROUPS.get(item, (item,)))
    return tuple(d for d in deck.DOF_NAMES if d in chosen)


def _parse_fix(r: _Reader, t: dict[str, Any], index: int) -> FixSpec:
    label = _label("fix", index, t)
    r.keys(t, label, _FIX_KEYS)
    box = r.raw(t, "box", label, _REQUIRED)
    if not isinstance(box, list) or len(box) != 2:
        raise r.error(f"'box' in {label} must be two corners [[xmin, ymin, zmin], [xmax, ymax, zmax]], "
                      f"got {box!r}")
    corners = {"lo": box[0], "hi": box[1]}
    lo = r.vector(corners, "lo", f"'box' of {label}")
    hi = r.vector(corners, "hi", f"'box' of {label}")
    if any(a > b for a, b in zip(lo, hi, strict=True)):
        raise r.error(f"'box' in {label}: the first corner {list(lo)} must not exceed the second {list(hi)} "
                      f"in any coordinate; write [[xmin, ymin, zmin], [xmax, ymax, zmax]]")
    return FixSpec(part=r.string(t, "part", label), box=(lo, hi), dofs=_parse_dofs(r, t, label))


def _parse_load(r: _Reader, t: dict[str, Any], index: int) -> LoadSpec:
    label = _label("load", index, t)
    r.keys(t, label, _LOAD_KEYS)
    return LoadSpec(
        part=r.string(t, "part", label),
        point=r.vector(t, "point", label),
        dof=r.string(t, "dof", label, choices=deck.DOF_NAMES),
        value=r.number(t, "value", label),
        ramp_time=r.number(t, "ramp_time", label, default=0.0, minimum=0.0),
    )


def _parse_track(r: _Reader, t: dict[str, Any], index: int) -> TrackSpec:
    label = _label("track", index, t)
    r.keys(t, label, _TRACK_KEYS)
    return TrackSpec(name=r.string(t, "name", label), part=r.string(t, "part", label),
                     point=r.vector(t, "point", label))


def _parse_contact(r: _Reader, t: dict[str, Any], index: int) -> ContactSpec:
    label = f"[[contact]] #{index + 1}"
    r.keys(t, label, _CONTACT_KEYS)
    parts = r.raw(t, "parts", label, _REQUIRED)
    if (not isinstance(parts, list) or len(parts) != 2 or not all(isinstance(p, str) for p in parts)
            or parts[0] == parts[1]):
        raise r.error(f"'parts' in {label} must name two different parts, e.g. parts = [\"a\", \"b\"]; "
                      f"got {parts!r}")
    symmetric = r.raw(t, "symmetric", label, ContactSpec.symmetric)
    if not isinstance(symmetric, bool):
        raise r.error(f"'symmetric' in {label} must be true (both passes every step) or false "
                      f"(slave and master swap every step, as in the paper); got {symmetric!r}")
    static = r.number(t, "static_friction", label, default=ContactSpec.static_friction, minimum=0.0)
    return ContactSpec(
        parts=(parts[0], parts[1]),
        penalty_scale=r.number(t, "penalty_scale", label, default=ContactSpec.penalty_scale, positive=True),
        static_friction=static,
        dynamic_friction=r.number(t, "dynamic_friction", label, default=static, minimum=0.0),
        friction_decay=r.number(t, "friction_decay", label, default=ContactSpec.friction_decay, minimum=0.0),
        symmetric=symmetric,
        kind=(r.string(t, "kind", label, choices=tuple(_schema.ENUMS["contact_kind"])) if "kind" in t
              else ContactSpec.kind),
    )


def _check_references(r: _Reader, scene: Scene) -> None:
    _unique(r, [m.name for m in scene.materials], "material")
    _unique(r, [p.name for p in scene.parts], "part")
    _unique(r, [t.name for t in scene.tracks], "track")
    if not scene.parts:
        raise r.error("the scene has no [[part]]; add at least one part with a geometry")
    materials = [m.name for m in scene.materials]
    for part in scene.parts:
        if part.material not in materials:
            known = ", ".join(materials) or "none defined"
            raise r.error(f"part '{part.name}' uses material '{part.material}', which is not defined "
                          f"(materials: {known}); add a [[material]] with that name")
    parts = [p.name for p in scene.parts]
    for kind, items in (("fix", scene.fixes), ("load", scene.loads), ("track", scene.tracks)):
        for index, item in enumerate(items):
            if item.part not in parts:
                raise r.error(f"[[{kind}]] #{index + 1} refers to part '{item.part}', which is not "
                              f"defined (parts: {', '.join(parts)})")
    for index, contact in enumerate(scene.contacts):
        for name in contact.parts:
            if name not in parts:
                raise r.error(f"[[contact]] #{index + 1} names part '{name}', which is not defined "
                              f"(parts: {', '.join(parts)})")


def _unique(r: _Reader, names: list[str], kind: str) -> None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise r.error(f"two [[{kind}]] entries are named '{name}'; names must be unique")
        seen.add(name)


# ----------------------------------------------------------------------------------------------
# building the model


@dataclass
class _PartMesh:
    spec: PartSpec
    mesh: geometry.Mesh
    first_node: int

    @property
    def nodes(self) -> np.ndarray:
        return np.arange(self.first_node, self.first_node + self.mesh.n_nodes)

    @property
    def tolerance(self) -> float:
        """Largest element edge: how far a load or track point may lie from the part's nodes."""
        return float(self.mesh.edge_lengths().max())

    @property
    def size(self) -> float:
        c = self.mesh.coordinates
        return float(np.linalg.norm(c.max(axis=0) - c.min(axis=0)))


def build_model(scene: Scene) -> deck.Model:
    """Mesh every part and assemble the deck model (parts do not share nodes)."""
    r = _Reader(scene.path)
    meshes = _mesh_parts(r, scene)
    coordinates = np.concatenate([m.mesh.coordinates for m in meshes])
    connectivity = np.concatenate([m.mesh.quads + m.first_node for m in meshes])
    element_part = np.concatenate([np.full(m.mesh.n_elements, i) for i, m in enumerate(meshes)])
    velocity = np.concatenate([np.tile(m.spec.initial_velocity, (m.mesh.n_nodes, 1)) for m in meshes])
    by_name = {m.spec.name: m for m in meshes}
    fixed = _fixed_dofs(r, scene, by_name, len(coordinates))
    velocity[fixed[:, :3] == 1] = 0.0  # a fixed translation cannot start moving
    material_index = {m.name: i for i, m in enumerate(scene.materials)}
    model = deck.Model(
        coordinates=coordinates,
        connectivity=connectivity.astype(np.int32),
        element_part=element_part.astype(np.int32),
        thickness=np.array([p.thickness for p in scene.parts]),
        part_material=np.array([material_index[p.material] for p in scene.parts], dtype=np.int32),
        integration_points=np.array([p.integration_points for p in scene.parts], dtype=np.int32),
        hourglass_coefficient=np.array([p.hourglass_coefficient for p in scene.parts]),
        hourglass_form=np.array([HOURGLASS_FORMS[p.hourglass_form] for p in scene.parts], dtype=np.int32),
        material_model=np.array([m.model_code for m in scene.materials], dtype=np.int32),
        density=np.array([m.density for m in scene.materials]),
        youngs_modulus=np.array([m.youngs_modulus for m in scene.materials]),
        poisson_ratio=np.array([m.poisson_ratio for m in scene.materials]),
        yield_stress=np.array([m.yield_stress for m in scene.materials]),
        tangent_modulus=np.array([m.tangent_modulus for m in scene.materials]),
        hardening_mixing=np.array([m.hardening_mixing for m in scene.materials]),
        initial_velocity=velocity,
        fixed_dofs=fixed,
        control=deck.Control(**vars(scene.run)),
        title=scene.title,
        part_names=[p.name for p in scene.parts],
        material_names=[m.name for m in scene.materials],
    )
    _apply_loads(r, scene, by_name, model)
    _apply_tracks(r, scene, by_name, model)
    _apply_contacts(scene, model)
    try:
        deck.validate_model(model, source=f"{scene.path} (built model)")
    except deck.DeckError as exc:
        raise SceneError(str(exc)) from exc
    return model


def _mesh_parts(r: _Reader, scene: Scene) -> list[_PartMesh]:
    meshes: list[_PartMesh] = []
    first = 0
    for part in scene.parts:
        try:
            mesh = part.geometry.mesh()
        except geometry.GeometryError as exc:
            raise r.error(f"[part.geometry] of part '{part.name}': {exc}") from exc
        meshes.append(_PartMesh(spec=part, mesh=mesh, first_node=first))
        first += mesh.n_nodes
    return meshes


def _fixed_dofs(r: _Reader, scene: Scene, by_name: dict[str, _PartMesh], n_nodes: int) -> np.ndarray:
    fixed = np.zeros((n_nodes, 6), dtype=np.int32)
    columns_of = {name: i for i, name in enumerate(deck.DOF_NAMES)}
    for index, fix in enumerate(scene.fixes):
        part = by_name[fix.part]
        local = geometry.nodes_in_box(part.mesh.coordinates, fix.box[0], fix.box[1],
                                      tol=1e-9 * max(part.size, 1.0))
        if local.size == 0:
            c = part.mesh.coordinates
            raise r.error(f"[[fix]] #{index + 1}: the box {[list(fix.box[0]), list(fix.box[1])]} contains "
                          f"no node of part '{fix.part}' (its nodes span {c.min(axis=0).tolist()} to "
                          f"{c.max(axis=0).tolist()}); enlarge or move the box")
        columns = [columns_of[d] for d in fix.dofs]
        fixed[np.ix_(local + part.first_node, columns)] = 1
    return fixed


def _located_node(r: _Reader, part: _PartMesh, point: tuple[float, float, float], label: str) -> int:
    local = geometry.nearest_node(part.mesh.coordinates, point)
    distance = float(np.linalg.norm(part.mesh.coordinates[local] - np.asarray(point)))
    if distance > part.tolerance:
        raise r.error(f"{label}: point {list(point)} is {distance:.4g} m from the nearest node of part "
                      f"'{part.spec.name}' (at {part.mesh.coordinates[local].tolist()}), more than one "
                      f"element size ({part.tolerance:.4g} m); put the point on the part's mid-surface")
    return local + part.first_node


def _apply_loads(r: _Reader, scene: Scene, by_name: dict[str, _PartMesh], model: deck.Model) -> None:
    nodes = [_located_node(r, by_name[load.part], load.point, f"[[load]] #{i + 1}")
             for i, load in enumerate(scene.loads)]
    model.load_node = np.array(nodes, dtype=np.int32)
    model.load_dof = np.array([deck.DOF_NAMES.index(load.dof) + 1 for load in scene.loads], dtype=np.int32)
    model.load_value = np.array([load.value for load in scene.loads], dtype=np.float64)
    model.load_ramp_time = np.array([load.ramp_time for load in scene.loads], dtype=np.float64)


def _apply_tracks(r: _Reader, scene: Scene, by_name: dict[str, _PartMesh], model: deck.Model) -> None:
    nodes = [_located_node(r, by_name[track.part], track.point, f"[[track]] '{track.name}'")
             for track in scene.tracks]
    model.tracked_nodes = np.array(nodes, dtype=np.int32)
    model.tracked_names = [track.name for track in scene.tracks]


# ----------------------------------------------------------------------------------------------
# effects


def _apply_contacts(scene: Scene, model: deck.Model) -> None:
    index = {p.name: i for i, p in enumerate(scene.parts)}
    contacts = scene.contacts
    model.contact_pairs = np.array([[index[c.parts[0]], index[c.parts[1]]] for c in contacts],
                                   dtype=np.int32).reshape(-1, 2)
    model.contact_penalty_scale = np.array([c.penalty_scale for c in contacts])
    model.contact_static_friction = np.array([c.static_friction for c in contacts])
    model.contact_dynamic_friction = np.array([c.dynamic_friction for c in contacts])
    model.contact_friction_decay = np.array([c.friction_decay for c in contacts])
    passes = _schema.ENUMS["contact_passes"]
    model.contact_passes = np.array([passes["both"] if c.symmetric else passes["alternate"] for c in contacts],
                                    dtype=np.int32)
    model.contact_kind = np.array([_schema.ENUMS["contact_kind"][c.kind] for c in contacts], dtype=np.int32)


def effects(model: deck.Model) -> list[str]:
    """Physical effects a model switches on, in the order the engine reports them."""
    active = ["shell_elements", "time_integration"]
    used_materials = np.asarray(model.part_material)[np.unique(np.asarray(model.element_part))]
    if np.any(np.asarray(model.material_model)[used_materials] == deck.J2_PLASTICITY):
        active.append("plasticity")
    if model.fixed_dofs is not None and np.any(np.asarray(model.fixed_dofs) != 0):
        active.append("fixed_boundaries")
    if model.n_loads > 0:
        active.append("point_loads")
    if model.n_contacts > 0:
        active.append("contact")
    if model.control.mass_damping and model.control.mass_damping > 0:
        active.append("mass_damping")
    return active
