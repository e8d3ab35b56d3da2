"""Building the deck model from a scene: :func:`build_model` meshes the parts and assembles a deck.Model.

Parts do not share nodes; fixes and prescribed velocities select nodes in a box, loads and tracked
points take the nearest node of their part, contacts become part pairs, curves are numbered in
scene order with one constant curve added for the pressures and prescribed velocities without one.
(The engine alone decides which effects a model declares: results.h5 /effects.)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from paradyn import _schema, deck
from paradyn.arguments import did_you_mean
from paradyn.deck.rigid_bodies import RigidBodyError, complete_rigid_bodies
from paradyn.mesh import geometry
from paradyn.scene.welds import scene_welds

from .row_tables import needs_constant_curve, rows_to_model, scene_words
from .specs import HOURGLASS_FORMS, ContactSpec, PartSpec, Scene, SceneError
from .tables import _Reader

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
    _check_thickness_updates(r, scene, meshes)
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
        warping_correction=np.array([int(p.warping_correction) for p in scene.parts], dtype=np.int32),
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
    _apply_material_extras(scene, model)
    apply_trusses(scene, model)
    _apply_loads(r, scene, by_name, model)
    _apply_tracks(r, scene, by_name, model)
    _apply_contacts(scene, model)
    _apply_curve_loads(r, scene, by_name, model)
    _apply_file_ids(meshes, model)
    welds = scene_welds(scene.welds, lambda part, point, label: _located_node(r, by_name[part], point, label))
    try:
        complete_rigid_bodies(model, nodal=welds)
    except RigidBodyError as exc:
        raise SceneError(f"{scene.path}: {exc}") from exc
    try:
        deck.validate_model(model, source=f"{scene.path} (built model)")
    except deck.DeckError as exc:
        raise SceneError(scene_words(str(exc))) from exc
    return model


def _mesh_parts(r: _Reader, scene: Scene) -> list[_PartMesh]:
    meshes: list[_PartMesh] = []
    first = 0
    for part in scene.parts:
        try:
            mesh = geometry.shapes_in_runs(part.geometry.mesh())   # a part's triangles after its quads
        except geometry.GeometryError as exc:
            raise r.error(f"[part.geometry] of part '{part.name}': {exc}") from exc
        meshes.append(_PartMesh(spec=part, mesh=mesh, first_node=first))
        first += mesh.n_nodes
    return meshes


def _fixed_dofs(r: _Reader, scene: Scene, by_name: dict[str, _PartMesh], n_nodes: int) -> np.ndarray:
    fixed = np.zeros((n_nodes, 6), dtype=np.int32)
    columns_of = {name: i for i, name in enumerate(deck.DOF_NAMES)}
    for index, fix in enumerate(scene.fixes):
        nodes = _nodes_in_box(r, by_name[fix.part], fix.box, f"[[fix]] #{index + 1}")
        columns = [columns_of[d] for d in fix.dofs]
        fixed[np.ix_(nodes, columns)] = 1
    return fixed


def _nodes_in_box(r: _Reader, part: _PartMesh, box: tuple[tuple[float, ...], tuple[float, ...]],
                  label: str) -> np.ndarray:
    """Global indices of the part's nodes inside the box; an empty box is an error."""
    local = geometry.nodes_in_box(part.mesh.coordinates, box[0], box[1], tol=1e-9 * max(part.size, 1.0))
    if local.size == 0:
        c = part.mesh.coordinates
        raise r.error(f"{label}: the box {[list(box[0]), list(box[1])]} contains "
                      f"no node of part '{part.spec.name}' (its nodes span {c.min(axis=0).tolist()} to "
                      f"{c.max(axis=0).tolist()}); enlarge or move the box")
    return local + part.first_node


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


def _deck_contacts(scene: Scene) -> list[tuple[int, int, str, ContactSpec]]:
    """The deck's contact definitions (part, part, kind, spec). A single_surface contact over
    several parts is one surface: each part against itself, and each two parts a symmetric
    node_to_segment pair (docs/scene.md); with no parts named, every shell part. With edges, the
    kinds with edge checks: edge_to_edge pairs and single_surface_edges."""
    index = {p.name: i for i, p in enumerate(scene.parts)}
    rows: list[tuple[int, int, str, ContactSpec]] = []
    for c in scene.contacts:
        pair_kind = "edge_to_edge" if c.edges else "node_to_segment"
        if c.kind != "single_surface":
            rows.append((index[c.parts[0]], index[c.parts[1]], pair_kind if c.kind == "node_to_segment" else c.kind, c))
            continue
        every = [p.name for p in scene.parts if p.element_kind == "shell"]   # trusses have no surface
        members = [index[name] for name in (c.parts or every)]
        rows += [(a, a, "single_surface_edges" if c.edges else "single_surface", c) for a in members]
        pair = dataclasses.replace(c, symmetric=True)
        rows += [(a, b, pair_kind, pair) for i, a in enumerate(members) for b in members[i + 1:]]
    return rows


