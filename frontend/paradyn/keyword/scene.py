"""An LS-DYNA keyword deck as a ParaDyn scene and deck model (docs/keyword.md).

:func:`load_keyword` reads a ``.k`` file (:mod:`paradyn.keyword.reader`, :mod:`paradyn.keyword.cards`)
and returns a :class:`KeywordScene`: the scene-level description (materials, parts, contacts as
:mod:`paradyn.scene.specs` objects, with the node-level data of the deck beside them), the deck
model in SI, the ids of the deck's nodes, elements and parts, and the warnings. :func:`read_keyword`
returns the model alone and prints the warnings. Nodes keep the deck's sharing between parts (a
keyword mesh is one mesh, unlike a TOML scene's parts).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from paradyn import _schema, deck
from paradyn.deck.rigid_bodies import RigidBodyError, complete_rigid_bodies
from paradyn.deck.rotation_ties import add_rotation_ties
from paradyn.scene.building import _apply_contacts, _apply_material_extras, apply_trusses
from paradyn.scene.specs import CurveSpec, MaterialSpec, PartSpec, RunSettings, Scene

from .beams import beam_pids, beam_thickness, truss_part_spec
from .cards import KeywordData, Record, with_warnings
from .contacts import contact_specs
from .erosion import warn_unused_erosions
from .ids import in_deck_ids
from .keywords import collect
from .loads import apply_loads, set_velocities
from .masses import apply_masses
from .materials import apply_material_curves, material_of
from .mesh import KeywordMesh, fixed_dofs, initial_velocities, mesh_of
from .parts import part_spec, split_by_thickness
from .reader import KeywordError, read_keyword_file
from .rigid import (
    SolidGeometry,
    add_solid_faces,
    body_motions,
    body_velocities,
    extra_nodes,
    merged_pairs,
    nodal_bodies,
    part_inertia,
    rigid_body_rows,
    rigid_material_key,
    solid_face_thickness,
)
from .units import Units, UnitsError
from .walls import apply_rigid_walls


@dataclass
class KeywordScene:
    """A keyword deck read: the scene it describes, the deck model, ids and warnings."""

    scene: Scene
    model: deck.Model
    mesh: KeywordMesh
    units: Units
    warnings: list[str] = field(default_factory=list)

    @property
    def part_ids(self) -> np.ndarray:
        return self.mesh.part_ids


def read_keyword(path: str | Path, units: str | None = None, quiet: bool = False) -> deck.Model:
    """The deck model of an LS-DYNA keyword file, in SI; the warnings go to standard error.

    Parameters
    ----------
    path : str or Path
        The ``.k`` file; ``*INCLUDE`` files are found relative to the file that names them.
    units : str, optional
        The deck's unit system, one of :data:`paradyn.keyword.units.SYSTEMS` (``"SI"``,
        ``"mm-t-s"``, ``"mm-kg-ms"``, ``"mm-g-ms"``); by default the deck's ``*CONTROL_UNITS``, or SI.
    quiet : bool
        True keeps the warnings (unsupported keywords and fields, the units) off standard error.

    Raises
    ------
    paradyn.keyword.reader.KeywordError
        A deck that cannot be read; the message names the file, the line and the field.
    """
    read = load_keyword(path, units)
    if not quiet:
        for line in read.warnings:
            print(f"paradyn: warning: {line}", file=sys.stderr)
    return read.model


def keyword_scene(path: str | Path, units: str | None = None) -> Scene:
    """The scene-level description of a keyword file: run settings, materials, parts (each with
    its elements of the deck's mesh as geometry) and contacts, in SI. The node-level data (fixed
    dofs, initial velocities, tracked nodes) has no scene form; :func:`load_keyword` adds it."""
    return _read(Path(path), units)[0]


def _read(path: Path, units: str | None) -> tuple[Scene, KeywordData, Units, KeywordMesh]:
    data = collect(read_keyword_file(path))
    try:
        unit = _units(path, data, units)
        solids = add_solid_faces(data)
        mesh = mesh_of(data, unit)
        _add_solid_masses(data, solids, unit, mesh)
        split_by_thickness(data, mesh, {pid: t / unit.length for pid, t in mesh.face_thickness.items()}
                           | beam_thickness(data))
        return _scene(path, data, unit, mesh), data, unit, mesh
    except KeywordError as exc:
        raise with_warnings(exc, data.warnings) from exc


def load_keyword(path: str | Path, units: str | None = None) -> KeywordScene:
    """Read a keyword file into a :class:`KeywordScene` (see :func:`read_keyword`); an error
    carries the warnings collected before it."""
    path = Path(path)
    scene, data, unit, mesh = _read(path, units)
    try:
        model = _model(scene, data, unit, mesh)
        deck.validate_model(model, source=f"{path} (model read from the keyword deck)")
    except KeywordError as exc:
        raise with_warnings(exc, data.warnings) from exc
    except deck.DeckError as exc:
        raise with_warnings(KeywordError(in_deck_ids(str(exc), data, mesh)), data.warnings) from exc
    return KeywordScene(scene=scene, model=model, mesh=mesh, units=unit, warnings=data.warnings)


def _units(path: Path, data: KeywordData, units: str | None) -> Units:
    record = data.control.get("CONTROL_UNITS")
    try:
        if units is not None:
            chosen = Units.named(units)
            said = f"units = '{units}' given by the caller"
            if record is not None:
                said += f" (the deck's *CONTROL_UNITS at {record.where} is overridden)"
        elif record is not None:
            chosen = Units.of(str(record["LENGTH"]), str(record["TIME"]), str(record["MASS"]))
            said = f"*CONTROL_UNITS at {record.where}"
        else:
            chosen = Units.named("SI")
            said = ("no *CONTROL_UNITS: the numbers are taken as SI; add *CONTROL_UNITS or pass "
                    "units='mm-t-s' (or another system) if they are not")
    except UnitsError as exc:
        raise KeywordError(f"{path}: {exc}") from exc
    data.warn(f"{path}: units {chosen.describe()}, converted to SI: {said}")
    return chosen


def _scene(path: Path, data: KeywordData, unit: Units, mesh: KeywordMesh) -> Scene:
    run = _run(data, unit)
    curves: list[CurveSpec] = []   # the materials' curves (LCSS, EPS/ES, LCSR), in SI
    parts, materials = _parts_and_materials(data, unit, mesh, curves)
    names_of: dict[int, list[str]] = {}   # the parts with a contact surface: trusses have none
    for pid, part in zip(mesh.part_ids.tolist(), parts, strict=True):
        if part.element_kind == "shell":
            names_of.setdefault(pid, []).append(part.name)
    contacts = contact_specs(data, names_of, unit, run.end_time / unit.time)
    return Scene(path=path, title=data.title or path.stem, run=run, materials=materials, parts=parts,
                 contacts=contacts, curves=curves)


def _part_name(record: Record, taken: set[str]) -> str:
    heading, pid = str(record["HEADING"] or "").strip(), int(record["PID"])
    name = heading if heading and heading not in taken else f"part_{pid}"
    taken.add(name)
    return name


def _add_solid_masses(data: KeywordData, solids: SolidGeometry, unit: Units, mesh: KeywordMesh) -> None:
    """The rigid solids' lumped mass on the mesh's nodes (SI) and their faces' contact thickness."""
    mass = np.zeros(len(mesh.node_ids))
    for nid, value in solids.node_mass.items():
        if nid in mesh.node_index:
            mass[mesh.node_index[nid]] += value * unit.mass
    mesh.added_mass = mass
    mesh.face_thickness = {pid: t * unit.length for pid, t in solid_face_thickness(data, solids).items()}


