"""The fields a d3plot user expects in the frames and the history (docs/outputs.md, "Frames"):
layer stresses, membrane strain, internal energy density, acceleration, nodal contact force,
the shell thickness, and the supports' reaction force (LS-DYNA's SPCFORC).

The kernels (element/shell_field_measures.f90, through f2py) are checked against exact answers:
a stress linear through the thickness is recovered at the surfaces' points and exactly at the
mid-surface; an affine in-plane stretch A of a quadrilateral turned anywhere in space has the
Green-Lagrange strain (A^T A - I) / 2 (Malvern, Introduction to the Mechanics of a Continuous
Medium, sec. 4.5). The engine's fields are checked against Newton and statics: a plate in free
fall accelerates at g at every node with no reaction; a cantilever at rest under its own weight
has the reaction -M g, the bending stress 6 M(x) zeta / (b t^2) at its outer points (beam
theory, Timoshenko & Gere), and internal energy densities whose integral is the history's
internal energy; the nodal contact forces on one plate sum to the history's contact force on it.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import models as M
from contact_cases import PLATE, STEEL, N, T
from paradyn import _kernels as K
from paradyn.deck import Control


@pytest.mark.parametrize("nip", [1, 2, 3, 4, 5])
def test_layer_stresses_of_a_linear_stress_are_exact(nip: int) -> None:
    """sigma(zeta) = a + b zeta at every point: bottom and top are the outermost points' values,
    the middle is a to round-off (the interpolation of a linear field is exact)."""
    zeta, _ = K.thickness_points(nip)
    a, b = np.array([1.0, -2.0, 0.5, 0.3, -0.1]), np.array([4.0, 3.0, -1.0, 0.0, 0.2])
    stress = np.asfortranarray((a[:, None] + b[:, None] * zeta[None, :])[None, :, :])
    layers = K.shell_layer_stresses(stress)
    np.testing.assert_allclose(layers[:, 0, 0], a + b * zeta[0], rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(layers[:, 1, 0], a, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(layers[:, 2, 0], a + b * zeta[-1], rtol=1e-15, atol=1e-15)


def _turn(x: np.ndarray) -> np.ndarray:
    """A rotation about an oblique axis and a shift: a rigid motion of (.., 3) points."""
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    angle = 0.7
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    return x @ rotation.T + np.array([0.3, -1.0, 2.0])


@pytest.mark.parametrize("triangle", [False, True])
def test_membrane_strain_of_an_affine_stretch_is_green_lagrange(triangle: bool) -> None:
    """x = A X in the plane, then any rigid motion: E = (A^T A - I) / 2 in the element's axes
    (its first axis along x for this rectangle) to round-off; a rigid motion alone gives zero."""
    corners = np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0], [0.02, 0.01, 0.0], [0.0, 0.01, 0.0]])
    if triangle:
        corners[3] = corners[2]
    a = np.array([[1.10, 0.00], [0.06, 0.95]])   # lower triangular keeps the first axis along x
    stretched = corners.copy()
    stretched[:, :2] = corners[:, :2] @ a.T
    x0 = np.asfortranarray(np.stack([corners.T, corners.T])[:, :, :])
    x = np.asfortranarray(np.stack([_turn(stretched).T, _turn(corners).T]))
    strain = K.shell_membrane_strain(x0, x)
    expected = 0.5 * (a.T @ a - np.eye(2))
    np.testing.assert_allclose(strain[:, 0], [expected[0, 0], expected[1, 1], expected[0, 1]], atol=1e-14)
    np.testing.assert_allclose(strain[:, 1], 0.0, atol=1e-14)
    volume = K.shell_initial_volumes(x0[:1], 0.002)
    assert volume[0] == pytest.approx((0.5 if triangle else 1.0) * 0.02 * 0.01 * 0.002, rel=1e-14)


def test_free_fall_accelerates_at_g_with_no_reaction(tmp_path) -> None:
    """Every node of a free plate accelerates at g in every frame (1e-9), the plate stays
    unstrained, the reaction is exactly zero (nothing holds it) and the thickness is the part's."""
    g = np.array([1.0, -2.0, -9.81])
    end = 1.0e-3
    control = Control(end_time=end, output_interval=end / 4, history_interval=end / 20,
                      gravity_x=g[0], gravity_y=g[1], gravity_z=g[2])
    res = M.run(M.shell_model(M.strip(0.1, 0.05, 4, 2), 0.002, STEEL, control), tmp_path).results
    acceleration = np.asarray(res.acceleration.read_all())
    np.testing.assert_allclose(acceleration, np.broadcast_to(g, acceleration.shape), rtol=1e-9)
    assert np.abs(np.asarray(res.membrane_strain.read_all())).max() < 1e-12
    assert np.all(res.history["reaction_force"] == 0.0) and np.all(res.history["reaction_moment"] == 0.0)
    assert not np.any(np.asarray(res.nodal_contact_force.read_all()))
    with h5py.File(res.path) as h5:
        np.testing.assert_array_equal(h5["/mesh/thickness"][()], 0.002)


