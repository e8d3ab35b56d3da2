"""Validation of a deck model against the schema (docs/formats.md): every dataset's and /control
attribute's rules from :mod:`paradyn._schema`, then the relations between fields, which are
written out by hand here and in the engine (model_deck's check_deck_relations).

Used through :func:`paradyn.deck.validate_model` and the deck reader and writer.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from paradyn._schema import (
    CONDITIONS,
    CONTROL,
    DATASETS,
    ENUMS,
    NAME_ATTRIBUTES,
    SIZES,
    AttributeSpec,
    DatasetSpec,
)
from paradyn.deck.model import trait_codes
from paradyn.deck.part_relations import check_thickness_updates
from paradyn.deck.walls import walls_of

if TYPE_CHECKING:
    from .model import Model



_BY_ATTRIBUTE = {d.python: d for d in DATASETS}
_BY_PATH = {d.path: d for d in DATASETS}
_SYMBOL_OF = {s.entity: s.symbol for s in SIZES.values()}


class DeckError(ValueError):
    """A deck (file or in-memory model) that breaks the format of docs/formats.md."""




class _Checker:
    """Checks a model and raises DeckError with messages prefixed by the source (file or 'model')."""

    def __init__(self, model: Model, source: str) -> None:
        self.model = model
        self.source = source

    def fail(self, message: str) -> None:
        raise DeckError(f"{self.source}: {message}")

    def array(self, attribute: str) -> np.ndarray:
        return np.asarray(getattr(self.model, attribute))

    def sizes(self) -> dict[str, int]:
        """Row count of every symbol; the datasets that define a symbol with a minimum must have it."""
        for spec in DATASETS:
            size = SIZES[spec.shape[0]]
            if not spec.defines_rows or size.min_rows == 0:
                continue
            a = self.array(spec.python)
            if a.ndim != len(spec.shape) or a.shape[1:] != tuple(spec.shape[1:]) or a.shape[0] < size.min_rows:
                self.fail(f"{spec.path} has shape {a.shape}, expected {_symbolic(spec.shape)} with at least "
                          f"one {size.entity}")
        return {symbol: int(getattr(self.model, symbol) or 0) for symbol in SIZES}

    def dtype(self, spec: DatasetSpec) -> None:
        dtype = self.array(spec.python).dtype
        if spec.type == "int" and dtype.kind not in "iu":
            self.fail(f"{spec.path} has dtype {dtype}, must be an integer type; write it with an integer "
                      f"dtype such as int32")
        if spec.type == "float" and dtype.kind != "f":
            self.fail(f"{spec.path} has dtype {dtype}, must be floating point; write it with dtype float64")

    def shape(self, spec: DatasetSpec, sizes: dict[str, int]) -> None:
        actual = self.array(spec.python).shape
        expected = tuple(sizes[d] if isinstance(d, str) else d for d in spec.shape)
        if actual != expected:
            entity = SIZES[spec.shape[0]].entity
            setter = next(d for d in DATASETS if d.shape[0] == spec.shape[0] and d.defines_rows)
            if actual[1:] == expected[1:] and setter.path != spec.path:
                self.fail(f"{spec.path} has {actual[0]} rows but {setter.path}, which sets the number of {entity}s, "
                          f"has {expected[0]}; give both one row per {entity} (expected {_symbolic(spec.shape)})")
            self.fail(f"{spec.path} has shape {actual}, expected {_symbolic(spec.shape)} = {expected}; "
                      f"every array must have one row per {entity}")

    def entries(self, spec: DatasetSpec, bad: np.ndarray, rule: str, fix: str) -> None:
        """Fail on the first entry where ``bad`` is true, naming index, value and count."""
        if not np.any(bad):
            return
        index = tuple(int(i) for i in np.argwhere(bad)[0])
        value = self.array(spec.python)[index]
        more = int(np.count_nonzero(bad)) - 1
        extra = f" ({more} more entries too)" if more > 0 else ""
        self.fail(f"{spec.path}[{', '.join(str(i) for i in index)}] = {_fmt(value)} {rule}{extra}; {fix}")

    def values(self, spec: DatasetSpec, sizes: dict[str, int]) -> None:
        """The schema's per-entry rules: finite, bounds, enum codes, index range."""
        a = self.array(spec.python)
        if a.size == 0:
            return
        rows, where = self.selected_rows(spec, a)
        if spec.type == "float":
            self.entries(spec, rows & ~np.isfinite(a), f"must be finite{where}", spec.fix)
        if spec.lower is not None or spec.upper is not None:
            self.entries(spec, rows & ~within_bounds(a, spec), f"{spec.rule}{where}", spec.fix)
        if spec.enum is not None:
            self.entries(spec, ~np.isin(a, list(ENUMS[spec.enum].values())), spec.enum_rule, spec.fix)
        if spec.reference is not None:
            upper = sizes[_SYMBOL_OF[spec.reference]]
            lowest = -1 if spec.lower is not None and spec.lower.value == -1 else 0   # -1: names none
            self.entries(spec, (a < lowest) | (a >= upper), f"is out of range {lowest}..{upper - 1}",
                         f"{spec.reference} indices are 0-based and must be below the number of "
                         f"{spec.reference}s ({upper})")

    def selected_rows(self, spec: DatasetSpec, a: np.ndarray) -> tuple[np.ndarray, str]:
        """Rows the rules apply to (broadcast to ``a``), and words for them in messages."""
        if spec.checked_when is None:
            return np.ones(a.shape, dtype=bool), ""
        condition = CONDITIONS[spec.checked_when]
        selected = np.isin(self.array(_BY_PATH[condition.dataset].python), condition.codes)
        return selected.reshape(selected.shape + (1,) * (a.ndim - 1)) & np.ones(a.shape, dtype=bool), \
            f" {condition.rows}"


