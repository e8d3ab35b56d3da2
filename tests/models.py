"""Decks for the verification problems of ``tests/test_verification.py``, built in Python.

Meshes come from :mod:`paradyn.mesh.geometry` or from numpy, decks from :class:`paradyn.deck.Model`;
:func:`run` writes the deck, runs the engine and reads the results with :func:`paradyn.run`
(no post-processing). Nothing here knows a reference value: the tests hold those.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

import paradyn
from paradyn._schema import ENUMS
from paradyn.deck import ELASTIC, Control, Model
from paradyn.mesh import geometry

HOURGLASS_FORMS = dict(ENUMS["hourglass_form"])
SHELL_ELEMENTS = dict(ENUMS["shell_element"])

THREADS = 2  # OpenMP threads per engine run (one rank)

ALL_DOFS = (1, 1, 1, 1, 1, 1)


@dataclass(frozen=True)
class Material:
    """Linear elastic material (SI units, or the consistent units of a benchmark)."""

    young: float
    poisson: float
    density: float

    @property
    def plate_wave_speed(self) -> float:
        """sqrt(E / (rho (1 - nu^2)))."""
        return float(np.sqrt(self.young / (self.density * (1.0 - self.poisson**2))))

    @property
    def bar_wave_speed(self) -> float:
        """sqrt(E / rho)."""
        return float(np.sqrt(self.young / self.density))


@dataclass
class Load:
    """Point loads: nodes, dof (1..6), values, and one ramp time for all of them."""

    nodes: np.ndarray
    dof: int
    values: np.ndarray
    ramp_time: float = 0.0


@dataclass
class Run:
    """An engine run: the results and the wall-clock time of the engine process (s)."""

    results: paradyn.Results
    wall_s: float

    @property
    def dt(self) -> float:
        return float(self.results.run["dt_s"])

    @property
    def cycles(self) -> int:
        return int(self.results.run["cycles"])


def _load_arrays(loads) -> dict[str, np.ndarray]:
    """The deck's /loads datasets for a list of Load (empty when there are none)."""
    if not loads:
        return {}
    return {
        "load_node": np.concatenate([np.asarray(ld.nodes, dtype=np.int64) for ld in loads]),
        "load_dof": np.concatenate([np.full(len(ld.nodes), ld.dof) for ld in loads]),
        "load_value": np.concatenate([np.asarray(ld.values, dtype=np.float64) for ld in loads]),
        "load_ramp_time": np.concatenate([np.full(len(ld.nodes), float(ld.ramp_time)) for ld in loads]),
    }


def shell_model(
    mesh: geometry.Mesh,
    thickness: float,
    material: Material,
    control: Control,
    *,
    fixed: dict[int, Sequence[int]] | None = None,
    loads: Sequence[Load] = (),
    velocity: np.ndarray | None = None,
    angular_velocity: np.ndarray | None = None,
    tracked: Sequence[int] = (),
    hourglass_coefficient: float = 0.1,
    hourglass_form: str | None = None,
    integration_points: int = 5,
    warping_correction: bool = True,
    element: str = "blt",
    title: str = "verification",
) -> Model:
    """One part, one elastic material; ``fixed`` maps node -> six 0/1 flags (ux uy uz rx ry rz)."""
    n = mesh.n_nodes
    fixed_dofs = np.zeros((n, 6), dtype=np.int32)
    for node, flags in (fixed or {}).items():
        fixed_dofs[node] = np.maximum(fixed_dofs[node], np.asarray(flags, dtype=np.int32))
    load_arrays = _load_arrays(loads)
    return Model(
        coordinates=mesh.coordinates,
        connectivity=mesh.quads,
        element_part=np.zeros(mesh.n_elements, dtype=np.int32),
        thickness=np.array([thickness]),
        part_material=np.array([0]),
        material_model=np.array([ELASTIC]),
        density=np.array([material.density]),
        youngs_modulus=np.array([material.young]),
        poisson_ratio=np.array([material.poisson]),
        control=control,
        initial_velocity=None if velocity is None else np.asarray(velocity, dtype=np.float64),
        initial_angular_velocity=(
            None if angular_velocity is None else np.asarray(angular_velocity, dtype=np.float64)
        ),
        fixed_dofs=fixed_dofs,
        integration_points=np.array([integration_points]),
        hourglass_coefficient=np.array([hourglass_coefficient]),
        hourglass_form=None if hourglass_form is None else np.array([HOURGLASS_FORMS[hourglass_form]], dtype=np.int32),
        warping_correction=np.array([int(warping_correction)], dtype=np.int32),
        shell_element=None if element == "blt" else np.array([SHELL_ELEMENTS[element]], dtype=np.int32),
        tracked_nodes=np.asarray(tracked, dtype=np.int64),
        title=title,
        **load_arrays,
    )


