"""The C0 triangle's kernels (shell_c0_triangle, shell_measures), through the f2py wrappers of
``fortran/python/triangle_f2py.f90`` (``paradyn._kernels``); the layout of test_kernels_blt.py: a
triangle is a quadrilateral whose fourth node repeats its third, ``x[i, :, k]`` node ``k`` of element
``i``, ``force[i, 0:3, k]`` the force and ``force[i, 3:6, k]`` the moment at corner ``k`` (global).

Each test names its reference and a tolerance that a wrong formulation fails by orders of magnitude.
"""

from __future__ import annotations

import numpy as np
import pytest

from kernel_cases import C_PLANE, NU, RHO, SY0, E, F, G, T, _rotation
from paradyn import _kernels as K

NIP = 5
ELASTIC, J2 = 1, 2


def _state(n: int, nip: int = NIP) -> dict[str, np.ndarray]:
    return {"stress": F(np.zeros((n, 5, nip))), "back": F(np.zeros((n, 3, nip))), "eps_p": F(np.zeros((n, nip))),
            "hourglass": F(np.zeros((n, 10))), "e_internal": np.zeros(n), "e_hourglass": np.zeros(n)}


def _layout(rows: np.ndarray) -> np.ndarray:
    """(n, 3, 3) node rows of n triangles (node, xyz) -> the kernel layout (n, 3, 4), corner 4 = corner 3."""
    a = np.asarray(rows, dtype=np.float64).transpose(0, 2, 1)
    return F(np.concatenate([a, a[:, :, 2:3]], axis=2))


def _step(x: np.ndarray, v: np.ndarray, w: np.ndarray, dt: float, state: dict[str, np.ndarray],
          model: int = ELASTIC, nip: int = NIP) -> tuple[np.ndarray, int, np.ndarray]:
    """One step of n triangles; x, v, w (n, 3 nodes, 3); returns force (n, 3 nodes, 6), inverted, dt_element."""
    force, inverted, dt_element = K.triangle_forces(
        _layout(x), _layout(v), _layout(w), T, RHO, E, NU, SY0, 0.0, 1.0, model, dt,
        state["stress"], state["back"], state["eps_p"], state["hourglass"], state["e_internal"], state["e_hourglass"],
        nip=nip)
    force = np.asarray(force)
    assert np.all(force[:, :, 3] == 0.0)   # the repeated fourth corner gets nothing
    return force[:, :, :3].transpose(0, 2, 1), int(inverted), np.asarray(dt_element)


def _patch() -> tuple[np.ndarray, np.ndarray, int]:
    """An irregular patch of 5 triangles around interior node 5 (0.4 m): node coordinates (6, 3), the
    triangles (5, 3) counter-clockwise, and the interior node."""
    nodes = np.array([[0.0, 0.0, 0.0], [0.4, 0.0, 0.0], [0.45, 0.3, 0.0], [0.2, 0.42, 0.0], [-0.05, 0.25, 0.0],
                      [0.17, 0.19, 0.0]])
    tris = np.array([[0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 4, 5], [4, 0, 5]])
    return nodes, tris, 5


def _placed(p: np.ndarray) -> np.ndarray:
    """The patch turned and moved to a general place in space (frame invariance)."""
    return p @ _rotation(np.array([0.3, -0.5, 0.8]), 0.7).T + np.array([0.2, -0.3, 0.5])


def _assembled(force: np.ndarray, tris: np.ndarray, n_nodes: int) -> np.ndarray:
    out = np.zeros((n_nodes, 6))
    np.add.at(out, tris.ravel(), force.reshape(-1, 6))
    return out