def within_bounds(a: np.ndarray, spec: DatasetSpec | AttributeSpec) -> np.ndarray:
    """Where the entries of ``a`` meet the spec's lower and upper bounds."""
    ok = np.ones(np.shape(a), dtype=bool)
    with np.errstate(invalid="ignore"):
        if spec.lower is not None:
            ok &= (a >= spec.lower.value) if spec.lower.inclusive else (a > spec.lower.value)
        if spec.upper is not None:
            ok &= (a <= spec.upper.value) if spec.upper.inclusive else (a < spec.upper.value)
    return ok


def _symbolic(shape: tuple[str | int, ...]) -> str:
    return "(" + ", ".join(str(d) for d in shape) + ("," if len(shape) == 1 else "") + ")"


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
    present = [spec for spec in DATASETS if getattr(model, spec.python) is not None]
    for spec in present:
        check.dtype(spec)
        check.shape(spec, sizes)
    for spec in present:
        check.values(spec, sizes)
    _check_relations(check, sizes)
    _check_names(check, sizes)
    _check_control(check)


def _check_presence(check: _Checker) -> None:
    """Datasets required when a dataset condition holds (the J2 data when a material is J2)."""
    for spec in DATASETS:
        condition = CONDITIONS.get(spec.required_when or "")
        if condition is None or condition.dataset is None or getattr(check.model, spec.python) is not None:
            continue
        values = check.array(_BY_PATH[condition.dataset].python)
        holds = np.flatnonzero(np.isin(values, condition.codes))
        if holds.size:
            check.fail(f"{spec.path} is missing but {condition.dataset}[{int(holds[0])}] = {values[holds[0]]}; it is "
                       f"required when {condition.meaning}: give it for every {SIZES[spec.shape[0]].entity}")


