"""Element erosion at a material's failure strain, and contact birth and death times (issue 33).

Erosion reference: LS-DYNA's rule for shells (MAT_024 FAIL, MAT_003 FS; *CONTROL_SHELL NUMFIP
default 1): an element is deleted once the effective plastic strain at one of its through-thickness
points reaches the failure strain. On a uniaxial stress path at a constant logarithmic strain rate
D the axial strain is D t and, for a perfectly plastic J2 material, the effective plastic strain
is the axial strain less its elastic part sigma_y / E, so the element fails at

    t_f = (FAIL + sigma_y / E) / D.

A rule on the total strain (t = FAIL / D) is 2.3 % early for the strip below, a rule on the plastic
strain of the mean point no different here (membrane path), the tolerance 0.5 %.

Birth and death (LS-DYNA *CONTACT card 2 BT, DT): the contact acts while BT <= t <= DT. A
one-element plate falling at 10 m/s onto a held plate: with the contact alive at the impact it
bounces (its momentum change is the contact impulse, the integral of the contact force history),
with a death time before the impact it passes through untouched (its velocity stays -10 m/s, no
contact force ever). A contact born after the start is not checked at the start: a plate that
crosses the other at t = 0 and moves away before the birth runs (with birth 0 it is refused).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch
from paradyn.running.engine_process import EngineError
from test_material_rate import stretch

RATE = 100.0        # 1/s
FAIL = 0.05         # failure plastic strain
YIELD, YOUNG = 250e6, 210e9
STEEL = {"density": 7850.0, "youngs_modulus": YOUNG, "poisson_ratio": 0.3}


def _history(folder: Path) -> dict[str, np.ndarray]:
    with h5py.File(folder / "results.h5") as f:
        return {k: f["history"][k][()] for k in f["history"]}


def _strip(model: str, end: float = 0.08 / RATE) -> paradyn.Scene:
    s = paradyn.Scene(f"{model} strip", end_time=end, output_interval=end / 40, history_interval=end / 4000)
    s.add_material("steel", model=model, yield_stress=YIELD, failure_strain=FAIL, **STEEL)
    return stretch(s, RATE, end)


@pytest.mark.parametrize("model", ["j2_plasticity", "piecewise_linear"])
def test_strip_erodes_when_its_plastic_strain_reaches_fail(tmp_path: Path, model: str) -> None:
    """The strip erodes at t_f = (FAIL + sigma_y / E) / D within 0.5 % (the history's record
    interval is 0.3 % of t_f); afterwards its stress is zero, its internal energy frozen, and the
    energy balance (external work = internal + kinetic) keeps the error it had before, under 0.5 %."""
    res = paradyn.run(_strip(model), tmp_path, ranks=1, threads=1, post=False)
    h = _history(tmp_path)
    eroded = h["eroded_elements"]
    assert set(eroded.tolist()) == {0.0, 1.0} and eroded[-1] == 1.0
    first = int(np.argmax(eroded > 0))
    expected = (FAIL + YIELD / YOUNG) / RATE
    assert abs(FAIL / RATE - expected) > 0.02 * expected   # the total-strain rule is told apart
    assert h["time"][first - 1] < expected * 1.005 and h["time"][first] == pytest.approx(expected, rel=0.005)
    stress = np.asarray(res.membrane_stress.read_all())[:, 0, :]
    eps_p = np.asarray(res.plastic_strain.read_all())[:, 0]
    assert np.all(stress[-1] == 0.0) and FAIL <= eps_p[-1] < 1.01 * FAIL
    assert np.all(h["internal_energy"][first:] == h["internal_energy"][first])
    balance = h["external_work"] - h["internal_energy"] - h["kinetic_energy"]
    assert np.abs(balance).max() < 0.005 * h["external_work"][-1]
    assert abs(balance[-1] - balance[first - 1]) < 0.001 * h["external_work"][-1]


def test_no_failure_strain_never_erodes(tmp_path: Path) -> None:
    """failure_strain 0 (the default): the same strip stretched past FAIL keeps its element."""
    s = paradyn.Scene("no failure", end_time=0.08 / RATE, output_interval=0.02 / RATE)
    s.add_material("steel", model="j2_plasticity", yield_stress=YIELD, **STEEL)
    res = paradyn.run(stretch(s, RATE, 0.08 / RATE), tmp_path, ranks=1, threads=1, post=False)
    assert np.all(_history(tmp_path)["eroded_elements"] == 0.0)
    assert np.asarray(res.plastic_strain.read_all())[-1, 0] > 1.5 * FAIL


def _bar(end: float) -> paradyn.deck.Model:
    """A strip of 8 x 2 elements held at x = 0 and pulled at x = L at 20 m/s (plastic waves, so
    the elements fail at different times), piecewise_linear with FAIL."""
    s = paradyn.Scene("bar", end_time=end, output_interval=end / 8, history_interval=end / 80)
    s.add_material("steel", model="piecewise_linear", yield_stress=YIELD, tangent_modulus=1e9,
                   failure_strain=0.02, **STEEL)
    s.add_part("bar", material="steel", thickness=0.001, integration_points=3,
               geometry=paradyn.Plate((0.08, 0.02), (8, 2)))
    s.add_fix("bar", box=[[-1, -1, -1], [1, 1, 1]], dofs=["uz", "rotations"])
    s.add_fix("bar", box=[[-1e-6, -1, -1], [1e-6, 1, 1]], dofs=["ux", "uy"])
    s.add_prescribe("bar", box=[[0.08 - 1e-6, -1, -1], [1, 1, 1]], dof="ux", value=20.0)
    return s.build()


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


@pytest.mark.parametrize("ranks", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_and_ranks_keep_the_erosion_bitwise(tmp_path: Path, ranks: int) -> None:
    """The erosion state is the plastic strains, which checkpoints keep: the pulled bar restarted
    from its checkpoint (after the first erosions) on 1 rank and on 2 gives every frame and the
    eroded count of the uninterrupted one-rank run bit for bit."""
    end = 2e-4
    model = _bar(end)
    reference = _run(model, tmp_path / "plain")
    with h5py.File(reference) as f:
        eroded = f["history/eroded_elements"][:]
        assert 0 < eroded[-1] < 16 and eroded[len(eroded) // 2] > 0   # some fail, some before the checkpoint
    model.control.checkpoint_interval = end / 2
    folder = tmp_path / "checkpointed"
    results = _run(model, folder)
    target = folder / f"restart{ranks}.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / f"restart{ranks}.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, ranks, 1, restart=True)
    with h5py.File(reference) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        for key in ("frames/displacement", "frames/velocity", "frames/element_von_mises", "history/eroded_elements"):
            assert np.array_equal(one[key][:], two[key][:]), key
    if ranks == 2:   # and the whole run on 2 ranks
        with h5py.File(reference) as one, h5py.File(_run(model, tmp_path / "two", 2)) as two:
            for key in ("frames/displacement", "history/eroded_elements"):
                assert np.array_equal(one[key][:], two[key][:]), key


# --- contact birth and death ----------------------------------------------------------------

def _fall(end: float = 2e-3, **contact: float) -> paradyn.deck.Model:
    """A 20 mm one-element plate 10 mm above a held 0.1 m plate (4 x 4), falling at 10 m/s."""
    s = paradyn.Scene("fall", end_time=end, output_interval=end / 4, history_interval=end / 8000)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("target", material="steel", thickness=0.002, geometry=paradyn.Plate((0.1, 0.1), (4, 4)))
    s.add_fix("target", box=[[-1, -1, -1], [1, 1, 1]])
    s.add_part("faller", material="steel", thickness=0.002, initial_velocity=[0.0, 0.0, -10.0],
               geometry=paradyn.Plate((0.02, 0.02), (1, 1), origin=[0.04, 0.04, 0.01]))
    s.add_contact("faller", "target", **contact)
    return s.build()


def _faller_velocity(results: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Time, the faller's vertical velocity (the mean of its 4 equal nodes: momentum / mass) at
    the frames, the contact force's z history with its times."""
    with h5py.File(results) as f:
        v = f["frames/velocity"][:, -4:, 2].mean(axis=1)
        return v, f["history/time"][:], f["history/contact_force"][:, 0, 2]


