"""The engine's pure kernels, called through the f2py wrappers (``paradyn._kernels``).

Each test names the reference it checks against in its docstring. Real arrays passed to the
wrappers are float64 and Fortran-ordered; ``intent(inout)`` arrays are updated in place.

Element arrays of ``blt_forces`` put the element index first: ``x[i, :, k]`` is node ``k`` of
element ``i``; ``force[i, 0:3, k]`` is the internal force and ``force[i, 3:6, k]`` the internal
moment at that node (global axes).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from paradyn import _kernels as K
from paradyn import deck, geometry

F = np.asfortranarray

# steel
E = 200e9
NU = 0.3
RHO = 7860.0
C_PLANE = E / (1.0 - NU**2)        # plane-stress modulus


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
# J2 plasticity, plane stress, driven along a uniaxial stress path

SY0 = 250e6     # initial yield stress
ET = 2e9        # tangent modulus
H = E * ET / (E - ET)   # plastic modulus dsigma / deps_p of the uniaxial curve


def _von_mises(s: np.ndarray) -> float:
    return math.sqrt(s[0] ** 2 - s[0] * s[1] + s[1] ** 2 + 3.0 * s[2] ** 2)


class UniaxialPoint:
    """One J2 material point driven along a uniaxial stress path sigma = (s, 0, 0).

    The routine takes in-plane strain increments, so each axial increment ``de`` is paired with
    the lateral increment that leaves syy = 0 after the update, found by secant iteration from
    the elastic guess -nu de (each trial restarts from the converged state).
    """

    def __init__(self, beta: float, tangent: float = ET) -> None:
        self.beta = beta
        self.tangent = tangent
        self.stress = np.zeros(3)
        self.back = np.zeros(3)
        self.eps_p = np.array(0.0)   # rank-0 in/out argument: a 0-d array, updated in place
        self.strain = 0.0            # total axial strain

    def trial(self, de: float, dey: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        stress, back, eps_p = self.stress.copy(), self.back.copy(), np.array(float(self.eps_p))
        K.j2_update(stress, back, eps_p, np.array([de, dey, 0.0]), E, NU, SY0, self.tangent, self.beta)
        return stress, back, eps_p

    def step(self, de: float) -> None:
        scale = max(abs(self.sigma), SY0)
        guesses = [-NU * de, -NU * de * (1.0 + 1e-3) if de != 0.0 else 1e-12]
        trials = [self.trial(de, d) for d in guesses]
        for _ in range(60):
            (d0, d1), (g0, g1) = guesses[-2:], (trials[-2][0][1], trials[-1][0][1])
            if abs(g1) <= 1e-14 * scale or abs(trials[0][0][1]) <= 1e-14 * scale or g1 == g0:
                break
            guesses.append(d1 - g1 * (d1 - d0) / (g1 - g0))
            trials.append(self.trial(de, guesses[-1]))
        best = min(trials, key=lambda trial: abs(trial[0][1]))
        assert abs(best[0][1]) <= 1e-12 * scale, "lateral strain iteration did not reach syy = 0"
        self.stress, self.back, self.eps_p = best
        self.strain += de

    @property
    def sigma(self) -> float:
        return float(self.stress[0])


def _load(point: UniaxialPoint, strain_target: float, de: float) -> list[tuple[float, float, float]]:
    """Increments of ``de`` up to ``strain_target``; returns (strain, sigma, eps_p) after each."""
    path = []
    n = int(round((strain_target - point.strain) / de))
    for _ in range(n):
        point.step(de)
        path.append((point.strain, point.sigma, float(point.eps_p)))
    return path


def test_j2_uniaxial_elastic_slope_yield_point_and_hardening_slope() -> None:
    """Reference: the bilinear uniaxial stress-strain curve of linear isotropic hardening
    (Simo & Hughes, Computational Inelasticity, sec. 1.4 and 3.4): slope E up to sigma = sy0,
    then dsigma/deps = Et and dsigma/deps_p = H = E Et / (E - Et); eps_p = eps - sigma / E."""
    point = UniaxialPoint(beta=1.0)
    de = 1e-5
    eps_yield = SY0 / E                                   # 1.25e-3, a whole number of increments
    path = np.array(_load(point, 3 * eps_yield, de))
    strain, sigma, eps_p = path.T

    elastic = strain <= eps_yield * (1 + 1e-12)
    assert np.all(eps_p[elastic] == 0.0)
    np.testing.assert_allclose(np.diff(np.r_[0.0, sigma[elastic]]) / de, E, rtol=1e-9)
    yield_index = int(np.flatnonzero(elastic)[-1])
    assert sigma[yield_index] == pytest.approx(SY0, rel=1e-12)    # the yield point itself
    assert eps_p[yield_index + 1] > 0.0                            # and flow right after it

    plastic = ~elastic
    slope = np.diff(sigma[yield_index:]) / np.diff(strain[yield_index:])
    np.testing.assert_allclose(slope, ET, rtol=1e-6)
    plastic_slope = np.diff(sigma[plastic]) / np.diff(eps_p[plastic])
    np.testing.assert_allclose(plastic_slope, H, rtol=1e-6)

    # on the yield surface after every plastic step (isotropic: radius sy0 + H eps_p, no back stress)
    for s, ep in zip(sigma[plastic], eps_p[plastic]):
        assert abs(s) == pytest.approx(SY0 + H * ep, rel=1e-9)
    # plastic strain consistency: eps_p = total axial strain - sigma / E
    np.testing.assert_allclose(eps_p, strain - sigma / E, rtol=0, atol=1e-9)


@pytest.mark.parametrize("beta", [0.0, 0.5, 1.0])
def test_j2_returned_stress_lies_on_the_yield_surface(beta: float) -> None:
    """Reference: consistency of the return mapping (Simo & Hughes sec. 3.4): after a plastic
    update, von Mises(sigma - alpha) = sy0 + beta H eps_p, for uniaxial steps and for large
    random plane-stress strain increments."""
    point = UniaxialPoint(beta=beta)
    path = _load(point, 4e-3, 2e-5)
    assert path[-1][2] > 0
    xi = point.stress - point.back
    assert _von_mises(xi) == pytest.approx(SY0 + beta * H * float(point.eps_p), rel=1e-9)

    rng = np.random.default_rng(12)
    stress, back, eps_p = np.zeros(3), np.zeros(3), np.array(0.0)
    plastic_steps = 0
    for _ in range(200):
        de = rng.uniform(-1.0, 1.0, 3) * 1.5e-3
        before = float(eps_p)
        K.j2_update(stress, back, eps_p, de, E, NU, SY0, ET, beta)
        if float(eps_p) > before:
            plastic_steps += 1
            radius = SY0 + beta * H * float(eps_p)
            assert _von_mises(stress - back) == pytest.approx(radius, rel=1e-9)
        else:
            assert _von_mises(stress - back) <= (SY0 + beta * H * float(eps_p)) * (1 + 1e-12)
    assert plastic_steps > 50




@pytest.mark.parametrize("beta", [
    0.0,
    0.5,
])
def test_j2_uniaxial_hardening_slope_with_kinematic_hardening(beta: float) -> None:
    """Reference: J2 flow with linear combined hardening and Prager's rule (Simo & Hughes sec. 1.5
    and 2.3.2) gives, under uniaxial stress, the same bilinear curve for every beta: slope Et
    after yield, dsigma/deps_p = H = E Et / (E - Et) (docs/formats.md: Et is the tangent modulus)."""
    point = UniaxialPoint(beta=beta)
    path = np.array(_load(point, 3 * SY0 / E, 1e-5))
    strain, sigma, eps_p = path.T
    plastic = eps_p > 0
    np.testing.assert_allclose(np.diff(sigma[plastic]) / np.diff(strain[plastic]), ET, rtol=1e-6)
    np.testing.assert_allclose(np.diff(sigma[plastic]) / np.diff(eps_p[plastic]), H, rtol=1e-6)


@pytest.mark.parametrize("beta", [
    0.0,
    0.5,
    1.0,
])
def test_j2_reverse_yield_bauschinger(beta: float) -> None:
    """Reference: uniaxial load reversal under linear combined hardening (Simo & Hughes sec. 1.5):
    after loading to sigma_max with plastic strain eps_p, the elastic range is
    2 (sy0 + beta H eps_p), so re-yield happens at sigma_max - 2 (sy0 + beta H eps_p):
    sigma_max - 2 sy0 for kinematic (beta = 0), -sigma_max for isotropic (beta = 1). The
    unloading is bracketed to 1e-7 of the elastic range on either side of that point."""
    point = UniaxialPoint(beta=beta)
    _load(point, 5e-3, 2e-5)
    sigma_max, eps_p = point.sigma, float(point.eps_p)
    assert eps_p > 1e-3
    elastic_range = 2.0 * (SY0 + beta * H * eps_p)
    expected = sigma_max - elastic_range
    if beta == 0.0:
        assert expected == pytest.approx(sigma_max - 2 * SY0, rel=1e-12)
    if beta == 1.0:
        assert expected == pytest.approx(-sigma_max, rel=1e-9)

    unload = -elastic_range / E       # the elastic strain range back to the re-yield point
    inside = UniaxialPoint(beta)
    outside = UniaxialPoint(beta)
    for p in (inside, outside):
        p.stress, p.back, p.eps_p, p.strain = point.stress.copy(), point.back.copy(), \
            np.array(eps_p), point.strain
    inside.step(unload * (1 - 1e-7))
    outside.step(unload * (1 + 1e-7))
    assert float(inside.eps_p) == eps_p, "re-yielded too early"
    assert inside.sigma == pytest.approx(expected, rel=1e-6)
    assert float(outside.eps_p) > eps_p, "did not re-yield"
    assert outside.sigma == pytest.approx(expected, rel=1e-6)


# ------------------------------------------------------------------------------------------------
# BLT shell element

T = 0.01          # thickness
NIP = 5


def _state(n: int = 1, nip: int = NIP) -> dict[str, np.ndarray]:
    return {
        "stress": F(np.zeros((n, 5, nip))),
        "back": F(np.zeros((n, 3, nip))),
        "eps_p": F(np.zeros((n, nip))),
        "hourglass": F(np.zeros((n, 9))),
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


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    a = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


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


G = E / (2.0 * (1.0 + NU))
KAPPA_S = 5.0 / 6.0             # transverse shear correction


@pytest.mark.parametrize("mode", ["in_plane_shear", "bending_x", "bending_y", "twist", "transverse_shear"])
def test_blt_constant_strain_modes_of_a_unit_square(mode: str) -> None:
    """Reference: Mindlin-Reissner plate kinematics of the BLT element (Belytschko, Lin & Tsay
    1984; Hughes, The Finite Element Method, sec. 5.4) with plane-stress Hooke's law, one step of
    a linear velocity field on the unit square centred at the origin (mid-step geometry):
    in-plane shear v = (g y, 0, 0): sxy = G g dt at every point; bending w_y = k x: sxx =
    E/(1-nu^2) k dt z, syy = nu sxx, moment t^3/12 sxx/z per length, nodal y-moments
    +-M L/2 on the edges x = +-1/2; bending w_x = -k y: syy = E/(1-nu^2) k dt z; twist
    w = (-k x, k y, 0) / 2 (u = z w_y, v = -z w_x, so gxy = k z): sxy = G k dt z; transverse shear v_z = g x: sxz = 5/6 G g dt and
    nodal z forces +-Q L/2."""
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


def test_j2_elastic_shear_and_biaxial_increments() -> None:
    """Reference: plane-stress Hooke's law with engineering shear strain, below yield:
    dsxx = E/(1-nu^2) (dexx + nu deyy), dsyy = E/(1-nu^2) (deyy + nu dexx), dsxy = G dgxy."""
    stress, back, eps_p = np.zeros(3), np.zeros(3), np.array(0.0)
    de = np.array([2e-4, -1e-4, 3e-4])
    K.j2_update(stress, back, eps_p, de, E, NU, SY0, ET, 1.0)
    expected = [C_PLANE * (de[0] + NU * de[1]), C_PLANE * (de[1] + NU * de[0]), G * de[2]]
    np.testing.assert_allclose(stress, expected, rtol=1e-14)
    assert float(eps_p) == 0.0 and np.all(back == 0.0)


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


def test_j2_points_match_the_scalar_return_and_do_not_depend_on_their_neighbours() -> None:
    """Reference: j2_update (the scalar return mapping, checked against closed forms above).
    The array form used by the element kernel runs the same algorithm across points: 200 random
    states and increments, about half yielding, agree with the scalar return to round-off, and a
    point's result is bitwise the same in any batch (whole, alone, shifted)."""
    rng = np.random.default_rng(5)
    m = 200
    stress0 = rng.uniform(-2e8, 2e8, (m, 3))
    back0 = rng.uniform(-3e7, 3e7, (m, 3))
    eps0 = rng.uniform(0.0, 1e-2, m)
    de = rng.uniform(-1.5e-3, 1.5e-3, (m, 3))

    def batch(sl: slice) -> tuple[np.ndarray, ...]:
        s, b, e = F(stress0[sl].copy()), F(back0[sl].copy()), eps0[sl].copy()
        K.j2_update_points(s, b, e, F(de[sl]), E, NU, SY0, ET, 0.5)
        return s, b, e

    s_all, b_all, e_all = batch(slice(0, m))
    yielded = e_all > eps0
    assert 0.2 * m < np.count_nonzero(yielded) < 0.8 * m
    for i in range(m):
        s, b, e = stress0[i].copy(), back0[i].copy(), np.array(eps0[i])
        K.j2_update(s, b, e, de[i], E, NU, SY0, ET, 0.5)
        np.testing.assert_allclose(s_all[i], s, rtol=1e-12, atol=1e-12 * SY0)
        np.testing.assert_allclose(b_all[i], b, rtol=1e-12, atol=1e-12 * SY0)
        assert float(e_all[i]) == pytest.approx(float(e), rel=1e-12, abs=1e-18)
    for sl in (slice(3, 4), slice(1, 66), slice(70, 200), slice(131, 140)):
        s, b, e = batch(sl)
        assert np.array_equal(s, s_all[sl]) and np.array_equal(b, b_all[sl]) and np.array_equal(e, e_all[sl])