def test_cantilever_at_rest_has_its_weight_as_reaction_and_beam_stresses(tmp_path) -> None:
    """The cantilever of tests/test_gravity.py brought to rest by mass damping (transient 5e-5):
    the reaction is -M g (1e-3) and its moment about the origin balances the weights' (1e-3 of
    M g L); the root element's
    outermost points carry sxx = 6 M(x) zeta / (b t^2) with M(x) = q (L - x)^2 / 2 at its centre
    (3 %: shear-deformable shell against the beam) and the middle none (1 % of it); the internal
    energy densities times the initial volumes add up to the history's internal energy."""
    beam = M.cantilever(STEEL)
    g = 9.81
    period = 1.0 / beam.first_frequency
    control = Control(end_time=2.0 * period, output_interval=period, history_interval=period / 50,
                      mass_damping=2.0 * (2.0 * np.pi * beam.first_frequency), gravity_z=-g)
    model = beam.model(control)
    res = M.run(model, tmp_path).results
    weight = STEEL.density * beam.length * beam.width * beam.thickness * g
    np.testing.assert_allclose(res.history["reaction_force"][-1], [0.0, 0.0, weight], rtol=0, atol=1e-3 * weight)
    # at rest the supports' moment about the origin balances the weights': -sum x_i x m_i g
    x = res.coordinates + res.frame_arrays(-1).displacement
    gravity_moment = np.cross(x, M.lumped_masses(model)[:, None] * np.array([0.0, 0.0, -g])).sum(axis=0)
    np.testing.assert_allclose(res.history["reaction_moment"][-1], -gravity_moment, rtol=0,
                               atol=1e-3 * weight * beam.length)

    frame = res.frame_arrays(-1)
    root = np.flatnonzero(res.coordinates[res.connectivity].mean(axis=1)[:, 0] < beam.length / 20)
    x = beam.length / 40   # the root elements' centre
    moment = STEEL.density * beam.thickness * beam.width * g * (beam.length - x) ** 2 / 2
    zeta = K.thickness_points(_points(res))[0]
    bending = 6.0 * moment / (beam.width * beam.thickness**2)
    layers = frame.layer_stress[root]
    # the sag is down (-z), so the top (zeta = +1 side, normal +z) is in tension
    np.testing.assert_allclose(layers[:, 2, 0], bending * zeta[-1], rtol=0.03)
    np.testing.assert_allclose(layers[:, 0, 0], bending * zeta[0], rtol=0.03)
    assert np.abs(layers[:, 1, 0]).max() < 0.01 * bending

    corners = res.coordinates[res.connectivity]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1]), axis=1)
    energy = float(np.sum(frame.internal_energy_density * area * beam.thickness))
    at = int(np.argmin(np.abs(res.history["time"] - frame.time)))
    assert res.history["time"][at] == pytest.approx(frame.time, rel=1e-12)
    assert energy == pytest.approx(res.history["internal_energy"][at], rel=1e-12)


def _points(res) -> int:
    with h5py.File(res.deck_path) as h5:
        return int(h5["/parts/integration_points"][0])


def test_nodal_contact_forces_add_up_to_the_contact_force(tmp_path) -> None:
    """Two plates meeting (the impact of tests/test_contact_activity.py, a frame at every
    record): in every frame the nodal contact forces on the lower plate sum to the history's
    contact force on it (its first part) at that step (1e-9 of the peak), and all of them sum to
    zero (action and reaction, 1e-9)."""
    speed, end = 50.0, 400.0e-6
    clearance = speed * 0.5 * end
    lower = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.5 * PLATE, -0.5 * PLATE, 0.0))
    upper = M.flat_plate((PLATE, PLATE), (N, N), origin=(-0.4 * PLATE, -0.5 * PLATE, T + clearance))
    control = Control(end_time=end, output_interval=end / 400, history_interval=end / 400)
    asm = M.contact_model([M.Body(lower, T), M.Body(upper, T, (3.0, 0.0, -speed))], STEEL, control,
                          static_friction=0.3)
    res = M.run(asm.model, tmp_path).results
    forces = np.asarray(res.nodal_contact_force.read_all())
    on_lower = forces[:, asm.nodes[0]].sum(axis=1)
    history = res.history["contact_force"][:, 0]
    rows = [int(np.argmin(np.abs(res.history["time"] - t))) for t in res.frame_times]
    np.testing.assert_array_equal(res.history["time"][rows], res.frame_times)
    peak = np.abs(history).max()
    assert peak > 0 and np.count_nonzero(np.abs(on_lower).sum(axis=1)) >= 2
    np.testing.assert_allclose(on_lower, history[rows], rtol=0, atol=1e-9 * peak)
    np.testing.assert_allclose(forces.sum(axis=1), 0.0, rtol=0, atol=1e-9 * peak)