def test_death_before_the_impact_lets_the_plate_through(tmp_path: Path) -> None:
    """Alive (defaults): the plate bounces, its momentum change the contact impulse (the force
    history, recorded every step, summed over time) to 1e-6 and its speed back up; dead at 0.4 ms (before the
    impact at about 0.8 ms): it passes through, -10 m/s to the end, no contact force ever; born at
    0.4 ms: the bounce of the contact that lived throughout, to 1e-6."""
    mass = 7850.0 * 0.02 * 0.02 * 0.002
    alive_v, t, force = _faller_velocity(_run(_fall(), tmp_path / "alive"))
    impulse = np.trapezoid(force, t) if hasattr(np, "trapezoid") else np.trapz(force, t)
    assert alive_v[-1] > 5.0
    # the contact force on the first part (the faller) changes its momentum
    assert mass * (alive_v[-1] - alive_v[0]) == pytest.approx(impulse, rel=1e-6)
    dead_v, _, dead_force = _faller_velocity(_run(_fall(death_time=4e-4), tmp_path / "dead"))
    assert np.all(dead_v == -10.0) and np.all(dead_force == 0.0)
    born_v, _, _ = _faller_velocity(_run(_fall(birth_time=4e-4), tmp_path / "born"))
    np.testing.assert_allclose(born_v, alive_v, rtol=0, atol=1e-6)


