"""Eroded elements leave the contact (issue 33): LS-DYNA removes an eroded shell's segment from
every contact and a node from the slaves once every element around it is eroded (LS-DYNA Keyword
User's Manual, *MAT_ADD_EROSION and *CONTACT: "eroding" surfaces; the Theory Manual's element
deletion). ParaDyn does the same for every kind (node to segment, single surface, the edge kinds,
tied: a tie to an eroded segment is released), with results independent of the layout.

References used below:

- A strip stretched at the constant log strain rate D erodes at t_f = (FAIL + sigma_y / E) / D
  (test_erosion); a plate that falls onto it after t_f meets nothing: its velocity stays v0 exactly
  and no contact force is ever recorded (a free body). Before t_f the same plate bounces (the
  control: the strip made not to fail).
- A node tied to a segment that erodes is released: from then on it is a free body under gravity,
  its velocity v(t) = v(t_r) - g (t - t_r) and the tie's force zero; while tied, the tie holds it
  up (the strip is held in z).
- A heavy rigid punch that perforates a held plate leaves through the hole: after the last element
  under it erodes it is a free body (constant velocity, zero contact force), its momentum change is
  the contact impulse (Newton's second law), and its exit speed is above the one it keeps when the
  plate cannot fail (the control, which keeps slowing it).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch
from test_material_rate import stretch

RATE, FAIL, YIELD, YOUNG = 100.0, 0.05, 250e6, 210e9
STEEL = {"density": 7850.0, "youngs_modulus": YOUNG, "poisson_ratio": 0.3}
T_FAIL = (FAIL + YIELD / YOUNG) / RATE      # the strip's erosion time, 0.512 ms
G = 1000.0                                  # m/s^2, 100 g: a free fall shows within the run


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


def _strip_and_faller(fail: float, kind: str, end: float = 1.2e-3) -> paradyn.deck.Model:
    """The strip (10 mm, at z = 0) stretched to erosion, and a 4 mm plate 4 mm above its middle
    falling at 5 m/s: it would touch the strip (1 mm gap) at 0.6 ms, after t_f."""
    s = paradyn.Scene("through", end_time=end, output_interval=end / 12, history_interval=end / 1200)
    s.add_material("steel", model="j2_plasticity", yield_stress=YIELD, failure_strain=fail, **STEEL)
    s.add_material("elastic", model="elastic", **STEEL)
    stretch(s, RATE, end)
    s.add_part("faller", material="elastic", thickness=0.001, initial_velocity=[0.0, 0.0, -5.0],
               geometry=paradyn.Plate((0.004, 0.004), (1, 1), origin=[0.003, 0.003, 0.004]))
    s.add_contact("faller", "strip", kind=kind)
    return s.build()


def _faller(results: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    with h5py.File(results) as f:
        return (f["frames/velocity"][:, -4:, 2], f["history/contact_force"][:, 0, 2], f["history/eroded_elements"][()])


@pytest.mark.parametrize("kind", ["node_to_segment", "single_surface", "edge_to_edge"])
def test_a_plate_passes_where_the_strip_has_eroded(tmp_path: Path, kind: str) -> None:
    """After t_f the strip's segment is gone from the contact: the faller keeps -5 m/s exactly and
    no contact force is recorded; with a strip that does not fail (FAIL 10) it bounces (a single
    surface's force is internal to its surface, so only the two-part kinds record one)."""
    v, force, eroded = _faller(_run(_strip_and_faller(FAIL, kind), tmp_path / "eroding"))
    assert eroded[-1] == 1.0
    assert np.all(v == -5.0) and np.all(force == 0.0)
    v_kept, force_kept, eroded_kept = _faller(_run(_strip_and_faller(10.0, kind), tmp_path / "kept"))
    assert np.all(eroded_kept == 0.0) and v_kept[-1].mean() > 2.0
    if kind != "single_surface":
        assert force_kept.max() > 0.0


def test_no_erosion_gives_the_bits_of_a_material_without_failure(tmp_path: Path) -> None:
    """A failure strain never reached (10) runs the erosion bookkeeping of the contact and changes
    no bit of the run without one (0): the bouncing faller, frames and history."""
    a = _run(_strip_and_faller(10.0, "node_to_segment"), tmp_path / "ten")
    b = _run(_strip_and_faller(0.0, "node_to_segment"), tmp_path / "zero")
    with h5py.File(a) as one, h5py.File(b) as two:
        for key in ("frames/displacement", "frames/velocity", "history/contact_force", "history/contact_energy"):
            assert np.array_equal(one[key][()], two[key][()]), key


def _tied(fail: float) -> paradyn.deck.Model:
    """A rigid 4 mm plate lying on the strip (at the two half thicknesses), tied to it, under 100 g;
    the step held at 1 us (the stable step grows once the strip is gone)."""
    end = 1.0e-3
    s = paradyn.Scene("tied", end_time=end, output_interval=end / 10, history_interval=end / 1000)
    s.add_material("steel", model="j2_plasticity", yield_stress=YIELD, failure_strain=fail, **STEEL)
    s.add_material("rigid", model="rigid", **STEEL)
    stretch(s, RATE, end)
    s.add_part("slave", material="rigid", thickness=0.001,
               geometry=paradyn.Plate((0.004, 0.004), (1, 1), origin=[0.003, 0.003, 0.001]))
    s.add_contact("slave", "strip", kind="tied")
    model = s.build()
    model.control.gravity_z = -G
    model.control.time_step = 1e-6
    return model


def test_a_tie_to_an_eroded_segment_is_released(tmp_path: Path) -> None:
    """While the strip lives the tie holds the slave up (it sinks less than 1e-8 m, where a free
    fall would take it 1.3e-4 m by t_f); from the step the strip erodes at t_f the tie's force is
    zero and the slave falls freely: between frames v changes by -g dt to round-off."""
    with h5py.File(_run(_tied(FAIL), tmp_path / "tied")) as f:
        t = f["history/time"][()]
        force = f["history/contact_force"][:, 0, 2]
        eroded = f["history/eroded_elements"][()]
        frame_t = f["frames/time"][()]
        v = f["frames/velocity"][:, -4:, 2].mean(axis=1)
        z = f["frames/displacement"][:, -4:, 2].mean(axis=1)
    first = int(np.argmax(eroded > 0))
    assert t[first] == pytest.approx(T_FAIL, rel=0.005)
    assert np.abs(z[frame_t < t[first]]).max() < 1e-8 and np.abs(force[:first]).max() > 0.0
    assert np.all(force[first:] == 0.0)
    after = frame_t > t[first]
    assert after.sum() >= 4
    np.testing.assert_allclose(np.diff(v[after]), -G * np.diff(frame_t[after]), rtol=0, atol=1e-9)


PUNCH_MASS = 7850e3 * 0.02 * 0.02 * 0.002   # kg: a rigid 20 mm plate 2 mm thick, 1000 x steel's density


def _punch(fail: float) -> paradyn.deck.Model:
    """A held 0.1 m plate (4 x 4, 1 mm, sigma_y 100 MPa, FAIL) and a heavy rigid 20 mm punch over its
    middle at 10 m/s: the four elements under the punch stretch to FAIL and erode, a 50 mm hole."""
    end = 2e-3
    s = paradyn.Scene("punch", end_time=end, output_interval=end / 8, history_interval=1e-9)
    s.add_material("soft", model="j2_plasticity", density=7850.0, youngs_modulus=YOUNG, poisson_ratio=0.3,
                   yield_stress=100e6, failure_strain=fail)
    s.add_material("heavy", model="rigid", density=7850e3, youngs_modulus=YOUNG, poisson_ratio=0.3)
    s.add_part("plate", material="soft", thickness=0.001, integration_points=3,
               geometry=paradyn.Plate((0.1, 0.1), (4, 4)))
    for box in ([[-1, -1, -1], [1e-6, 1, 1]], [[0.1 - 1e-6, -1, -1], [1, 1, 1]],
                [[-1, -1, -1], [1, 1e-6, 1]], [[-1, 0.1 - 1e-6, -1], [1, 1, 1]]):
        s.add_fix("plate", box=box)
    s.add_part("punch", material="heavy", thickness=0.002, initial_velocity=[0.0, 0.0, -10.0],
               geometry=paradyn.Plate((0.02, 0.02), (1, 1), origin=[0.04, 0.04, 0.002]))
    s.add_contact("punch", "plate")
    return s.build()


def test_a_punch_leaves_through_the_hole_it_makes(tmp_path: Path) -> None:
    """The four elements under the punch erode together (their strains are equal by symmetry); from
    that step the punch meets nothing (zero contact force, constant velocity: with the eroded
    segments left in the contact it is still pushed, 37 kN, past the hole's rim); its momentum change
    is the contact impulse (Newton's second law, 1e-9: the trapezoidal sum of the per-step force);
    the plate without failure keeps slowing it (-7.2 m/s at 2 ms, against the -9.54 it leaves with)."""
    with h5py.File(_run(_punch(FAIL), tmp_path / "hole")) as f:
        t = f["history/time"][()]
        force = f["history/contact_force"][:, 0, 2]
        eroded = f["history/eroded_elements"][()]
        frame_t = f["frames/time"][()]
        v = f["frames/velocity"][:, -4:, 2].mean(axis=1)
    last = int(np.argmax(eroded == 4.0))
    assert eroded[-1] == 4.0 and eroded[last - 1] == 0.0
    assert np.all(force[last:] == 0.0) and force[:last].max() > 1e4
    after = frame_t > t[last]
    assert after.sum() >= 3
    np.testing.assert_allclose(v[after], v[after][0], rtol=0, atol=1e-9)
    impulse = np.trapezoid(force, t) if hasattr(np, "trapezoid") else np.trapz(force, t)
    assert PUNCH_MASS * (v[-1] - v[0]) == pytest.approx(impulse, rel=1e-9)
    assert -10.0 < v[-1] < -9.0   # slowed by the plate, then through (-9.54 m/s)
    with h5py.File(_run(_punch(10.0), tmp_path / "no_hole")) as f:
        assert np.all(f["history/eroded_elements"][()] == 0.0)
        assert f["frames/velocity"][-1, -4:, 2].mean() > v[-1] + 1.0   # still held back: -7.2 m/s at 2 ms


@pytest.mark.parametrize("gather", ["near", pytest.param("all", marks=pytest.mark.mpi)])
@pytest.mark.parametrize("ranks", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_and_ranks_keep_the_hole_bitwise(tmp_path: Path, ranks: int, gather: str) -> None:
    """The punch through its hole restarted from its last checkpoint (0.8 ms, after the hole opened
    at 0.77 ms: the restart finds the eroded elements again), on 1 rank and on 2, and the whole run
    on 2 ranks (local contact, and the replicated scheme:
    contact_gather "all"), give the frames and the contact history of the uninterrupted one-rank
    run bit for bit."""
    model = _punch(FAIL)
    model.control.end_time = 1.2e-3
    model.control.history_interval = 2e-6
    reference = _run(model, tmp_path / "plain")
    model.control.contact_gather = gather
    model.control.checkpoint_interval = 4e-4     # the last checkpoint at 0.8 ms
    folder = tmp_path / "checkpointed"
    results = _run(model, folder, ranks)
    keys = ("frames/displacement", "frames/velocity", "history/contact_force", "history/eroded_elements")
    with h5py.File(reference) as one, h5py.File(results) as two:
        for key in keys:
            assert np.array_equal(one[key][()], two[key][()]), key
    target = folder / "restart.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / "restart.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, ranks, 1, restart=True)
    with h5py.File(reference) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        for key in keys:
            assert np.array_equal(one[key][()], two[key][()]), key