def _check_relations(check: _Checker, sizes: dict[str, int]) -> None:
    """The schema's [relations], which need more than one field (model_deck's check_deck_relations)."""
    conn = check.array("connectivity")
    truss = _truss_elements(check)
    _check_trusses(check, conn, truss)
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3)]   # (2, 3) equal: a triangle
    repeated = np.any([conn[:, a] == conn[:, b] for a, b in pairs], axis=0) if conn.size else np.zeros(0, bool)
    repeated &= ~truss
    if np.any(repeated):
        element = int(np.flatnonzero(repeated)[0])
        check.fail(f"/elements/connectivity[{element}] = {conn[element].tolist()} repeats a node; every "
                   f"quadrilateral needs four distinct nodes, a triangle three with the third repeated as the "
                   f"fourth (remesh without collapsed elements)")
    _check_distinct_elements(check, conn)
    _check_element_shapes(check, conn, truss)
    check_thickness_updates(check, conn, truss)
    plastic = np.isin(check.array("material_model"), trait_codes("material_model", "plastic"))
    if np.any(plastic):
        tangent, young = check.array("tangent_modulus"), check.array("youngs_modulus")
        bad = np.flatnonzero(plastic & ~(tangent < young))
        if bad.size:
            i = int(bad[0])
            check.fail(f"/materials/tangent_modulus[{i}] = {_fmt(tangent[i])} must be below "
                       f"/materials/youngs_modulus[{i}] = {_fmt(young[i])} for a plastic material; give "
                       f"the plastic tangent modulus in Pa below Young's modulus")
    pairs = check.array("contact_pairs")
    if sizes["n_contacts"] > 0:
        single = np.isin(check.array("contact_kind"), trait_codes("contact_kind", "self_contact"))
        same = pairs[:, 0] == pairs[:, 1]
        check.entries(_BY_ATTRIBUTE["contact_pairs"], same & ~single, "pairs a part with itself",
                      "name two different parts, or make the contact single_surface")
        check.entries(_BY_ATTRIBUTE["contact_pairs"], single & ~same, "names two parts for a single_surface contact",
                      "name its one part twice")
        truss_parts = np.isin(check.array("element_kind"), trait_codes("element_kind", "truss"))
        check.entries(_BY_ATTRIBUTE["contact_pairs"], truss_parts[pairs].any(axis=1), "names a truss part",
                      "trusses have no contact surface, name shell parts only")
    used = np.zeros(sizes["n_nodes"], dtype=bool)
    used[conn.ravel()] = True
    if not np.all(used):
        unused = np.flatnonzero(~used)
        check.fail(f"/nodes/coordinates[{int(unused[0])}] belongs to no element ({unused.size} such nodes); "
                   f"a node without elements has no mass, remove unused nodes")
    _check_rigid_walls(check, sizes)
    _check_curve_relations(check, sizes)
    _check_rigid_bodies(check, sizes)
    _check_rotation_ties(check, sizes)


def _check_rigid_walls(check: _Checker, sizes: dict[str, int]) -> None:
    """rigid_wall_nodes_wall, rigid_wall_normal_nonzero, rigid_wall_geometry and
    rigid_wall_nodes_in_front (the engine's check_rigid_walls): a node counts as inside a wall below
    1e-9 of the model's size, so nodes on its surface pass; a wall with rows of /rigid_wall_nodes
    is checked on those nodes only."""
    listed = _optional(check, "rigid_wall_node_wall")
    nodes = _optional(check, "rigid_wall_node")
    n_walls = len(check.array("rigid_wall_point"))
    bad = np.flatnonzero(listed >= n_walls)
    if bad.size:
        k = int(bad[0])
        check.fail(f"/rigid_wall_nodes/wall[{k}] = {int(listed[k])} names no rigid wall (the deck has {n_walls}); "
                   f"give the 0-based index of a wall")
    if sizes["n_rigid_walls"] == 0:
        return
    coordinates = check.array("coordinates")
    tolerance = 1e-9 * float(np.max(np.abs(coordinates)))
    walls = walls_of(*(check.array(f"rigid_wall_{key}") for key in
                       ("shape", "point", "normal", "edge", "size", "radius", "length")))
    births = check.model.rigid_wall_birth_time
    for w, wall in enumerate(walls):
        if not float(np.linalg.norm(wall.normal)) > 0.0:
            check.fail(f"/rigid_walls/normal[{w}] is the zero vector; give a nonzero normal pointing from the "
                       f"wall towards the model (a cylinder: its axis)")
        if wall.requirement():
            check.fail(f"/rigid_walls/shape[{w}] = {wall.requirement()}; give the wall its /rigid_walls/edge, "
                       f"size or radius")
        if births is not None and float(births[w]) > 0.0:
            continue   # born later: the model may pass through its place before its birth
        acts = np.unique(nodes[listed == w]) if np.any(listed == w) else np.arange(len(coordinates))
        gaps = wall.gaps(coordinates[acts])
        if gaps.size and gaps.min() < -tolerance:
            k = int(acts[np.argmin(gaps)])
            check.fail(f"/rigid_walls/point[{w}] puts node {k} behind the wall at the start (signed distance "
                       f"{_fmt(float(gaps.min()))} m to its surface, inside it); move the wall or flip its normal so "
                       f"that the model starts on its outer side")


def _optional(check: _Checker, attribute: str) -> np.ndarray:
    """A table's integer column, empty when the table is absent."""
    value = getattr(check.model, attribute)
    return np.zeros(0, dtype=np.int64) if value is None else np.asarray(value, dtype=np.int64)


