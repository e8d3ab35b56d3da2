"""Failed integration points and NUMFIP (issue 33): a point whose effective plastic strain reached
the failure strain carries no stress, and an element is eroded once NUMFIP of its layers failed.

References:
- LS-DYNA Keyword User's Manual, *MAT_ADD_EROSION, NUMFIP: > 0 the number of failed integration
  points before the element is deleted; < 0 (shells) the percentage of layers; < -100, |NUMFIP| -
  100 points; for shells with 4 points per layer a layer fails with any of its points. ParaDyn
  counts failed layers (docs/theory.md, "Element erosion").
- The share of one layer in the section's resultants is the thickness rule's: N = (t/2) sum_k w_k
  sigma_k, M = (t/2)^2 sum_k w_k zeta_k sigma_k (Gauss-Legendre points zeta_k, weights w_k;
  shell_section's thickness_rule). A linear bending stress sigma_k = s zeta_k gives M =
  (t/2)^2 s sum w_k zeta_k^2 = (t/2)^2 s 2/3, so losing the outer point takes the share
  w_1 zeta_1^2 / (2/3) of the moment (0.2918 for 5 points).
- A strip stretched at the constant logarithmic rate D with its width narrowing at D/2 follows
  the uniaxial stress path at its mid-surface; a perfectly plastic J2 point there has the plastic
  strain D t - sigma_y / E, so it fails at t_f = (FAIL + sigma_y / E) / D (as tests/test_erosion.py).
  Bending at the curvature rate D / t adds zeta D / 2 to the axial rate of the point at zeta, so
  the points fail from the top down: the outer one at about t_f / 1.48, the mid-surface one at t_f.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch

K = pytest.importorskip("paradyn._kernels")

RATE, FAIL = 100.0, 0.05                   # 1/s; failure plastic strain
YIELD, YOUNG, NU, RHO = 250e6, 210e9, 0.3, 7850.0
STEEL = {"density": RHO, "youngs_modulus": YOUNG, "poisson_ratio": NU}
SIZE, T = 0.01, 0.001                      # the strip's side and thickness, m
T_FAIL = (FAIL + YIELD / YOUNG) / RATE     # the mid-surface point's failure time


def F(a: np.ndarray) -> np.ndarray:
    return np.asfortranarray(a, dtype=np.float64)


# --- the counting rules -----------------------------------------------------------------------

@pytest.mark.parametrize(("numfip", "layers", "needed"), [
    (1.0, 5, 1), (3.0, 5, 3), (0.0, 5, 1), (7.0, 5, 5),          # a number; 0 the default; at most all
    (-60.0, 5, 3), (-50.0, 5, 3), (-20.0, 5, 1), (-100.0, 5, 5),  # a percentage of the layers, rounded up
    (-40.0, 3, 2), (-102.0, 5, 2), (-101.0, 1, 1),               # < -100: |NUMFIP| - 100 points
])
def test_failed_layers_needed_follow_numfip(numfip: float, layers: int, needed: int) -> None:
    """LS-DYNA's NUMFIP read as a number of failed layers (manual, *MAT_ADD_EROSION)."""
    assert K.erosion_layers_needed(numfip, layers) == needed


def test_a_layer_of_the_fully_integrated_element_fails_with_any_of_its_points() -> None:
    """4 in-plane points x 3 layers (in-plane point slowest): two failed points of one layer are
    one failed layer; two failed points of two layers are two (NUMFIP 2 erodes only then)."""
    nip, fail = 3, 0.1
    eps = np.zeros(4 * nip)
    eps[[0, nip]] = 0.2                       # layer 1 at in-plane points 1 and 2
    assert K.erosion_element_eroded(eps, fail, nip, 1) == 1
    assert K.erosion_element_eroded(eps, fail, nip, 2) == 0
    eps[nip + 1] = 0.1                        # layer 2 at in-plane point 2, exactly at FAIL
    assert K.erosion_element_eroded(eps, fail, nip, 2) == 1
    assert K.erosion_element_eroded(eps, fail, nip, 3) == 0
    assert K.erosion_element_eroded(eps, 0.0, nip, 1) == 0    # no failure strain: never


# --- the kernels: a failed point carries no stress --------------------------------------------