# ------------------------------------------------------------------------------------------------
# mass and stable time step


def _pipe_elements(radius: float = 0.08, length: float = 2.0, around: int = 16,
                   along: int = 32) -> np.ndarray:
    """The pipe whip mesh built analytically: (n, 4, 3) node rows, outward normals."""
    angles = 2 * np.pi * np.arange(around + 1) / around
    xs = np.linspace(-length / 2, length / 2, along + 1)
    elements = []
    for i in range(along):
        for j in range(around):
            p = [(xs[i], angles[j]), (xs[i + 1], angles[j]), (xs[i + 1], angles[j + 1]),
                 (xs[i], angles[j + 1])]
            elements.append([[x, radius * math.cos(a), radius * math.sin(a)] for x, a in p])
    return np.array(elements)


def _layout(elements: np.ndarray) -> np.ndarray:
    return F(np.transpose(elements, (0, 2, 1)))


def _plate_elements(rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """A 6 x 4 plate with jiggled interior nodes (general convex quads), tilted in 3D; area."""
    nx, ny = 6, 4
    gx, gy = np.meshgrid(np.linspace(0, 0.3, nx + 1), np.linspace(0, 0.2, ny + 1), indexing="ij")
    gx[1:-1, 1:-1] += rng.uniform(-0.01, 0.01, (nx - 1, ny - 1))
    gy[1:-1, 1:-1] += rng.uniform(-0.01, 0.01, (nx - 1, ny - 1))
    rotation = _rotation(np.array([1.0, 2.0, -0.5]), 0.9)
    elements, area = [], 0.0
    for i in range(nx):
        for j in range(ny):
            q = np.array([[gx[i, j], gy[i, j]], [gx[i + 1, j], gy[i + 1, j]],
                          [gx[i + 1, j + 1], gy[i + 1, j + 1]], [gx[i, j + 1], gy[i, j + 1]]])
            area += 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])
            elements.append(np.c_[q, np.zeros(4)] @ rotation.T)
    return np.array(elements), area


