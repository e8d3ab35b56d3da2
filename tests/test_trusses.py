"""Trusses, the 2-node axial-force members of the element family (element/truss_element.f90;
docs/theory.md, "Truss"; docs/validation.md, "Trusses"): a mass hanging on an elastic wire
oscillates with the spring-mass period, a bar pulled and pushed back yields at the yield force
and hardens as its material says, and the answers are bitwise the same on 1 and 2 ranks."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from truss_cases import hanging_mass, pulled_bar, rigid_pendulum, truss_model

# a steel wire 1 m long, 1 cm^2, 100 kg hanging: k = E A / L = 2e7 N/m, the wire's own mass 0.78 kg
LENGTH, AREA, MASS, GRAVITY = 1.0, 1e-4, 100.0, 9.81
E, RHO = 200e9, 7800.0
# a bar of mild steel, bilinear: yield 250 MPa, tangent 2 GPa
YIELD, TANGENT = 250e6, 2e9


def _crossings(t: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Times where s crosses zero downwards, by linear interpolation."""
    k = np.flatnonzero((s[:-1] > 0.0) & (s[1:] <= 0.0))
    return t[k] - s[k] * (t[k + 1] - t[k]) / (s[k + 1] - s[k])


def test_a_mass_hanging_on_a_wire_oscillates_with_the_spring_mass_period(tmp_path: Path) -> None:
    """A mass m on an elastic wire (ten trusses) released unstretched under gravity oscillates
    about its static stretch (m + m_w / 2) g / k between 0 and twice it, with the period of a mass
    on a spring with the wire's mass m_w: T = 2 pi sqrt((m + m_w / 3) L / (E A)) (Rayleigh's
    correction of the spring's mass, Timoshenko, Young & Weaver, Vibration Problems in
    Engineering, 4th ed. 1974, sec. 1.6; exact to O((m_w / m)^2) = 6e-5 here). Measured: period
    and amplitude within 4e-5, energy balance 4e-6. Tolerance 0.2 %: a stiffness off by 1 % (the
    plate modulus E / (1 - nu^2) instead of E would be 10 %) moves the period by 0.5 %, the
    amplitude by 1 %."""
    k = E * AREA / LENGTH
    wire = RHO * AREA * LENGTH
    period = 2.0 * np.pi * np.sqrt((MASS + wire / 3.0) / k)
    model = hanging_mass(10, LENGTH, AREA, MASS, GRAVITY, 3.0, period)
    res = paradyn.run(model, tmp_path / "one", ranks=1, threads=1, post=False)
    t, u = res.history["time"][:], res.history["tracked_displacement"][:, 0, 2]
    static = -(MASS + wire / 2.0) * GRAVITY / k   # the lumped end mass of the wire hangs on it too
    measured = np.diff(_crossings(t, u - static))
    assert len(measured) >= 2
    assert measured.mean() == pytest.approx(period, rel=2e-3)
    assert u.min() == pytest.approx(2.0 * static, rel=2e-3)
    assert u.max() <= 1e-3 * abs(static)
    h = res.history
    total = h["kinetic_energy"][:] + h["internal_energy"][:] - h["external_work"][:]
    assert np.abs(total).max() < 1e-4 * h["internal_energy"][:].max()
    # the same run on two ranks: every position bitwise the same
    two = paradyn.run(model, tmp_path / "two", ranks=2, threads=1, post=False)
    with h5py.File(tmp_path / "one" / "results.h5") as a, h5py.File(tmp_path / "two" / "results.h5") as b:
        assert np.array_equal(a["frames/displacement"][:], b["frames/displacement"][:])
        assert np.array_equal(a["history/tracked_displacement"][:], b["history/tracked_displacement"][:])
    np.testing.assert_allclose(two.history["internal_energy"][:], h["internal_energy"][:], rtol=1e-12, atol=0.0)


