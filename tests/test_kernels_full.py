"""The fully integrated shell's kernel (fortran/src/element/shell_full.f90) through f2py: patch
tests, the rigid-body modes of a free element, objectivity, and a thin plate without shear locking.

The stiffness of an element is read off the kernel: from zero stress, one step of dt with a unit
velocity on one dof gives forces K e_j dt (the geometry moves by dt / 2, a relative O(dt) change).
"""

from __future__ import annotations

import numpy as np
import pytest

from kernel_cases import NU, RHO, SY0, E, F, T, _rotation
from paradyn import _kernels as K

NIP = 3


def _kernel_state(n: int, nip: int = NIP) -> dict[str, np.ndarray]:
    return {
        "stress": F(np.zeros((n, 5, 4 * nip))),
        "back": F(np.zeros((n, 3, 4 * nip))),
        "eps_p": F(np.zeros((n, 4 * nip))),
        "drilling": F(np.zeros((n, 4))),
        "e_internal": np.zeros(n),
    }


def _full_step(x: np.ndarray, v: np.ndarray, w: np.ndarray, dt: float, state: dict[str, np.ndarray],
               thickness: float = T, model: int = 1, warping: int = 1) -> tuple[np.ndarray, int]:
    """One step of elements x, v, w (n, 4, 3); returns the forces (n, 4, 6) and the inverted count."""
    def layout(a: np.ndarray) -> np.ndarray:
        return F(np.transpose(np.asarray(a, dtype=np.float64), (0, 2, 1)))
    force, inverted, _ = K.full_forces(
        layout(x), layout(v), layout(w), thickness, RHO, E, NU, SY0, 0.0, 1.0, model, dt,
        state["stress"], state["back"], state["eps_p"], state["drilling"], state["e_internal"],
        warping_correction=warping)
    return np.transpose(np.asarray(force), (0, 2, 1)), int(inverted)