def run(model: Model, directory: Path, threads: int = THREADS) -> Run:
    """Write ``directory/deck.h5``, run the engine on one rank, read ``results.h5``."""
    results = paradyn.run(model, Path(directory), ranks=1, threads=threads, post=False)
    return Run(results=results, wall_s=results.engine_run.elapsed_s)


# ----------------------------------------------------------------------------------------------
# meshes and node sets


def strip(length: float, width: float, nx: int, ny: int) -> geometry.Mesh:
    """Flat strip in the x-y plane, x in [0, length], y in [0, width], normal +z."""
    return geometry.plate(size=(length, width), elements=(nx, ny))


def nodes_at(mesh: geometry.Mesh, axis: int, value: float, tol: float = 1e-9) -> np.ndarray:
    """Nodes whose coordinate ``axis`` equals ``value``, sorted by the other coordinates."""
    c = mesh.coordinates
    found = np.flatnonzero(np.abs(c[:, axis] - value) <= tol * max(1.0, abs(value)))
    others = [a for a in range(3) if a != axis]
    return found[np.lexsort((c[found, others[1]], c[found, others[0]]))]


def edge_weights(n_nodes: int) -> np.ndarray:
    """Consistent weights of a uniform line load on an edge of n_nodes - 1 equal segments."""
    w = np.ones(n_nodes)
    w[[0, -1]] = 0.5
    return w / w.sum()


def nodal_areas(mesh: geometry.Mesh) -> np.ndarray:
    """Tributary area of every node: a quarter of the area of each quad around it."""
    c = mesh.coordinates[mesh.quads]
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    out = np.zeros(mesh.n_nodes)
    np.add.at(out, mesh.quads.ravel(), np.repeat(0.25 * area, 4))
    return out


def cylinder_patch(radius: float, angles: tuple[float, float], length: float, n_around: int,
                   n_along: int, centre: Sequence[float] = (0.0, 0.0, 0.0)) -> geometry.Mesh:
    """Part of a cylinder of axis y: x = R sin(phi), z = R cos(phi) about ``centre``, phi from
    ``angles[0]`` to ``angles[1]`` (radians, phi = 0 is the crown), y from 0 to ``length``.

    Normals point outward (+z at the crown). Node ``j * (n_around + 1) + i`` sits at angle index
    i and axial index j; the quads are planar rectangles.
    """
    phi = np.linspace(angles[0], angles[1], n_around + 1)
    y = np.linspace(0.0, length, n_along + 1)
    pp, yy = np.meshgrid(phi, y)
    coordinates = np.column_stack([radius * np.sin(pp.ravel()), yy.ravel(),
                                   radius * np.cos(pp.ravel())])
    coordinates += np.asarray(centre, dtype=np.float64)
    i, j = np.meshgrid(np.arange(n_around), np.arange(n_along))
    first = (j * (n_around + 1) + i).ravel()
    quads = np.stack([first, first + 1, first + n_around + 2, first + n_around + 1], axis=1)
    mesh = geometry.Mesh(coordinates=coordinates, quads=quads)
    radial = (coordinates[quads].mean(axis=1) - np.asarray(centre)) * np.array([1.0, 0.0, 1.0])
    if not np.all(np.einsum("ij,ij->i", mesh.normals(), radial) > 0.0):
        raise AssertionError("cylinder_patch: the quad normals must point outward")
    return mesh


# ----------------------------------------------------------------------------------------------
# signal processing


def crossings(t: np.ndarray, y: np.ndarray, level: float = 0.0) -> np.ndarray:
    """Times where ``y`` crosses ``level`` (either way), by linear interpolation."""
    s = np.asarray(y) - level
    k = np.flatnonzero((s[:-1] < 0.0) != (s[1:] < 0.0))
    return t[k] - s[k] * (t[k + 1] - t[k]) / (s[k + 1] - s[k])


