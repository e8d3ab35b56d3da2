"""Reading and checking a scene file: :func:`load_scene` turns the TOML text into a :class:`Scene`.

The reader rejects unknown keys, missing keys, wrong types and out-of-range values, then checks that
names are unique and that every reference (a part's material, the part of a fix, load, track or
contact) is defined; every problem raises :class:`SceneError` naming the file, the table and the key.
"""

from __future__ import annotations

import dataclasses
import itertools
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from paradyn import _schema, deck
from paradyn.arguments import did_you_mean
from paradyn.scene.building import check_material_curves
from paradyn.scene.contact_reading import parse_contact
from paradyn.scene.row_tables import ROW_TABLES, check_row_references, parse_rows, read_key
from paradyn.scene.specs import (
    DOF_GROUPS,
    HOURGLASS_FORMS,
    MATERIAL_MODELS,
    ROTARY_INERTIAS,
    SHELL_ELEMENTS,
    CurveSpec,
    CylinderGeometry,
    FileGeometry,
    FixSpec,
    Geometry,
    LoadSpec,
    MaterialSpec,
    PartSpec,
    PlateGeometry,
    PrescribeSpec,
    PressureSpec,
    RunSettings,
    Scene,
    SceneError,
    TrackSpec,
)
from paradyn.scene.tables import _REQUIRED, _Reader, read_life
from paradyn.scene.welds import parse_weld

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]


def _label(kind: str, index: int, table: Mapping[str, Any]) -> str:
    name = table.get("name")
    suffix = f" '{name}'" if isinstance(name, str) else ""
    return f"[[{kind}]] #{index + 1}{suffix}"


# ----------------------------------------------------------------------------------------------
# parsing

_TOP_KEYS = ("title", "run", "effects", "material", "part", "fix", "load", "track", "contact", "curve", "pressure",
             "prescribe", "weld", "study", *ROW_TABLES)
_RUN_KEYS = ("end_time", "output_interval", "history_interval", "time_step", "time_step_safety",
             "mass_damping", "progress_interval", "contact_sort_interval", "checkpoint_interval", "partition",
             "contact_gather", "gravity", "energy_error_limit", "time_step_floor", "contact_travel_limit",
             "contact_closing_limit", "mass_scaling_step", "mass_scaling_limit", "precision")
# the keys of [[material]] besides its name: the /materials datasets', by their scene key
_MATERIAL_KEYS = {d.scene.split()[1]: d for d in _schema.DATASETS if d.path.startswith("/materials/")}
_PART_KEYS = ("name", "material", "thickness", "integration_points", "hourglass_coefficient",
              "hourglass_form", "warping_correction", "element", "rotary_inertia", "thickness_update",
              "initial_velocity", "geometry")
_GEOMETRY_KEYS = {
    "cylinder": ("kind", "radius", "length", "axis", "center", "elements_around", "elements_along"),
    "plate": ("kind", "size", "elements", "origin", "u_axis", "v_axis"),
    "file": ("kind", "path", "group"),
}
_FIX_KEYS = ("part", "box", "dofs")
_LOAD_KEYS = ("part", "point", "dof", "value", "ramp_time")
_TRACK_KEYS = ("name", "part", "point")
_CURVE_KEYS = ("name", "time", "value")
_PRESSURE_KEYS = ("part", "value", "curve")
_PRESCRIBE_KEYS = ("part", "box", "dof", "value", "curve", "birth_time", "death_time")


def load_scene(path: str | Path) -> Scene:
    """Parse and check a scene file; raise SceneError naming the file, table and key on any problem."""
    path = Path(path)
    return scene_from_tables(_parse_toml(path), path)