def test_blt_lumped_mass_adds_up_to_the_total_mass() -> None:
    """Reference: mass conservation of the lumped mass, sum over elements of 4 * node_mass =
    rho t (total area), on a tilted plate of general quadrilaterals (shoelace area) and on the
    pipe whip's 16 x 32 polygonal cylinder (512 rectangles 2 R sin(pi/16) x 0.0625); and the
    documented rotary inertia I = m (t^2 + A) / 4."""
    rng = np.random.default_rng(3)
    plate, area = _plate_elements(rng)
    mass, inertia = K.blt_mass(_layout(plate), T, RHO)
    assert 4.0 * mass.sum() == pytest.approx(RHO * T * area, rel=1e-12)
    element_area = 4.0 * mass / (RHO * T)
    np.testing.assert_allclose(inertia, mass * (T**2 + element_area) / 4.0, rtol=1e-12)

    pipe = _pipe_elements()
    t_pipe = 0.003
    mass, _ = K.blt_mass(_layout(pipe), t_pipe, RHO)
    side = 2 * 0.08 * math.sin(math.pi / 16)
    assert 4.0 * mass.sum() == pytest.approx(RHO * t_pipe * 512 * side * 0.0625, rel=1e-12)


def test_blt_time_step_of_the_pipe_element() -> None:
    """Reference: LS-DYNA Theory Manual shell time step dt = L / c, L = area / longest side,
    c = sqrt(E / (rho (1 - nu^2))). Pipe whip (R = 0.08, 16 around, 32 along, nu = 0.28): the
    element is 2 R sin(pi/16) x 0.0625, so dt = 2 R sin(pi/16) / c = 5.94 us; a true circle's
    arc 2 pi R / 16 would give the benchmark's ~5.98 us (before the 0.9 safety factor)."""
    nu = 0.28
    pipe = _pipe_elements()
    dt = K.blt_time_step(_layout(pipe), 0.003, RHO, E, nu)
    c = math.sqrt(E / (RHO * (1 - nu**2)))
    side, length = 2 * 0.08 * math.sin(math.pi / 16), 0.0625
    expected = side * length / max(side, length) / c
    np.testing.assert_allclose(dt, expected, rtol=1e-12)
    arc = 2 * math.pi * 0.08 / 16
    assert arc / c == pytest.approx(5.98e-6, rel=2e-3)
    assert dt.min() == pytest.approx(5.98e-6 * side / arc, rel=2e-3)


