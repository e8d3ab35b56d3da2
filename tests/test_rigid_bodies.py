"""Rigid bodies (docs/theory.md, "Rigid bodies"; docs/validation.md): a part with a rigid material
moves as one body by the Newton-Euler equations, its nodes carried with it.

- Free spin about the intermediate axis: a torque-free body tumbles (Euler's equations; Landau &
  Lifshitz, Mechanics, section 37); the engine's body-axis angular velocity follows an RK4
  solution of Euler's equations with the same inertia through the flip, and keeps its energy.
- Free flight: the momentum of the nodes is the body's, constant to rounding.
- Held dofs (LS-DYNA MAT_RIGID CON1/CON2): a held translation does not move under gravity.
- Impact: the momentum the rigid impactor loses is what the free plate gains (Newton's third law
  through the contact), and the run is bitwise the same on 1 and 2 ranks.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from models import lumped_masses
from paradyn.running import launch, preflight
from rigid_cases import SIDES, body_omega, euler_free_spin, impact, lumped_inertia, spinning_plate

ROOT = Path(__file__).resolve().parents[1]
OMEGA0 = np.array([0.01, 50.0, 0.0])   # rad/s: about the intermediate (y) axis, a little off it


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


@pytest.fixture(scope="module")
def spin(tmp_path_factory: pytest.TempPathFactory) -> tuple[paradyn.deck.Model, Path]:
    model = spinning_plate(0.4, tuple(OMEGA0), velocity=(1.0, 2.0, 3.0))
    return model, _run(model, tmp_path_factory.mktemp("spin"))


def test_free_spin_about_the_intermediate_axis_tumbles_as_euler(spin: tuple[paradyn.deck.Model, Path]) -> None:
    """Body-axis omega within 1e-5 |omega| of RK4 on Euler's equations at every record of 0.4 s,
    through the flip of omega_y from +50 to -50 rad/s (a wrong inertia, a rotation update of first
    order or an explicit omega drifts by 1e-2 and more within the first flip)."""
    model, results = spin
    with h5py.File(results) as f:
        t = f["history/time"][:]
        displacement = f["history/tracked_displacement"][:]
        velocity = f["history/tracked_velocity"][:]
        kinetic = f["history/kinetic_energy"][:]
    a, b = SIDES
    start = np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0]])
    _, _, inertia = lumped_inertia(model)
    assert np.allclose(inertia, np.diag(np.diag(inertia)), atol=1e-12 * inertia.max())   # principal axes x, y, z
    reference = euler_free_spin(np.diag(inertia), OMEGA0, t)
    omega = body_omega(displacement, velocity, start)
    assert reference[:, 1].min() < -0.99 * OMEGA0[1]   # the reference flips within the run
    assert np.abs(omega - reference).max() < 1e-5 * OMEGA0[1]
    translation = 0.5 * lumped_masses(model).sum() * (1.0 + 4.0 + 9.0)
    # the record at t = 0 averages the initial and first half-step velocities: O(dt) from the exact value
    assert kinetic[0] == pytest.approx(translation + 0.5 * OMEGA0 @ inertia @ OMEGA0, rel=1e-7)
    assert np.abs(kinetic / kinetic[0] - 1.0).max() < 1e-6


def test_free_flight_keeps_the_momentum(spin: tuple[paradyn.deck.Model, Path]) -> None:
    """The nodes' momentum in every frame is the body's, M (1, 2, 3) m/s, to 1e-10: each node's
    velocity is the chord to its place on the body over the step, (X + R s - x) / dt, whose
    rounding is about 1e-16 |x| / dt (1e-11 m/s here); the body's own velocity is exact."""
    model, results = spin
    mass = lumped_masses(model)
    with h5py.File(results) as f:
        velocity = f["frames/velocity"][:]
    momentum = np.einsum("i,fij->fj", mass, velocity)
    np.testing.assert_allclose(momentum, np.tile(mass.sum() * np.array([1.0, 2.0, 3.0]), (len(velocity), 1)),
                               rtol=1e-10)


def test_held_translation_does_not_fall(tmp_path: Path) -> None:
    """fixed = [0, 0, 1, 1, 1, 1] under gravity -z: the body slides along x at 1 m/s, never
    falls and never turns; a free body falls g t^2 / 2."""
    moves = {}
    for name, fixed in (("held", (0, 0, 1, 1, 1, 1)), ("free", (0, 0, 0, 0, 0, 0))):
        model = spinning_plate(0.01, (0.0, 0.0, 0.0), velocity=(1.0, 0.0, 0.0), fixed=fixed)
        model.control.gravity_z = -9.81
        with h5py.File(_run(model, tmp_path / name)) as f:
            moves[name] = f["history/tracked_displacement"][-1], float(f["history/time"][-1])
    (held, t), (free, _) = moves["held"], moves["free"]
    np.testing.assert_allclose(held[:, 0], t, rtol=1e-12)
    assert np.abs(held[:, 1:]).max() == 0.0
    np.testing.assert_allclose(free[:, 2], -0.5 * 9.81 * t * t, rtol=1e-3)


