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
from paradyn.scene.building import _apply_contacts, _apply_material_extras, set_curves
from paradyn.scene.specs import ContactSpec, MaterialSpec, PartSpec, RunSettings, Scene

from .cards import KeywordData, Record, collect, with_warnings
from .mesh import KeywordMesh, fixed_dofs, initial_velocities, mesh_of
from .reader import KeywordError, read_keyword_file
from .units import Units, UnitsError
from .walls import apply_rigid_walls

MAX_INTEGRATION_POINTS = int(next(d.upper.value for d in _schema.DATASETS if d.python == "integration_points"))
# LS-DYNA's IHQ for shells -> ParaDyn's hourglass form (docs/keyword.md)
HOURGLASS_OF_IHQ = {0: "viscous", 1: "viscous", 2: "viscous", 3: "viscous", 4: "stiffness", 5: "stiffness"}
WARPING_OF_ELFORM = {2: False, 10: True}   # Belytschko-Tsay; Belytschko-Wong-Chiang


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
        mesh = mesh_of(data, unit)
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
        raise with_warnings(KeywordError(str(exc)), data.warnings) from exc
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


def _id_list(data: KeywordData, kind: int, ident: int, where: str, what: str) -> list[int]:
    """Part ids of a contact side: ``kind`` is LS-DYNA's SSTYP/MSTYP (2 part set, 3 part, 5 all);
    an id of 0 takes every part."""
    every = [int(p["PID"]) for p in data.parts]
    if kind == 5 or ident == 0:
        return every
    if kind == 3:
        return [ident]
    if kind == 2:
        if ident not in data.part_sets:
            raise KeywordError(f"{where}: {what} names part set {ident}, which no *SET_PART defines")
        return data.part_sets[ident]
    raise KeywordError(f"{where}: {what} type {kind} is not read; give parts (3), a part set (2) or all (5)")


def _scene(path: Path, data: KeywordData, unit: Units, mesh: KeywordMesh) -> Scene:
    parts, materials = _parts_and_materials(data, unit, mesh)
    name_of = {pid: p.name for pid, p in zip(mesh.part_ids.tolist(), parts, strict=True)}
    contacts = [c for kind, cards in data.contacts for c in _contacts(data, kind, cards, name_of, unit)]
    return Scene(path=path, title=data.title or path.stem, run=_run(data, unit), materials=materials,
                 parts=parts, contacts=contacts)


def _part_name(record: Record, taken: set[str]) -> str:
    heading, pid = str(record["HEADING"] or "").strip(), int(record["PID"])
    name = heading if heading and heading not in taken else f"part_{pid}"
    taken.add(name)
    return name


def _parts_and_materials(data: KeywordData, unit: Units,
                         mesh: KeywordMesh) -> tuple[list[PartSpec], list[MaterialSpec]]:
    by_pid = {int(p["PID"]): p for p in data.parts}
    parts: list[PartSpec] = []
    materials: dict[int, MaterialSpec] = {}
    taken: set[str] = set()
    for pid in mesh.part_ids.tolist():
        record = by_pid[pid]
        mid = int(record["MID"] or 0)
        if mid not in data.materials:
            raise KeywordError(f"{record.where}: *PART {pid} names material {mid}, which no *MAT_ELASTIC or "
                               f"*MAT_PLASTIC_KINEMATIC defines")
        if mid not in materials:
            materials[mid] = _material(mid, *data.materials[mid], unit)
            title = str(data.materials[mid][1][0]["TITLE"])
            if title and title not in {m.name for m in materials.values()}:
                materials[mid].name = title
        parts.append(_part(data, record, _part_name(record, taken), materials[mid].name, unit, mesh))
    return parts, list(materials.values())


def _material(mid: int, model: str, cards: list[Record], unit: Units) -> MaterialSpec:
    first = cards[0]
    for name in ("RO", "E", "PR"):
        if first[name] is None:
            raise KeywordError(f"{first.where}: *MAT {mid} field {name} is blank; give its value")
    spec = MaterialSpec(name=f"mat_{mid}", model=model, density=float(first["RO"]) * unit.density,
                        youngs_modulus=float(first["E"]) * unit.stress, poisson_ratio=float(first["PR"]))
    if model == "j2_plasticity":
        if first["SIGY"] is None:
            raise KeywordError(f"{first.where}: *MAT_PLASTIC_KINEMATIC {mid} field SIGY is blank; give the "
                               f"yield stress")
        spec.yield_stress = float(first["SIGY"]) * unit.stress
        spec.tangent_modulus = float(first["ETAN"]) * unit.stress
        spec.hardening_mixing = float(first["BETA"])
        _rates(mid, cards[1], unit, spec)
    return spec