def test_membrane_patch_test() -> None:
    """Reference: the constant-strain patch test (Irons; MacNeal & Harder 1985, patch test a) and
    plane-stress Hooke's law. A linear velocity field of constant strain rate D on an irregular patch
    of five triangles, placed anywhere in space: every element's stress (in its own frame, e1 along
    side 1-2) is the local components of C D dt, and the interior node carries no net force or moment.
    Tolerances 1e-9 of the stress, 1e-7 of the boundary forces (the step of 1e-8 s moves the geometry
    of the forces by 1e-8 of its size): a wrong membrane gradient errs by order 1."""
    nodes, tris, inner = _patch()
    rot = _rotation(np.array([0.3, -0.5, 0.8]), 0.7)
    d = np.array([[1.0, 0.4, 0.0], [0.4, -0.6, 0.0], [0.0, 0.0, 0.0]])   # strain rate in the patch plane
    dt = 1e-8
    x_mid = _placed(nodes)
    v = nodes @ d.T @ rot.T
    x = x_mid + 0.5 * dt * v
    state = _state(len(tris))
    force, inverted, _ = _step(x[tris], v[tris], np.zeros_like(x[tris]), dt, state)
    assert inverted == 0
    eps = d * dt
    sigma = C_PLANE * np.array([[eps[0, 0] + NU * eps[1, 1], (1 - NU) * eps[0, 1]],
                                [(1 - NU) * eps[0, 1], eps[1, 1] + NU * eps[0, 0]]])
    for i, tri in enumerate(tris):
        p = nodes[tri]
        e1 = (p[1] - p[0])[:2] / np.linalg.norm(p[1] - p[0])
        e2 = np.array([-e1[1], e1[0]])
        local = np.array([e1 @ sigma @ e1, e2 @ sigma @ e2, e1 @ sigma @ e2])
        for k in range(NIP):
            np.testing.assert_allclose(state["stress"][i, :3, k], local, rtol=0, atol=1e-9 * np.abs(sigma).max())
            np.testing.assert_allclose(state["stress"][i, 3:, k], 0.0, atol=1e-9 * np.abs(sigma).max())
    total = _assembled(force, tris, len(nodes))
    scale = np.abs(total[:, :3]).max()
    np.testing.assert_allclose(total[inner], 0.0, atol=1e-7 * scale)
    np.testing.assert_allclose(total.sum(axis=0)[:3], 0.0, atol=1e-7 * scale)


