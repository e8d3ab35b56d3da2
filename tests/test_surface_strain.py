"""Strains at the bottom and top surfaces of the shells (docs/outputs.md, LS-DYNA's lower and upper
surface strains, STRFLG): E(z) = E_m + z k, the membrane strain plus z = -+t/2 times the change of
curvature k measured from the nodal rotations (element/shell_field_measures.f90, surface_strains).

The kernel is checked against exact answers: an element bent to a cylinder of curvature kappa
(the nodes on the arc, each turned by kappa X about the axis) and then moved rigidly anywhere has
exx = E_m -+ kappa t / 2 (to O((kappa a)^2)); a rigid motion alone has none. The nodal orientation
update turns a node by the exact angle of its angular velocity. The engine is checked against beam
theory (Timoshenko & Gere, Mechanics of Materials): a cantilever strip under an end moment M at rest
bends uniformly to kappa = M / (E I), so its surfaces strain by -+ kappa t / 2 along it and by
+- nu kappa t / 2 across it (the anticlastic curvature of a narrow strip), for the one-point,
fully integrated and triangle elements; a strip stretched in its plane strains both surfaces as
its mid-surface, F / (E b t).
"""

from __future__ import annotations

import numpy as np
import pytest

import models as M
from contact_cases import STEEL
from paradyn import _kernels as K
from paradyn.deck import Control


def _quaternion(axis: np.ndarray, angle: float) -> np.ndarray:
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


def _product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.concatenate([[a[0] * b[0] - a[1:] @ b[1:]], a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:])])


TURN_AXIS, TURN_ANGLE, SHIFT = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0), 0.7, np.array([0.3, -1.0, 2.0])


def _turn(x: np.ndarray) -> np.ndarray:
    k = np.array([[0, -TURN_AXIS[2], TURN_AXIS[1]], [TURN_AXIS[2], 0, -TURN_AXIS[0]],
                  [-TURN_AXIS[1], TURN_AXIS[0], 0]])
    rotation = np.eye(3) + np.sin(TURN_ANGLE) * k + (1 - np.cos(TURN_ANGLE)) * k @ k
    return x @ rotation.T + SHIFT


@pytest.mark.parametrize("triangle", [False, True])
def test_a_bent_element_strains_its_surfaces_by_kappa_t_over_2(triangle: bool) -> None:
    """Corners on an arc of curvature kappa about y, each node turned by kappa X about y, then one
    rigid motion: exx = E_m -+ kappa t / 2 at bottom and top (1e-4 of kappa t / 2), eyy = exy = 0
    beyond the membrane's; the rigid motion alone gives zero at both surfaces."""
    a, b, t, kappa = 0.02, 0.01, 0.002, 0.5    # kappa a = 0.01
    corners = np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]])
    if triangle:
        corners[3] = corners[2]
    bent = np.stack([np.sin(kappa * corners[:, 0]) / kappa, corners[:, 1],
                     -(1 - np.cos(kappa * corners[:, 0])) / kappa], axis=1)
    turn = _quaternion(TURN_AXIS, TURN_ANGLE)
    q_bent = np.stack([_product(turn, _quaternion([0, 1, 0], kappa * x)) for x in corners[:, 0]], axis=1)
    q_rigid = np.stack([turn] * 4, axis=1)
    x0 = np.asfortranarray(np.stack([corners.T, corners.T]))
    x = np.asfortranarray(np.stack([_turn(bent).T, _turn(corners).T]))
    q = np.asfortranarray(np.stack([q_bent, q_rigid]))
    membrane = K.shell_membrane_strain(x0, x)
    surface = K.shell_surface_strains(x0, x, q, t, membrane)
    half = kappa * t / 2
    np.testing.assert_allclose(surface[:, 0, 0] - membrane[:, 0], [-half, 0.0, 0.0], rtol=0, atol=1e-4 * half)
    np.testing.assert_allclose(surface[:, 1, 0] - membrane[:, 0], [half, 0.0, 0.0], rtol=0, atol=1e-4 * half)
    assert membrane[0, 0] == pytest.approx(-(kappa * a) ** 2 / 24, rel=0.01)   # the chord's shortening
    np.testing.assert_allclose(surface[:, :, 1], 0.0, atol=1e-14)


def test_orientation_update_turns_by_the_exact_angle() -> None:
    """n steps of a constant angular velocity w turn a node by the angle n dt |w| about w
    (the quaternion's product over the steps, to round-off), however large the angle."""
    w, dt, steps = np.array([3.0, -1.0, 2.0]), 0.05, 40
    q = np.asfortranarray(np.array([[1.0], [0.0], [0.0], [0.0]]))
    for _ in range(steps):
        K.node_update_orientations(dt, np.asfortranarray(w[:, None]), q)
    expected = _quaternion(w, steps * dt * np.linalg.norm(w))
    np.testing.assert_allclose(q[:, 0], expected, atol=1e-13)


def _triangles(mesh):
    """Each quadrilateral split into two triangles (corner 4 = corner 3)."""
    quads = mesh.quads
    tri = np.concatenate([quads[:, [0, 1, 2, 2]], quads[:, [0, 2, 3, 3]]])
    return type(mesh)(coordinates=mesh.coordinates, quads=tri)