def scene_from_tables(data: Mapping[str, Any], path: Path) -> Scene:
    """Check the tables of a scene (a parsed TOML file, or :class:`paradyn.Scene`'s) and return the
    :class:`Scene`; messages start with ``path``, and mesh file paths are relative to its folder."""
    reader = _Reader(path)
    reader.keys(data, "the top level of the scene", _TOP_KEYS)
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise reader.error(f"'title' must be a string, got {title!r}")
    run = _parse_run(reader, reader.table(data, "run", "the scene"))
    run.effect_switches = _parse_effects(reader, reader.table(data, "effects", "the scene", required=False))
    reader.table(data, "study", "the scene", required=False)   # paradyn-study's, docs/accuracy-cost.md
    materials = [_parse_material(reader, t, i) for i, t in enumerate(reader.tables(data, "material"))]
    parts = [_parse_part(reader, t, i) for i, t in enumerate(reader.tables(data, "part"))]
    _check_mesh_size(reader, parts)
    fixes = [_parse_fix(reader, t, i) for i, t in enumerate(reader.tables(data, "fix"))]
    loads = [_parse_load(reader, t, i) for i, t in enumerate(reader.tables(data, "load"))]
    tracks = [_parse_track(reader, t, i) for i, t in enumerate(reader.tables(data, "track"))]
    contacts = [parse_contact(reader, t, i) for i, t in enumerate(reader.tables(data, "contact"))]
    curves = [_parse_curve(reader, t, i) for i, t in enumerate(reader.tables(data, "curve"))]
    pressures = [_parse_pressure(reader, t, i) for i, t in enumerate(reader.tables(data, "pressure"))]
    prescribed = [_parse_prescribe(reader, t, i) for i, t in enumerate(reader.tables(data, "prescribe"))]
    welds = [parse_weld(reader, t, i) for i, t in enumerate(reader.tables(data, "weld"))]
    scene = Scene(path=path, title=title, run=run, materials=materials, parts=parts,
                  fixes=fixes, loads=loads, tracks=tracks, contacts=contacts, curves=curves,
                  pressures=pressures, prescribed=prescribed, welds=welds, rows=parse_rows(reader, data))
    _check_references(reader, scene)
    _check_load_references(reader, scene)
    check_material_curves(reader, scene)
    check_row_references(reader, scene)
    return scene


def _parse_toml(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise SceneError(f"{path}: scene file not found; check the path") from exc
    except OSError as exc:
        raise SceneError(f"{path}: cannot read the scene file ({exc})") from exc
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: not a text file in UTF-8 ({exc.reason} at byte {exc.start}); save the scene "
                         f"as UTF-8 TOML") from exc
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
        energy_error_limit=r.number(t, "energy_error_limit", label, default=RunSettings.energy_error_limit,
                                    minimum=0.0),
        time_step_floor=r.number(t, "time_step_floor", label, default=RunSettings.time_step_floor, positive=True),
        contact_travel_limit=r.number(t, "contact_travel_limit", label, default=RunSettings.contact_travel_limit,
                                      minimum=0.0),
        contact_closing_limit=r.number(t, "contact_closing_limit", label,
                                       default=RunSettings.contact_closing_limit, minimum=0.0),
        mass_scaling_step=r.number(t, "mass_scaling_step", label, default=RunSettings.mass_scaling_step,
                                   minimum=0.0),
        mass_scaling_limit=r.number(t, "mass_scaling_limit", label, default=RunSettings.mass_scaling_limit,
                                    minimum=0.0),
    )
    for key in ("partition", "contact_gather", "precision"):   # /control strings: members of their enums
        if key in t:
            setattr(run, key, r.string(t, key, label, choices=tuple(_schema.ENUMS[key])))
    if run.time_step_safety > 1.0:
        raise r.error(f"'time_step_safety' in {label} must be in (0, 1], got {run.time_step_safety}")
    if run.contact_travel_limit >= 1.0:
        raise r.error(f"'contact_travel_limit' in {label} must be in [0, 1), a fraction of the wall thickness "
                      f"(0.1 keeps the penetration near a fifth of it; 0 = no limit), got {run.contact_travel_limit}")
    if run.contact_closing_limit >= 1.0:
        raise r.error(f"'contact_closing_limit' in {label} must be in [0, 1), a fraction of the thinner wall "
                      f"(0.05 is the default; 0 switches the automatic limit off), got {run.contact_closing_limit}")
    if run.time_step_floor >= 1.0:
        raise r.error(f"'time_step_floor' in {label} must be in (0, 1), a fraction of the first step, "
                      f"got {run.time_step_floor}")
    run.gravity_x, run.gravity_y, run.gravity_z = r.vector(t, "gravity", label, default=(0.0, 0.0, 0.0))
    return run


def _parse_effects(r: _Reader, t: dict[str, Any]) -> dict[str, str]:
    """[effects] <switch> = true | false: an effect the scene declares but wants off for a study
    or a check (schema/effects.toml names the switches)."""
    r.keys(t, "[effects]", _schema.EFFECT_SWITCHES)
    switches = {}
    for name, value in t.items():
        if not isinstance(value, bool):
            raise r.error(f"'{name}' in [effects] must be true or false, got {value!r}")
        switches[name] = "on" if value else "off"
    return switches