def first_rise(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time ``y`` reaches ``level`` from below, by linear interpolation."""
    k = int(np.argmax(np.asarray(y) >= level))
    if y[k] < level or k == 0:
        raise ValueError(f"the signal never rises through {level}")
    return float(t[k - 1] + (level - y[k - 1]) * (t[k] - t[k - 1]) / (y[k] - y[k - 1]))


# ----------------------------------------------------------------------------------------------
# beams


BETA1_L = 1.8751040687119611  # first root of cos(x) cosh(x) = -1


def cantilever_mode(x: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray]:
    """First bending mode of a clamped-free beam, normalised to 1 at the tip, and its slope."""
    b = BETA1_L / length
    s = (np.cosh(BETA1_L) + np.cos(BETA1_L)) / (np.sinh(BETA1_L) + np.sin(BETA1_L))
    bx = b * np.asarray(x)
    phi = np.cosh(bx) - np.cos(bx) - s * (np.sinh(bx) - np.sin(bx))
    dphi = b * (np.sinh(bx) + np.sin(bx) - s * (np.cosh(bx) - np.cos(bx)))
    tip = np.cosh(BETA1_L) - np.cos(BETA1_L) - s * (np.sinh(BETA1_L) - np.sin(BETA1_L))
    return phi / tip, dphi / tip


def stable_time_step(mesh: geometry.Mesh, material: Material, safety: float = 0.9) -> float:
    """The engine's automatic step (docs/theory.md): safety * min(area / longest side) / c_plate."""
    c = mesh.coordinates[mesh.quads]
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    longest = mesh.edge_lengths().max(axis=1)
    return safety * float(np.min(area / longest)) / material.plate_wave_speed


# ----------------------------------------------------------------------------------------------
# the verification problems


@dataclass
class Cantilever:
    """Plate strip along x, clamped (all six dofs) at x = 0, tip nodes at x = length."""

    mesh: geometry.Mesh
    length: float
    width: float
    thickness: float
    material: Material
    root: np.ndarray
    tip: np.ndarray

    @property
    def bending_stiffness(self) -> float:
        """E I with I = b t^3 / 12 (beam: E, not E / (1 - nu^2))."""
        return self.material.young * self.width * self.thickness**3 / 12.0

    @property
    def mass_per_length(self) -> float:
        return self.material.density * self.width * self.thickness

    @property
    def first_frequency(self) -> float:
        """Euler-Bernoulli f1 = (1.8751^2 / 2 pi) sqrt(EI / (m L^4)) in Hz."""
        return BETA1_L**2 / (2.0 * np.pi) * float(
            np.sqrt(self.bending_stiffness / (self.mass_per_length * self.length**4)))

    @property
    def tip_weights(self) -> np.ndarray:
        return edge_weights(len(self.tip))

    def model(self, control: Control, **kwargs: object) -> Model:
        return shell_model(self.mesh, self.thickness, self.material, control,
                           fixed={int(n): ALL_DOFS for n in self.root}, tracked=self.tip, **kwargs)


def cantilever(material: Material, nx: int = 20, ny: int = 2, length: float = 1.0,
               width: float = 0.1, thickness: float = 0.01) -> Cantilever:
    mesh = strip(length, width, nx, ny)
    return Cantilever(mesh=mesh, length=length, width=width, thickness=thickness, material=material,
                      root=nodes_at(mesh, 0, 0.0), tip=nodes_at(mesh, 0, length))


@dataclass
class ScordelisLo:
    """Quarter of the Scordelis-Lo roof (MacNeal & Harder 1985).

    Axis along y, vertical z: x = R sin(phi), z = R cos(phi), phi in [0, 40 deg] from the crown
    (phi = 0) to the free edge; y in [0, L/2] from the diaphragm (y = 0) to midspan (y = L/2).
    Diaphragm y = 0: ux = uz = 0. Midspan symmetry plane y = L/2: uy = rx = rz = 0. Crown symmetry
    plane x = 0: ux = ry = rz = 0. Self-weight in -z as nodal loads, tributary area times the load
    per area.
    """

    mesh: geometry.Mesh
    fixed: dict[int, np.ndarray]
    weights: np.ndarray      # nodal loads in -z for a load of 1 per unit area
    point_b: int             # midside of the free edge (phi = 40 deg, y = L/2)

    RADIUS = 25.0
    LENGTH = 50.0
    THICKNESS = 0.25
    HALF_ANGLE_DEG = 40.0
    YOUNG = 4.32e8
    POISSON = 0.0
    WEIGHT = 90.0            # per unit area

    def model(self, control: Control, load_per_area: float, density: float,
              ramp_time: float, **kwargs: object) -> Model:
        material = Material(self.YOUNG, self.POISSON, density)
        nodes = np.arange(self.mesh.n_nodes)
        return shell_model(self.mesh, self.THICKNESS, material, control, fixed=self.fixed,
                           loads=[Load(nodes, 3, -load_per_area * self.weights, ramp_time)],
                           tracked=[self.point_b], **kwargs)


def scordelis_lo_quarter(n: int) -> ScordelisLo:
    """n x n elements on the quarter (n along the arc, n along the half length)."""
    S = ScordelisLo
    angle = np.radians(S.HALF_ANGLE_DEG)
    mesh = cylinder_patch(S.RADIUS, (0.0, angle), 0.5 * S.LENGTH, n, n)
    c = mesh.coordinates
    tol = 1e-9 * S.RADIUS
    fixed: dict[int, np.ndarray] = {}

    def fix(nodes: np.ndarray, flags: Sequence[int]) -> None:
        for node in nodes:
            fixed[int(node)] = np.maximum(fixed.get(int(node), np.zeros(6, dtype=np.int32)), flags)

    fix(np.flatnonzero(np.abs(c[:, 1]) < tol), (1, 0, 1, 0, 0, 0))                   # diaphragm
    fix(np.flatnonzero(np.abs(c[:, 1] - 0.5 * S.LENGTH) < tol), (0, 1, 0, 1, 0, 1))  # midspan
    fix(np.flatnonzero(np.abs(c[:, 0]) < tol), (1, 0, 0, 0, 1, 1))                   # crown
    b = geometry.nearest_node(c, (S.RADIUS * np.sin(angle), 0.5 * S.LENGTH,
                                  S.RADIUS * np.cos(angle)))
    return ScordelisLo(mesh=mesh, fixed=fixed, weights=nodal_areas(mesh), point_b=b)


# ----------------------------------------------------------------------------------------------
# contact between parts (tests/test_contact_*.py)


@dataclass
class Body:
    """One part of a contact deck: a mesh, its shell thickness, a uniform initial velocity, and
    whether every dof of every node is fixed."""

    mesh: geometry.Mesh
    thickness: float
    velocity: Sequence[float] = (0.0, 0.0, 0.0)
    fixed: bool = False


@dataclass
class Assembly:
    """A multi-part deck and where each body's nodes went: body b has the nodes
    ``nodes[b]`` (consecutive, in its mesh's order) and the elements of part b."""

    model: Model
    nodes: list[np.ndarray]

    def masses(self) -> np.ndarray:
        """Lumped nodal masses (docs/theory.md): a quarter of rho t A from every element corner."""
        return lumped_masses(self.model)


def lumped_masses(model: Model) -> np.ndarray:
    """Lumped translational mass of every node: each element gives rho t A / 4 to each corner,
    A = half the cross product of the diagonals (exact for a flat quadrilateral)."""
    c = np.asarray(model.coordinates)[np.asarray(model.connectivity)]
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    part = np.asarray(model.element_part)
    rho = np.asarray(model.density)[np.asarray(model.part_material)[part]]
    element_mass = rho * np.asarray(model.thickness)[part] * area
    out = np.zeros(len(model.coordinates))
    np.add.at(out, np.asarray(model.connectivity).ravel(), np.repeat(0.25 * element_mass, 4))
    return out


def contact_model(
    bodies: Sequence[Body],
    material: Material,
    control: Control,
    *,
    pairs: Sequence[tuple[int, int]] = ((0, 1),),
    penalty_scale: float = 0.1,
    static_friction: float = 0.0,
    dynamic_friction: float | None = None,
    friction_decay: float = 0.0,
    passes: int = 2,
    loads: Sequence[Load] = (),
    tracked: Sequence[int] = (),
    hourglass_coefficient: float = 0.1,
    title: str = "contact",
) -> Assembly:
    """One part per body, one elastic material, the same contact settings for every pair.

    Load and tracked node numbers are global (use ``Assembly.nodes`` to find them: build the
    assembly once without loads, or offset the body's local numbers by the node counts before
    it). ``dynamic_friction`` defaults to ``static_friction``.
    """
    offsets = np.cumsum([0] + [b.mesh.n_nodes for b in bodies])
    nodes = [np.arange(offsets[i], offsets[i + 1]) for i in range(len(bodies))]
    coordinates = np.concatenate([b.mesh.coordinates for b in bodies])
    connectivity = np.concatenate([b.mesh.quads + offsets[i] for i, b in enumerate(bodies)])
    element_part = np.concatenate([np.full(b.mesh.n_elements, i, dtype=np.int32)
                                   for i, b in enumerate(bodies)])
    velocity = np.concatenate([np.tile(np.asarray(b.velocity, dtype=np.float64),
                                       (b.mesh.n_nodes, 1)) for b in bodies])
    fixed_dofs = np.concatenate([np.full((b.mesh.n_nodes, 6), int(b.fixed), dtype=np.int32)
                                 for b in bodies])
    n_parts, n_pairs = len(bodies), len(pairs)
    load_arrays = _load_arrays(loads)
    mu_d = static_friction if dynamic_friction is None else dynamic_friction
    model = Model(
        coordinates=coordinates,
        connectivity=connectivity,
        element_part=element_part,
        thickness=np.array([b.thickness for b in bodies], dtype=np.float64),
        part_material=np.zeros(n_parts, dtype=np.int32),
        material_model=np.array([ELASTIC]),
        density=np.array([material.density]),
        youngs_modulus=np.array([material.young]),
        poisson_ratio=np.array([material.poisson]),
        control=control,
        initial_velocity=velocity,
        fixed_dofs=fixed_dofs,
        hourglass_coefficient=np.full(n_parts, hourglass_coefficient),
        tracked_nodes=np.asarray(tracked, dtype=np.int64),
        contact_pairs=np.asarray(pairs, dtype=np.int32).reshape(n_pairs, 2),
        contact_penalty_scale=np.full(n_pairs, float(penalty_scale)),
        contact_static_friction=np.full(n_pairs, float(static_friction)),
        contact_dynamic_friction=np.full(n_pairs, float(mu_d)),
        contact_friction_decay=np.full(n_pairs, float(friction_decay)),
        contact_passes=np.full(n_pairs, int(passes), dtype=np.int32),
        title=title,
        **load_arrays,
    )
    return Assembly(model=model, nodes=nodes)


def flat_plate(size: tuple[float, float], elements: tuple[int, int],
               origin: Sequence[float] = (0.0, 0.0, 0.0)) -> geometry.Mesh:
    """Flat plate in a plane z = const, x from origin[0] over size[0], y from origin[1] over
    size[1], normal +z (node ``j * (nx + 1) + i`` at column i, row j)."""
    return geometry.plate(size=size, elements=elements, origin=origin)


def segment_stiffness(mesh: geometry.Mesh, material: Material, scale: float) -> np.ndarray:
    """The engine's penalty stiffness of every segment of ``mesh`` (docs/formats.md
    /contact/penalty_scale): k = scale K A / longest diagonal, K = E / (3 (1 - 2 nu))."""
    c = mesh.coordinates[mesh.quads]
    d13, d24 = c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]
    area = 0.5 * np.linalg.norm(np.cross(d13, d24), axis=1)
    diagonal = np.maximum(np.linalg.norm(d13, axis=1), np.linalg.norm(d24, axis=1))
    bulk = material.young / (3.0 * (1.0 - 2.0 * material.poisson))
    return scale * bulk * area / diagonal


def interrupted_copy(results: Path, target: Path) -> None:
    """A copy of a finished run's results marked as an interrupted one (complete = 0), as a run that
    stopped at or after its checkpoint leaves them: what a restart continues (a restart over a
    finished run is refused)."""
    target.write_bytes(results.read_bytes())
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
