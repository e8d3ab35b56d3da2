"""The thickness update (``[[part]] thickness_update``, /parts/thickness_update; LS-DYNA's *CONTROL_SHELL
ISTUPD = 1, OpenRadioss's Ithick = 1; docs/theory.md, "Thickness update"): the element's forces use
its current thickness t, a state updated each step from the thickness strain rate.

Reference (plane stress, isotropic elasticity, volume-keeping J2 flow: the Prandtl-Reuss relations,
Hill, The Mathematical Theory of Plasticity, 1950, ch. II). A strip in uniaxial tension sigma with
effective plastic strain eps_p has the lateral and thickness strains

    eps_y = eps_z = -eps_p / 2 - nu sigma / E,

so its width is w0 exp(eps_y) and its thickness t0 exp(eps_z), and the axial force that holds it is

    F = sigma(eps_p) w0 t0 exp(-eps_p - 2 nu sigma / E)            (thickness updated),
    F = sigma(eps_p) w0 t0 exp(-eps_p / 2 - nu sigma / E)          (t0 kept: the width alone),

sigma(eps_p) = sigma_y + H eps_p the linear isotropic hardening (H = E Et / (E - Et)). A 0.05 x
0.01 m strip, 1 mm, 5 x 1 one-point elements, pulled by a slowly ramped end force F = 3170 N and
held (mass damping), reaches eps_p of about 10 %; the two laws then differ by 5 %.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.running import launch
from paradyn.scene import SceneError

E, NU, RHO = 200.0e9, 0.3, 7850.0
YIELD, TANGENT = 250.0e6, 1.0e9
H = E * TANGENT / (E - TANGENT)
LENGTH, WIDTH, T0 = 0.05, 0.01, 1.0e-3
FORCE = 3170.0
RAMP, END = 4.0e-3, 6.0e-3


def _strip(update: bool, end: float = END) -> paradyn.Scene:
    s = paradyn.Scene("strip", end_time=end, output_interval=end / 4, history_interval=end / 40, mass_damping=2.0e4)
    s.add_material("steel", model="j2_plasticity", density=RHO, youngs_modulus=E, poisson_ratio=NU,
                   yield_stress=YIELD, tangent_modulus=TANGENT, hardening_mixing=1.0)
    s.add_part("strip", material="steel", thickness=T0, integration_points=3, thickness_update=update,
               geometry=paradyn.Plate((LENGTH, WIDTH), (5, 1)))
    s.add_fix("strip", box=[[-1, -1, -1], [1, 1, 1]], dofs=["uz", "rotations"])
    s.add_fix("strip", box=[[-1e-6, -1, -1], [1e-6, 1, 1]], dofs=["ux"])
    s.add_fix("strip", box=[[-1e-6, -1e-6, -1], [1e-6, 1e-6, 1]], dofs=["uy"])
    for y in (0.0, WIDTH):
        s.add_load("strip", point=[LENGTH, y, 0.0], dof="ux", value=0.5 * FORCE, ramp_time=RAMP)
    return s


def _predicted_force(res: paradyn.Results, update: bool) -> np.ndarray:
    """Each element's F from its own plastic strain (the two laws of the module docstring)."""
    eps_p = np.asarray(res.frame_arrays(-1).plastic_strain)
    sigma = YIELD + H * eps_p
    squeeze = -eps_p - 2.0 * NU * sigma / E if update else -0.5 * eps_p - NU * sigma / E
    return sigma * WIDTH * T0 * np.exp(squeeze)


@pytest.mark.parametrize("update", [True, False], ids=["updated", "t0"])
def test_a_pulled_strip_carries_its_force_on_the_current_section(tmp_path: Path, update: bool) -> None:
    res = paradyn.run(_strip(update), tmp_path, ranks=1, threads=1, post=False)
    frame = res.frame_arrays(-1)
    eps_p = np.asarray(frame.plastic_strain)
    assert eps_p.min() > 0.05 and np.ptp(eps_p) < 0.02 * eps_p.mean()   # past yield, about uniform
    np.testing.assert_allclose(_predicted_force(res, update), FORCE, rtol=2e-3)
    other = _predicted_force(res, not update)
    assert np.all(np.abs(other / FORCE - 1.0) > 0.03)   # the other law is told apart
    if update:   # the frames report the thickness the forces use: the Prandtl-Reuss thinning
        sigma = YIELD + H * eps_p
        np.testing.assert_allclose(np.asarray(frame.thickness), T0 * np.exp(-0.5 * eps_p - NU * sigma / E), rtol=1e-3)


