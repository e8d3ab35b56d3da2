"""The current shell thickness of the frames (`/frames/element_thickness`, docs/theory.md "Shell
thickness"; LS-DYNA's d3plot thickness with ISTUPD = 1): t = t0 exp(eps_z), eps_z = -ln(A/A0) +
(1 - 2 nu)/E (sxx + syy) from the element's mid-surface area and mid-surface stress. An output only:
the element keeps t0 in its forces.

References (plane stress, isotropic elasticity, volume-keeping J2 flow: Hooke's law, e.g.
Timoshenko & Goodier, Theory of Elasticity, ch. 1; the Prandtl-Reuss relations, Hill, The
Mathematical Theory of Plasticity, 1950, ch. II):

- uniaxial elastic stress sigma: eps_z = -nu sigma / E (Hooke's law);
- uniaxial plastic flow to the effective plastic strain eps_p: the plastic strain increments are
  (1, -1/2, -1/2) d eps_p (incompressible, isotropic), so eps_z = -eps_p / 2 - nu sigma / E;
- a rigid motion strains nothing: t = t0.

The plate and the strip run through the whole engine for the one-point, fully integrated and
triangle elements; the rigid motion through the kernel (exact finite rotations) and the engine (a
translating plate, a spinning rigid plate).
"""

from __future__ import annotations

import shutil

import h5py
import numpy as np
import pytest

import models as M
import paradyn
from paradyn import _kernels as K
from paradyn._schema import ENUMS
from paradyn.deck import Control
from paradyn.results import write_vtk_series
from paradyn.results.vtkhdf_export import write_vtkhdf
from rigid_cases import THICKNESS, spinning_plate

STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)
ELEMENTS = ["blt", "full", "triangle"]


def _triangles(mesh):
    """Each quadrilateral split into two triangles (corner 4 = corner 3)."""
    quads = mesh.quads
    return type(mesh)(coordinates=mesh.coordinates, quads=np.concatenate([quads[:, [0, 1, 2, 2]],
                                                                          quads[:, [0, 2, 3, 3]]]))


def _pulled(mesh, thickness: float, control: Control, element: str, displacement: float, ramp: float):
    """The strip held at x = 0 (ux; uy at one node), uz and the rotations held everywhere, its
    lateral edges free, and its x = max edge moved along x by `displacement` at the velocity
    (displacement / ramp) (1 - cos(2 pi t / ramp)) over [0, ramp], then held: a slow, smooth stretch."""
    length = float(mesh.coordinates[:, 0].max())
    root, end = M.nodes_at(mesh, 0, 0.0), M.nodes_at(mesh, 0, length)
    fixed = {int(n): (0, 0, 1, 1, 1, 1) for n in range(mesh.n_nodes)}
    for n in root:
        fixed[int(n)] = (1, 0, 1, 1, 1, 1)
    fixed[int(root[0])] = M.ALL_DOFS
    mesh = _triangles(mesh) if element == "triangle" else mesh
    model = M.shell_model(mesh, thickness, STEEL, control, fixed=fixed, integration_points=3,
                          element="blt" if element == "triangle" else element)
    time = np.linspace(0.0, ramp, 41)
    model.curve_first_point = np.array([0], dtype=np.int32)
    model.curve_time = np.append(time, 2.0 * ramp)
    model.curve_value = np.append(1.0 - np.cos(2.0 * np.pi * time / ramp), 0.0)
    model.prescribed_node = np.asarray(end, dtype=np.int32)
    model.prescribed_dof = np.full(len(end), 1, dtype=np.int32)
    model.prescribed_value = np.full(len(end), displacement / ramp)
    model.prescribed_curve = np.zeros(len(end), dtype=np.int32)
    return model


def _elastic_plate(element: str, directory) -> tuple[M.Run, float, float]:
    """The plate of the elastic test, pulled to the strain 1e-3 and at rest: the run, t0, sigma."""
    length, width, t0, strain = 0.1, 0.05, 0.002, 1.0e-3
    period = 4.0 * length / STEEL.bar_wave_speed
    ramp, end = 10.0 * period, 16.0 * period
    control = Control(end_time=end, output_interval=end / 4, history_interval=end / 20,
                      mass_damping=2.0 * (2.0 * np.pi / period))
    model = _pulled(M.strip(length, width, 4, 2), t0, control, element, strain * length, ramp)
    return M.run(model, directory), t0, STEEL.young * np.log1p(strain)