def _parts_and_materials(data: KeywordData, unit: Units, mesh: KeywordMesh,
                         curves: list[CurveSpec]) -> tuple[list[PartSpec], list[MaterialSpec]]:
    by_pid = {int(p["PID"]): p for p in data.parts}
    parts: list[PartSpec] = []
    materials: dict[tuple[str, int], MaterialSpec] = {}
    taken: set[str] = set()
    base_names: dict[int, str] = {}
    trusses = beam_pids(data)
    warn_unused_erosions(data, {int(by_pid[pid]["MID"] or 0) for pid in mesh.part_ids.tolist()})
    for index, pid in enumerate(mesh.part_ids.tolist()):
        record = by_pid[pid]
        mid = int(record["MID"] or 0)
        if mid not in data.materials:
            raise KeywordError(f"{record.where}: *PART {pid} names material {mid}, which no *MAT_ELASTIC, "
                               f"*MAT_PLASTIC_KINEMATIC, *MAT_PIECEWISE_LINEAR_PLASTICITY or *MAT_RIGID defines")
        key = rigid_material_key(data, pid, mid)
        if key not in materials:
            materials[key] = material_of(mid, data, unit, curves, rigid=bool(key[0]))
            title = str(data.materials[mid][1][0]["TITLE"])
            if title and title not in {m.name for m in materials.values()}:
                materials[key].name = title
            if key[0]:
                materials[key].name += "_rigid"
        if pid not in base_names:
            base_names[pid] = _part_name(record, taken)
        name = base_names[pid] + mesh.part_suffix[index]
        if pid in trusses:   # *ELEMENT_BEAM on a *SECTION_BEAM ELFORM 3 (keyword/beams.py)
            parts.append(truss_part_spec(data, record, name, materials[key].name, unit.length,
                                         mesh.part_geometry(index)))
        elif pid in mesh.face_thickness:   # a rigid solid: its faces, a contact surface (keyword/rigid.py)
            parts.append(PartSpec(name=name, material=materials[key].name, thickness=mesh.face_thickness[pid],
                                  geometry=mesh.part_geometry(index), integration_points=1))
        else:
            parts.append(part_spec(data, record, name, materials[key].name, unit, mesh, index))
    rigid = {m.name for m in materials.values() if m.model == "rigid"}
    for part in parts:   # a rigid part does not deform: ISTUPD leaves it alone
        part.thickness_update = part.thickness_update and part.material not in rigid
    return parts, list(materials.values())