def _parse_material(r: _Reader, t: dict[str, Any], index: int) -> MaterialSpec:
    """A [[material]]: its keys are the /materials datasets' (schema/deck.toml scene), each read with
    its bounds; a key whose dataset is checked only for some models (checked_when) applies to those."""
    label = _label("material", index, t)
    r.keys(t, label, ("name", *_MATERIAL_KEYS))
    model = r.string(t, "model", label, choices=tuple(MATERIAL_MODELS))
    values: dict[str, Any] = {"model": model}
    for key, spec in _MATERIAL_KEYS.items():
        if key == "model":
            continue
        models = _models_of(spec)
        if model not in models:
            if key in t:
                raise r.error(f"'{key}' in {label} only applies to model = " + " or ".join(f'"{m}"' for m in models)
                              + "; remove it or change the model")
            continue
        values[spec.python] = read_key(r, t, key, spec, label)
    fields = {f.name for f in dataclasses.fields(MaterialSpec)}
    material = MaterialSpec(name=r.string(t, "name", label), **{k: v for k, v in values.items() if k in fields},
                            extra={k: v for k, v in values.items() if k not in fields})
    if material.model in _schema.ENUM_TRAITS["material_model"]["plastic"] \
            and material.tangent_modulus >= material.youngs_modulus:
        raise r.error(f"'tangent_modulus' in {label} must be below youngs_modulus "
                      f"({material.youngs_modulus:g} Pa), got {material.tangent_modulus:g}")
    return material


def _models_of(spec: _schema.DatasetSpec) -> list[str]:
    """The material models a /materials dataset applies to (every model unless checked_when)."""
    if spec.checked_when is None:
        return list(MATERIAL_MODELS)
    codes = _schema.CONDITIONS[spec.checked_when].codes
    return [name for name, code in MATERIAL_MODELS.items() if code in codes]


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
        warping_correction=r.flag(t, "warping_correction", label, default=PartSpec.warping_correction),
        element=r.string(t, "element", label, default=PartSpec.element, choices=tuple(SHELL_ELEMENTS)),
        rotary_inertia=r.string(t, "rotary_inertia", label, default=PartSpec.rotary_inertia,
                                choices=tuple(ROTARY_INERTIAS)),
        thickness_update=r.flag(t, "thickness_update", label, default=PartSpec.thickness_update),
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
    return FileGeometry(path=file, group=r.string(t, "group", label) if "group" in t else None)


# Memory of one element through meshing, the deck and the engine (bytes, measured order of magnitude:
# gmsh's mesh, the deck's arrays, the engine's state and results buffers); docs/scene.md.
BYTES_PER_ELEMENT = 4000


def _machine_memory() -> int:
    """Physical memory of this machine in bytes (0 where the system does not say)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return 0


def _requested_elements(geometry: Geometry) -> int:
    """The elements a generated geometry asks for (0 for a mesh file, which is already made)."""
    if isinstance(geometry, CylinderGeometry):
        return geometry.elements_around * geometry.elements_along
    if isinstance(geometry, PlateGeometry):
        return geometry.elements[0] * geometry.elements[1]
    return 0


def _check_mesh_size(r: _Reader, parts: list[PartSpec]) -> None:
    """A mesh request beyond this machine's memory is refused before meshing starts (issue 17)."""
    counts = {p.name: _requested_elements(p.geometry) for p in parts}
    total, memory = sum(counts.values()), _machine_memory()
    if memory and total * BYTES_PER_ELEMENT > memory:
        largest = max(counts, key=counts.__getitem__)
        raise r.error(f"the parts ask for {total:.3g} elements (part '{largest}': {counts[largest]:.3g}), about "
                      f"{total * BYTES_PER_ELEMENT / 2**30:.0f} GiB to mesh and run, more than this machine's "
                      f"{memory / 2**30:.0f} GiB; use fewer elements")


def _parse_dofs(r: _Reader, t: dict[str, Any], label: str) -> tuple[str, ...]:
    value = r.raw(t, "dofs", label, ["all"])
    items = [value] if isinstance(value, str) else value
    allowed = deck.DOF_NAMES + tuple(DOF_GROUPS)
    if not isinstance(items, list) or not items or not all(isinstance(v, str) for v in items):
        raise r.error(f"'dofs' in {label} must be a list of dof names from: {', '.join(allowed)}")
    chosen: set[str] = set()
    for item in items:
        if item not in allowed:
            raise r.error(f"'dofs' in {label} contains '{item}', which is not one of: {', '.join(allowed)}; "
                          f"{did_you_mean(item, allowed)}".rstrip("; ").rstrip())
        chosen.update(DOF_GROUPS.get(item, (item,)))
    return tuple(d for d in deck.DOF_NAMES if d in chosen)


def _parse_fix(r: _Reader, t: dict[str, Any], index: int) -> FixSpec:
    label = _label("fix", index, t)
    r.keys(t, label, _FIX_KEYS)
    return FixSpec(part=r.string(t, "part", label), box=_parse_box(r, t, label), dofs=_parse_dofs(r, t, label))