def _check_rigid_bodies(check: _Checker, sizes: dict[str, int]) -> None:
    """rigid_bodies_whole (the engine's small_table_message and rigid_node_message, in that order):
    a body's part is rigid (or -1, a body of nodes alone), the nodes of a rigid part's elements are
    in a body, and every body has a node."""
    rigid = np.isin(check.array("material_model"), trait_codes("material_model", "rigid"))
    part_rigid = rigid[check.array("part_material")]
    body_part = check.array("rigid_body_part")
    for row in range(sizes["n_rigid_bodies"]):
        if body_part[row] >= 0 and not part_rigid[body_part[row]]:
            check.fail(f"/rigid_bodies/part[{row}] = {int(body_part[row])} names a part whose material is not rigid; "
                       f"give the part a rigid material, or remove the body")
    in_body = check.array("node_rigid_body") >= 0
    conn = check.array("connectivity")
    loose = part_rigid[check.array("element_part")][:, None] & ~in_body[conn]
    if np.any(loose):
        element, corner = (int(i) for i in np.argwhere(loose)[0])
        check.fail(f"/nodes/rigid_body[{int(conn[element, corner])}] = -1 but the node is on element {element} of "
                   f"part {int(check.array('element_part')[element])}, whose material is rigid; give every node of "
                   f"a rigid part's elements the row of its body in /rigid_bodies")
    counts = np.bincount(check.array("node_rigid_body") + 1, minlength=sizes["n_rigid_bodies"] + 1)[1:]
    for row in np.flatnonzero(counts[:sizes["n_rigid_bodies"]] == 0):
        check.fail(f"/nodes/rigid_body: rigid body {int(row)} (/rigid_bodies/part[{int(row)}]) has no node; give "
                   f"every body its nodes, or remove it")
    if check.model.rigid_body_given_mass is not None and check.model.rigid_body_given_inertia is not None:
        given, tensors = check.array("rigid_body_given_mass"), check.array("rigid_body_given_inertia")
        for row in np.flatnonzero(given[:len(tensors)] > 0.0):
            xx, yy, zz, xy, yz, zx = (float(v) for v in tensors[row])
            if np.any(np.linalg.eigvalsh(np.array([[xx, xy, zx], [xy, yy, yz], [zx, yz, zz]])) <= 0.0):
                check.fail(f"/rigid_bodies/given_inertia[{int(row)}] = {tensors[row].tolist()} is not positive "
                           f"definite; give the body's inertia tensor about its centre (xx, yy, zz, xy, yz, zx)")
    if check.model.rigid_body_failure_node is None:
        return
    failure_node, body_of = check.array("rigid_body_failure_node"), check.array("node_rigid_body")
    for row in range(min(sizes["n_rigid_bodies"], len(failure_node))):
        node = int(failure_node[row])
        if node >= 0 and node < len(body_of) and body_of[node] != row:
            check.fail(f"/rigid_bodies/failure_node[{row}] = {node} is not a node of body {row} (its "
                       f"/nodes/rigid_body is {int(body_of[node])}); give the weld's N1, a node of the body, or -1")


def _check_rotation_ties(check: _Checker, sizes: dict[str, int]) -> None:
    """A rotation tie's weights sum to 1 (a point of its segment) and its node is not one of its masters."""
    if not sizes.get("n_rotation_ties"):
        return
    node, masters = check.array("rotation_tie_node"), check.array("rotation_tie_masters")
    weights = check.array("rotation_tie_weights")
    for row in range(sizes["n_rotation_ties"]):
        if abs(float(weights[row].sum()) - 1.0) > 1e-9:
            check.fail(f"/rotation_ties/weights[{row}] = {weights[row].tolist()} sum to {float(weights[row].sum()):g}; "
                       f"give the segment's shape functions at the tied point (they sum to 1)")
        if node[row] in masters[row]:
            check.fail(f"/rotation_ties/node[{row}] = {int(node[row])} is one of its own masters; tie a node to "
                       f"another segment's nodes")