def test_a_spinning_wire_turns_without_spurious_strain(tmp_path: Path) -> None:
    """Co-rotational exactness: a wire (one truss, held at the origin) with a mass at its tip,
    started unstretched with the tip moving across it at omega r, spins through two and a half
    turns. Its stretch oscillates about the steady x = m omega^2 r / (k - m omega^2) (the
    centripetal force), between 0 and about 2 x; the angular momentum about the held end is kept
    (the wire's force points at it) and so is the energy. A truss that measured strain along its
    initial axis (no co-rotation) would read a quarter turn as a strain of -1 and throw the mass
    off. Measured: radius in [r, r + 1.88 x] (mean r + 0.94 x), angular momentum to 6e-15, energy to 1.3e-5."""
    omega, r, m, area = 20.0, 1.0, 10.0, 1e-6
    k = E * area / r
    stretch = m * omega**2 * r / (k - m * omega**2)
    turns = 2.5
    end = turns * 2.0 * np.pi / omega
    control = paradyn.deck.Control(end_time=end, output_interval=end / 50, history_interval=end / 2000)
    model = truss_model(np.array([[0.0, 0.0, 0.0], [r, 0.0, 0.0]]), [(0, 1)], area, control,
                        fixed=[0], added_mass={1: m}, tracked=[1])
    model.initial_velocity = np.array([[0.0, 0.0, 0.0], [0.0, omega * r, 0.0]])
    res = paradyn.run(model, tmp_path, ranks=1, threads=1, post=False)
    h = res.history
    x = model.coordinates[1] + h["tracked_displacement"][:, 0, :]
    v = h["tracked_velocity"][:, 0, :]
    radius = np.linalg.norm(x, axis=1)
    angle = np.unwrap(np.arctan2(x[:, 1], x[:, 0]))
    assert angle[-1] > 2.0 * np.pi * turns * 0.9
    assert radius.min() >= r - 1e-9 * r
    assert radius.max() <= r + 2.2 * stretch
    assert abs(radius.mean() - (r + stretch)) < 0.1 * stretch
    tip_mass = m + 0.5 * 7800.0 * area * r
    momentum = tip_mass * np.cross(x, v)[:, 2]
    assert np.abs(momentum - momentum[0]).max() < 1e-6 * momentum[0]
    total = h["kinetic_energy"][:] + h["internal_energy"][:] - h["external_work"][:]
    assert np.abs(total - total[0]).max() < 1e-3 * h["kinetic_energy"][0]


@pytest.mark.parametrize(("mixing", "reverse_yield"), [(0.0, "kinematic"), (1.0, "isotropic")])
def test_a_bar_pulled_and_pushed_back_yields_and_hardens(tmp_path: Path, mixing: float, reverse_yield: str) -> None:
    """One truss of a bilinear J2 material (MAT_PLASTIC_KINEMATIC: yield 250 MPa, tangent 2 GPa,
    BETA 0 kinematic or 1 isotropic) pulled to 0.5 % strain and pushed back to zero at a strain
    rate of 0.01 /s (quasi-static: its ends are driven). The 1-D law (Simo & Hughes,
    Computational Inelasticity, sec. 1.4): stress E eps to the yield, then
    sigma_y + Et (eps - sigma_y / E) (the force sigma_y A at the yield); unloading along E; reverse
    yield at sigma_max - 2 sigma_y (kinematic: the elastic range keeps its width 2 sigma_y) or at
    -sigma_max (isotropic: it grows to 2 sigma_max). Strain: the log strain of the length, the
    truss's measure. Tolerances 0.1 % of the yield stress (measured on the loading: 2e-11)."""
    material = {"young": E, "yield_stress": YIELD, "tangent_modulus": TANGENT, "hardening_mixing": mixing}
    bar = pulled_bar(1.0, 1e-4, 0.01, 0.5, 1.0, material, "j2_plasticity")
    paradyn.run(bar, tmp_path, ranks=1, threads=1, post=False)
    with h5py.File(tmp_path / "results.h5") as f:
        stress = f["frames/element_membrane_stress"][:, 0, 0]
        eps = np.log(1.0 + f["frames/displacement"][:, 1, 0])
        plastic = f["frames/element_plastic_strain"][:, 0]
        work = f["history/part_plastic_work"][-1, 0]
    top = int(np.argmax(eps))
    loading, unloading = slice(0, top + 1), slice(top, None)
    yield_strain = YIELD / E
    elastic = eps[loading] <= yield_strain
    tol = 1e-3 * YIELD
    np.testing.assert_allclose(stress[loading][elastic], E * eps[loading][elastic], atol=tol)
    np.testing.assert_allclose(stress[loading][~elastic], YIELD + TANGENT * (eps[loading][~elastic] - yield_strain),
                               atol=tol)
    np.testing.assert_allclose(plastic[loading], eps[loading] - stress[loading] / E, atol=1e-3 * yield_strain)
    peak = stress[top]
    back = peak - 2.0 * YIELD if reverse_yield == "kinematic" else -peak
    still = stress[unloading] > back + tol   # the elastic unloading, then the reverse yield
    np.testing.assert_allclose(stress[unloading][still], peak - E * (eps[top] - eps[unloading][still]), atol=tol)
    assert np.any(~still)
    assert stress[unloading][~still].max() <= back + tol and stress[unloading][~still].min() >= back - 0.05 * YIELD
    # the plastic work: sigma_y eps_p (+ beta H eps_p^2 / 2), over the volume A L
    h_iso = mixing * E * TANGENT / (E - TANGENT)
    volume = 1e-4   # A L at the end, where the bar is back at its length
    assert work == pytest.approx(volume * (YIELD * plastic[-1] + 0.5 * h_iso * plastic[-1] ** 2), rel=1e-3)