def _square(n: int = 1) -> np.ndarray:
    corners = np.array([[0, 0, 0], [SIZE, 0, 0], [SIZE, SIZE, 0], [0, SIZE, 0]], dtype=float).T
    return np.repeat(corners[None], n, axis=0)


def _kernel(kind: str, stress: np.ndarray, eps: np.ndarray, fail: float, v: np.ndarray) -> np.ndarray:
    """One step of the element ``kind`` (x the unit square, angular velocities zero) from the
    state (stress, eps), J2 perfectly plastic; the nodal forces and moments (1, 6, 4)."""
    x = _square()
    if kind == "triangle":
        x[0, :, 3] = x[0, :, 2]
        v = v.copy()
        v[0, :, 3] = v[0, :, 2]
    nip = eps.shape[1] // (4 if kind == "full" else 1)
    common = (F(x), F(v), F(np.zeros_like(v)), T, RHO, YOUNG, NU, YIELD, 0.0, 1.0)
    e_int, e_hg = F(np.zeros(1)), F(np.zeros(1))
    if kind == "blt":
        force, _ = K.blt_forces(*common, 0.1, 2, 1e-7, stress, F(np.zeros((1, 3, nip))), eps, F(np.zeros((1, 10))),
                                e_int, e_hg, failure_strain=fail)
    elif kind == "full":
        force, _, _ = K.full_forces(*common, 2, 1e-7, stress, F(np.zeros((1, 3, 4 * nip))), eps,
                                    F(np.zeros((1, 4))), e_int, failure_strain=fail)
    else:
        force, _, _ = K.triangle_forces(*common, 2, 1e-7, stress, F(np.zeros((1, 3, nip))), eps,
                                        F(np.zeros((1, 10))), e_int, e_hg, failure_strain=fail)
    return force


@pytest.mark.parametrize("kind", ["blt", "full", "triangle"])
def test_the_failed_outer_point_takes_its_share_of_the_moment(kind: str) -> None:
    """A linear bending stress sigma = s zeta (s = 0.8 sigma_y, elastic, no motion): with the
    top point failed (its plastic strain at FAIL) the nodal moments are those of the intact
    section times 1 - w_1 zeta_1^2 / (2/3) to 1e-9, the failed point's stress is 0 and the
    others are unchanged; failure_strain 0 (no failure) leaves every stress as it was."""
    nip = 5
    zeta, weight = K.thickness_points(nip)
    top = int(np.argmax(zeta))
    per = 4 if kind == "full" else 1
    layer_stress = np.zeros((1, 5, nip))
    layer_stress[0, 0, :] = 0.8 * YIELD * zeta
    stress0 = np.tile(layer_stress, (1, 1, per))
    eps0 = np.zeros((1, per * nip))
    eps0[0, [g * nip + top for g in range(per)]] = FAIL
    v = np.zeros((1, 3, 4))
    intact_stress, failed_stress = F(stress0), F(stress0)
    intact = _kernel(kind, intact_stress, F(eps0), 0.0, v)
    failed = _kernel(kind, failed_stress, F(eps0), FAIL, v)
    share = weight[top] * zeta[top] ** 2 / (2.0 / 3.0)
    assert 0.29 < share < 0.30
    moments = intact[0, 3:6, :]
    assert np.abs(moments).max() > 0.0
    np.testing.assert_allclose(failed[0, 3:6, :], (1.0 - share) * moments, rtol=1e-9,
                               atol=1e-9 * np.abs(moments).max())
    np.testing.assert_array_equal(intact_stress, stress0)
    dead = [g * nip + top for g in range(per)]
    assert np.all(failed_stress[0, :, dead] == 0.0)
    alive = [p for p in range(per * nip) if p not in dead]
    np.testing.assert_array_equal(failed_stress[0, :, alive], stress0[0, :, alive])