def _check_curve_relations(check: _Checker, sizes: dict[str, int]) -> None:
    """curve_first_points and curve_times_increase (model_deck's check_curve_relations)."""
    first, points = check.array("curve_first_point"), sizes["n_curve_points"]
    previous = np.concatenate([[-1], first[:-1]])
    ok = (first > previous) & (first < points)
    if first.size:
        ok[0] = first[0] == 0 and points >= 1
    if not np.all(ok):
        i = int(np.flatnonzero(~ok)[0])
        check.fail(f"/curves/first_point[{i}] = {int(first[i])} breaks the order of the curves; the first curve "
                   f"starts at point 0 and each next one later, below the number of curve points ({points})")
    time = check.array("curve_time")
    stops = [*first[1:], points] if first.size else []
    for c, (start, stop) in enumerate(zip(first, stops, strict=True)):
        steps = np.flatnonzero(~(np.diff(time[start:stop]) > 0))
        if steps.size:
            k = int(start + steps[0] + 1)
            check.fail(f"/curves/time[{k}] = {_fmt(time[k])} does not follow /curves/time[{k - 1}] = "
                       f"{_fmt(time[k - 1])} of curve {c}; give the times of each curve strictly increasing")
    for i, model in enumerate(check.array("material_model")):
        for python, kind in (("hardening_curve", "hardening"), ("rate_curve", "rate")):
            spec = _BY_ATTRIBUTE[python]
            if getattr(check.model, python) is None:   # absent: no material of its models
                continue
            c = int(check.array(python)[i])
            if c < 0 or model not in CONDITIONS[str(spec.checked_when)].codes:
                continue
            stop = first[c + 1] if c + 1 < first.size else points
            fault = material_curve_fault(kind, time[first[c]:stop], check.array("curve_value")[first[c]:stop],
                                         float(check.array("yield_stress")[i]))
            if fault:
                check.fail(f"{spec.path}[{i}] = {c}: {fault}")


def material_curve_fault(kind: str, x: np.ndarray, y: np.ndarray, yield_stress: float) -> str:
    """What breaks the relation material_curves for a material's curve (model_deck's
    material_curve_message), in words with the fix; '' when it holds. ``kind``: "hardening" (x the
    plastic strains, y the yield stresses) or "rate" (x the strain rates, y the factors)."""
    if kind == "hardening":
        if x[0] != 0.0 or y[0] != yield_stress:
            return (f"the curve starts at ({_fmt(x[0])}, {_fmt(y[0])}), not at zero plastic strain with "
                    f"/materials/yield_stress = {_fmt(yield_stress)}; start the curve at (0, yield_stress)")
        drops = np.flatnonzero(np.diff(y) < 0)
        if drops.size:
            k = int(drops[0]) + 1
            return (f"the yield stress decreases to {_fmt(y[k])} at plastic strain {_fmt(x[k])}; give a curve that "
                    f"never decreases (no softening)")
        return ""
    if x[0] < 0.0 or np.any(y <= 0.0):
        return (f"a rate curve has strain rates >= 0 and factors > 0, this one starts at rate {_fmt(x[0])} with "
                f"least factor {_fmt(np.min(y))}; give rates >= 0 and factors > 0")
    return ""


def _check_distinct_elements(check: _Checker, conn: np.ndarray) -> None:
    """No two elements have the same four nodes (in any order): the second of the first such pair is named."""
    if conn.shape[0] < 2:
        return
    ordered = np.sort(conn, axis=1)
    _, first, inverse = np.unique(ordered, axis=0, return_index=True, return_inverse=True)
    twins = np.flatnonzero(first[inverse.ravel()] != np.arange(conn.shape[0]))
    if twins.size:
        element = int(twins[0])
        original = int(first[inverse.ravel()[element]])
        check.fail(f"/elements/connectivity[{element}] = {conn[element].tolist()} has the same nodes as element "
                   f"{original}; a duplicated element doubles its mass and stiffness, remove it")


def _truss_elements(check: _Checker) -> np.ndarray:
    """Whether each element is of a truss part (/parts/element_kind with the trait truss)."""
    kinds = check.array("element_kind")
    return np.isin(kinds[check.array("element_part")], trait_codes("element_kind", "truss"))


def _check_trusses(check: _Checker, conn: np.ndarray, truss: np.ndarray) -> None:
    """A truss names two distinct nodes, the second repeated as third and fourth, and has a length."""
    if not np.any(truss):
        return
    bad = truss & ~((conn[:, 0] != conn[:, 1]) & (conn[:, 1] == conn[:, 2]) & (conn[:, 2] == conn[:, 3]))
    if np.any(bad):
        element = int(np.flatnonzero(bad)[0])
        check.fail(f"/elements/connectivity[{element}] = {conn[element].tolist()} is an element of truss part "
                   f"{int(check.array('element_part')[element])}; a truss names two distinct nodes, the second "
                   f"repeated as the third and fourth (N1 N2 N2 N2)")
    x = check.array("coordinates")
    short = truss & ~(np.linalg.norm(x[conn[:, 1]] - x[conn[:, 0]], axis=1) > 0.0)
    if np.any(short):
        element = int(np.flatnonzero(short)[0])
        check.fail(f"/nodes/coordinates: element {element} (truss part {int(check.array('element_part')[element])}, "
                   f"nodes {conn[element].tolist()}) has zero length (its two nodes coincide); move a node or remove "
                   f"the truss")


