"""The BLT shell element kernels, called through the f2py wrappers (``paradyn._kernels``).

Each test names the reference it checks against in its docstring. Real arrays passed to the
wrappers are float64 and Fortran-ordered; ``intent(inout)`` arrays are updated in place.

Element arrays of ``blt_forces`` put the element index first: ``x[i, :, k]`` is node ``k`` of
element ``i``; ``force[i, 0:3, k]`` is the internal force and ``force[i, 3:6, k]`` the internal
moment at that node (global axes).

Constants shared with the other kernel tests are in ``tests/kernel_cases.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel_cases import C_PLANE, ET, NU, RHO, SY0, E, F, G, T, _rotation
from paradyn import _kernels as K

# ------------------------------------------------------------------------------------------------
# Gauss points through the thickness


@pytest.mark.parametrize("n", range(1, 10))
def test_thickness_points_are_gauss_legendre(n: int) -> None:
    """Reference: numpy.polynomial.legendre.leggauss(n), the n-point Gauss-Legendre rule on [-1, 1]."""
    zeta, weight = K.thickness_points(n)
    z_ref, w_ref = np.polynomial.legendre.leggauss(n)
    np.testing.assert_allclose(zeta, z_ref, rtol=0, atol=1e-14)
    np.testing.assert_allclose(weight, w_ref, rtol=0, atol=1e-14)


# ------------------------------------------------------------------------------------------------
# BLT shell element

NIP = 5


def _state(n: int = 1, nip: int = NIP) -> dict[str, np.ndarray]:
    return {
        "stress": F(np.zeros((n, 5, nip))),
        "back": F(np.zeros((n, 3, nip))),
        "eps_p": F(np.zeros((n, nip))),
        "hourglass": F(np.zeros((n, 10))),
        "e_internal": np.zeros(n),
        "e_hourglass": np.zeros(n),
    }


def _element(a: np.ndarray) -> np.ndarray:
    """(4, 3) node rows of one element -> the kernel layout (1, 3, 4), Fortran-ordered."""
    return F(np.asarray(a, dtype=np.float64).T[None, :, :])


def _forces(x: np.ndarray, v: np.ndarray, w: np.ndarray, dt: float, state: dict[str, np.ndarray],
            hourglass_coefficient: float = 0.1, model: int = 1) -> tuple[np.ndarray, int]:
    """One BLT step on one element; returns force as (4 nodes, 6) and the inverted count."""
    force, inverted = K.blt_forces(
        _element(x), _element(v), _element(w), T, RHO, E, NU, SY0, 0.0, 1.0, hourglass_coefficient,
        model, dt, state["stress"], state["back"], state["eps_p"], state["hourglass"],
        state["e_internal"], state["e_hourglass"])
    return np.asarray(force)[0].T, int(inverted)


def _general_element(warp: float = 0.0) -> np.ndarray:
    """A non-rectangular quadrilateral (5 cm) placed at an arbitrary position and orientation;
    ``warp`` lifts nodes 1, 3 and lowers 2, 4 out of the plane (fraction of the size)."""
    q = 0.05 * np.array([[0.0, 0.0, warp], [1.1, 0.1, -warp], [0.9, 0.8, warp], [-0.1, 1.0, -warp]])
    return q @ _rotation(np.array([0.3, -0.5, 0.8]), 0.7).T + np.array([0.2, -0.3, 0.5])


def test_blt_uniform_stretch_of_a_unit_square() -> None:
    """Reference: plane-stress Hooke's law sxx = E/(1-nu^2) eps, syy = nu E/(1-nu^2) eps, and
    the nodal forces of a constant stress on a rectangle: the x force at each node of an edge
    x = const is t sxx L / 2 (L = edge length), -/+ on the x = 0 / x = 1 edges; the y force is
    t syy a / 2 with a the current width. Rates are taken on the mid-step geometry, which is
    the unit square here, so the strain increment is exactly D dt."""
    square = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    d_rate, dt = 1e3, 1e-9                       # strain increment 1e-6
    v = np.zeros((4, 3))
    v[:, 0] = d_rate * square[:, 0]
    x_end = square + 0.5 * dt * v
    state = _state()
    force, inverted = _forces(x_end, v, np.zeros((4, 3)), dt, state)
    assert inverted == 0

    eps = d_rate * dt
    sxx, syy = C_PLANE * eps, NU * C_PLANE * eps
    stress = state["stress"][0]                  # (5, nip)
    np.testing.assert_allclose(stress[0], sxx, rtol=1e-10)
    np.testing.assert_allclose(stress[1], syy, rtol=1e-10)
    np.testing.assert_allclose(stress[2:], 0.0, rtol=0, atol=1e-10 * sxx)

    scale = T * sxx
    np.testing.assert_allclose(force.sum(axis=0), 0.0, rtol=0, atol=1e-12 * scale)
    edge = 1.0
    np.testing.assert_allclose(force[:, 0], T * sxx * edge / 2 * np.array([-1, 1, 1, -1]), rtol=1e-10)
    width = 1.0 + 0.5 * dt * d_rate
    np.testing.assert_allclose(force[:, 1], T * syy * width / 2 * np.array([-1, -1, 1, 1]), rtol=1e-10)
    np.testing.assert_allclose(force[:, 2:], 0.0, rtol=0, atol=1e-12 * scale)
    # stress work of the step: midpoint rule, 1/2 (0 + sigma) . eps * volume
    assert state["e_internal"][0] == pytest.approx(0.5 * sxx * eps * T * 1.0, rel=1e-9)


KAPPA_S = 5.0 / 6.0             # transverse shear correction


@pytest.mark.parametrize("mode", ["in_plane_shear", "bending_x", "bending_y", "twist", "transverse_shear"])
def test_blt_constant_strain_modes_of_a_unit_square(mode: str) -> None:
    """Reference: Mindlin-Reissner plate kinematics of the BLT element (Belytschko, Lin & Tsay
    1984; Hughes, The Finite Element Method, sec. 5.4) with plane-stress Hooke's law, one step of
    a linear velocity field on the unit square centred at the origin (mid-step geometry):
    in-plane shear v = (g y, 0, 0): sxy = G g dt at every point; bending w_y = k x: sxx =
    E/(1-nu^2) k dt z, syy = nu sxx, moment t^3/12 sxx/z per length, nodal y-moments
    +-M L/2 on the edges x = +-1/2; bending w_x = -k y: syy = E/(1-nu^2) k dt z; twist
    w = (-k x, k y, 0) / 2 (u = z w_y, v = -z w_x, so gxy = k z): sxy = G k dt z; transverse
    shear v_z = g x: sxz = 5/6 G g dt and nodal z forces +-Q L/2."""
    square = np.array([[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]])
    rate, dt = 1e3, 1e-9
    v, w = np.zeros((4, 3)), np.zeros((4, 3))
    xs, ys = square[:, 0], square[:, 1]
    if mode == "in_plane_shear":
        v[:, 0] = rate * ys
    elif mode == "bending_x":
        w[:, 1] = rate * xs
    elif mode == "bending_y":
        w[:, 0] = -rate * ys
    elif mode == "twist":
        w[:, 0], w[:, 1] = -0.5 * rate * xs, 0.5 * rate * ys
    else:
        v[:, 2] = rate * xs
    state = _state()
    force, inverted = _forces(square + 0.5 * dt * v, v, w, dt, state, hourglass_coefficient=0.0)
    assert inverted == 0
    zeta, weight = np.polynomial.legendre.leggauss(NIP)
    z = 0.5 * T * zeta
    expected = np.zeros((5, NIP))
    if mode == "in_plane_shear":
        expected[2] = G * rate * dt
    elif mode == "bending_x":
        expected[0] = C_PLANE * rate * dt * z
        expected[1] = NU * expected[0]
    elif mode == "bending_y":
        expected[1] = C_PLANE * rate * dt * z
        expected[0] = NU * expected[1]
    elif mode == "twist":
        expected[2] = G * rate * dt * z
    else:
        expected[3] = KAPPA_S * G * rate * dt
    scale = np.abs(expected).max()
    np.testing.assert_allclose(state["stress"][0], expected, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(force.sum(axis=0)[0:3], 0.0, rtol=0, atol=1e-12 * scale * T)
    if mode == "bending_x":
        moment = np.sum(0.5 * T * weight * z * expected[0])       # M_xx per unit length
        assert moment == pytest.approx(C_PLANE * rate * dt * T**3 / 12, rel=1e-12)
        np.testing.assert_allclose(force[:, 4], moment * 0.5 * np.array([-1, 1, 1, -1]), rtol=1e-10)
        np.testing.assert_allclose(force[:, 3], -NU * moment * 0.5 * np.array([-1, -1, 1, 1]), rtol=1e-10)
    if mode == "transverse_shear":
        shear_force = T * expected[3, 0]                           # Q_x per unit length
        np.testing.assert_allclose(force[:, 2], shear_force * 0.5 * np.array([-1, 1, 1, -1]), rtol=1e-10)


@pytest.mark.parametrize("component", range(5))
def test_blt_hourglass_modes(component: int) -> None:
    """Reference: Flanagan & Belytschko (1981) hourglass control as used by BLT: on a square the
    hourglass vector is gamma = h = (1, -1, 1, -1), the one-point strain rates do not see a
    velocity (or rotation) field c h, so stresses stay 0; the stiffness-form resultant grows
    linearly with the coefficient, its nodal forces are gamma Q (no net force), and its work in
    the step from rest is the midpoint rule 1/2 Q (gamma . c h) dt (the energy of a linear
    spring, Q^2 / 2k). Components: membrane x, y; rotation x, y; transverse z."""
    square = np.array([[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]])
    h = np.array([1.0, -1.0, 1.0, -1.0])
    c, dt = 2.0, 1e-10       # forces use the end-of-step geometry, c dt / size = 2e-10 off the square
    v, w = np.zeros((4, 3)), np.zeros((4, 3))
    field, axis = [(v, 0), (v, 1), (w, 0), (w, 1), (v, 2)][component]
    field[:, axis] = c * h
    resultants = []
    for coefficient in (0.1, 0.2):
        state = _state()
        force, inverted = _forces(square + 0.5 * dt * v, v, w, dt, state, hourglass_coefficient=coefficient)
        assert inverted == 0
        q = state["hourglass"][0]
        assert np.all(state["stress"] == 0.0)
        assert q[component] != 0.0 and np.all(np.delete(q, component) == 0.0)
        rate = float(h @ (c * h))
        assert state["e_hourglass"][0] == pytest.approx(0.5 * q[component] * rate * dt, rel=1e-12)
        assert state["e_internal"][0] == 0.0
        slot = [0, 1, 3, 4, 2][component]          # force / moment column driven by this resultant
        np.testing.assert_allclose(force[:, slot], h * q[component], rtol=1e-8)
        np.testing.assert_allclose(np.delete(force, slot, axis=1), 0.0, atol=1e-8 * abs(q[component]))
        resultants.append(q[component])
    assert resultants[1] == pytest.approx(2.0 * resultants[0], rel=1e-12)


def test_blt_rigid_translation_gives_no_stress_or_force() -> None:
    """Reference: objectivity; a rigid translation has zero strain rate."""
    x0 = _general_element()
    dt = 1e-6
    v = np.tile([3.0, -2.0, 1.5], (4, 1))
    state = _state()
    force, inverted = _forces(x0 + dt * v, v, np.zeros((4, 3)), dt, state)
    assert inverted == 0
    stress_scale = E * 3.0 * dt / 0.05            # the stress a velocity difference of 3 m/s would give
    assert np.abs(state["stress"]).max() <= 1e-12 * stress_scale
    assert np.abs(state["hourglass"]).max() <= 1e-12 * stress_scale * T * 0.05
    assert np.abs(force).max() <= 1e-12 * stress_scale * T * 0.05
    assert abs(state["e_internal"][0]) <= 1e-20


def test_blt_rigid_rotation_about_an_arbitrary_axis() -> None:
    """Reference: objectivity of the co-rotational BLT element (Belytschko, Lin & Tsay 1984):
    an exact rigid rotation by theta = |Omega| dt about an axis through an arbitrary point,
    v = (x(n+1) - x(n)) / dt and w = Omega, gives strain increments on the mid-step geometry of
    O(theta^3) only (membrane exactly 0; the transverse shear sees tan(theta/2) against
    theta/2), so stresses stay below E theta^3 while a rate on the start or end geometry would
    leave O(E theta^2). The element is flat: without a warping correction a warped BLT element
    sees hourglass rates (gamma . z-offsets) in a rigid rotation about an in-plane axis."""
    x0 = _general_element()
    omega = np.array([40.0, -25.0, 60.0])
    dt = 1e-5
    theta = float(np.linalg.norm(omega)) * dt
    pivot = np.array([0.1, 0.4, -0.2])
    x1 = pivot + (x0 - pivot) @ _rotation(omega, theta).T
    v = (x1 - x0) / dt
    w = np.tile(omega, (4, 1))
    state = _state()
    force, inverted = _forces(x1, v, w, dt, state)
    assert inverted == 0
    bound = E * theta**3
    assert np.abs(state["stress"][0, 0:3]).max() <= 1e-4 * bound      # membrane, bending: round-off
    assert np.abs(state["stress"]).max() <= bound
    assert np.abs(state["hourglass"]).max() <= bound * T * 0.05
    assert np.abs(force).max() <= bound * T * 0.05

    # the same rotation with the rate taken on the start geometry would be strained at O(theta^2)
    assert E * theta**2 > 1e3 * bound


def test_blt_element_turned_inside_out_is_reported() -> None:
    """Reference: docs/formats.md exit status 3 'inverted element' and the kernel contract
    (inverted counts elements of zero or negative area). An element counter-clockwise at
    mid-step whose nodes end the step ordered clockwise (mirrored through its centre line)
    has turned inside out and must be counted."""
    square = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    mirrored = square.copy()
    mirrored[:, 0] = 1.0 - mirrored[:, 0]        # the same nodes mirrored: clockwise seen from +z
    dt = 1e-6
    v = 2.0 * (mirrored - square) / dt           # mid-step geometry x - dt/2 v = the square
    x_end = mirrored
    np.testing.assert_allclose(x_end - 0.5 * dt * v, square, atol=1e-15)
    # the end-of-step geometry is clockwise: signed area (shoelace, seen from +z) is negative
    xs, ys = x_end[:, 0], x_end[:, 1]
    assert 0.5 * np.sum(xs * np.roll(ys, -1) - np.roll(xs, -1) * ys) < 0
    state = _state()
    _, inverted = _forces(x_end, v, np.zeros((4, 3)), dt, state)
    assert inverted == 1


def test_blt_degenerate_element_is_reported() -> None:
    """Reference: kernel contract (inverted counts elements of zero area): four collinear nodes."""
    line = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
    state = _state()
    force, inverted = _forces(line, np.zeros((4, 3)), np.zeros((4, 3)), 1e-6, state)
    assert inverted == 1
    assert np.all(force == 0.0)


def _power_step(dt: float) -> tuple[float, float]:
    """Energy increment of one step and dt * (internal power at the end of the step)."""
    rng = np.random.default_rng(7)
    x0 = _general_element(warp=0.01)
    state = _state()
    state["stress"][...] = rng.uniform(-1e8, 1e8, state["stress"].shape)
    state["hourglass"][...] = rng.uniform(-10.0, 10.0, state["hourglass"].shape)
    v = rng.uniform(-1.0, 1.0, (4, 3))
    w = rng.uniform(-20.0, 20.0, (4, 3))
    force, inverted = _forces(x0 + dt * v, v, w, dt, state)
    assert inverted == 0
    increment = float(state["e_internal"][0] + state["e_hourglass"][0])
    power = float(np.sum(force[:, 0:3] * v) + np.sum(force[:, 3:6] * w))
    return increment, dt * power


def test_blt_internal_power_consistency() -> None:
    """Reference: the discrete virtual-power identity of the element (Belytschko, Liu & Moran,
    Nonlinear Finite Elements, sec. 4.5 and 6.2): the nodal forces are the transpose of the
    strain-rate operator, so the stress + hourglass work of a step equals dt * sum(f . v + m . w)
    up to O(dt^2) (midpoint against end-of-step stress and geometry). Random velocities and
    angular velocities on a slightly warped element with a random stress state, linear elastic:
    relative agreement 1e-6 at a tiny step, and halving dt divides the gap by 4."""
    increment, work = _power_step(1e-11)
    assert increment == pytest.approx(work, rel=1e-6)
    gaps = []
    for dt in (1e-8, 5e-9, 2.5e-9):
        increment, work = _power_step(dt)
        gaps.append(increment - work)
    assert gaps[0] / gaps[1] == pytest.approx(4.0, rel=1e-3)
    assert gaps[1] / gaps[2] == pytest.approx(4.0, rel=1e-3)


# ------------------------------------------------------------------------------------------------
# vectorised kernels: an element's result must not depend on its group (tests/test_parallel.py
# compares layouts bit for bit, and groups differ in size between layouts)


def _random_group(n: int, seed: int) -> tuple[np.ndarray, ...]:
    """n distorted 1 cm quads at random orientations, velocities that yield within one step of
    1e-7 s, a random elastic-plastic history (stress, back stress, plastic strain, hourglass)."""
    rng = np.random.default_rng(seed)
    square = 0.01 * np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    x = np.empty((n, 3, 4))
    for i in range(n):
        q = square + 1e-3 * rng.uniform(-1, 1, (4, 3))
        x[i] = (q @ _rotation(rng.normal(size=3), rng.uniform(0, math.pi)).T).T
    v = 20.0 * rng.uniform(-1, 1, (n, 3, 4))
    w = 100.0 * rng.uniform(-1, 1, (n, 3, 4))
    state = _state(n)
    state["stress"][...] = rng.uniform(-2e8, 2e8, state["stress"].shape)
    state["back"][...] = rng.uniform(-2e7, 2e7, state["back"].shape)
    state["eps_p"][...] = rng.uniform(0.0, 1e-2, state["eps_p"].shape)
    state["hourglass"][...] = rng.uniform(-1.0, 1.0, state["hourglass"].shape)
    return x, v, w, state


def _group_step(x: np.ndarray, v: np.ndarray, w: np.ndarray, state: dict[str, np.ndarray],
                hourglass_form: int) -> dict[str, np.ndarray]:
    """One plastic step (hardening, mixed isotropic/kinematic) of a group; all results by name."""
    state = {k: F(a.copy()) for k, a in state.items()}
    force, inverted = K.blt_forces(F(x), F(v), F(w), T, RHO, E, NU, SY0, ET, 0.5, 0.1, 2, 1e-7,
                                   state["stress"], state["back"], state["eps_p"], state["hourglass"],
                                   state["e_internal"], state["e_hourglass"], hourglass_form=hourglass_form)
    return {"force": np.asarray(force), "inverted": np.array([inverted]), **state}


@pytest.mark.parametrize("hourglass_form", [1, 2], ids=["viscous", "stiffness"])
def test_blt_element_result_is_independent_of_its_group(hourglass_form: int) -> None:
    """Reference: the kernel contract (docs/theory.md, parallel design): every element gets the
    same arithmetic wherever it sits in a group, so the layouts agree bit for bit. 150 elements
    (more than one pass of 64, about half the points yielding, one turned inside out) computed as
    one call, one element per call, and in groups of 1 to 64 starting anywhere: bitwise equal."""
    n = 150
    x, v, w, state = _random_group(n, seed=11)
    # element 7 ends the step with nodes 2 and 4 swapped (turned inside out), mid-step unchanged
    x_mid = x[7] - 0.5e-7 * v[7]
    x[7] = x_mid[:, [0, 3, 2, 1]]
    v[7] = (x[7] - x_mid) / 0.5e-7
    whole = _group_step(x, v, w, state, hourglass_form)
    assert int(whole["inverted"][0]) == 1
    assert 0.2 < np.count_nonzero(whole["eps_p"] > state["eps_p"]) / whole["eps_p"].size < 0.8

    def part(first: int, count: int) -> dict[str, np.ndarray]:
        sl = slice(first, first + count)
        return _group_step(x[sl], v[sl], w[sl], {k: a[sl] for k, a in state.items()}, hourglass_form)

    pieces = [(i, 1) for i in range(0, 12)] + [(3, 61), (64, 64), (5, 7), (100, 50), (0, 63), (1, 64)]
    for first, count in pieces:
        got = part(first, count)
        for key in ("force", "stress", "back", "eps_p", "hourglass", "e_internal", "e_hourglass"):
            assert np.array_equal(got[key], whole[key][first:first + count]), (key, first, count)
