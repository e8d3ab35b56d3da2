"""The physical hourglass form (docs/theory.md, Hourglass control): one element through the f2py
kernel, then a structure through the engine.

The form stiffens the hourglass modes by the strain energy of the fields the one-point rule
misses, from the section's elastic constants (no coefficient): membrane and bending by the
bending-exact assumed strains of Belytschko & Bindeman (1991), transverse shear by edge tying
(Bathe & Dvorkin 1985) as Belytschko & Leviathan (1994) do for the shell.
"""

from __future__ import annotations

import numpy as np
import pytest

import models as M
from kernel_cases import RHO, SY0, E, F
from paradyn import _kernels as K
from paradyn.deck import Control

PHYSICAL, STIFFNESS = M.HOURGLASS_FORMS["physical"], M.HOURGLASS_FORMS["stiffness"]
NU = 0.3
T = 0.01
NIP = 5


def _state() -> dict[str, np.ndarray]:
    return {"stress": F(np.zeros((1, 5, NIP))), "back": F(np.zeros((1, 3, NIP))), "eps_p": F(np.zeros((1, NIP))),
            "hourglass": F(np.zeros((1, 10))), "e_internal": np.zeros(1), "e_hourglass": np.zeros(1)}


def _step(x: np.ndarray, v: np.ndarray, w: np.ndarray, dt: float, form: int, state=None, coefficient=0.1):
    """One kernel step of one elastic element; x, v, w are (4 nodes, 3). Returns force (4, 6), state."""
    state = _state() if state is None else state
    x_end = x + dt * v   # the kernel takes the end-of-step positions and the mid-step velocities
    force, _ = K.blt_forces(F(x_end.T[None]), F(v.T[None]), F(w.T[None]), T, RHO, E, NU, SY0, 0.0, 1.0,
                            coefficient, 1, dt, state["stress"], state["back"], state["eps_p"],
                            state["hourglass"], state["e_internal"], state["e_hourglass"], hourglass_form=form)
    return np.asarray(force)[0].T, state


def _rectangle(a: float, b: float) -> np.ndarray:
    """Corners of a 2a x 2b rectangle in the x-y plane, counter-clockwise from (-a, -b)."""
    return np.array([[-a, -b, 0.0], [a, -b, 0.0], [a, b, 0.0], [-a, b, 0.0]])


def test_in_plane_bending_mode_stores_the_beam_bending_energy():
    """The membrane hourglass mode u_x = q xi eta of a 2a x 2b rectangle is pure bending of a beam
    of length 2a and depth 2b: curvature q / (a b), energy U = E I kappa^2 (2 a) / 2 with
    I = t (2b)^3 / 12 (Euler-Bernoulli; the lateral strain free, so E and not E / (1 - nu^2)).
    One small step moving along the mode stores U in the hourglass energy and nothing at the
    centre. The stiffness form with coefficient 0.1 stores 3.75 times less here (k = 0.1 E t
    (b/a + a/b) / 8 against E t b / (12 a) at b / a = 2), which the 1e-6 tolerance tells apart.
    """
    a, b, dt, rate = 0.05, 0.1, 1.0e-7, 1.0e-2   # q = rate * dt = 1e-9 m: no change of shape
    x = _rectangle(a, b)
    xi_eta = np.array([1.0, -1.0, 1.0, -1.0])
    v = np.zeros((4, 3))
    v[:, 0] = rate * xi_eta
    _, state = _step(x, v, np.zeros((4, 3)), dt, PHYSICAL)
    q = rate * dt
    inertia = T * (2.0 * b) ** 3 / 12.0
    expected = 0.5 * E * inertia * (q / (a * b)) ** 2 * (2.0 * a)
    assert state["e_hourglass"][0] == pytest.approx(expected, rel=1e-6)
    assert abs(state["e_internal"][0]) < 1e-12 * expected