def test_restart_keeps_the_thickness_bitwise(tmp_path: Path) -> None:
    """The thickness is element state: a run restarted from its checkpoint (at 0.7 of it, on 1 rank)
    gives the uninterrupted run's frames bit for bit, the thickness with them."""
    end = END
    model = _strip(True, end).build()
    plain, folder = tmp_path / "plain", tmp_path / "checkpointed"
    for where in (plain, folder):
        where.mkdir()
    paradyn.deck.write_deck(model, plain / "deck.h5")
    launch.run_engine(plain / "deck.h5", plain / "results.h5", 1, 1)
    model.control.checkpoint_interval = 0.7 * end   # in the plastic flow after the ramp
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", 1, 1)
    target = folder / "restart.h5"
    shutil.copy(folder / "results.h5", target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / "restart.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, 1, 1, restart=True)
    with h5py.File(plain / "results.h5") as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        assert one["frames/element_thickness"][3].max() < 0.99 * T0   # thinned soon after the checkpoint
        for key in ("frames/displacement", "frames/element_thickness", "frames/element_membrane_stress"):
            assert np.array_equal(one[key][:], two[key][:]), key


@pytest.mark.parametrize(("options", "why"), [({"element": "full"}, "full"), ({}, "triangles")])
def test_the_update_is_the_one_point_quadrilaterals(tmp_path: Path, options: dict, why: str) -> None:
    """A fully integrated part, or one with triangles, is refused with a message naming the part."""
    s = _strip(True)
    if why == "triangles":
        mesh = paradyn.mesh.geometry.plate((LENGTH, WIDTH), (5, 1))
        quads = mesh.quads.copy()
        quads[0] = [quads[0][0], quads[0][1], quads[0][2], quads[0][2]]
        s = paradyn.Scene("s", end_time=1e-4, output_interval=1e-4)
        s.add_material("steel", model="elastic", density=RHO, youngs_modulus=E, poisson_ratio=NU)
        path = tmp_path / "strip.msh"
        _write_msh(path, mesh.coordinates, quads)
        s.add_part("strip", material="steel", thickness=T0, thickness_update=True, geometry=paradyn.MeshFile(path))
    else:
        s.add_part("other", material="steel", thickness=T0, thickness_update=True, **options,
                   geometry=paradyn.Plate((LENGTH, WIDTH), (5, 1), origin=(0.0, 0.1, 0.0)))
    with pytest.raises(SceneError, match=f"thickness_update = true, but .*{why}"):
        s.build()


def _write_msh(path: Path, coordinates: np.ndarray, quads: np.ndarray) -> None:
    import meshio
    triangles = quads[quads[:, 2] == quads[:, 3]][:, :3]
    cells = [("quad", quads[quads[:, 2] != quads[:, 3]]), ("triangle", triangles)]
    meshio.write(str(path), meshio.Mesh(coordinates, cells), file_format="gmsh22", binary=False)


def test_the_study_knob_and_the_keyword(tmp_path: Path) -> None:
    """Knob thickness_update sets every part; *CONTROL_SHELL ISTUPD = 1 sets a one-point part's."""
    from paradyn.keyword.scene import load_keyword
    from paradyn.studies.design import KNOBS
    from test_keyword import HEAD, MESH, _deck

    scene = paradyn.scene.load_scene(Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml")
    assert KNOBS["thickness_update"].base(scene) is False
    KNOBS["thickness_update"].apply(scene, True)
    assert [p.thickness_update for p in scene.parts] == [True, True]
    assert list(paradyn.scene.build_model(scene).thickness_update) == [1, 1]
    shell = "*CONTROL_SHELL\n      20.0         0        -1         1         2         2         1         0\n"
    read = load_keyword(_deck(tmp_path, HEAD + MESH + shell + "*END\n"))
    assert read.model.thickness_update.tolist() == [1]
    read = load_keyword(_deck(tmp_path, HEAD + MESH + shell.replace("        -1         1", "        -1         0")
                              + "*END\n"))
    assert read.model.thickness_update is None or read.model.thickness_update.tolist() == [0]