def element_stiffness(x: np.ndarray, thickness: float = T, dt: float = 1e-12) -> np.ndarray:
    """(n, 24, 24) stiffness of elements x (n, 4, 3), dofs node-major (vx vy vz wx wy wz)."""
    n = x.shape[0]
    k = np.zeros((n, 24, 24))
    for j in range(24):
        v = np.zeros((n, 4, 3))
        w = np.zeros((n, 4, 3))
        (v if j % 6 < 3 else w)[:, j // 6, j % 6 % 3] = 1.0
        force, inverted = _full_step(x, v, w, dt, _kernel_state(n), thickness)
        assert inverted == 0
        k[:, :, j] = force.reshape(n, 24) / dt
    return k


def _irregular_element() -> np.ndarray:
    return 0.05 * np.array([[0.0, 0.0, 0.0], [1.1, 0.1, 0.0], [0.9, 0.8, 0.0], [-0.1, 1.0, 0.0]])


# ------------------------------------------------------------------------------------------------
# the MacNeal-Harder patch (MacNeal & Harder 1985): a 0.24 x 0.12 rectangle of 5 distorted elements


PATCH_NODES = np.array([[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12],
                        [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
PATCH_ELEMENTS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])
INTERIOR = [4, 5, 6, 7]


def _patch_step(u: callable, rotation: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """One step of the patch (placed by `rotation`) with nodal rates u(x, y) -> (v(3), w(3)) in
    the patch's plane axes; returns the assembled nodal forces (8, 6) in the patch axes."""
    xyz = np.column_stack([PATCH_NODES, np.zeros(len(PATCH_NODES))])
    rates = np.array([np.concatenate(u(px, py)) for px, py in PATCH_NODES])
    x = (xyz @ rotation.T)[PATCH_ELEMENTS]
    v = (rates[:, :3] @ rotation.T)[PATCH_ELEMENTS]
    w = (rates[:, 3:] @ rotation.T)[PATCH_ELEMENTS]
    dt = 1e-9
    state = _kernel_state(len(PATCH_ELEMENTS))
    force, inverted = _full_step(x + 0.5 * dt * v, v, w, dt, state)   # mid-step geometry = the patch
    assert inverted == 0
    nodal = np.zeros((len(PATCH_NODES), 6))
    for e, nodes in enumerate(PATCH_ELEMENTS):
        nodal[nodes, :3] += force[e, :, :3] @ rotation
        nodal[nodes, 3:] += force[e, :, 3:] @ rotation
    return nodal, state, x


@pytest.mark.parametrize("case", ["membrane", "bending"])
def test_full_patch_test_constant_strain_is_exact(case: str) -> None:
    """Reference: the patch test (Irons; MacNeal & Harder 1985, the 5-element patch): a linear
    membrane field, or a quadratic deflection with its Kirchhoff rotations (constant curvature,
    zero transverse shear), gives the same constant stress at every in-plane and through-thickness
    point of every distorted element, and forces that cancel at the interior nodes. The covariant
    shear at the MITC4 tying points is exact for that field, so no shear appears."""
    a, b, c = 1.0e-3, 0.5e-3, 2.0e-3
    if case == "membrane":
        def u(px: float, py: float) -> tuple[np.ndarray, np.ndarray]:
            return np.array([a * px + b * py, b * px + c * py, 0.0]), np.zeros(3)
    else:   # w = (a x^2 + 2 b x y + c y^2) / 2; theta_x = dw/dy, theta_y = -dw/dx (gamma = 0)
        def u(px: float, py: float) -> tuple[np.ndarray, np.ndarray]:
            return np.array([0.0, 0.0, 0.5 * (a * px**2 + 2 * b * px * py + c * py**2)]), \
                np.array([b * px + c * py, -(a * px + b * py), 0.0])
    rotation = _rotation(np.array([0.2, 0.7, -0.4]), 0.9)
    nodal, state, _ = _patch_step(u, rotation)
    stress = state["stress"]   # (elements, 5, 4 points x NIP layers), element frames
    layers = stress.reshape(5, 5, 4, NIP)
    # the frame-independent invariants of the in-plane stress at each point
    trace = layers[:, 0] + layers[:, 1]
    det = layers[:, 0] * layers[:, 1] - layers[:, 2] ** 2
    scale = np.abs(layers[:, :3]).max()
    assert scale > 0.0
    for inv, power in ((trace, 1), (det, 2)):
        for k in range(NIP):
            ref = inv[0, 0, k]
            assert np.abs(inv[:, :, k] - ref).max() <= 1e-9 * scale**power
    assert np.abs(layers[:, 3:5]).max() <= 1e-9 * scale       # no transverse shear
    boundary_scale = np.abs(nodal).max()
    assert np.abs(nodal[INTERIOR]).max() <= 1e-9 * boundary_scale


def test_full_free_element_has_exactly_six_zero_energy_modes() -> None:
    """Reference: a fully integrated element has no spurious zero-energy modes (Hughes, The Finite
    Element Method, sec. 4.7; MITC4: Dvorkin & Bathe 1984): of the 24 dofs of a free irregular
    quadrilateral exactly 6 eigenvalues of the stiffness vanish, the rigid-body modes (the
    drilling rotations are held by the drilling penalty). Without its hourglass control the
    one-point element has 6 more; the gap to the softest deformation mode (the drilling penalty,
    1e-4 E t A per radian) is more than 1e6."""
    x = _irregular_element()[None]
    k = element_stiffness(x)[0]
    assert np.abs(k - k.T).max() <= 1e-6 * np.abs(k).max()      # symmetric: a potential
    lam = np.sort(np.abs(np.linalg.eigvalsh(0.5 * (k + k.T))))
    assert lam[5] <= 1e-6 * lam[6]
    assert lam[5] <= 1e-12 * lam[-1]
    # the rigid modes themselves: translations and rotations about the axes through node 1
    xyz = x[0]
    for axis in range(3):
        t = np.zeros(24)
        t[axis::6] = 1.0
        r = np.zeros(24)
        rot = np.zeros(3)
        rot[axis] = 1.0
        for node in range(4):
            r[6 * node:6 * node + 3] = np.cross(rot, xyz[node] - xyz[0])
            r[6 * node + 3:6 * node + 6] = rot
        for mode in (t, r):
            assert np.abs(k @ mode).max() <= 1e-9 * np.abs(k).max()


def test_full_rigid_rotation_about_an_arbitrary_axis_leaves_no_stress() -> None:
    """Reference: objectivity of the co-rotational formulation (Belytschko, Lin & Tsay 1984): an
    exact rigid rotation by theta in one step, rates on the mid-step geometry, leaves strains of
    O(theta^3) only at every point."""
    x0 = 0.05 * np.array([[0.0, 0.0, 0.0], [1.1, 0.1, 0.0], [0.9, 0.8, 0.0], [-0.1, 1.0, 0.0]])
    omega = np.array([40.0, -25.0, 60.0])
    dt = 1e-5
    theta = float(np.linalg.norm(omega)) * dt
    pivot = np.array([0.1, 0.4, -0.2])
    x1 = pivot + (x0 - pivot) @ _rotation(omega, theta).T
    state = _kernel_state(1)
    force, inverted = _full_step(x1[None], ((x1 - x0) / dt)[None], np.tile(omega, (1, 4, 1)), dt, state)
    assert inverted == 0
    bound = E * theta**3
    assert np.abs(state["stress"]).max() <= bound
    assert np.abs(force).max() <= bound * T * 0.05
    assert E * theta**2 > 1e3 * bound


def test_full_warped_element_rigid_rotation_is_strain_free() -> None:
    """Reference: the rigid links of the warping correction (Belytschko, Wong & Chiang 1992): a
    warped element rotating rigidly about an in-plane axis stays unstrained to O(theta^3)."""
    q = 0.05 * np.array([[0.0, 0.0, 0.05], [1.1, 0.1, -0.05], [0.9, 0.8, 0.05], [-0.1, 1.0, -0.05]])
    omega = np.array([50.0, 20.0, 0.0])
    dt = 1e-5
    theta = float(np.linalg.norm(omega)) * dt
    x1 = q @ _rotation(omega, theta).T
    state = _kernel_state(1)
    _, inverted = _full_step(x1[None], ((x1 - q) / dt)[None], np.tile(omega, (1, 4, 1)), dt, state)
    assert inverted == 0
    assert np.abs(state["stress"]).max() <= E * theta**3
    state = _kernel_state(1)   # without the correction the offsets strain it at O(theta)
    _full_step(x1[None], ((x1 - q) / dt)[None], np.tile(omega, (1, 4, 1)), dt, state, warping=0)
    assert np.abs(state["stress"]).max() > 1e3 * E * theta**3


def test_full_element_result_is_independent_of_its_group() -> None:
    """Reference: bitwise layout independence (docs/performance.md): an element's forces and
    state do not depend on the group it is computed in (vector body or scalar remainder)."""
    rng = np.random.default_rng(7)
    n = 70
    base = _irregular_element()
    x = np.array([base @ _rotation(rng.normal(size=3), rng.uniform(0, 3)).T + rng.normal(size=3)
                  for _ in range(n)])
    x += 0.002 * rng.normal(size=x.shape)   # warped too
    v = rng.normal(size=(n, 4, 3))
    w = 10.0 * rng.normal(size=(n, 4, 3))
    dt = 1e-6
    whole = _kernel_state(n)
    f_whole, _ = _full_step(x, v, w, dt, whole, model=2)
    for first, count in ((0, 1), (3, 61), (64, 6)):
        part = _kernel_state(count)
        f_part, _ = _full_step(x[first:first + count], v[first:first + count], w[first:first + count], dt, part,
                               model=2)
        assert np.array_equal(f_part, f_whole[first:first + count])
        assert np.array_equal(part["stress"], whole["stress"][first:first + count])


# ------------------------------------------------------------------------------------------------
# a simply supported square plate under uniform pressure, assembled from the kernel's stiffness


def plate_centre_deflection(cells: int, thickness: float, side: float = 1.0) -> float:
    """Centre deflection of a hard simply supported square plate (w = 0 and the rotation about
    the edge normal held on each edge) under a unit uniform load, cells x cells elements."""
    nn = cells + 1
    grid = np.linspace(0.0, side, nn)
    xyz = np.array([[gx, gy, 0.0] for gy in grid for gx in grid])
    conn = np.array([[j * nn + i, j * nn + i + 1, (j + 1) * nn + i + 1, (j + 1) * nn + i]
                     for j in range(cells) for i in range(cells)])
    ke = element_stiffness(xyz[conn], thickness)
    ndof = 6 * len(xyz)
    kg = np.zeros((ndof, ndof))
    for e, nodes in enumerate(conn):
        dofs = (6 * nodes[:, None] + np.arange(6)).ravel()
        kg[np.ix_(dofs, dofs)] += ke[e]
    load = np.zeros(ndof)
    h = side / cells
    for node, (px, py, _) in enumerate(xyz):   # consistent load of a bilinear element: q A / 4 per corner
        wx = 0.5 if px in (0.0, side) else 1.0
        wy = 0.5 if py in (0.0, side) else 1.0
        load[6 * node + 2] = wx * wy * h * h
    fixed = set()
    for node, (px, py, _) in enumerate(xyz):
        fixed.update([6 * node + 0, 6 * node + 1, 6 * node + 5])   # no membrane action; drilling
        if px in (0.0, side):
            fixed.update([6 * node + 2, 6 * node + 3])
        if py in (0.0, side):
            fixed.update([6 * node + 2, 6 * node + 4])
    free = np.array(sorted(set(range(ndof)) - fixed))
    u = np.linalg.solve(kg[np.ix_(free, free)], load[free])
    centre = (nn // 2) * nn + nn // 2
    return float(u[list(free).index(6 * centre + 2)])


@pytest.mark.parametrize("ratio", [1.0e-2, 1.0e-3])
def test_full_thin_plate_does_not_lock(ratio: float) -> None:
    """Reference: Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells (1959), table 8: the
    centre deflection of a simply supported square plate under uniform load q is
    0.00406 q a^4 / D (nu = 0.3), D = E t^3 / (12 (1 - nu^2)). With MITC4 shear a 12 x 12 mesh is
    within 3 % at t / a = 1/100 and 1/1000; an element whose shear locks gives a fraction of it
    that falls as (t / a)^2."""
    a = 1.0
    t = ratio * a
    d = E * t**3 / (12.0 * (1.0 - NU**2))
    kirchhoff = 0.00406235 * a**4 / d
    w = plate_centre_deflection(12, t, a)
    assert w == pytest.approx(kirchhoff, rel=0.03)


def _corner_turns_and_point_jacobians(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A flat quad's corner turns (cross product of its two edges at each corner) and the bilinear
    map's Jacobian determinants at the 2 x 2 Gauss points."""
    def turn(k: int) -> float:
        a, b = q[(k + 1) % 4] - q[k], q[(k + 3) % 4] - q[k]
        return float(a[0] * b[1] - a[1] * b[0])
    turns = np.array([turn(k) for k in range(4)])
    g = 1.0 / np.sqrt(3.0)
    xi_n, eta_n = np.array([-1.0, 1.0, 1.0, -1.0]), np.array([-1.0, -1.0, 1.0, 1.0])
    dets = []
    for xi, eta in ((-g, -g), (g, -g), (g, g), (-g, g)):
        d_xi = 0.25 * xi_n * (1.0 + eta_n * eta)
        d_eta = 0.25 * eta_n * (1.0 + xi_n * xi)
        dets.append(np.linalg.det(np.array([[d_xi @ q[:, 0], d_xi @ q[:, 1]], [d_eta @ q[:, 0], d_eta @ q[:, 1]]])))
    return turns, np.array(dets)


def test_full_element_past_convex_keeps_working_while_its_points_are_valid() -> None:
    """Reference: the isoparametric patch test holds wherever the map's Jacobian is positive at the
    quadrature points (Irons; Zienkiewicz & Taylor): a quad squashed past convex at one corner (as the
    first fold of a crushed tube squashes them) still reproduces a constant membrane strain exactly and
    is not counted inverted; a bow-tie, whose Jacobian changes sign at a point, is."""
    squashed = 0.05 * np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.45, 0.45, 0.0], [0.0, 1.0, 0.0]])
    turns, dets = _corner_turns_and_point_jacobians(squashed[:, :2])
    assert turns.min() < 0.0 < dets.min()
    a, b, c = 1.0e-3, 0.5e-3, 2.0e-3
    v = np.column_stack([a * squashed[:, 0] + b * squashed[:, 1], b * squashed[:, 0] + c * squashed[:, 1],
                         np.zeros(4)])
    dt = 1e-9
    state = _kernel_state(1)
    force, inverted = _full_step((squashed + 0.5 * dt * v)[None], v[None], np.zeros((1, 4, 3)), dt, state)
    assert inverted == 0
    layers = state["stress"].reshape(5, 4, NIP)
    trace = layers[0] + layers[1]
    assert np.abs(trace - trace[0, 0]).max() <= 1e-9 * np.abs(trace).max()
    assert np.abs(force[0, :, :3].sum(axis=0)).max() <= 1e-9 * np.abs(force).max()
    bow_tie = squashed[[0, 1, 3, 2]]
    turns, dets = _corner_turns_and_point_jacobians(bow_tie[:, :2])
    assert dets.min() < 0.0
    _, inverted = _full_step(bow_tie[None], np.zeros((1, 4, 3)), np.zeros((1, 4, 3)), dt, _kernel_state(1))
    assert inverted == 1