def test_twist_has_no_shear_hourglass_resultant():
    """Pure twist w = c x y with the Kirchhoff rotations (theta_x = dw/dy = c x, theta_y = -dw/dx =
    -c y in the element's convention gamma_xz = w,x + theta_y, gamma_yz = w,y - theta_x) has no
    transverse shear anywhere, so the tied edge shears, and the physical form's shear hourglass
    resultants, are zero: the form does not lock in twist (Bathe & Dvorkin 1985). The lateral
    hourglass rate gamma . v_z = 4 c a b is not zero, and the stiffness form resists it.
    """
    a, b, dt, c = 0.05, 0.08, 1.0e-7, 1.0e-2
    x = _rectangle(a, b)
    v = np.zeros((4, 3))
    w = np.zeros((4, 3))
    v[:, 2] = c * x[:, 0] * x[:, 1]
    w[:, 0] = c * x[:, 0]
    w[:, 1] = -c * x[:, 1]
    _, physical = _step(x, v, w, dt, PHYSICAL)
    _, stiffness = _step(x, v, w, dt, STIFFNESS)
    shear_scale = abs(stiffness["hourglass"][0, 4])
    assert shear_scale > 0.0
    assert abs(physical["hourglass"][0, 4]) < 1e-9 * shear_scale * 1e3
    assert abs(physical["hourglass"][0, 9]) < 1e-9 * shear_scale * 1e3


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_rigid_rotation_gives_no_hourglass_resultants(axis):
    """A flat, non-rectangular element spinning rigidly about a global axis through its centre
    (nodal velocities omega x r, every node's angular velocity omega): no strain, so no hourglass
    resultant of the physical form (round-off only) and no net force."""
    x = np.array([[0.0, 0.0, 0.0], [0.06, -0.01, 0.0], [0.07, 0.05, 0.0], [-0.01, 0.04, 0.0]])
    omega = np.zeros(3)
    omega[axis] = 3.0
    r = x - x.mean(axis=0)
    v = np.cross(omega, r)
    w = np.tile(omega, (4, 1))
    force, state = _step(x, v, w, 1.0e-7, PHYSICAL)
    scale = E * T * 1.0e-7 * 3.0   # a resultant of one strain 1e-7 * 3
    assert np.max(np.abs(state["hourglass"][0, [0, 1, 2, 3, 4, 9]])) < 1e-9 * scale
    assert np.max(np.abs(force[:, :3].sum(axis=0))) < 1e-9 * scale


def test_coefficient_does_not_change_the_physical_form():
    """The physical form has no coefficient: 0.1 and 1.0 give bitwise the same step; 0 alone
    switches hourglass control off (docs/scene.md, [effects] hourglass = false): no hourglass
    resultant, only the drilling moments (slots 6 to 9), which every form keeps."""
    x = _rectangle(0.05, 0.1)
    rng = np.random.default_rng(3)
    v, w = rng.normal(size=(4, 3)), rng.normal(size=(4, 3))
    f1, s1 = _step(x, v, w, 1.0e-7, PHYSICAL, coefficient=0.1)
    f2, s2 = _step(x, v, w, 1.0e-7, PHYSICAL, coefficient=1.0)
    assert np.array_equal(f1, f2) and np.array_equal(s1["hourglass"], s2["hourglass"])
    assert np.all(s1["hourglass"][0, [0, 1, 2, 3, 4, 9]] != 0.0)
    _, off = _step(x, v, w, 1.0e-7, PHYSICAL, coefficient=0.0)
    assert np.all(off["hourglass"][0, [0, 1, 2, 3, 4, 9]] == 0.0)
    assert np.array_equal(off["hourglass"][0, 5:9], s1["hourglass"][0, 5:9])