@pytest.fixture(scope="module")
def impacts(tmp_path_factory: pytest.TempPathFactory) -> dict[int, Path]:
    folder = tmp_path_factory.mktemp("impact")
    model = impact(4e-4)
    return {ranks: _run(model, folder / f"ranks{ranks}", ranks) for ranks in (1, 2)}


def test_impact_momentum_goes_from_the_body_to_the_plate(impacts: dict[int, Path]) -> None:
    """The impactor's loss of z-momentum equals the plate's gain to 1e-6 of it (the contact forces
    on the body are summed exactly), and it is a real exchange (over 10 % of the impactor's); the
    energy balance holds within 1 % of the impact's kinetic energy."""
    model = impact(4e-4)
    mass = lumped_masses(model)
    node_part = np.full(len(mass), -1)
    node_part[model.connectivity] = model.element_part[:, None]
    with h5py.File(impacts[1]) as f:
        velocity = f["frames/velocity"][:]
        energy = {k: f[f"history/{k}"][:] for k in ("kinetic_energy", "internal_energy", "hourglass_energy",
                                                      "contact_energy", "external_work")}
    momentum = {part: np.einsum("i,fi->f", mass[node_part == part], velocity[:, node_part == part, 2])
                for part in (0, 1)}
    target, impactor = momentum[0], momentum[1]
    braked = impactor[-1] - impactor[0]    # the impactor moves along -z: the contact pushes it back
    assert braked > 0.1 * abs(impactor[0])
    assert target[-1] - target[0] == pytest.approx(-braked, rel=1e-6)
    total = sum(energy[k] for k in ("kinetic_energy", "internal_energy", "hourglass_energy", "contact_energy"))
    assert np.abs(total - energy["external_work"] - total[0]).max() < 0.01 * energy["kinetic_energy"][0]


@pytest.mark.mpi
def test_impact_is_bitwise_the_same_on_two_ranks(impacts: dict[int, Path]) -> None:
    with h5py.File(impacts[1]) as one, h5py.File(impacts[2]) as two:
        for key in ("frames/displacement", "frames/velocity", "history/tracked_displacement"):
            assert np.array_equal(one[key][:], two[key][:]), key


def test_a_rigid_part_without_its_body_is_refused(tmp_path: Path) -> None:
    """The deck relation rigid_bodies_whole, on both sides: the frontend's validator names the node
    and the fix, and so does the engine for a deck that skipped it."""
    model = spinning_plate(1e-3, (0.0, 0.0, 0.0))
    model.node_rigid_body = np.full(len(model.coordinates), -1, dtype=np.int32)
    with pytest.raises(paradyn.deck.DeckError, match=r"/nodes/rigid_body\[\d+\] = -1 .* rigid"):
        paradyn.deck.validate_model(model)
    with pytest.raises(paradyn.scene.SceneError, match="not rigid"):
        scene = paradyn.Scene("wrong body", end_time=1e-3, output_interval=1e-4)
        scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2e11, poisson_ratio=0.3)
        scene.add_part("plate", material="steel", thickness=0.01,
                       geometry=paradyn.Plate(size=(0.1, 0.1), elements=(2, 2)))
        scene.add("rigid_body", part="plate")
        scene.build()