# ------------------------------------------------------------------------------------------------
# domain decomposition


@pytest.mark.parametrize("n_elements, n_ranks", [
    (1, 1), (10, 1), (10, 3), (32, 4), (512, 3), (1024, 7), (3, 5), (7, 7), (1_000_003, 13),
])
def test_block_partition(n_elements: int, n_ranks: int) -> None:
    """Reference: the paper's contiguous element blocks (domain_decomposition.block_owner):
    owners are 0-based, non-decreasing (contiguous blocks), every element has exactly one owner
    in 0..n_ranks-1, block sizes differ by at most one, and block r holds elements
    floor(r n / p) + 1 .. floor((r + 1) n / p) (1-based)."""
    owner = np.asarray(K.block_partition(n_elements, n_ranks))
    assert owner.shape == (n_elements,)
    assert owner.min() >= 0 and owner.max() <= n_ranks - 1
    assert np.all(np.diff(owner) >= 0)
    sizes = np.bincount(owner, minlength=n_ranks)
    assert sizes.sum() == n_elements
    assert sizes.max() - sizes.min() <= 1
    r = np.arange(n_ranks + 1, dtype=np.int64)
    bounds = (r * n_elements) // n_ranks
    np.testing.assert_array_equal(sizes, np.diff(bounds))