def _in_strip_axes(strain: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(n, 2, 3) tensors in each element's axes (its first axis along x2 + x3 - x1 - x4: a
    triangle's along its diagonal) turned into the strip's x, y axes."""
    g = corners[:, 1] + corners[:, 2] - corners[:, 0] - corners[:, 3]
    phi = np.arctan2(g[:, 1], g[:, 0])[:, None]
    c, s = np.cos(phi), np.sin(phi)
    exx, eyy, exy = strain[..., 0], strain[..., 1], strain[..., 2]
    return np.stack([c * c * exx - 2 * c * s * exy + s * s * eyy, s * s * exx + 2 * c * s * exy + c * c * eyy,
                     c * s * (exx - eyy) + (c * c - s * s) * exy], axis=-1)


@pytest.mark.parametrize("element", ["blt", "full", "triangle"])
def test_end_moment_strains_the_surfaces_by_kappa_t_over_2(element: str, tmp_path) -> None:
    """A cantilever strip (0.2 x 0.02 x 0.002 m, steel) under an end moment M ramped on and brought
    to rest by mass damping: every element but the two columns at the clamp and
    the loaded tip has top and bottom exx are +- M t / (2 E I) (2 %), its
    eyy -+ nu of that (10 % of exx: the anticlastic bending of a narrow strip), its membrane strain
    below 2 % of them."""
    beam = M.cantilever(STEEL, nx=10, ny=2, length=0.2, width=0.02, thickness=0.002)
    mesh = _triangles(beam.mesh) if element == "triangle" else beam.mesh
    kappa = 0.1                                  # 1/m: surface strain 1e-4, tip rotation 0.02 rad
    moment = kappa * beam.bending_stiffness
    period = 1.0 / beam.first_frequency
    control = Control(end_time=2.5 * period, output_interval=2.5 * period, history_interval=period / 20,
                      mass_damping=2.0 * (2.0 * np.pi * beam.first_frequency))
    load = M.Load(nodes=beam.tip, dof=5, values=moment * beam.tip_weights, ramp_time=0.5 * period)
    model = M.shell_model(mesh, beam.thickness, STEEL, control, fixed={int(n): M.ALL_DOFS for n in beam.root},
                          loads=[load], element="blt" if element == "triangle" else element)
    res = M.run(model, tmp_path).results
    frame = res.frame_arrays(-1)
    half = kappa * beam.thickness / 2
    corners = res.coordinates[res.connectivity]
    x = corners.mean(axis=1)[:, 0]
    away = (x > beam.length / 5) & (x < 0.9 * beam.length)   # the clamp holds two columns; the tip takes the load
    surface = _in_strip_axes(frame.surface_strain, corners)[away]
    np.testing.assert_allclose(surface[:, 1, 0], half, rtol=0.02)
    np.testing.assert_allclose(surface[:, 0, 0], -half, rtol=0.02)
    np.testing.assert_allclose(surface[:, 1, 1], -STEEL.poisson * half, rtol=0, atol=0.1 * half)
    np.testing.assert_allclose(surface[:, 0, 1], STEEL.poisson * half, rtol=0, atol=0.1 * half)
    assert np.abs(frame.membrane_strain).max() < 0.02 * half


def test_in_plane_stretch_strains_both_surfaces_as_the_mid_surface(tmp_path) -> None:
    """A strip pulled along its length by F at rest: both surfaces strain as the
    mid-surface (to round-off) (no bending), exx = F / (E b t) (1 %) and eyy = -nu exx (2 % of exx)."""
    length, width, t = 0.2, 0.02, 0.002
    mesh = M.strip(length, width, 10, 2)
    root, tip = M.nodes_at(mesh, 0, 0.0), M.nodes_at(mesh, 0, length)
    fixed = {int(n): (1, 0, 1, 1, 1, 1) for n in root}
    fixed[int(root[0])] = M.ALL_DOFS
    strain = 1.0e-4
    force = strain * STEEL.young * width * t
    omega = 2.0 * np.pi * STEEL.bar_wave_speed / (4.0 * length)
    period = 2.0 * np.pi / omega
    control = Control(end_time=4.0 * period, output_interval=4.0 * period, history_interval=period / 20,
                      mass_damping=2.0 * omega)
    load = M.Load(nodes=tip, dof=1, values=force * M.edge_weights(len(tip)), ramp_time=period)
    res = M.run(M.shell_model(mesh, t, STEEL, control, fixed=fixed, loads=[load]), tmp_path).results
    frame = res.frame_arrays(-1)
    for side in (0, 1):   # to round-off: the nodes turn about the normal only (drilling)
        np.testing.assert_allclose(frame.surface_strain[:, side], frame.membrane_strain, rtol=0, atol=1e-12 * strain)
    np.testing.assert_allclose(frame.membrane_strain[:, 0], strain, rtol=0.01)
    np.testing.assert_allclose(frame.membrane_strain[:, 1], -STEEL.poisson * strain, rtol=0, atol=0.02 * strain)