def _kirchhoff_rates(p: np.ndarray, hess: np.ndarray, slope: np.ndarray, w0: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodal rates of the deflection w = w0 + slope.x + x.H.x / 2 (local plane) with the Kirchhoff
    rotations theta_x = dw/dy, theta_y = -dw/dx (no transverse shear): v (n, 3), w (n, 3) local."""
    xy = p[:, :2]
    wz = w0 + xy @ slope + 0.5 * np.einsum("ni,ij,nj->n", xy, hess, xy)
    grad = slope + xy @ hess.T
    v = np.zeros((len(p), 3))
    v[:, 2] = wz
    w = np.zeros((len(p), 3))
    w[:, 0] = grad[:, 1]
    w[:, 1] = -grad[:, 0]
    return v, w


def test_bending_patch_test_and_no_shear_locking() -> None:
    """Reference: the constant-curvature (Kirchhoff) bending patch test (MacNeal & Harder 1985,
    patch test; Batoz & Dhatt): nodal rates of any quadratic deflection with Kirchhoff rotations on the
    irregular patch give every element the curvature -H, the bending stress C z (-H) dt at each point,
    zero transverse shear (the edge-tied shear of a quadratic field vanishes: no shear locking), and
    no net force or moment on the interior node. Tolerances 1e-9 of the bending stress: a
    centroid-only shear (grad w + phi at the centroid) leaves a shear of the order of the curvature
    times the element size, 1e6 times that; the interior node's balance within 1e-7 of the largest
    nodal load (the forces are taken on the end-of-step geometry)."""
    nodes, tris, inner = _patch()
    rot = _rotation(np.array([0.3, -0.5, 0.8]), 0.7)
    hess = np.array([[2.0, 0.7], [0.7, -1.2]])
    v_loc, w_loc = _kirchhoff_rates(nodes, hess, np.array([0.3, -0.2]), 0.1)
    dt = 1e-8
    x_mid = _placed(nodes)
    v, w = v_loc @ rot.T, w_loc @ rot.T
    x = x_mid + 0.5 * dt * v
    state = _state(len(tris))
    force, inverted, _ = _step(x[tris], v[tris], w[tris], dt, state)
    assert inverted == 0
    zeta, _ = np.polynomial.legendre.leggauss(NIP)
    kappa = -hess * dt
    sigma_unit = C_PLANE * np.array([[kappa[0, 0] + NU * kappa[1, 1], (1 - NU) * kappa[0, 1]],
                                     [(1 - NU) * kappa[0, 1], kappa[1, 1] + NU * kappa[0, 0]]])
    scale = np.abs(sigma_unit).max() * 0.5 * T
    for i, tri in enumerate(tris):
        p = nodes[tri]
        e1 = (p[1] - p[0])[:2] / np.linalg.norm(p[1] - p[0])
        e2 = np.array([-e1[1], e1[0]])
        local = np.array([e1 @ sigma_unit @ e1, e2 @ sigma_unit @ e2, e1 @ sigma_unit @ e2])
        for k in range(NIP):
            z = 0.5 * T * zeta[k]
            np.testing.assert_allclose(state["stress"][i, :3, k], z * local, rtol=0, atol=1e-9 * scale)
            np.testing.assert_allclose(state["stress"][i, 3:, k], 0.0, atol=1e-9 * scale)
    total = _assembled(force, tris, len(nodes))
    np.testing.assert_allclose(total[inner], 0.0, atol=1e-7 * np.abs(total).max())


@pytest.mark.parametrize("motion", ["translation", "rotation"])
def test_rigid_body_motion_gives_no_strain(motion: str) -> None:
    """Reference: a rigid motion does no stress work (objectivity; Belytschko, Liu & Moran 2014,
    sec. 5.4). A general triangle in space moved by v = v0 + omega x (x - c), with angular velocity
    omega at the nodes, over one step: the mid-step geometry makes the strain increment of a rigid
    rotation vanish to second order, so the stress stays below 1e-6 of E omega dt (a first-order
    error gives 1e-4 at omega dt = 1e-4), no drilling moment arises and no force acts."""
    nodes, tris, _ = _patch()
    tri = _placed(nodes)[tris[1]]
    omega = np.array([0.0, 0.0, 0.0]) if motion == "translation" else np.array([30.0, -50.0, 80.0])
    v = np.array([3.0, -2.0, 1.0]) + np.cross(omega, tri - tri.mean(axis=0))
    w = np.tile(omega, (3, 1))
    dt = 1e-4 / max(np.linalg.norm(omega), 1.0)
    state = _state(1)
    force, _, _ = _step((tri + 0.5 * dt * v)[None], v[None], w[None], dt, state)
    bound = 1e-6 * E * max(np.linalg.norm(omega), 1.0) * dt
    assert np.abs(state["stress"]).max() < bound
    assert np.abs(state["hourglass"]).max() < bound * T * 1e-3
    assert np.abs(force).max() < bound * T * 0.1


def _random_group(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    base = np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.02, 0.04, 0.0]])
    x = np.empty((n, 3, 3))
    for i in range(n):
        r = _rotation(rng.normal(size=3), rng.uniform(0, np.pi))
        x[i] = (base + 0.01 * rng.uniform(-1, 1, (3, 3)) * [1, 1, 0.2]) @ r.T + rng.uniform(-1, 1, 3)
    return x, rng.normal(scale=2.0, size=(n, 3, 3)), rng.normal(scale=40.0, size=(n, 3, 3))


def test_forces_are_the_power_conjugates_of_the_strain_rates() -> None:
    """Reference: the virtual power of a one-point element (Belytschko, Liu & Moran, sec. 9.5): the
    nodal forces times the nodal velocities equal the stress power A int(sigma : d) dz, here the rate
    of the stress and drilling work the kernel accumulates. After a prestressing step (all five
    stress components and the drilling moments), a step of 1e-12 s with other random velocities:
    (dE_int + dE_drill) / dt = sum(f . v + m . w) within 1e-6 (the step changes the stress by 1e-7
    of itself). A missing or wrong edge-shear moment errs by order 1."""
    x, v1, w1 = _random_group(20, seed=3)
    state = _state(20)
    _step(x + 0.5e-5 * v1, v1, w1, 1e-5, state)
    x = x + 1e-5 * v1
    _, v2, w2 = _random_group(20, seed=4)
    state["e_internal"][:] = 0.0
    state["e_hourglass"][:] = 0.0
    dt = 1e-12
    force, _, _ = _step(x + 0.5 * dt * v2, v2, w2, dt, state)
    power = np.einsum("nki,nki->n", force[:, :, :3], v2) + np.einsum("nki,nki->n", force[:, :, 3:], w2)
    rate = (state["e_internal"] + state["e_hourglass"]) / dt
    np.testing.assert_allclose(rate, power, rtol=1e-6, atol=1e-6 * np.abs(power).max())


def test_element_result_is_independent_of_its_group() -> None:
    """Reference: the kernel contract (docs/theory.md, parallel design): every element gets the same
    arithmetic wherever it sits in a group, so that the layouts agree bit for bit. 150 plastic
    triangles as one call, one per call, and in groups of 1 to 64 starting anywhere: bitwise equal."""
    n = 150
    x, v, w = _random_group(n, seed=11)
    v *= 10.0    # some of the points yield in the step

    def run(first: int, count: int) -> dict[str, np.ndarray]:
        sl = slice(first, first + count)
        s = _state(count)
        force, _, dt_el = _step(x[sl] + 0.5e-6 * v[sl], v[sl], w[sl], 1e-6, s, model=J2)
        return {**s, "force": force, "dt": dt_el}

    whole = run(0, n)
    assert 0.05 < np.count_nonzero(whole["eps_p"]) / whole["eps_p"].size < 0.95
    for first, count in [(i, 1) for i in range(8)] + [(3, 61), (64, 64), (5, 7), (100, 50), (1, 64)]:
        got = run(first, count)
        for key, value in got.items():
            assert np.array_equal(value, whole[key][first:first + count]), (key, first, count)


def test_lumped_mass_and_time_step() -> None:
    """Reference: a third of rho t A at each node, I = m (t^2 + A) / 4 (docs/theory.md), and the
    stable step L / c with L = 2 A / longest side, the smallest altitude (LS-DYNA Theory Manual, time
    step of triangular shells), c = sqrt(E / (rho (1 - nu^2))): exact to round-off for a general
    triangle in space."""
    nodes, tris, _ = _patch()
    tri = _placed(nodes)[tris[:2]]
    mass, inertia = K.triangle_mass(_layout(tri), T, RHO)
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    np.testing.assert_allclose(mass, RHO * T * area / 3.0, rtol=1e-14)
    np.testing.assert_allclose(inertia, mass * (T**2 + area) / 4.0, rtol=1e-14)
    dt = K.triangle_time_step(_layout(tri), T, RHO, E, NU)
    longest = np.linalg.norm(tri - np.roll(tri, -1, axis=1), axis=2).max(axis=1)
    c = np.sqrt(E / (RHO * (1.0 - NU**2)))
    np.testing.assert_allclose(dt, 2.0 * area / longest / c, rtol=1e-14)
    # and the kernel's step on its end-of-step frame is the same
    _, _, dt_kernel = _step(tri, np.zeros_like(tri), np.zeros_like(tri), 1e-7, _state(2))
    np.testing.assert_allclose(dt_kernel, dt, rtol=1e-12)


def test_transverse_shear_of_a_tilted_plate_is_the_slope_plus_rotation() -> None:
    """Reference: Mindlin-Reissner shear gamma = grad w + phi (phi = (theta_y, -theta_x)) for constant
    rotations and a linear deflection, which the edge field reproduces exactly: tau = kappa G gamma dt
    at every point, kappa = 5/6. Tolerance 1e-10: the edge-field's weights 1/3 per edge give gamma
    exactly; other weights miss it by order 1."""
    nodes, tris, _ = _patch()
    tri = nodes[tris[2]]
    slope = np.array([0.3, -0.7])
    theta = np.array([0.2, 0.5, 0.0])      # theta_x, theta_y
    v = np.zeros((3, 3))
    v[:, 2] = tri[:, :2] @ slope
    w = np.tile(theta, (3, 1))
    dt = 1e-9
    state = _state(1)
    _step((tri + 0.5 * dt * v)[None], v[None], w[None], dt, state)
    p = tri
    e1 = (p[1] - p[0])[:2] / np.linalg.norm(p[1] - p[0])
    e2 = np.array([-e1[1], e1[0]])
    gamma = slope + np.array([theta[1], -theta[0]])
    tau = 5.0 / 6.0 * G * dt * np.array([gamma @ e1, gamma @ e2])
    for k in range(NIP):
        np.testing.assert_allclose(state["stress"][0, 3:, k], tau, rtol=1e-10)