def _rcb(centroids: np.ndarray, n_ranks: int) -> np.ndarray:
    """rcb_partition on centroids given as (n, 3)."""
    c = F(np.asarray(centroids, dtype=np.float64).T)
    return np.asarray(K.rcb_partition(c.shape[1], c, n_ranks))


def _rcb_reference(centroids: np.ndarray, n_ranks: int) -> np.ndarray:
    """The rule of docs/theory.md written independently with numpy: cut the longest side of the
    bounding box (lowest axis on a tie), the first n q_low / q elements in (coordinate, id) order
    go to the first q_low = q // 2 ranks."""
    owner = np.full(len(centroids), -1)

    def split(ids: np.ndarray, rank0: int, q: int) -> None:
        if q == 1 or ids.size == 0:
            owner[ids] = rank0
            return
        extent = centroids[ids].max(axis=0) - centroids[ids].min(axis=0)
        axis = int(np.argmax(extent))            # first maximum: the lowest axis on a tie
        ids = ids[np.lexsort((ids, centroids[ids, axis]))]
        n_low = ids.size * (q // 2) // q
        split(ids[:n_low], rank0, q // 2)
        split(ids[n_low:], rank0 + q // 2, q - q // 2)

    split(np.arange(len(centroids)), 0, n_ranks)
    return owner


def _grid_centroids(nx: int, ny: int) -> np.ndarray:
    """Centroids of an nx x ny grid of unit squares, numbered row by row (x fastest)."""
    x, y = np.meshgrid(np.arange(nx) + 0.5, np.arange(ny) + 0.5, indexing="xy")
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(nx * ny)])


def _point_sets() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(5)
    return {
        "grid_12x7": _grid_centroids(12, 7),
        "random_3d_500": rng.random((500, 3)) * [3.0, 1.0, 2.0],
        "line_with_duplicates": np.repeat(np.column_stack([np.arange(9.0), np.zeros(9), np.zeros(9)]), 3, axis=0),
        "three_points": rng.random((3, 3)),
    }


@pytest.mark.parametrize("name", list(_point_sets()))
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4, 5, 7, 8])
def test_rcb_partition_owners_and_sizes(name: str, n_ranks: int) -> None:
    """Reference: the rule of docs/theory.md (recursive coordinate bisection), as an independent
    numpy implementation: the owners are exactly its owners, every element has one owner in
    0..p-1 and part sizes differ by at most one, for any rank count (not only powers of two)."""
    centroids = _point_sets()[name]
    owner = _rcb(centroids, n_ranks)
    assert owner.shape == (len(centroids),)
    assert owner.min() >= 0 and owner.max() <= n_ranks - 1
    sizes = np.bincount(owner, minlength=n_ranks)
    assert sizes.sum() == len(centroids)
    assert sizes.max() - sizes.min() <= 1
    np.testing.assert_array_equal(owner, _rcb_reference(centroids, n_ranks))


