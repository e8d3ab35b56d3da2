"""The fully integrated shell (element = "full", /parts/shell_element 2, keyword ELFORM 16 / -16)
through the whole stack: selection by scene, static bending against beam theory with no
hourglass energy, a plastic run bitwise the same on 1 and 2 ranks and across a restart's
checkpoint rows, and the frames' fields from its four in-plane points.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
import paradyn
import report_full_shell as R
import shell_obstacles as S
import test_checkpoint as C
import test_verification as V
import test_warping as W
from paradyn.deck import Control
from paradyn.running import launch
from paradyn.scene import build_model, load_scene

STEEL = M.Material(young=200.0e9, poisson=0.0, density=7850.0)


def test_scene_part_selects_the_element(tmp_path: Path) -> None:
    """A part's ``element = "full"`` gives /parts/shell_element 2, the default 1
    (the one-point element); an unknown name is refused with the choices."""
    text = """
title = "two plates"
[run]
end_time = 1e-5
output_interval = 1e-5
[[material]]
name = "steel"
model = "elastic"
density = 7850.0
youngs_modulus = 2.0e11
poisson_ratio = 0.3
[[part]]
name = "a"
material = "steel"
thickness = 0.01
element = "%s"
[part.geometry]
kind = "plate"
size = [0.1, 0.1]
elements = [2, 2]
"""
    path = tmp_path / "scene.toml"
    path.write_text(text % "full")
    model = build_model(load_scene(path))
    assert model.shell_element.tolist() == [2]
    path.write_text(text % "blt")
    assert build_model(load_scene(path)).shell_element.tolist() == [1]
    path.write_text(text % "ful")
    with pytest.raises(Exception, match=r"blt.*full|full.*blt"):
        load_scene(path)


def test_cantilever_tip_deflection_without_hourglass_energy(tmp_path: Path) -> None:
    """Reference: delta = P L^3 / (3 E I) (Timoshenko, Strength of Materials), the setup of
    tests/test_verification.py's cantilever (20 x 2 elements, L = 1 m, b = 0.1 m, t = 0.01 m, nu = 0,
    dynamic relaxation), with the fully integrated element: within 2 %, the stored energy half
    the load's work, and the hourglass energy exactly 0 (the element has no hourglass control)."""
    beam = M.cantilever(STEEL)
    load = 5.0
    f1 = beam.first_frequency
    period = 1.0 / f1
    control = Control(end_time=4.0 * period, output_interval=period, history_interval=period / 50,
                      mass_damping=2.0 * (2.0 * np.pi * f1))
    model = beam.model(control, loads=[M.Load(beam.tip, 3, load * beam.tip_weights, ramp_time=period)],
                       element="full")
    run = M.run(model, tmp_path)
    h = run.results.history
    w_tip = h["tracked_displacement"][:, :, 2] @ beam.tip_weights
    reference = load * beam.length**3 / (3.0 * beam.bending_stiffness)
    k = int(0.8 * (len(w_tip) - 1))
    assert abs(w_tip[-1] - w_tip[k]) < 1e-3 * abs(w_tip[-1])
    assert w_tip[-1] == pytest.approx(reference, rel=0.02)
    assert np.all(h["hourglass_energy"] == 0.0)
    assert h["internal_energy"][-1] == pytest.approx(0.5 * load * w_tip[-1], rel=0.01)


def _plastic_plate(control: Control) -> M.Model:
    """A 4 x 4 steel plate, J2 plastic, clamped on one edge, struck at 60 m/s over its free half."""
    mesh = M.strip(0.1, 0.1, 4, 4)
    c = mesh.coordinates
    velocity = np.zeros((mesh.n_nodes, 3))
    velocity[c[:, 0] > 0.05, 2] = 60.0 * c[c[:, 0] > 0.05, 0] / 0.1
    fixed = {int(k): M.ALL_DOFS for k in np.flatnonzero(c[:, 0] < 1e-12)}
    model = M.shell_model(mesh, 0.002, M.Material(200e9, 0.3, 7850.0), control, fixed=fixed, velocity=velocity,
                          tracked=[int(np.argmax(c[:, 0] + c[:, 1]))], element="full", integration_points=3)
    model.material_model = np.array([M.ENUMS["material_model"]["j2_plasticity"]], dtype=np.int32)
    model.yield_stress = np.array([250e6])
    model.tangent_modulus = np.array([2e9])
    model.hardening_mixing = np.array([0.5])
    return model