def _rates(mid: int, card: Record, unit: Units, spec: MaterialSpec) -> None:
    """MAT 3's Cowper-Symonds rate scaling: SRC = C (1 / the deck's time) and SRP = P make the
    material j2_rate; SRC = 0 means no rate effect, as in LS-DYNA."""
    c, p = float(card["SRC"] or 0.0), float(card["SRP"] or 0.0)
    if c == 0.0:
        return
    if c < 0.0 or p <= 0.0:
        raise KeywordError(f"{card.where}: *MAT_PLASTIC_KINEMATIC {mid} SRC = {c:g}, SRP = {p:g}: the Cowper-Symonds "
                           f"constants must both be > 0 (or SRC = 0 for no rate effect)")
    spec.model = "j2_rate"
    spec.extra = {"rate_c": c / unit.time, "rate_p": p}


def _part(data: KeywordData, record: Record, name: str, material: str, unit: Units, mesh: KeywordMesh) -> PartSpec:
    pid, secid = int(record["PID"]), int(record["SECID"] or 0)
    if secid not in data.sections:
        raise KeywordError(f"{record.where}: *PART {pid} names section {secid}, which no *SECTION_SHELL defines")
    first, second = data.sections[secid]
    thicknesses = [float(second[f"T{k}"]) for k in range(1, 5) if second[f"T{k}"]]
    if not thicknesses or thicknesses[0] <= 0.0:
        raise KeywordError(f"{second.where}: *SECTION_SHELL {secid} has no positive thickness T1; give it")
    if len(set(thicknesses)) > 1:
        data.warn(f"{second.where}: *SECTION_SHELL {secid} T1..T4 differ; ParaDyn's parts have one thickness, "
                  f"their mean {np.mean(thicknesses):g} is used")
    elform = int(first["ELFORM"])
    if elform not in WARPING_OF_ELFORM:
        data.warn(f"{first.where}: *SECTION_SHELL {secid} ELFORM = {elform} is not available; ParaDyn's "
                  f"Belytschko-Lin-Tsay shell (ELFORM 2) is used")
    nip = int(first["NIP"]) or 2
    if not 1 <= nip <= MAX_INTEGRATION_POINTS:
        raise KeywordError(f"{first.where}: *SECTION_SHELL {secid} NIP = {nip}; ParaDyn takes 1 to "
                           f"{MAX_INTEGRATION_POINTS} points through the thickness")
    form, coefficient = _hourglass(data, record)
    return PartSpec(name=name, material=material, thickness=float(np.mean(thicknesses)) * unit.length,
                    geometry=mesh.part_geometry(pid), integration_points=nip,
                    hourglass_coefficient=coefficient, hourglass_form=form,
                    warping_correction=WARPING_OF_ELFORM.get(elform, False))


def _hourglass(data: KeywordData, part: Record) -> tuple[str, float]:
    """The part's hourglass form and coefficient: its *HOURGLASS, else *CONTROL_HOURGLASS, else IHQ 1, 0.1."""
    hgid = int(part["HGID"] or 0)
    if hgid:
        if hgid not in data.hourglasses:
            raise KeywordError(f"{part.where}: *PART {part['PID']} names hourglass {hgid}, which no "
                               f"*HOURGLASS defines")
        record = data.hourglasses[hgid]
        ihq, coefficient = int(record["IHQ"]), float(record["QM"])
    elif "CONTROL_HOURGLASS" in data.control:
        record = data.control["CONTROL_HOURGLASS"]
        ihq, coefficient = int(record["IHQ"]), float(record["QH"])
    else:
        return "viscous", 0.1
    if ihq not in HOURGLASS_OF_IHQ:
        data.warn(f"{record.where}: IHQ = {ihq} has no ParaDyn counterpart for shells; the physical form is used")
        return "physical", coefficient
    return HOURGLASS_OF_IHQ[ihq], coefficient