@pytest.mark.parametrize("n_ranks", [2, 3, 4, 5, 7, 8])
def test_rcb_parts_are_separated_by_axis_aligned_planes(n_ranks: int) -> None:
    """Reference: the definition of a bisection by planes x_k = const: for every two parts
    there is an axis along which one part lies entirely at or below the other (random points in
    general position, where no two coordinates tie). Contiguous blocks of a random numbering fail
    this, so the check has teeth."""
    centroids = np.random.default_rng(11).random((400, 3)) * [4.0, 2.0, 1.0]
    owner = _rcb(centroids, n_ranks)

    def separated(a: np.ndarray, b: np.ndarray) -> bool:
        return bool(np.any((a.max(axis=0) <= b.min(axis=0)) | (b.max(axis=0) <= a.min(axis=0))))

    parts = [centroids[owner == r] for r in range(n_ranks)]
    for r in range(n_ranks):
        for s in range(r + 1, n_ranks):
            assert separated(parts[r], parts[s]), (r, s)
    blocks = np.asarray(K.block_partition(len(centroids), n_ranks))
    assert not separated(centroids[blocks == 0], centroids[blocks == 1])


def test_rcb_partition_of_a_grid_is_boxes() -> None:
    """Reference: hand count on an 8 x 2 grid of unit squares (long axis x): 2 ranks get the two
    4 x 2 halves, 4 ranks the four 2 x 2 quarters, in order of x."""
    centroids = _grid_centroids(8, 2)
    halves = _rcb(centroids, 2).reshape(2, 8)
    np.testing.assert_array_equal(halves, [[0, 0, 0, 0, 1, 1, 1, 1]] * 2)
    quarters = _rcb(centroids, 4).reshape(2, 8)
    np.testing.assert_array_equal(quarters, [[0, 0, 1, 1, 2, 2, 3, 3]] * 2)
    # a 2 x 8 grid (long axis y) is cut across y instead: rows 0-3 and rows 4-7
    tall = _rcb(_grid_centroids(2, 8), 2).reshape(8, 2)
    np.testing.assert_array_equal(tall, [[0, 0]] * 4 + [[1, 1]] * 4)