def test_plastic_run_is_bitwise_the_same_on_one_and_two_ranks(tmp_path: Path) -> None:
    """Reference: layout independence (docs/performance.md): the fully integrated element's forces
    and its 4 x 3 stored points per element give the same bits (tracked nodes, frames) on 1 rank x 1
    thread and 2 ranks x 2 threads; the plastic work is positive and there is no hourglass energy."""
    control = Control(end_time=4e-4, output_interval=2e-4, history_interval=2e-5)
    one = paradyn.run(_plastic_plate(control), tmp_path / "one", ranks=1, threads=1, post=False)
    two = paradyn.run(_plastic_plate(control), tmp_path / "two", ranks=2, threads=2, post=False)
    h1, h2 = one.history, two.history
    for key in ("tracked_displacement", "tracked_velocity"):
        assert np.array_equal(np.asarray(h1[key]), np.asarray(h2[key])), key
    assert np.array_equal(np.asarray(one.displacement[-1]), np.asarray(two.displacement[-1]))
    assert np.array_equal(np.asarray(one.plastic_strain[-1]), np.asarray(two.plastic_strain[-1]))
    # the energies are summed per rank, then across ranks (tests/test_parallel.py): round-off
    scale = np.abs(np.asarray(h1["internal_energy"])).max()
    for key in ("internal_energy", "kinetic_energy"):
        np.testing.assert_allclose(np.asarray(h2[key]), np.asarray(h1[key]), rtol=0, atol=1e-14 * scale)
    assert np.asarray(h1["part_plastic_work"]).max() > 0.0
    assert np.all(np.asarray(h1["hourglass_energy"]) == 0.0)
    assert np.asarray(one.plastic_strain[-1]).max() > 0.0


# ------------------------------------------------------------------------------------------------
# the verification table's shell problems with the fully integrated element (docs/validation.md,
# "Fully integrated shell"; tests/report_full_shell.py prints every mesh)


def test_scordelis_lo_roof(tmp_path: Path) -> None:
    """Scordelis-Lo roof (MacNeal & Harder 1985: 0.3024), the one-point element's set-up
    (tests/test_verification.py), 16 x 16 on the quarter, within its 5 %: 0.9914 of the reference
    (8 x 8: 0.9738, converging from below as a fully integrated element does); settled, the
    internal energy half the loads' work, no hourglass energy."""
    w, run, clapeyron = R.roof(16, tmp_path)
    assert V._settled(w) < 1e-3
    assert clapeyron == pytest.approx(1.0, rel=5e-3)
    assert np.all(run.results.history["hourglass_energy"] == 0.0)
    assert w[-1] == pytest.approx(V.ROOF_REFERENCE, rel=0.05)


@pytest.mark.parametrize("load", list(W.TWISTED_BEAM))
def test_twisted_beam(tmp_path: Path, load: str) -> None:
    """Twisted beam (MacNeal & Harder 1985: 5.424e-3 in-plane, 1.754e-3 out-of-plane), every
    element warped, 4 x 24, within the one-point element's 3 %; settled, Clapeyron to 0.5 %."""
    u, reference, run, _ = W.twisted_beam_run(load, 4, 24, tmp_path, element="full")
    h = run.results.history
    assert W._settled(u) < W.SETTLED
    assert h["internal_energy"][-1] == pytest.approx(0.5 * u[-1], rel=5e-3)
    assert np.all(h["hourglass_energy"] == 0.0)
    assert u[-1] == pytest.approx(reference, rel=0.03)