def _contacts(data: KeywordData, kind: str, cards: list[Record], name_of: dict[int, str],
              unit: Units) -> list[ContactSpec]:
    first, second, third = cards
    slave = _id_list(data, int(first["SSTYP"]), int(first["SSID"]), first.where, "SSTYP")
    unknown = [pid for pid in slave if pid not in name_of]
    if unknown:
        raise KeywordError(f"{first.where}: the contact names part {unknown[0]}, which has no shell elements")
    slave_scale = _scale(third, "SFS")
    if _scale(third, "SFM") != slave_scale:
        data.warn(f"{third.where}: SFM = {third['SFM']} differs from SFS = {third['SFS']}; ParaDyn has one "
                  f"penalty scale per contact, SLSFAC x SFS is used")
    penalty = float(data.control["CONTROL_CONTACT"]["SLSFAC"]) if "CONTROL_CONTACT" in data.control else 0.1
    common = {"penalty_scale": penalty * slave_scale, "static_friction": float(second["FS"]),
              "dynamic_friction": float(second["FD"]),
              "friction_decay": float(second["DC"]) * unit.time / unit.length}
    if kind == "single_surface":   # every part: no parts, as in a scene (docs/scene.md)
        every = int(first["SSTYP"]) == 5 or int(first["SSID"]) == 0
        return [ContactSpec(parts=() if every else tuple(name_of[p] for p in slave), kind="single_surface",
                            **common)]
    master = _id_list(data, int(first["MSTYP"]), int(first["MSID"]), first.where, "MSTYP")
    pairs: dict[frozenset[int], tuple[int, int]] = {}   # symmetric: (a, b) and (b, a) are one contact
    for s, m in ((s, m) for s in slave for m in master if s != m and m in name_of):
        pairs.setdefault(frozenset((s, m)), (s, m))
    return [ContactSpec(parts=(name_of[s], name_of[m]), symmetric=True, **common) for s, m in pairs.values()]


def _scale(record: Record, name: str) -> float:
    value = record[name]
    return 1.0 if value is None else float(value)


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
    velocity, angular = initial_velocities(data, mesh, unit)
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
    _apply_body_loads(data, unit, model)
    _apply_contacts(scene, model)
    apply_rigid_walls(data, unit, mesh, model)
    _apply_tracks(data, mesh, model)
    mesh.store_ids(model)
    return model


def _apply_body_loads(data: KeywordData, unit: Units, model: deck.Model) -> None:
    """*LOAD_BODY_X/Y/Z as base accelerations (docs/keyword.md): SF times the curve LCID, an
    acceleration of the base, so the model is pushed the other way: a curve of 9.81 in
    *LOAD_BODY_Z is gravity along -z, as in LS-DYNA. Curves by *DEFINE_CURVE (SFA, SFO 0 meaning 1)."""
    if not data.body_loads:
        return
    used: list[int] = []
    for axis, record in data.body_loads:
        lcid = int(record["LCID"] or 0)
        if lcid not in data.curves:
            raise KeywordError(f"{record.where}: *LOAD_BODY_{axis} LCID = {lcid} names no *DEFINE_CURVE; define the "
                               f"curve of the acceleration")
        if lcid not in used:
            used.append(lcid)
    times, values = [], []
    for lcid in used:
        head, points = data.curves[lcid]
        sfa, sfo = float(head["SFA"]) or 1.0, float(head["SFO"]) or 1.0
        times.append([(a * sfa + float(head["OFFA"])) * unit.time for a, _ in points])
        values.append([o * sfo + float(head["OFFO"]) for _, o in points])
    set_curves(model, times, values)
    acceleration = unit.length / unit.time**2
    model.base_acceleration_direction = np.array([-np.eye(3)["XYZ".index(axis)] for axis, _ in data.body_loads])
    model.base_acceleration_value = np.array([float(r["SF"]) * acceleration for _, r in data.body_loads])
    model.base_acceleration_curve = np.array([used.index(int(r["LCID"])) for _, r in data.body_loads], dtype=np.int32)


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