@pytest.mark.parametrize("kind", ["blt", "full", "triangle"])
def test_a_failed_point_adds_no_increment(kind: str) -> None:
    """Stretched along x in a step, the intact points gain E' de of stress; the failed one stays 0
    (its stress was zero and stays so, whatever the increment)."""
    nip = 3
    per = 4 if kind == "full" else 1
    eps0 = np.zeros((1, per * nip))
    eps0[0, ::nip] = 2 * FAIL                  # layer 1 failed at every in-plane point
    stress = F(np.zeros((1, 5, per * nip)))
    v = np.zeros((1, 3, 4))
    v[0, 0, 1:3] = 1.0                         # the x = SIZE side at 1 m/s for 1e-7 s: 1e-5 strain
    _kernel(kind, stress, F(eps0), FAIL, v)
    assert np.all(stress[0, :, ::nip] == 0.0)
    live = np.delete(stress[0, 0, :], np.arange(0, per * nip, nip))
    expected = YOUNG / (1 - NU * NU) * 1e-5
    np.testing.assert_allclose(live, expected, rtol=1e-3)


# --- the bent strip -----------------------------------------------------------------------------

def _bent_strip(numfip: float, end: float = 1.1 * T_FAIL, frames: int = 440, mesh: tuple[int, int] = (1, 1),
                nip: int = 5, bend: bool = True, element: str = "blt") -> paradyn.Scene:
    """A strip of side SIZE (5 points through the thickness, perfectly plastic J2, FAIL) stretched
    at the logarithmic rate D, its width narrowing at D/2, and bent at the curvature rate D / t
    by opposite rotation rates of its ends about y: the axial rate at zeta is D (1 + zeta / 2)."""
    s = paradyn.Scene(f"bent strip numfip {numfip}", end_time=end, output_interval=end / frames,
                      history_interval=end / 4000)
    s.add_material("steel", model="j2_plasticity", yield_stress=YIELD, failure_strain=FAIL, failure_points=numfip,
                   **STEEL)
    s.add_part("strip", material="steel", thickness=T, integration_points=nip, element=element,
               geometry=paradyn.Plate((SIZE, SIZE), mesh))
    lo, hi = -1e-6, SIZE + 1e-6
    s.add_fix("strip", box=[[lo, lo, -1.0], [hi, hi, 1.0]], dofs=["uz", "rx", "rz"])
    s.add_fix("strip", box=[[lo, lo, -1.0], [1e-6, hi, 1.0]], dofs=["ux"])
    s.add_fix("strip", box=[[lo, lo, -1.0], [hi, 1e-6, 1.0]], dofs=["uy"])
    times = np.linspace(0.0, end, 11)
    s.add_curve("stretch", time=times.tolist(), value=np.exp(RATE * times).tolist())
    s.add_curve("narrow", time=times.tolist(), value=np.exp(-0.5 * RATE * times).tolist())
    s.add_prescribe("strip", box=[[SIZE - 1e-6, lo, -1.0], [hi, hi, 1.0]], dof="ux", value=RATE * SIZE,
                    curve="stretch")
    s.add_prescribe("strip", box=[[lo, SIZE - 1e-6, -1.0], [hi, hi, 1.0]], dof="uy", value=-0.5 * RATE * SIZE,
                    curve="narrow")
    spin = 0.5 * RATE * SIZE / T if bend else 0.0   # each end turns at half the curvature rate times SIZE
    s.add_prescribe("strip", box=[[SIZE - 1e-6, lo, -1.0], [hi, hi, 1.0]], dof="ry", value=spin)
    s.add_prescribe("strip", box=[[lo, lo, -1.0], [1e-6, hi, 1.0]], dof="ry", value=-spin)
    return s


def _history(folder: Path) -> dict[str, np.ndarray]:
    with h5py.File(folder / "results.h5") as f:
        return {k: f["history"][k][()] for k in f["history"]}


def _frames(folder: Path) -> dict[str, np.ndarray]:
    with h5py.File(folder / "results.h5") as f:
        return {k: f["frames"][k][()] for k in ("time", "element_layer_stress", "element_membrane_stress")}


def _erosion_time(h: dict[str, np.ndarray]) -> float:
    eroded = h["eroded_elements"]
    assert eroded[-1] == 1.0, "the strip did not erode"
    return float(h["time"][int(np.argmax(eroded > 0))])