def _run(data: KeywordData, unit: Units) -> RunSettings:
    termination = data.control.get("CONTROL_TERMINATION")
    if termination is None or not float(termination["ENDTIM"]) > 0.0:
        where = termination.where if termination else "the deck"
        raise KeywordError(f"{where}: *CONTROL_TERMINATION ENDTIM must be given and positive; give the end time")
    end = float(termination["ENDTIM"]) * unit.time
    plot = data.control.get("DATABASE_BINARY_D3PLOT")
    output = float(plot["DT"]) * unit.time if plot and float(plot["DT"]) > 0.0 else end / 20.0
    if not plot:
        data.warn("no *DATABASE_BINARY_D3PLOT: field frames every ENDTIM / 20")
    histories = [float(data.control[k]["DT"]) * unit.time for k in ("DATABASE_GLSTAT", "DATABASE_NODOUT")
                 if k in data.control and float(data.control[k]["DT"]) > 0.0]
    run = RunSettings(end_time=end, output_interval=output, history_interval=min(histories) if histories else None)
    if float(termination["DTMIN"]) > 0.0:
        run.time_step_floor = float(termination["DTMIN"])
    step = data.control.get("CONTROL_TIMESTEP")
    if step is not None:
        _time_step(data, step, unit, run)
    return run


def _time_step(data: KeywordData, step: Record, unit: Units, run: RunSettings) -> None:
    if float(step["TSSFAC"]) > 0.0:
        run.time_step_safety = float(step["TSSFAC"])
    dt2ms = float(step["DT2MS"])
    if dt2ms < 0.0:
        run.mass_scaling_step = run.time_step_safety * abs(dt2ms) * unit.time
    elif dt2ms > 0.0:
        data.warn(f"{step.where}: *CONTROL_TIMESTEP DT2MS > 0 (mass scaling of every element) is not "
                  f"supported and ignored; a negative DT2MS scales only the elements that need it")
    lctm = int(step["LCTM"])
    if lctm:
        if lctm not in data.curves:
            raise KeywordError(f"{step.where}: *CONTROL_TIMESTEP LCTM = {lctm} names no *DEFINE_CURVE")
        head, points = data.curves[lctm]
        values = {float(head["SFO"]) * o + float(head["OFFO"]) for _, o in points}
        if len(values) != 1:
            raise KeywordError(f"{head.where}: *DEFINE_CURVE {lctm} (LCTM, the largest step) must be constant; "
                               f"ParaDyn's step cap does not vary in time")
        run.time_step = values.pop() * unit.time