def test_prescribed_motion_of_a_body(tmp_path: Path) -> None:
    """prescribed = [0, 0, 1, 0, 0, 1], velocity (vz, wz) = (-2 m/s, 10 rad/s) x a ramp 0 -> 1 over
    5 ms, under gravity (LS-DYNA *BOUNDARY_PRESCRIBED_MOTION_RIGID, VAD 0): the centre falls by the
    ramp's integral and the plate turns by omega's (to 1e-9 of them), the free x and y keep their
    initial 1 and 0 m/s; the work of the prescribing reaction is external work, so the energy
    balance KE - W holds: within 1e-3 of the kinetic energy while the ramp drives the body (the
    records' kinetic energy lags the work by half a step of the drive's power, 1100 W x 2 us), 1e-4
    (measured 1.4e-5) once it runs at a constant velocity."""
    model = spinning_plate(0.01, (0.0, 0.0, 0.0), velocity=(1.0, 0.0, 0.0))
    model.control.gravity_z = -9.81
    model.rigid_body_prescribed = np.array([[0, 0, 1, 0, 0, 1]])
    model.rigid_body_velocity = np.array([[0.0, 0.0, -2.0, 0.0, 0.0, 10.0]])
    paradyn.scene.building.set_curves(model, [[0.0, 0.005, 1.0]], [[0.0, 1.0, 1.0]])
    model.rigid_body_curve = np.array([0])
    with h5py.File(_run(model, tmp_path)) as f:
        t = f["history/time"][:]
        displacement = f["history/tracked_displacement"][:]
        kinetic, work = f["history/kinetic_energy"][:], f["history/external_work"][:]
    a, b = SIDES
    start = np.array([[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0]])
    x = start[None] + displacement
    centre = 0.5 * (x[:, 1] + x[:, 2])          # the plate's centre: the middle of the +x and +y corners
    ramp = np.minimum(t / 0.005, 1.0)
    travelled = np.where(t < 0.005, 0.5 * t * ramp, t - 0.0025)   # the ramp's integral (s)
    np.testing.assert_allclose(centre[:, 2], -2.0 * travelled, rtol=0, atol=1e-9 * 2.0 * travelled.max())
    np.testing.assert_allclose(centre[:, 0] - a / 2, t, rtol=0, atol=1e-9)
    edge = x[:, 1] - x[:, 0]
    angle = np.unwrap(np.arctan2(edge[:, 1], edge[:, 0]))
    np.testing.assert_allclose(angle, 10.0 * travelled, rtol=0, atol=1e-9 * 10.0 * travelled.max())
    balance = np.abs(kinetic - kinetic[0] - work)
    assert balance.max() < 1e-3 * kinetic.max()   # while the ramp drives it: half a step of its power
    assert balance[-1] < 1e-4 * kinetic.max()


def test_a_body_driven_alone_is_not_an_idle_model() -> None:
    """The check's "nothing in this model moves or is loaded" (docs/outputs.md) knows a rigid body
    with a prescribed velocity as loading; held dofs alone are not."""
    model = spinning_plate(0.01, (0.0, 0.0, 0.0))
    assert any("nothing in this model moves" in w for w in preflight.idle_warnings(model))
    model.rigid_body_prescribed = np.array([[0, 0, 1, 0, 0, 0]])
    model.rigid_body_velocity = np.array([[0.0, 0.0, -2.0, 0.0, 0.0, 0.0]])
    assert preflight.idle_warnings(model) == []


def test_the_rigid_punch_case(tmp_path: Path) -> None:
    """cases/rigid_impact: the punch, driven at 10 m/s along -z, is 40 mm down at 4 ms in every frame's
    time (to 1e-9), never turns or slides; the work of what drives it (external work) goes into the
    dented plate: the energy balance within 1 % of that work, most of it plastic."""
    model = paradyn.scene.build_model(paradyn.scene.load_scene(ROOT / "cases" / "rigid_impact" / "scene.toml"))
    with h5py.File(_run(model, tmp_path)) as f:
        t, displacement = f["frames/time"][:], f["frames/displacement"][:]
        history = {k: f[f"history/{k}"][:] for k in ("kinetic_energy", "internal_energy", "hourglass_energy",
                                                      "contact_energy", "external_work", "part_plastic_work")}
    punch = model.node_rigid_body == 0
    np.testing.assert_allclose(displacement[:, punch, 2], np.tile(-10.0 * t[:, None], (1, punch.sum())), rtol=0,
                               atol=1e-9)
    assert np.abs(displacement[:, punch, :2]).max() < 1e-12
    work = history["external_work"]
    total = sum(history[k] for k in ("kinetic_energy", "internal_energy", "hourglass_energy", "contact_energy"))
    assert np.abs(total - work - total[0]).max() < 0.01 * work[-1]
    assert history["part_plastic_work"][-1, 0] > 0.5 * work[-1] > 0


@pytest.mark.parametrize("ranks", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_with_rigid_bodies_is_the_uninterrupted_run(tmp_path: Path, ranks: int) -> None:
    """The bodies' motion goes into checkpoints (nodal_effect%state_words): the impactor run
    restarted from its checkpoint at 0.2 ms, while the body is in contact, on 1 rank and on 2,
    gives every frame and history record of the uninterrupted run bit for bit (positions,
    velocities, tracked points; on 2 ranks the energies, summed per rank, to 1e-12)."""
    model = impact(4e-4)
    reference = _run(model, tmp_path / "plain")
    model.control.checkpoint_interval = 2e-4
    folder = tmp_path / "checkpointed"
    results = _run(model, folder)
    target = folder / f"restart{ranks}.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)   # as a run stopped after its checkpoint leaves it
    shutil.copy(folder / "results.checkpoint.h5", folder / f"restart{ranks}.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, ranks, 1, restart=True)
    with h5py.File(reference) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        for key in ("frames/displacement", "frames/velocity", "history/tracked_displacement"):
            assert np.array_equal(one[key][:], two[key][:]), key
        np.testing.assert_allclose(two["history/kinetic_energy"][:], one["history/kinetic_energy"][:], rtol=1e-12)