def test_rcb_partition_follows_coordinates_not_numbering() -> None:
    """Reference: hand count on a line of 10 elements numbered against x (element 0 at the far
    end): 3 ranks get 3, 3 and 4 elements (n_low = 10 // 3, then 7 // 2) in order of x."""
    centroids = np.column_stack([np.arange(10.0)[::-1], np.zeros(10), np.zeros(10)])
    owner = _rcb(centroids, 3)
    np.testing.assert_array_equal(owner, [2, 2, 2, 2, 1, 1, 1, 0, 0, 0])


def test_rcb_partition_breaks_ties_by_element_id() -> None:
    """Reference: docs/theory.md, ties in the cut coordinate go by element id. With every
    centroid at the same point the parts are the id ranges of the block partition; with each
    point of a line present twice, the copies with lower ids come first; and a second call gives
    the same array (every rank computes it alone)."""
    same = np.ones((10, 3))
    np.testing.assert_array_equal(_rcb(same, 3), K.block_partition(10, 3))
    line = np.column_stack([np.arange(5.0), np.zeros(5), np.zeros(5)])
    doubled = np.vstack([line, line])             # element i and i + 5 coincide
    owner = _rcb(doubled, 5)
    np.testing.assert_array_equal(owner, [0, 1, 2, 3, 4, 0, 1, 2, 3, 4])
    owner = _rcb(doubled, 4)   # x order 0, 5, 1, 6, 2 | 7, 3, 8, 4, 9, then 0, 5 | 1, 6, 2 and 7, 3 | 8, 4, 9
    np.testing.assert_array_equal(owner, [0, 1, 1, 2, 3, 0, 1, 2, 3, 3])
    random = np.round(np.random.default_rng(3).random((300, 3)) * 4) / 4   # many exact ties
    np.testing.assert_array_equal(_rcb(random, 7), _rcb(random, 7))