def test_a_rigid_plate_hung_on_wires_swings_with_the_physical_pendulum_period(tmp_path: Path) -> None:
    """Issue 32's rigid pendulum: a rigid steel plate (material rigid, 5 cm square, 1 cm thick)
    hung by two steel wires (trusses, 0.4 mm across) from a held pivot 10 cm above its centre,
    swinging under gravity at 0.05 rad. The wires and the plate make a rigid triangle, so it is a
    physical pendulum: T = 2 pi sqrt(I_pivot / (m g d)) (e.g. Meriam & Kraige, Engineering
    Mechanics: Dynamics, sec. 6/8), I_pivot the plate's about the pivot (the body the engine holds:
    its lumped nodal masses as points with their rotary inertia m t^2 / 12, docs/theory.md, "Rigid
    bodies"), times 1 + theta0^2 / 16 for the amplitude (1.6e-4). The two wires weigh 8e-4 of the
    plate and stretch 6e-6 of their length under it: they are left out of the reference (they
    shift T by about 1e-4). Measured: period 1.6e-5, amplitude 5e-4, energy balance 2e-6.
    Tolerance 0.1 %: the period of a point mass at the centre (I = m d^2) is 2.1 % shorter. The
    first tenth of a swing on two ranks: the positions bitwise the same."""
    side, thickness, depth, area = 0.05, 0.01, 0.1, 1.3e-7
    n = 8
    # the plate's lumped masses (a quarter of each shell's rho t A at its corners), as the engine
    x = np.linspace(-side / 2, side / 2, n + 1)
    w = np.full(n + 1, 1.0)
    w[[0, -1]] = 0.5
    point = np.outer(w, w).ravel() / (n * n) * 7800.0 * thickness * side**2   # rows z, columns x
    xx, zz = np.meshgrid(x, x)
    zz = zz - depth
    mass = point.sum()
    inertia = float(point @ (xx.ravel() ** 2 + zz.ravel() ** 2)) + mass * thickness**2 / 12.0
    theta0 = 0.05
    period = 2.0 * np.pi * np.sqrt(inertia / (mass * 9.81 * depth)) * (1.0 + theta0**2 / 16.0)
    omega = theta0 * 2.0 * np.pi / period
    model = rigid_pendulum(side, thickness, depth, area, n, omega, 1.6 * period)
    res = paradyn.run(model, tmp_path, ranks=1, threads=1, post=False)
    t, u = res.history["time"][:], res.history["tracked_displacement"][:, 0, 0]
    k = np.flatnonzero(np.sign(u[:-1]) * np.sign(u[1:]) < 0)
    crossings = t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k])
    assert len(crossings) >= 3
    assert 2.0 * np.diff(crossings).mean() == pytest.approx(period, rel=1e-3)
    assert np.abs(u).max() == pytest.approx(theta0 * depth, rel=2e-2)
    short = rigid_pendulum(side, thickness, depth, area, n, omega, 0.1 * period)
    for ranks in (1, 2):
        paradyn.run(short, tmp_path / f"ranks_{ranks}", ranks=ranks, threads=1, post=False)
    with h5py.File(tmp_path / "ranks_1" / "results.h5") as a, h5py.File(tmp_path / "ranks_2" / "results.h5") as b:
        assert np.array_equal(a["frames/displacement"][:], b["frames/displacement"][:])