@pytest.mark.parametrize("element", ["blt", "full"])
def test_the_bent_strip_lives_until_its_third_layer_fails(tmp_path: Path, element: str) -> None:
    """NUMFIP 3: the strip erodes when its mid-surface point (the third from the top) fails, at
    t_f = (FAIL + sigma_y / E) / D within 0.5 %; NUMFIP 1 erodes it when the outer point fails,
    at t_f / 1.48 (within 3 %: that point's path is not uniaxial), and NUMFIP 2 in between. With
    NUMFIP 3, from the outer point's failure on the top layer's stress is zero while the element
    lives, and the membrane force drops in that step by the outer point's share w_1 sigma_1 / 2
    (sigma_1 its stress just before) within 0.5 %; the energy balance stays within 0.5 % of the work.
    The same with the fully integrated element (its 4 in-plane points have the same path here)."""
    times = {}
    for numfip in (1.0, 2.0, 3.0):
        paradyn.run(_bent_strip(numfip, element=element), tmp_path / f"n{numfip:g}", ranks=1, threads=1, post=False)
        times[numfip] = _erosion_time(_history(tmp_path / f"n{numfip:g}"))
    assert times[3.0] == pytest.approx(T_FAIL, rel=0.005)
    assert times[1.0] == pytest.approx(T_FAIL / 1.476, rel=0.03)
    assert times[1.0] < times[2.0] < times[3.0]
    frames = _frames(tmp_path / "n3")
    top = frames["element_layer_stress"][:, 0, 2, 0]       # sxx of the outermost point, normal side
    alive = frames["time"] < times[3.0]
    dead_top = alive & (frames["time"] >= times[1.0])
    assert dead_top.sum() > 50
    assert np.all(top[dead_top] == 0.0) and np.all(frames["element_layer_stress"][dead_top, 0, 1, 0] > 0.5 * YIELD)
    first = int(np.argmax((top == 0.0) & (np.cumsum(top > 0.0) > 0)))   # the first zero after yielding
    assert top[first - 1] > 0.9 * YIELD
    _, weight = K.thickness_points(5)
    membrane = frames["element_membrane_stress"][:, 0, 0]   # N / t
    drop = membrane[first - 1] - membrane[first]
    assert drop == pytest.approx(0.5 * weight.min() * top[first - 1], rel=0.005)
    h = _history(tmp_path / "n3")
    balance = h["external_work"] - h["internal_energy"] - h["kinetic_energy"]
    assert np.abs(balance).max() < 0.005 * h["external_work"][-1]


def test_uniaxial_strip_erodes_in_the_same_step_with_numfip_all_layers(tmp_path: Path) -> None:
    """Stretched without bending, every point has the same strain path and fails in the same step,
    so NUMFIP = nip (and -100 %) erodes the strip in the step NUMFIP 1 does: the histories agree
    bit for bit."""
    def run(numfip: float) -> dict[str, np.ndarray]:
        paradyn.run(_bent_strip(numfip, frames=20, nip=3, bend=False), tmp_path / f"u{numfip:g}", ranks=1, threads=1,
                    post=False)
        return _history(tmp_path / f"u{numfip:g}")
    one = run(1.0)
    assert _erosion_time(one) == pytest.approx(T_FAIL, rel=0.005)
    for numfip in (3.0, -100.0):
        other = run(numfip)
        for key in ("eroded_elements", "internal_energy", "external_work", "kinetic_energy"):
            assert np.array_equal(one[key], other[key]), (numfip, key)


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