def _parse_box(r: _Reader, t: dict[str, Any], label: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
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
    return (lo, hi)


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


def _parse_curve(r: _Reader, t: dict[str, Any], index: int) -> CurveSpec:
    label = _label("curve", index, t)
    r.keys(t, label, _CURVE_KEYS)
    name = r.string(t, "name", label)
    points = {key: r.raw(t, key, label, _REQUIRED) for key in ("time", "value")}
    for key, items in points.items():
        if not isinstance(items, list) or not items:
            raise r.error(f"'{key}' in {label} must be a non-empty list of numbers, got {items!r}")
    if len(points["time"]) != len(points["value"]):
        raise r.error(f"{label} has {len(points['time'])} times and {len(points['value'])} values; give one "
                      f"value per time")
    time = r.vector(points, "time", label, length=len(points["time"]))
    value = r.vector(points, "value", label, length=len(points["value"]))
    if any(b <= a for a, b in itertools.pairwise(time)):
        raise r.error(f"'time' in {label} must increase strictly, got {list(time)}")
    return CurveSpec(name=name, time=time, value=value)


def _parse_pressure(r: _Reader, t: dict[str, Any], index: int) -> PressureSpec:
    label = _label("pressure", index, t)
    r.keys(t, label, _PRESSURE_KEYS)
    return PressureSpec(part=r.string(t, "part", label), value=r.number(t, "value", label),
                        curve=r.string(t, "curve", label) if "curve" in t else None)


def _parse_prescribe(r: _Reader, t: dict[str, Any], index: int) -> PrescribeSpec:
    label = _label("prescribe", index, t)
    r.keys(t, label, _PRESCRIBE_KEYS)
    birth, death = read_life(r, t, label, "motion", PrescribeSpec)
    return PrescribeSpec(part=r.string(t, "part", label), box=_parse_box(r, t, label),
                         dof=r.string(t, "dof", label, choices=deck.DOF_NAMES), value=r.number(t, "value", label),
                         curve=r.string(t, "curve", label) if "curve" in t else None, birth_time=birth,
                         death_time=death)


def _check_load_references(r: _Reader, scene: Scene) -> None:
    """Curves are uniquely named; pressures and prescribed velocities name defined parts and curves."""
    r.unique([c.name for c in scene.curves], "curve")
    parts, curves = [p.name for p in scene.parts], [c.name for c in scene.curves]
    for kind, items in (("pressure", scene.pressures), ("prescribe", scene.prescribed)):
        for index, item in enumerate(items):
            if item.part not in parts:
                raise r.error(f"[[{kind}]] #{index + 1} refers to part '{item.part}', which is not "
                              f"defined; {did_you_mean(item.part, parts)}(parts: {', '.join(parts)})")
            if item.curve is not None and item.curve not in curves:
                known = ", ".join(curves) or "none defined"
                raise r.error(f"[[{kind}]] #{index + 1} refers to curve '{item.curve}', which is not defined; "
                              f"{did_you_mean(item.curve, curves)}(curves: {known}); add a [[curve]] with that "
                              f"name or leave 'curve' out for a constant load")


def _check_references(r: _Reader, scene: Scene) -> None:
    r.unique([m.name for m in scene.materials], "material")
    r.unique([p.name for p in scene.parts], "part")
    r.unique([t.name for t in scene.tracks], "track")
    if not scene.parts:
        raise r.error("the scene has no [[part]]; add at least one part with a geometry")
    materials = [m.name for m in scene.materials]
    for part in scene.parts:
        if part.material not in materials:
            known = ", ".join(materials) or "none defined"
            raise r.error(f"part '{part.name}' uses material '{part.material}', which is not defined; "
                          f"{did_you_mean(part.material, materials)}(materials: {known}); add a [[material]] "
                          f"with that name")
    parts = [p.name for p in scene.parts]
    for kind, items in (("fix", scene.fixes), ("load", scene.loads), ("track", scene.tracks)):
        for index, item in enumerate(items):
            if item.part not in parts:
                raise r.error(f"[[{kind}]] #{index + 1} refers to part '{item.part}', which is not "
                              f"defined; {did_you_mean(item.part, parts)}(parts: {', '.join(parts)})")
    for kind, entries in (("contact", scene.contacts), ("weld", scene.welds)):
        for index, names in enumerate(entry.parts for entry in entries):
            for name in (name for name in names if name not in parts):
                raise r.error(f"[[{kind}]] #{index + 1} names part '{name}', which is not defined; "
                              f"{did_you_mean(name, parts)}(parts: {', '.join(parts)})")