def _permuted_plate(nx: int, ny: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A flat nx x ny plate whose elements are numbered in random order: coordinates (n, 3),
    connectivity (e, 4) 0-based, and the permutation (element k is element perm[k] of the
    row-by-row numbering)."""
    mesh = geometry.plate((float(nx), float(ny)), (nx, ny))
    perm = np.random.default_rng(seed).permutation(mesh.n_elements)
    return mesh.coordinates, mesh.quads[perm], perm


def _shared_nodes(connectivity: np.ndarray, owner: np.ndarray) -> int:
    """Nodes touched by elements of more than one rank."""
    pairs = np.unique(np.column_stack([connectivity.ravel(), np.repeat(owner, 4)]), axis=0)
    return int(np.count_nonzero(np.bincount(pairs[:, 0]) > 1))


def _engine_owner(method: str, coordinates: np.ndarray, connectivity: np.ndarray, n_ranks: int) -> np.ndarray:
    return np.asarray(K.partition_elements(deck.PARTITIONS[method], F(coordinates.T),
                                           F(connectivity.T.astype(np.int32) + 1), n_ranks))


@pytest.mark.parametrize("n_ranks, cut_nodes", [(2, 17), (4, 33), (8, 65)])
def test_rcb_cuts_a_badly_numbered_plate_along_straight_lines(n_ranks: int, cut_nodes: int) -> None:
    """Reference: a 16 x 16 plate cut by straight grid lines: one line (17 shared nodes) on 2
    ranks, a line and a half-line each side (17 + 2 x 8 = 33) on 4, and 65 on 8, whatever the
    element numbering. Contiguous blocks of a random numbering share far more nodes (about all
    of them)."""
    coordinates, connectivity, perm = _permuted_plate(16, 16, seed=7)
    rcb = _engine_owner("rcb", coordinates, connectivity, n_ranks)
    blocks = _engine_owner("blocks", coordinates, connectivity, n_ranks)
    assert _shared_nodes(connectivity, rcb) == cut_nodes
    assert _shared_nodes(connectivity, blocks) > 3 * cut_nodes
    # the same parts as for the row-by-row numbering: here rcb depends on positions only
    plain = geometry.plate((16.0, 16.0), (16, 16))
    row_by_row = np.empty_like(rcb)
    row_by_row[perm] = rcb
    np.testing.assert_array_equal(row_by_row, _engine_owner("rcb", plain.coordinates, plain.quads, n_ranks))


def _two_part_mesh(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 6 x 5 plate and a 4 x 8 cylinder as one mesh, elements randomly renumbered: coordinates,
    connectivity (0-based) and element part."""
    plate = geometry.plate((0.3, 0.25), (6, 5))
    tube = geometry.cylinder(0.05, 0.4, center=(0.15, 0.1, 0.2), elements_around=4, elements_along=8)
    coordinates = np.vstack([plate.coordinates, tube.coordinates])
    connectivity = np.vstack([plate.quads, tube.quads + plate.n_nodes])
    part = np.concatenate([np.zeros(plate.n_elements, int), np.ones(tube.n_elements, int)])
    perm = np.random.default_rng(seed).permutation(len(connectivity))
    return coordinates, connectivity[perm], part[perm]


@pytest.mark.parametrize("method", ["blocks", "rcb"])
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4, 7])
def test_decomposition_sums_every_corner_exactly_once(method: str, n_ranks: int) -> None:
    """Reference: the serial nodal sum. Issue 5: every element owned by exactly one rank, shared
    nodes consistent, forces on shared nodes summed exactly once. decompose builds every rank's
    domain for the owners of the method, and the wrapper plays out the engine's corner exchange
    and fixed-order sum between them without MPI. Checked against numpy: each element is local on
    exactly its owner; each node is held by exactly the ranks whose elements touch it and owned
    by exactly one, the lowest; on every rank that holds a node, the sum of its corners equals
    the serial one: the count of corners, the sum of the corner ids (a corner lost or counted
    twice changes it) and, bitwise, a sum of random values taken in ascending element order."""
    coordinates, connectivity, part = _two_part_mesh(seed=n_ranks)
    n_nodes, n_elements = len(coordinates), len(connectivity)
    owner = _engine_owner(method, coordinates, connectivity, n_ranks)
    rng = np.random.default_rng(1)
    values = np.empty((3, 4, n_elements))
    values[0] = 1.0
    values[1] = np.arange(4 * n_elements).reshape(n_elements, 4).T      # corner id 4 e + c
    values[2] = rng.standard_normal((4, n_elements)) * 10.0 ** rng.integers(-3, 4, (4, n_elements))
    (element_holders, element_rank, node_holders, node_owners, n_neighbours, n_sent, node_sum,
     status) = K.decomposition_check(n_nodes, F(connectivity.T.astype(np.int32) + 1), part.astype(np.int32) + 1,
                                     owner.astype(np.int32), n_ranks, F(values))
    assert status == 0
    np.testing.assert_array_equal(element_holders, 1)
    np.testing.assert_array_equal(element_rank, owner)

    ranks_of_node = [set() for _ in range(n_nodes)]
    serial = np.zeros((3, n_nodes))
    for e in range(n_elements):                  # ascending element order, as the engine sums
        for c in range(4):
            n = connectivity[e, c]
            ranks_of_node[n].add(int(owner[e]))
            serial[:, n] += values[:, c, e]
    np.testing.assert_array_equal(node_holders, [len(r) for r in ranks_of_node])
    np.testing.assert_array_equal(node_owners, 1)
    for n in range(n_nodes):
        for r in range(n_ranks):
            if r in ranks_of_node[n]:
                assert np.array_equal(node_sum[:, n, r], serial[:, n]), (n, r)
            else:
                assert np.all(node_sum[:, n, r] == 0.0)
    neighbours = [set() for _ in range(n_ranks)]
    for held in ranks_of_node:
        for r in held:
            neighbours[r] |= held - {r}
    np.testing.assert_array_equal(n_neighbours, [len(s) for s in neighbours])
    assert (n_ranks == 1) == (n_sent.sum() == 0)