def _apply_contacts(scene: Scene, model: deck.Model) -> None:
    rows = _deck_contacts(scene)
    contacts = [c for _, _, _, c in rows]
    model.contact_pairs = np.array([[a, b] for a, b, _, _ in rows], dtype=np.int32).reshape(-1, 2)
    model.contact_penalty_scale = np.array([c.penalty_scale for c in contacts])
    model.contact_soft_constraint = np.array([c.soft_constraint for c in contacts])
    # a single_surface contact's one scale on each side of its rows
    model.contact_thickness_scale = np.array([c.thickness_scale for c in contacts], dtype=float).reshape(-1, 2)
    model.contact_static_friction = np.array([c.static_friction for c in contacts])
    model.contact_dynamic_friction = np.array([c.dynamic_friction for c in contacts])
    model.contact_friction_decay = np.array([c.friction_decay for c in contacts])
    passes = _schema.ENUMS["contact_passes"]
    model.contact_passes = np.array([passes["both"] if c.symmetric else passes["alternate"] for c in contacts],
                                    dtype=np.int32)
    model.contact_kind = np.array([_schema.ENUMS["contact_kind"][kind] for _, _, kind, _ in rows], dtype=np.int32)
    model.contact_initial_penetration = np.array([_schema.ENUMS["initial_penetration"][c.initial_penetration]
                                                  for c in contacts], dtype=np.int32)
    model.contact_birth_time = np.array([c.birth_time for c in contacts])
    model.contact_death_time = np.array([c.death_time for c in contacts])
    model.contact_normal_failure_stress = np.array([c.normal_failure_stress for c in contacts])
    model.contact_shear_failure_stress = np.array([c.shear_failure_stress for c in contacts])


def _apply_file_ids(meshes: list[_PartMesh], model: deck.Model) -> None:
    """The ids of meshes read from files (gmsh tags, the physical group's tag); 0 where a part has none."""
    if all(m.mesh.node_ids is None for m in meshes):
        return

    def ids(values: np.ndarray | None, count: int) -> np.ndarray:
        return np.zeros(count, dtype=np.int64) if values is None else values

    model.node_ids = np.concatenate([ids(m.mesh.node_ids, m.mesh.n_nodes) for m in meshes])
    model.element_ids = np.concatenate([ids(m.mesh.element_ids, m.mesh.n_elements) for m in meshes])
    model.part_ids = np.array([m.mesh.part_id or 0 for m in meshes], dtype=np.int64)


def _check_thickness_updates(r: _Reader, scene: Scene, meshes: list[_PartMesh]) -> None:
    """``thickness_update`` is the one-point quadrilateral's (docs/theory.md, "Thickness update"): a part
    with it has no triangles, no fully integrated element, no truss and no rigid material."""
    rigid = {m.name for m in scene.materials if m.model == "rigid"}
    for m in meshes:
        p = m.spec
        if not p.thickness_update:
            continue
        triangles = int(np.count_nonzero(m.mesh.quads[:, 2] == m.mesh.quads[:, 3])) if m.mesh.n_elements else 0
        why = ("its element is \"full\"" if p.element == "full" else "it is a truss part" if p.element_kind != "shell"
               else "its material is rigid" if p.material in rigid
               else f"it has {triangles} triangles" if triangles else "")
        if why:
            raise r.error(f"[[part]] '{p.name}' has thickness_update = true, but {why}: the thickness update is the "
                          f"one-point quadrilateral's (element = \"blt\", no triangles); remove thickness_update or "
                          f"mesh the part with quadrilaterals of the one-point element")


def apply_trusses(scene: Scene, model: deck.Model) -> None:
    """/parts/shell_element where some part is fully integrated (``element = "full"``), and
    /parts/element_kind and /parts/cross_section_area where some part is a truss part;
    /parts/rotary_inertia where some part's is not the default, /parts/thickness_update where some
    part updates its thickness (the default deck stays bitwise)."""
    if any(p.element != "blt" for p in scene.parts):
        elements = _schema.ENUMS["shell_element"]
        model.shell_element = np.array([elements[p.element] for p in scene.parts], dtype=np.int32)
    if any(p.rotary_inertia != PartSpec.rotary_inertia for p in scene.parts):
        rules = _schema.ENUMS["rotary_inertia"]
        model.rotary_inertia = np.array([rules[p.rotary_inertia] for p in scene.parts], dtype=np.int32)
    if any(p.thickness_update for p in scene.parts):
        model.thickness_update = np.array([int(p.thickness_update) for p in scene.parts], dtype=np.int32)
    if all(p.element_kind == "shell" for p in scene.parts):
        return
    kinds = _schema.ENUMS["element_kind"]
    model.element_kind = np.array([kinds[p.element_kind] for p in scene.parts], dtype=np.int32)
    model.cross_section_area = np.array([p.cross_section_area for p in scene.parts])