@pytest.mark.parametrize("n", [8, pytest.param(16, marks=pytest.mark.slow)])
def test_pinched_hemisphere(tmp_path: Path, n: int) -> None:
    """Closed pinched hemisphere (MacNeal & Harder 1985: 0.0924), the cubed sphere of
    tests/test_warping.py with n x n elements per face, every element warped, within the
    one-point element's 3 % (8 x 8: 0.9806, 16 x 16: 0.9913); the four load points alike to 1e-4,
    settled, Clapeyron to 0.5 %."""
    u, run, _ = W.hemisphere_run(n, tmp_path, element="full")
    final = u[-1]
    h = run.results.history
    assert W._settled(u[:, 0]) < W.SETTLED
    assert np.ptp(final) < 1e-4 * final.mean()
    work = 0.5 * W.HEMISPHERE_LOAD * W.HEMISPHERE_LOAD_FACTOR**2 * final.sum()
    assert h["internal_energy"][-1] == pytest.approx(work, rel=5e-3)
    assert final.mean() == pytest.approx(W.HEMISPHERE_REFERENCE, rel=0.03)


def test_undamped_warped_shell_conserves_energy_at_the_default_step(tmp_path: Path) -> None:
    """Reference: central differences conserve KE + IE + HG - W exactly for a linear system when
    the forces are the transpose of the rates (docs/theory.md, energies), and only below the
    stable step. The 8 x 8 cubed-sphere hemisphere of tests/test_warping.py (every element warped),
    step loads of 1, no damping, the default step (the BLT element's L / c), 10 000 cycles: finite,
    and the balance within 1e-5 of the largest external work, as the one-point element's test."""
    hemi = S.hemisphere(8)
    dt = M.stable_time_step(hemi.mesh, M.Material(hemi.YOUNG, hemi.POISSON, 1.0))
    end = 10000 * dt
    control = Control(end_time=end, output_interval=end, history_interval=end / 100)
    h = M.run(hemi.model(control, 1.0, 1.0, 0.0, element="full"), tmp_path).results.history
    stored = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"]
    assert np.all(np.isfinite(stored))
    assert h["internal_energy"].max() > 0.1 * np.abs(h["external_work"]).max()
    assert np.abs(stored - h["external_work"]).max() < 1e-5 * np.abs(h["external_work"]).max()
    assert np.all(h["hourglass_energy"] == 0.0)


@pytest.mark.mpi
def test_restart_of_a_mixed_model_is_bitwise(tmp_path: Path) -> None:
    """Checkpoint rows (docs/formats.md): the pipe whip of tests/test_checkpoint.py with the upper,
    hardening pipe (back stresses) fully integrated, 4 x 5 points per element, and the lower one
    on the one-point element; a restart from the 0.3 ms checkpoint on 1 and on 2 ranks continues
    the uninterrupted run bitwise (frames and tracked nodes), the upper pipe yielding by then."""
    def deck_file(name: str, **control: float) -> Path:
        path = C._hardening_pipe_whip(tmp_path, name, 0.5, **control)
        with h5py.File(path, "r+") as f:
            if "shell_element" in f["/parts"]:
                del f["/parts/shell_element"]
            f["/parts/shell_element"] = np.array([2, 1], dtype=np.int32)
        return path
    plain = deck_file("plain.h5")
    with_checkpoints = deck_file("deck.h5", checkpoint_interval=C.CHECKPOINT_INTERVAL)
    launch.run_engine(plain, tmp_path / "reference.h5")
    launch.run_engine(with_checkpoints, tmp_path / "results.h5")
    reference = C._read(tmp_path / "reference.h5")
    assert reference["frames/element_plastic_strain"][2].max() > 0.0
    assert np.all(reference["history/part_hourglass_energy"][:, 0] == 0.0)   # the upper pipe
    for ranks in (1, 2):
        target = tmp_path / f"restart_{ranks}.h5"
        C._interrupted_copy(tmp_path / "results.h5", target)
        shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / f"restart_{ranks}.checkpoint.h5")
        launch.run_engine(with_checkpoints, target, ranks, 1, restart=True)
        data = C._read(target)
        for key in ("frames/displacement", "frames/velocity", "frames/element_plastic_strain",
                    "history/tracked_displacement"):
            assert np.array_equal(data[key], reference[key]), (ranks, key)