@pytest.mark.parametrize("ranks", [1, pytest.param(2, marks=pytest.mark.mpi)])
def test_restart_and_ranks_keep_failed_points_bitwise(tmp_path: Path, ranks: int) -> None:
    """A 4 x 2 bent strip with NUMFIP 3 (failed points in living elements before the checkpoint,
    erosions after it): restarted from its checkpoint on 1 and 2 ranks, and run whole on 2, it
    gives the displacements, layer stresses and eroded count of the uninterrupted one-rank run bit
    for bit (its internal energy to round-off on 2 ranks, summed per rank)."""
    end = 1.1 * T_FAIL
    model = _bent_strip(3.0, end=end, frames=8, mesh=(4, 2)).build()
    reference = _run(model, tmp_path / "plain")
    with h5py.File(reference) as f:
        assert f["history/eroded_elements"][-1] > 0
        half = f["frames/element_layer_stress"][4]         # the frame at the checkpoint's time
        assert np.any(half[:, 2, 0] == 0.0) and np.all(f["history/eroded_elements"][:len(f["history/time"]) // 2] == 0)
    model.control.checkpoint_interval = end / 2
    folder = tmp_path / "checkpointed"
    results = _run(model, folder)
    target = folder / f"restart{ranks}.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / f"restart{ranks}.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, ranks, 1, restart=True)
    keys = ("frames/displacement", "frames/element_layer_stress", "history/eroded_elements")

    def same(one: h5py.File, two: h5py.File) -> None:
        for key in keys:
            assert np.array_equal(one[key][:], two[key][:]), key
        # the energies are summed per rank, then over the ranks: round-off apart (tests/test_parallel.py)
        energy = one["history/internal_energy"][:]
        np.testing.assert_allclose(two["history/internal_energy"][:], energy, rtol=0.0, atol=1e-13 * energy.max())

    with h5py.File(reference) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        same(one, two)
    if ranks == 2:
        with h5py.File(reference) as one, h5py.File(_run(model, tmp_path / "two", 2)) as two:
            same(one, two)


# --- the keyword deck ---------------------------------------------------------------------------

DECK = """*KEYWORD
*CONTROL_TERMINATION
     1e-4
{material}*SECTION_SHELL
         1         2       1.0         5
     0.001     0.001     0.001     0.001
*PART
strip
         1         1         1
*NODE
       1             0.0             0.0             0.0
       2            0.01             0.0             0.0
       3            0.01            0.01             0.0
       4             0.0            0.01             0.0
*ELEMENT_SHELL
       1       1       1       2       3       4
*END
"""
MAT24 = """*MAT_PIECEWISE_LINEAR_PLASTICITY
         1    7850.0   2.1E+11       0.3   2.5E+08       0.0      0.08
*MAT_ADD_EROSION
$      MID      EXCL    MXPRES     MNEPS    EFFEPS    VOLEPS    NUMFIP       NCS
         1       0.0       0.0       0.0     -0.05       0.0     -60.0       1.0
"""
MAT3 = """*MAT_PLASTIC_KINEMATIC
         1    7850.0   2.1E+11       0.3   2.5E+08       0.0       1.0
       0.0       0.0       0.0
*MAT_ADD_EROSION_TITLE
with a pressure criterion
         1       0.0     1.0E9       0.0      0.04       0.0       2.0
"""


def _read_deck(tmp_path: Path, material: str) -> tuple[paradyn.deck.Model, list[str]]:
    from paradyn.keyword.scene import load_keyword

    path = tmp_path / "deck.k"
    path.write_text(DECK.format(material=material))
    read = load_keyword(path)
    return read.model, read.warnings


def test_mat_add_erosion_reads_effeps_and_numfip(tmp_path: Path) -> None:
    """*MAT_ADD_EROSION (LS-DYNA card 1 MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS): on MAT 24,
    EFFEPS -0.05 (the plastic strain exactly) is below FAIL 0.08, so the failure strain is 0.05, and
    NUMFIP -60 stays a percentage (3 of 5 layers in the engine), with no warning. On MAT 3 (_TITLE):
    EFFEPS 0.04 > 0 (LS-DYNA's total strain, read as the plastic one) is warned, NUMFIP 2 read, and
    MXPRES named as a criterion that is not modelled. An erosion card for a material no *MAT
    defines is warned."""
    model, warnings = _read_deck(tmp_path, MAT24)
    assert model.failure_strain.tolist() == [0.05] and model.failure_points.tolist() == [-60.0]
    assert not any("EROSION" in w for w in warnings), warnings
    assert K.erosion_layers_needed(-60.0, 5) == 3
    model, warnings = _read_deck(tmp_path, MAT3)
    assert model.failure_strain.tolist() == [0.04] and model.failure_points.tolist() == [2.0]
    text = "\n".join(warnings)
    assert "MXPRES = 1000000000.0 (maximum pressure at failure) is not modelled" in text, text
    assert "EFFEPS = 0.04 is LS-DYNA's effective total strain" in text, text
    _, warnings = _read_deck(tmp_path, MAT24 + "*MAT_ADD_EROSION\n         7       0.0       0.0       0.0      -0.1\n")
    assert any("*MAT_ADD_EROSION names material 7, which no *MAT defines" in w for w in warnings), warnings