def _plastic_strip(element: str, directory, material: str = "j2_plasticity") -> tuple[M.Run, float]:
    """The strip of the plastic test, pulled by 10.7 %: the run and t0."""
    length, width, t0, stretch = 0.05, 0.01, 0.001, 0.107
    period = 4.0 * length / STEEL.bar_wave_speed
    ramp = 100.0 * period   # about 4e-3 s: a mean strain rate of 25 1/s
    control = Control(end_time=ramp, output_interval=ramp / 4, history_interval=ramp / 20)
    model = _pulled(M.strip(length, width, 5, 1), t0, control, element, stretch * length, ramp)
    model.material_model = np.array([ENUMS["material_model"][material]])
    model.yield_stress, model.tangent_modulus, model.hardening_mixing = [250.0e6], [1.0e9], [1.0]
    if material == "piecewise_linear":
        model.hardening_curve, model.rate_curve = [-1], [-1]   # the bilinear law, no rate effect
    model.normalise()
    return M.run(model, directory), t0


def _principal(stress: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The larger and smaller principal values of (n, 3) plane stresses (sxx, syy, sxy)."""
    mean = 0.5 * (stress[:, 0] + stress[:, 1])
    radius = np.hypot(0.5 * (stress[:, 0] - stress[:, 1]), stress[:, 2])
    return mean + radius, mean - radius


@pytest.mark.parametrize("element", ELEMENTS)
def test_uniaxial_elastic_stress_thins_by_nu_sigma_over_e(element: str, tmp_path) -> None:
    """A 0.1 x 0.05 m steel plate, 2 mm thick, 4 x 2 elements, pulled slowly (10 periods of its
    axial mode) to the strain 1e-3 along x with free lateral edges, then held and damped to rest:
    uniaxial stress sigma = E ln(1 + u / L); every element's eps_z = ln(t / t0) is -nu sigma / E
    within 1 % (Hooke's law). Without the elastic term (1 - 2 nu)/E (sxx + syy) it would be
    -(1 - nu) sigma / E, 2.3 times as large; a constant thickness gives 0."""
    run, t0, sigma = _elastic_plate(element, tmp_path)
    frame = run.results.frame_arrays(-1)
    largest, smallest = _principal(frame.membrane_stress)
    np.testing.assert_allclose(largest, sigma, rtol=0.01)        # the stress is the uniaxial one
    assert np.abs(smallest).max() < 0.01 * sigma
    np.testing.assert_allclose(np.log(frame.thickness / t0), -STEEL.poisson * sigma / STEEL.young, rtol=0.01)


@pytest.mark.parametrize(("element", "material"), [*((e, "j2_plasticity") for e in ELEMENTS),
                                                   ("blt", "piecewise_linear")])
def test_uniaxial_plastic_flow_thins_by_half_the_plastic_strain(element: str, material: str, tmp_path) -> None:
    """A 0.05 x 0.01 m J2 strip (yield 250 MPa, tangent modulus 1 GPa, isotropic; j2_plasticity, and
    LS-DYNA's MAT 24 piecewise_linear with the same bilinear law), 1 mm thick,
    5 x 1 elements, pulled by 10.7 % along x at about 25 1/s, lateral edges free: every element
    reaches an effective plastic strain eps_p of about 10 % in uniaxial stress sigma (its other
    principal stress below 2 % of it), and its thickness is t0 exp(-eps_p / 2 - nu sigma / E):
    ln(t / t0) within 1 % (t / t0 within 0.05 %)."""
    run, t0 = _plastic_strip(element, tmp_path, material)
    frame = run.results.frame_arrays(-1)
    sigma, smallest = _principal(frame.membrane_stress)
    assert np.abs(smallest).max() < 0.02 * sigma.min()
    assert frame.plastic_strain.min() > 0.095 and frame.plastic_strain.max() < 0.105
    expected = -0.5 * frame.plastic_strain - STEEL.poisson * sigma / STEEL.young
    np.testing.assert_allclose(np.log(frame.thickness / t0), expected, rtol=0.01)
    np.testing.assert_allclose(frame.thickness / t0, np.exp(expected), rtol=5e-4)


def _rotation(axis, angle: float) -> np.ndarray:
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_kernel_rigid_motion_keeps_t0_and_a_stretch_is_the_formula() -> None:
    """The kernel (shell_field_measures' current_thicknesses) on a warped quadrilateral and a
    triangle: turned by 2.1 rad about a skew axis and moved, unstressed, t = t0 to 1e-12; stretched
    by (1.2, 0.9) in its plane, then turned and moved, with sxx + syy = s, t = t0 exp(-ln(1.08) +
    (1 - 2 nu) s / E) to 1e-13."""
    t0, s = 0.003, 4.0e8
    quad = np.array([[0.0, 0.0, 0.0], [0.02, 0.001, 0.0004], [0.023, 0.015, -0.0003], [-0.001, 0.012, 0.0002]])
    triangle = quad[[0, 1, 2, 2]]
    stretch = np.diag([1.2, 0.9, 1.0])
    turn, shift = _rotation([1.0, -2.0, 0.5], 2.1), np.array([1.5, -0.7, 3.0])
    flat = np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0], [0.022, 0.015, 0.0], [0.0, 0.012, 0.0]])
    x0 = np.stack([quad, triangle, flat, flat[[0, 1, 2, 2]]])
    x = np.stack([quad @ turn.T + shift, triangle @ turn.T + shift,
                  flat @ stretch.T @ turn.T + shift, (flat @ stretch.T @ turn.T + shift)[[0, 1, 2, 2]]])
    trace = np.array([0.0, 0.0, s, s])
    t = K.shell_current_thicknesses(np.asfortranarray(x0.transpose(0, 2, 1)), np.asfortranarray(x.transpose(0, 2, 1)),
                                    t0, STEEL.young, STEEL.poisson, trace)
    np.testing.assert_allclose(t[:2], t0, rtol=1e-12, atol=0)
    expected = t0 * np.exp(-np.log(1.2 * 0.9) + (1 - 2 * STEEL.poisson) * s / STEEL.young)
    np.testing.assert_allclose(t[2:], expected, rtol=1e-13, atol=0)


@pytest.mark.parametrize("element", ELEMENTS)
def test_translating_tilted_plate_keeps_t0(element: str, tmp_path) -> None:
    """An unstressed 0.04 x 0.02 m plate turned by 0.8 rad about a skew axis and flying at
    (30, -20, 10) m/s for 400 steps, no support: every frame's thickness is t0 to 1e-12."""
    mesh = M.strip(0.04, 0.02, 4, 2)
    mesh = type(mesh)(coordinates=mesh.coordinates @ _rotation([1.0, 1.0, 2.0], 0.8).T, quads=mesh.quads)
    mesh = _triangles(mesh) if element == "triangle" else mesh
    end = 400 * M.stable_time_step(mesh, STEEL)
    control = Control(end_time=end, output_interval=end / 4)
    velocity = np.tile([30.0, -20.0, 10.0], (mesh.n_nodes, 1))
    model = M.shell_model(mesh, 0.002, STEEL, control, velocity=velocity,
                          element="blt" if element == "triangle" else element)
    res = M.run(model, tmp_path).results
    thickness = np.asarray(res.thickness.read_all())
    assert thickness.shape == (5, mesh.n_elements)
    np.testing.assert_allclose(thickness, 0.002, rtol=1e-12, atol=0)


def test_spinning_rigid_plate_keeps_t0(tmp_path) -> None:
    """A rigid part (LS-DYNA MAT 20; tests/rigid_cases.py) spinning at about 100 rad/s about a skew
    axis and moving: its thickness is t0 in every frame, exactly (a rigid body does not deform)."""
    model = spinning_plate(2.0e-3, (33.0, 67.0, 67.0), velocity=(5.0, 0.0, 0.0))
    res = M.run(model, tmp_path).results
    assert np.abs(res.displacement[-1]).max() > 1e-2   # it moved and turned
    assert np.all(np.asarray(res.thickness.read_all()) == THICKNESS)


def test_thickness_in_the_vtu_series_and_vtkhdf_and_older_files(tmp_path) -> None:
    """The stretched elastic plate's thickness reaches the .vtu series (read by pyvista's reader of
    the .pvd) and results.vtkhdf (pyvista.get_reader, every step) as paradyn.read has it, bit for
    bit. A results.h5 written before the field (/frames/element_thickness removed) reads as
    /mesh/thickness in every frame, the thickness the engine kept then, and its results.vtkhdf
    has no thickness array."""
    import pyvista

    run, t0, _ = _elastic_plate("blt", tmp_path / "run")
    res = run.results
    thickness = np.asarray(res.thickness.read_all())
    assert np.all(thickness[0] == t0)   # the start
    assert np.all(thickness[-1] < t0) and np.all(thickness[-1] > 0.999 * t0)   # thinned by nu sigma / E
    pvd = write_vtk_series(res, tmp_path / "series")[0]
    reader = pyvista.get_reader(pvd)
    for k, time in enumerate(reader.time_values):
        reader.set_active_time_value(time)
        grid = reader.read()[0]
        assert np.array_equal(grid.cell_data["thickness"], thickness[k, grid.cell_data["element_id"]])
    reader = pyvista.get_reader(write_vtkhdf(res, tmp_path / "results.vtkhdf"))
    for k in range(res.n_frames):
        reader.set_active_time_point(k)
        assert np.array_equal(reader.read().cell_data["thickness"], thickness[k])
    older = tmp_path / "older" / "results.h5"
    older.parent.mkdir()
    shutil.copy(res.path, older)
    with h5py.File(older, "a") as h5:
        del h5["/frames/element_thickness"]
    old = paradyn.read(older)
    assert np.array_equal(np.asarray(old.thickness.read_all()), np.full(thickness.shape, t0))
    assert np.array_equal(old.frame_arrays(-1).thickness, np.full(res.n_elements, t0))
    assert "thickness" not in pyvista.read(write_vtkhdf(old, tmp_path / "older.vtkhdf")).cell_data