def _model(scene: Scene, data: KeywordData, unit: Units, mesh: KeywordMesh) -> deck.Model:
    fixed = fixed_dofs(data, mesh)
    velocity, angular = initial_velocities(data, mesh, unit, start=set_velocities(data, mesh, unit))
    velocity[fixed[:, :3] == 1] = 0.0
    angular[fixed[:, 3:] == 1] = 0.0
    material_index = {m.name: i for i, m in enumerate(scene.materials)}
    parts, materials = scene.parts, scene.materials
    model = deck.Model(
        coordinates=mesh.coordinates, connectivity=mesh.connectivity, element_part=mesh.element_part,
        thickness=np.array([p.thickness for p in parts]),
        part_material=np.array([material_index[p.material] for p in parts], dtype=np.int32),
        integration_points=np.array([p.integration_points for p in parts], dtype=np.int32),
        hourglass_coefficient=np.array([p.hourglass_coefficient for p in parts]),
        hourglass_form=np.array([_schema.ENUMS["hourglass_form"][p.hourglass_form] for p in parts], dtype=np.int32),
        warping_correction=np.array([int(p.warping_correction) for p in parts], dtype=np.int32),
        material_model=np.array([m.model_code for m in materials], dtype=np.int32),
        density=np.array([m.density for m in materials]),
        youngs_modulus=np.array([m.youngs_modulus for m in materials]),
        poisson_ratio=np.array([m.poisson_ratio for m in materials]),
        yield_stress=np.array([m.yield_stress for m in materials]),
        tangent_modulus=np.array([m.tangent_modulus for m in materials]),
        hardening_mixing=np.array([m.hardening_mixing for m in materials]),
        initial_velocity=velocity, initial_angular_velocity=angular, fixed_dofs=fixed,
        control=deck.Control(**vars(scene.run)), title=scene.title,
        part_names=[p.name for p in parts], material_names=[m.name for m in materials],
    )
    _apply_material_extras(scene, model)
    apply_trusses(scene, model)
    apply_loads(data, mesh, unit, model, scene.run.end_time)
    apply_material_curves(scene, model)
    _apply_contacts(scene, model)
    apply_rigid_walls(data, unit, mesh, model)
    _apply_tracks(data, mesh, model)
    apply_masses(data, mesh, unit, model)
    _apply_rigid_bodies(data, mesh, unit, model)
    names = list(model.part_names or [])
    for slave, master in data.shell_edges:   # *CONTACT_TIED_SHELL_EDGE_TO_SURFACE: rotations tied too
        add_rotation_ties(model, names.index(slave), names.index(master))
    mesh.store_ids(model)
    return model


def _apply_rigid_bodies(data: KeywordData, mesh: KeywordMesh, unit: Units, model: deck.Model) -> None:
    """The rigid parts' bodies, the solids' faces as surfaces without mass and their mass on the nodes."""
    by_pid = {int(p["PID"]): p for p in data.parts}
    mids = [int(by_pid[pid]["MID"] or 0) for pid in mesh.part_ids.tolist()]
    parts, held = rigid_body_rows(data, mesh.part_ids, mids)
    if not parts and not data.welds:
        if data.rigid_motions:
            raise KeywordError(f"{data.rigid_motions[0][4]}: *BOUNDARY_PRESCRIBED_MOTION_RIGID names part "
                               f"{data.rigid_motions[0][0]}, but the deck has no rigid part; give it *MAT_RIGID")
        return
    model.rigid_body_part = np.array(parts, dtype=np.int32)
    model.rigid_body_fixed_dofs = np.array(held, dtype=np.int32).reshape(-1, 6)
    model.surface_only = np.array([int(pid in mesh.face_thickness) for pid in mesh.part_ids.tolist()], dtype=np.int32)
    if mesh.added_mass is not None and mesh.added_mass.any():   # the rigid solids' mass, besides *ELEMENT_MASS
        model.added_mass = mesh.added_mass + (0.0 if model.added_mass is None else np.asarray(model.added_mass))
    rows: dict[int, list[int]] = {}
    for k, pid in enumerate(mesh.part_ids.tolist()):
        rows.setdefault(pid, []).append(k)
    row = {pid: k[0] for pid, k in rows.items()}
    merge = [(k[0], other) for k in rows.values() for other in k[1:]]   # a PID split by thickness: one body
    for a, b in merged_pairs(data):
        if a not in row or b not in row:
            raise KeywordError(f"merging rigid bodies: part {a if a not in row else b} has no elements; name parts "
                               f"with elements in *CONSTRAINED_RIGID_BODIES and *DEFORMABLE_TO_RIGID MRB")
        merge.append((row[a], row[b]))
    try:
        for note in complete_rigid_bodies(model, merge, extra_nodes(data, mesh, row), nodal_bodies(data, mesh, unit)):
            data.warn(note)
    except RigidBodyError as exc:
        raise KeywordError(str(exc)) from exc
    part_inertia(data, mesh, row, unit, model)
    body_velocities(data, mesh, row, unit, model)
    body_motions(data, row, model)


def _apply_tracks(data: KeywordData, mesh: KeywordMesh, model: deck.Model) -> None:
    nodes, names = [], []
    for nid, heading, where in data.history_nodes:
        index = mesh.node_index.get(nid)
        if index is None:
            raise KeywordError(f"{where}: *DATABASE_HISTORY_NODE names node {nid}, which no shell element uses")
        name = heading.strip() or f"node_{nid}"
        names.append(name if name not in names else f"{name}_{nid}")
        nodes.append(index)
    model.tracked_nodes = np.array(nodes, dtype=np.int32)
    model.tracked_names = names


__all__ = ["KeywordScene", "keyword_scene", "load_keyword", "read_keyword"]