def _apply_material_extras(scene: Scene, model: deck.Model) -> None:
    """The /materials datasets that MaterialSpec keeps in ``extra`` (a model's own parameters):
    each material's value, or the dataset's default for a material of another model. A curve key
    holds a [[curve]]'s name: its index in scene order (the deck's curves start with the scene's),
    -1 where none is named."""
    curve_index = {c.name: i for i, c in enumerate(scene.curves)}
    for spec in _schema.DATASETS:
        if spec.path.startswith("/materials/") and any(spec.python in m.extra for m in scene.materials):
            values = [m.extra.get(spec.python, spec.default) for m in scene.materials]
            if spec.reference == "curve":
                values = [spec.default if v is None or v == spec.default else curve_index[v] for v in values]
            setattr(model, spec.python, np.array(values, dtype=np.int32 if spec.type == "int" else np.float64))


def check_material_curves(r: _Reader, scene: Scene) -> None:
    """A material's curve keys (hardening_curve, rate_curve) name defined [[curve]]s that meet the
    relation material_curves (docs/formats.md): a hardening curve from (0, yield_stress), never
    decreasing; a rate curve of rates >= 0 and factors > 0."""
    curves = {c.name: c for c in scene.curves}
    for index, material in enumerate(scene.materials):
        for key, kind in (("hardening_curve", "hardening"), ("rate_curve", "rate")):
            name = material.extra.get(key)
            if not isinstance(name, str):
                continue
            label = f"'{key}' = '{name}' in [[material]] #{index + 1} '{material.name}'"
            if name not in curves:
                raise r.error(f"{label} names no [[curve]]; {did_you_mean(name, curves)}defined: "
                              f"{', '.join(curves) or 'none'}")
            curve = curves[name]
            fault = deck.material_curve_fault(kind, np.asarray(curve.time), np.asarray(curve.value),
                                              material.yield_stress)
            if fault:
                words = "time = plastic strain, value = yield stress (Pa)" if kind == "hardening" else \
                    "time = strain rate (1/s), value = factor on the yield stress"
                raise r.error(f"{label} ({words}): {fault.replace('/materials/yield_stress', 'yield_stress')}")


def set_curves(model: deck.Model, times: list[list[float]], values: list[list[float]]) -> None:
    """The deck's curves, one list of times and of values each, in order (/curves)."""
    model.curve_first_point = np.cumsum([0] + [len(t) for t in times])[:-1].astype(np.int32)
    model.curve_time = np.array([t for curve in times for t in curve], dtype=np.float64)
    model.curve_value = np.array([v for curve in values for v in curve], dtype=np.float64)


def _apply_curve_loads(r: _Reader, scene: Scene, by_name: dict[str, _PartMesh], model: deck.Model) -> None:
    """Curves in scene order, then one constant curve (factor 1) if a pressure, a prescribed
    velocity or a row has none, so that every load of the deck names a curve; then the row tables."""
    curve_index = {c.name: i for i, c in enumerate(scene.curves)}
    times = [list(c.time) for c in scene.curves]
    values = [list(c.value) for c in scene.curves]
    if any(load.curve is None for load in [*scene.pressures, *scene.prescribed]) or needs_constant_curve(scene):
        times.append([0.0])
        values.append([1.0])
    constant = len(scene.curves)
    set_curves(model, times, values)
    part_index = {p.name: i for i, p in enumerate(scene.parts)}
    model.pressure_part = np.array([part_index[p.part] for p in scene.pressures], dtype=np.int32)
    model.pressure_value = np.array([p.value for p in scene.pressures], dtype=np.float64)
    model.pressure_curve = np.array([constant if p.curve is None else curve_index[p.curve] for p in scene.pressures],
                                    dtype=np.int32)
    rows: dict[tuple[int, int], int] = {}   # (node, dof) -> [[prescribe]] entry
    nodes, dofs, scales, curves, births, deaths = [], [], [], [], [], []
    for index, motion in enumerate(scene.prescribed):
        label = f"[[prescribe]] #{index + 1}"
        dof = deck.DOF_NAMES.index(motion.dof) + 1
        for node in _nodes_in_box(r, by_name[motion.part], motion.box, label):
            if (int(node), dof) in rows:
                raise r.error(f"{label}: node {int(node)} already has its {motion.dof} velocity prescribed by "
                              f"[[prescribe]] #{rows[(int(node), dof)] + 1}; make the boxes or dofs distinct")
            rows[(int(node), dof)] = index
            nodes.append(int(node))
            dofs.append(dof)
            scales.append(motion.value)
            curves.append(constant if motion.curve is None else curve_index[motion.curve])
            births.append(motion.birth_time)
            deaths.append(motion.death_time)
    model.prescribed_node = np.array(nodes, dtype=np.int32)
    model.prescribed_dof = np.array(dofs, dtype=np.int32)
    model.prescribed_value = np.array(scales, dtype=np.float64)
    model.prescribed_curve = np.array(curves, dtype=np.int32)
    model.prescribed_birth_time = np.array(births, dtype=np.float64)
    model.prescribed_death_time = np.array(deaths, dtype=np.float64)
    rows_to_model(scene, model, constant)