@pytest.mark.parametrize("form, ratio", [("physical", (0.98, 1.02)), ("stiffness", (2.0, 5.0))])
def test_in_plane_cantilever_under_end_couple(tmp_path, form, ratio):
    """In-plane bending of a cantilever one element deep, by dynamic relaxation.

    Reference: tip deflection M L^2 / (2 E I), I = t h^3 / 12 (Euler-Bernoulli pure bending;
    the strip's width is in its plane, so E and not E / (1 - nu^2)). L = 1 m, depth h = 0.1 m,
    t = 0.01 m, steel, 10 x 1 square elements, clamped at x = 0, a couple M = F h from the forces
    -F, +F along x on the bottom and top tip nodes, ramped over one period and held.

    One element deep, the one-point rule sees no bending at all: the hourglass control carries
    it. The physical form bends rectangles exactly (Belytschko & Bindeman 1991): within 2 %. The
    stiffness form with coefficient 0.1 is 3.3 times too flexible here, its answer set by the
    coefficient: it must fall between 2 and 5 times the reference, which tells the forms apart.
    """
    length, depth = 1.0, 0.1
    mesh = M.strip(length, depth, 10, 1)
    c = mesh.coordinates
    root = np.flatnonzero(np.abs(c[:, 0]) < 1e-12)
    tip = M.nodes_at(mesh, 0, length)            # sorted by y: bottom, top
    inertia = T * depth**3 / 12.0
    mass_per_length = M.Material(young=200.0e9, poisson=NU, density=7850.0).density * T * depth
    omega1 = 1.8751**2 * np.sqrt(200.0e9 * inertia / (mass_per_length * length**4))
    # the physical form's first mode; the stiffness form is softer, so give it three more periods
    period = 2.0 * np.pi / omega1 * (2.0 if form == "stiffness" else 1.0)
    control = Control(end_time=6.0 * period, output_interval=period, history_interval=period / 50,
                      mass_damping=2.0 * omega1 / (2.0 if form == "stiffness" else 1.0))
    force = 1.0e3   # M = 100 N m: tip deflection 1.9 mm = L / 500
    steel = M.Material(young=200.0e9, poisson=NU, density=7850.0)
    model = M.shell_model(mesh, T, steel, control, fixed={int(k): M.ALL_DOFS for k in root},
                          loads=[M.Load(tip, 1, np.array([-force, force]), period)], tracked=list(tip),
                          hourglass_form=form)
    run = M.run(model, tmp_path)
    h = run.results.history
    tip_y = -h["tracked_displacement"][:, :, 1].mean(axis=1)   # the couple bends the tip towards -y
    reference = force * depth * length**2 / (2.0 * 200.0e9 * inertia)
    assert abs(tip_y[-1] - tip_y[int(0.85 * (len(tip_y) - 1))]) < 2e-3 * abs(tip_y[-1])
    assert ratio[0] < tip_y[-1] / reference < ratio[1]


def test_yielding_element_keeps_the_tangent_share_of_its_hourglass_stiffness():
    """In a J2 element flowing plastically the physical form stiffens the hourglass modes by the
    element's tangent share of its elastic stiffness, not by E (docs/theory.md, Hourglass
    control): share = sum_k w_k ds_k . de / sum_k w_k de . C . de over the through-thickness
    points, the work of the step's stress increments against their elastic value, at least 0.05.

    A perfectly plastic element at yield in uniaxial tension is stretched further along x with
    the lateral strain held (ds is then the constrained flow's, not zero): the membrane hourglass
    increment is the elastic element's times that share, computed here from the stresses.
    """
    x = _rectangle(0.05, 0.1)
    xi_eta = np.array([1.0, -1.0, 1.0, -1.0])
    v = np.zeros((4, 3))
    v[:, 0] = 1.0 * x[:, 0] + 1.0e-3 * xi_eta      # stretch rate 1/s and an in-plane hourglass rate
    dt = 1.0e-7
    increments, shares = {}, {}
    for model in (1, 2):
        state = _state()
        state["stress"][0, 0, :] = SY0                # at yield in uniaxial tension
        x_end = x + dt * v
        K.blt_forces(F(x_end.T[None]), F(v.T[None]), F(np.zeros((1, 3, 4))), T, RHO, E, NU, SY0, 0.0, 1.0,
                     0.1, model, dt, state["stress"], state["back"], state["eps_p"], state["hourglass"],
                     state["e_internal"], state["e_hourglass"], hourglass_form=PHYSICAL)
        increments[model] = state["hourglass"][0, 0]
        _, weights = K.thickness_points(NIP)
        strain = dt * 1.0                              # uniform: no bending, the hourglass misses the centre
        stress_work = np.sum(weights * (state["stress"][0, 0, :] - SY0) * strain)
        shares[model] = stress_work / np.sum(weights * E / (1.0 - NU**2) * strain**2)
        if model == 2:
            assert np.all(state["eps_p"][0] > 0.0)     # it did flow
    assert shares[1] == pytest.approx(1.0, rel=1e-6)
    assert 0.05 < shares[2] < 0.5
    assert increments[2] / increments[1] == pytest.approx(shares[2], rel=1e-6)