def _crossing(birth: float) -> paradyn.deck.Model:
    """A vertical plate through the middle of a held horizontal one at t = 0, moving up at 20 m/s:
    clear of it (and of the contact thickness) after 0.6 ms."""
    s = paradyn.Scene("crossing", end_time=1.5e-3, output_interval=5e-4)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("floor", material="steel", thickness=0.002, geometry=paradyn.Plate((0.1, 0.1), (4, 4)))
    s.add_fix("floor", box=[[-1, -1, -1], [1, 1, 1]])
    s.add_part("blade", material="steel", thickness=0.002, initial_velocity=[0.0, 0.0, 20.0],
               geometry=paradyn.Plate((0.02, 0.01), (2, 1), origin=[0.035, 0.0375, -0.005],
                                      u_axis=[1, 0, 0], v_axis=[0, 0, 1]))
    s.add_contact("blade", "floor", birth_time=birth)
    return s.build()


def test_a_contact_born_later_is_not_checked_at_the_start(tmp_path: Path) -> None:
    """The blade crosses the floor at t = 0: with the contact born at 0 the start check refuses
    the run; born at 1 ms, after the blade is clear, the run goes on and the blade keeps 20 m/s."""
    with pytest.raises(EngineError, match="cross at the start"):
        _run(_crossing(0.0), tmp_path / "now")
    with h5py.File(_run(_crossing(1e-3), tmp_path / "later")) as f:
        assert np.abs(f["frames/velocity"][:, -6:, 2] - 20.0).max() < 1e-6
        assert np.all(f["history/contact_force"][()] == 0.0)


def test_death_before_birth_is_refused() -> None:
    s = paradyn.Scene("bad", end_time=1e-3, output_interval=1e-4)
    s.add_material("steel", model="elastic", **STEEL)
    s.add_part("a", material="steel", thickness=0.002, geometry=paradyn.Plate((0.1, 0.1), (1, 1)))
    s.add_part("b", material="steel", thickness=0.002,
               geometry=paradyn.Plate((0.1, 0.1), (1, 1), origin=[0, 0, 0.01]))
    with pytest.raises(paradyn.scene.SceneError, match=r"'death_time' in \[\[contact\]\] #1 .* must come after"):
        s.add_contact("a", "b", birth_time=2e-4, death_time=1e-4)