def _check_element_shapes(check: _Checker, conn: np.ndarray, truss: np.ndarray) -> None:
    """Every element convex without coincident or collinear corners (the engine's quad_shape): at each
    corner the turn from the incoming to the outgoing side points along the normal of the diagonals
    (trusses are checked by _check_trusses)."""
    x = check.array("coordinates")[conn]                       # (elements, 4, 3)
    normal = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
    incoming = x - np.roll(x, 1, axis=1)
    outgoing = np.roll(x, -1, axis=1) - x
    turn = np.einsum("eki,ei->ek", np.cross(incoming, outgoing), normal)
    floor = 1e-10 * np.einsum("ei,ei->e", normal, normal)[:, None]
    bad = (np.abs(turn) <= floor) | (floor == 0.0) | (turn < 0.0)
    # a triangle (third node repeated as the fourth, quad_shape's triangle_shape_fault): collapsed when
    # twice its area is at most 1e-5 of its longest side squared; flagged at its first corner
    triangle = conn[:, 2] == conn[:, 3]
    sides = np.stack([x[:, 1] - x[:, 0], x[:, 2] - x[:, 1], x[:, 0] - x[:, 2]], axis=1)
    longest = np.max(np.einsum("eki,eki->ek", sides, sides), axis=1)
    n_tri = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    flat = np.einsum("ei,ei->e", n_tri, n_tri) <= 1e-10 * longest**2
    bad[triangle] = False
    bad[triangle & flat & ~truss, 0] = True
    turn[triangle & flat, 0] = 0.0
    if not np.any(bad):
        return
    element = int(np.flatnonzero(bad.any(axis=1))[0])
    corner = int(np.flatnonzero(bad[element])[0])
    node, part = int(conn[element, corner]), int(check.array("element_part")[element])
    if abs(turn[element, corner]) <= floor[element, 0] or floor[element, 0] == 0.0:
        check.fail(f"/nodes/coordinates: element {element} (part {part}, nodes {conn[element].tolist()}) is "
                   f"collapsed or crossed at node {node} (coincident or collinear corners, or sides that cross); "
                   f"remesh it")
    check.fail(f"/nodes/coordinates: element {element} (part {part}, nodes {conn[element].tolist()}) is concave or "
               f"twisted at node {node}; remesh it (a concave quadrilateral turns inside out at the first step)")


def _check_names(check: _Checker, sizes: dict[str, int]) -> None:
    for spec in NAME_ATTRIBUTES:
        names = getattr(check.model, spec.python)
        if names and len(names) != sizes[spec.one_per]:
            check.fail(f"attribute {spec.name} on {spec.group} has {len(names)} names but there are "
                       f"{sizes[spec.one_per]} {SIZES[spec.one_per].entity}s; give one name each")
        for name in names or ():
            if "\0" in str(name):
                check.fail(f"attribute {spec.name} on {spec.group}: the name {str(name)!r} holds a NUL character, "
                           f"which HDF5 strings cannot; remove it")
    if "\0" in (check.model.title or ""):
        check.fail(f"the title {check.model.title!r} holds a NUL character, which HDF5 strings cannot; remove it")


def _check_control(check: _Checker) -> None:
    control = check.model.control
    for spec in CONTROL:
        value = control.value(spec.name)
        label = f"/control attribute {spec.name}"
        if value is None:
            if spec.required:
                check.fail(f"{label} is missing; {spec.fix}")
            continue
        if spec.type == "string":
            choices = ENUMS[spec.enum or ""]
            if value not in choices:
                check.fail(f"{label} = {value!r} is unknown; use {' or '.join(repr(p) for p in choices)}, or "
                           f"leave it out for the default ({spec.default!r})")
            continue
        try:
            number = float(value)
        except (TypeError, ValueError):
            check.fail(f"{label} = {value!r} is not a number; give a real value")
        if not np.isfinite(number):
            check.fail(f"{label} = {_fmt(number)} must be finite; {spec.fix}")
        if not within_bounds(np.asarray(number), spec):
            check.fail(f"{label} = {_fmt(number)} {spec.rule}; {spec.fix}")
