"""Truss models for tests/test_trusses.py (docs/validation.md, "Trusses"), built as deck models.

Nothing here knows a reference value: the tests hold those.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from paradyn._schema import ENUMS
from paradyn.deck import Control, Model
from paradyn.deck.rigid_bodies import complete_rigid_bodies
from paradyn.scene.building import set_curves

TRUSS = ENUMS["element_kind"]["truss"]
STEEL = {"density": 7800.0, "young": 200e9, "poisson": 0.3}


def truss_model(coordinates: np.ndarray, ends: Sequence[tuple[int, int]], area: float, control: Control, *,
                material: dict[str, float] | None = None, model: str = "elastic",
                fixed: Sequence[int] = (), added_mass: dict[int, float] | None = None,
                tracked: Sequence[int] = ()) -> Model:
    """One truss part (elements N1 N2 N2 N2) of one material (``model`` with the keys of
    ``material``: density, young, poisson, and yield_stress, tangent_modulus, hardening_mixing for
    j2_plasticity); the nodes ``fixed`` held in translation, point masses ``added_mass`` (kg)."""
    m = {**STEEL, **(material or {})}
    n = len(coordinates)
    fixed_dofs = np.zeros((n, 6), dtype=np.int32)
    fixed_dofs[list(fixed), :3] = 1
    mass = np.zeros(n)
    for node, value in (added_mass or {}).items():
        mass[node] = value
    extra = {}
    if model != "elastic":
        extra = {"yield_stress": np.array([m["yield_stress"]]), "tangent_modulus": np.array([m["tangent_modulus"]]),
                 "hardening_mixing": np.array([m.get("hardening_mixing", 1.0)])}
    return Model(
        coordinates=np.asarray(coordinates, dtype=np.float64),
        connectivity=np.array([[a, b, b, b] for a, b in ends], dtype=np.int32),
        element_part=np.zeros(len(ends), dtype=np.int32),
        thickness=np.array([np.sqrt(4.0 * area / np.pi)]), part_material=np.array([0]),
        material_model=np.array([ENUMS["material_model"][model]]), density=np.array([m["density"]]),
        youngs_modulus=np.array([m["young"]]), poisson_ratio=np.array([m["poisson"]]),
        element_kind=np.array([TRUSS], dtype=np.int32), cross_section_area=np.array([area]),
        control=control, fixed_dofs=fixed_dofs, added_mass=mass, tracked_nodes=np.asarray(tracked, dtype=np.int64),
        title="truss", **extra)


def hanging_mass(n_elements: int, length: float, area: float, mass: float, gravity: float,
                 periods: float, period: float) -> Model:
    """A vertical wire of n_elements trusses hanging from a held node at the origin down to the
    point mass at z = -length, released at rest (unstretched) under gravity -z; the mass tracked."""
    z = -np.linspace(0.0, length, n_elements + 1)
    coordinates = np.column_stack([np.zeros_like(z), np.zeros_like(z), z])
    control = Control(end_time=periods * period, output_interval=period / 2, history_interval=period / 400,
                      gravity_z=-gravity)
    return truss_model(coordinates, [(k, k + 1) for k in range(n_elements)], area, control, fixed=[0],
                       added_mass={n_elements: mass}, tracked=[n_elements])


def pulled_bar(length: float, area: float, speed: float, turn: float, end: float, material: dict[str, float],
               model: str) -> Model:
    """One truss along x from a held node at the origin, its far end pulled at ``speed`` (m/s)
    until ``turn`` (s), then pushed back at the same speed until ``end``; the far end tracked."""
    control = Control(end_time=end, output_interval=end / 50, history_interval=end / 400)
    bar = truss_model(np.array([[0.0, 0.0, 0.0], [length, 0.0, 0.0]]), [(0, 1)], area, control, material=material,
                      model=model, fixed=[0], tracked=[1])
    bar.fixed_dofs[1, 1:3] = 1
    set_curves(bar, [[0.0, turn, turn * (1 + 1e-9), end]], [[1.0, 1.0, -1.0, -1.0]])
    bar.prescribed_node = np.array([1], dtype=np.int32)
    bar.prescribed_dof = np.array([1], dtype=np.int32)
    bar.prescribed_value = np.array([speed])
    bar.prescribed_curve = np.array([0], dtype=np.int32)
    return bar


def rigid_pendulum(side: float, thickness: float, depth: float, wire_area: float, n: int, omega: float,
                   end: float) -> Model:
    """A rigid square plate (side x side, thickness, steel, n x n shells) in the x-z plane, its
    centre ``depth`` below a held pivot at the origin, hung from the pivot by two steel wires (one
    truss each) to its top corners; started swinging about y at angular velocity ``omega`` (rad/s),
    gravity -z. The plate's centre node is tracked (the last node)."""
    s = np.linspace(-side / 2, side / 2, n + 1)
    xx, zz = np.meshgrid(s, s)
    plate = np.column_stack([xx.ravel(), np.zeros(xx.size), zz.ravel() - depth])
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    first = (j * (n + 1) + i).ravel()
    quads = np.stack([first, first + 1, first + n + 2, first + n + 1], axis=1)
    pivot = len(plate)
    top = [n * (n + 1), n * (n + 1) + n]   # the corners at z = -depth + side / 2
    centre = (n // 2) * (n + 1) + n // 2
    coordinates = np.vstack([plate, [[0.0, 0.0, 0.0]]])
    connectivity = np.vstack([quads, [[top[0], pivot, pivot, pivot], [top[1], pivot, pivot, pivot]]])
    fixed = np.zeros((len(coordinates), 6), dtype=np.int32)
    fixed[pivot, :3] = 1
    axis = np.array([0.0, omega, 0.0])
    velocity = np.cross(axis, coordinates)
    velocity[pivot] = 0.0
    angular = np.tile(axis, (len(coordinates), 1))
    angular[pivot] = 0.0
    control = Control(end_time=end, output_interval=end / 10, history_interval=end / 2000, gravity_z=-9.81)
    model = Model(
        coordinates=coordinates, connectivity=connectivity.astype(np.int32),
        element_part=np.array([0] * len(quads) + [1, 1], dtype=np.int32),
        thickness=np.array([thickness, np.sqrt(4.0 * wire_area / np.pi)]), part_material=np.array([0, 1]),
        material_model=np.array([ENUMS["material_model"]["rigid"], ENUMS["material_model"]["elastic"]]),
        density=np.array([STEEL["density"]] * 2), youngs_modulus=np.array([STEEL["young"]] * 2),
        poisson_ratio=np.array([STEEL["poisson"]] * 2),
        element_kind=np.array([ENUMS["element_kind"]["shell"], TRUSS], dtype=np.int32),
        cross_section_area=np.array([0.0, wire_area]), control=control, fixed_dofs=fixed,
        initial_velocity=velocity, initial_angular_velocity=angular, tracked_nodes=np.array([centre]),
        title="rigid pendulum")
    complete_rigid_bodies(model)
    return model
