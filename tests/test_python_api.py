"""Issue 18, items 1 and 6: scenes built in Python (``paradyn.Scene``), checked by the scene file's
reader; ``paradyn.run(scene)``; the Results of a pyvista or pandas user (``to_pyvista``,
``to_dataframe``, ``plot``); ``results.vtkhdf``; the deformed picture's displacement factor."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import paradyn
from paradyn import scene
from paradyn.results import figures, rendering
from paradyn.results.vtkhdf_export import read_step, write_vtkhdf

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def small_plate() -> paradyn.Scene:
    """cases/small_plate/scene.toml, written in Python."""
    s = paradyn.Scene("Small cantilever plate", end_time=2e-4, output_interval=2e-5, history_interval=2e-6,
                      time_step_safety=0.9)
    s.add_material("steel", model="elastic", density=7860.0, youngs_modulus=200e9, poisson_ratio=0.3)
    s.add_part("plate", material="steel", thickness=0.002, initial_velocity=np.array([0.0, 0.0, 1.0]),
               geometry=paradyn.Plate(size=(0.2, 0.1), elements=(np.int64(8), 4), origin=(0.0, 0.0, 0.0)))
    s.add_fix("plate", box=[[-1e-6, -1e-6, -1e-6], [1e-6, 0.100001, 1e-6]], dofs=["all"])
    s.add_load("plate", point=[0.2, 0.1, 0.0], dof="uz", value=-20.0, ramp_time=5e-5)
    for name, point in (("tip_corner", [0.2, 0.1, 0.0]), ("tip_middle", [0.2, 0.05, 0.0]),
                        ("middle", [0.1, 0.05, 0.0])):
        s.add_track(name, part="plate", point=point)
    return s


def _same_scene(a: scene.Scene, b: scene.Scene) -> bool:
    return dataclasses.replace(a, path=b.path) == b


# ---- building and checking ----------------------------------------------------------------------


def test_scene_built_in_python_is_the_case_file() -> None:
    assert _same_scene(small_plate().validate(), scene.load_scene(SMALL_PLATE))


def test_to_toml_reads_back_to_the_same_scene(tmp_path: Path) -> None:
    s = small_plate()
    s.add_part("pipe", material="steel", thickness=0.001, geometry=paradyn.Cylinder(0.05, 0.3, elements_around=8))
    s.add_contact("plate", "pipe", static_friction=0.2)
    s.add_contact("pipe", kind="single_surface")
    s.add_contact(kind="single_surface")   # every part
    s.add_curve("pulse", time=(0.0, 1e-4), value=[1.0, 0.0])
    s.add_pressure("pipe", value=1e5, curve="pulse")
    s.add_rigid_wall(point=[0.0, 0.0, -1.0], normal=[0.0, 0.0, 1.0])
    path = s.to_toml(tmp_path / "scene.toml")
    assert _same_scene(scene.load_scene(path), s.validate())
    assert tomllib.loads(path.read_text()) == s.to_dict()
    assert paradyn.Scene.from_toml(path).to_dict() == s.to_dict()


@pytest.mark.parametrize(("call", "message"), [
    (lambda s: s.add_part("p2", material="steel", thickness=0.0, geometry=paradyn.Plate((1, 1), (2, 2))),
     r"'thickness' in \[\[part\]\] #2 'p2' must be > 0, got 0.0"),
    (lambda s: s.add_part("p2", material="steel", thickness=0.1, geometry=paradyn.Plate((1, 1), (2, 2)), colour=1),
     r"unknown key 'colour' in \[\[part\]\] #2 'p2'; allowed keys are: name, material"),
    (lambda s: s.add_part("p2", material="steel", thickness=0.1, geometry=paradyn.Cylinder(1, 1, elements_around=6)),
     r"'elements_around' in \[part.geometry\] of part 'p2' must be a multiple of 4, got 6"),
    (lambda s: s.add_material("m", model="elastic", density=1.0, youngs_modulus=1.0, poisson_ratio=0.5),
     r"'poisson_ratio' in \[\[material\]\] #2 'm' = 0.5 must be in \(-1, 0.5\)"),
    (lambda s: s.add_load("plate", point=[0, 0, 0], dof="uw", value=1.0),
     r"'dof' = 'uw' in \[\[load\]\] #2 is not one of: ux"),
    (lambda s: s.add_track("t", part="plate", point=[0.0, 0.0]),
     r"'point' in \[\[track\]\] #4 't' must be a list of 3 finite numbers"),
])
def test_each_entry_is_checked_when_added_naming_the_key(call, message: str) -> None:
    s = small_plate()
    before = s.to_dict()
    with pytest.raises(scene.SceneError, match=r"^paradyn.Scene 'Small cantilever plate': " + message):
        call(s)
    assert s.to_dict() == before  # a refused entry is not kept


def test_run_settings_are_checked_and_references_at_validate() -> None:
    with pytest.raises(scene.SceneError, match=r"'end_time' in \[run\] must be > 0, got -1"):
        paradyn.Scene(end_time=-1, output_interval=1e-5)
    with pytest.raises(scene.SceneError, match=r"unknown key 'end' in \[run\]"):
        paradyn.Scene(end_time=1e-3, output_interval=1e-5, end=2)
    s = small_plate()
    s.add_contact("plate", "wall")
    with pytest.raises(scene.SceneError, match=r"\[\[contact\]\] #1 names part 'wall', which is not defined"):
        s.validate()
    with pytest.raises(scene.SceneError, match="which is not defined"):
        s.to_toml("never_written.toml")
    assert not Path("never_written.toml").exists()


# ---- running and reading --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def plate(tmp_path_factory: pytest.TempPathFactory) -> paradyn.Results:
    return paradyn.run(small_plate(), tmp_path_factory.mktemp("plate"), ranks=1, threads=1, plots=False)


def test_run_of_a_python_scene_equals_the_run_of_its_file(plate: paradyn.Results, tmp_path: Path) -> None:
    from_file = paradyn.run(SMALL_PLATE, tmp_path, ranks=1, threads=1, post=False)
    assert plate.complete and plate.title == "Small cantilever plate"
    assert_allclose(plate.time_values, from_file.time_values, rtol=0, atol=0)
    assert np.array_equal(plate.displacement[-1], from_file.displacement[-1])


def test_to_pyvista_whole_and_by_part(plate: paradyn.Results) -> None:
    grid = plate.to_pyvista(3)
    arrays = plate.frame_arrays(3)
    assert grid.n_cells == 32 and float(grid.field_data["TimeValue"][0]) == plate.time_values[3]
    assert_allclose(grid.points, plate.coordinates[grid.point_data["node_id"]]
                    + arrays.displacement[grid.point_data["node_id"]])
    blocks = plate.to_pyvista(-1, by_part=True)
    assert blocks.keys() == ["plate"] and blocks["plate"].n_cells == 32
    assert [f.index for f in plate.iter_frames()] == list(range(plate.n_frames))


def test_history_as_dataframe_with_units(plate: paradyn.Results, monkeypatch: pytest.MonkeyPatch) -> None:
    pandas = pytest.importorskip("pandas")
    frame = plate.to_dataframe()
    assert isinstance(frame, pandas.DataFrame)
    table = plate.history_table()
    assert list(frame.columns) == list(table)
    assert_allclose(frame["tip_corner_dz"].to_numpy(), table["tip_corner_dz"], rtol=0, atol=0)
    assert frame.attrs["units"]["time"] == "s" and frame.attrs["units"]["tip_corner_vz"] == "m/s"
    assert frame.attrs["units"]["total_energy"] == "J" and frame.attrs["units"]["dt_element"] == "-"
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if pandas were not installed
    assert isinstance(plate.to_dataframe(), dict)


def test_plot_returns_figures_a_notebook_shows(plate: paradyn.Results, tmp_path: Path) -> None:
    energies = plate.plot()
    assert len(energies.axes[0].lines) == 6   # five energies and the total
    assert len(plate.plot("tracked", component="vz").axes[0].lines) == 3
    deformed = plate.plot("deformed", frame=-1, scalars="von_mises")
    for fig in (energies, deformed):
        assert fig._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"   # what Jupyter shows
    deformed.savefig(tmp_path / "d.png")
    assert (tmp_path / "d.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="choose one of energies, tracked, deformed"):
        plate.plot("stress")


# ---- outputs ------------------------------------------------------------------------------------


def test_vtkhdf_holds_every_frame_with_its_time(plate: paradyn.Results) -> None:
    path = plate.outputs["vtkhdf"]
    assert path.name == "results.vtkhdf"
    for k in range(plate.n_frames):
        grid, arrays = read_step(path, k), plate.frame_arrays(k)
        assert float(grid.field_data["Time"][0]) == plate.time_values[k]
        assert_allclose(grid.points, plate.coordinates + arrays.displacement, rtol=0, atol=0)
        assert_allclose(grid.cell_data["von_mises"], arrays.von_mises, rtol=0, atol=0)
        assert np.array_equal(grid.cell_data["element_id"], np.arange(plate.n_elements))
        assert np.array_equal(grid.cell_data["part"], plate.element_part)
    with pytest.raises(IndexError, match=f"holds {plate.n_frames} steps"):
        read_step(path, plate.n_frames)


def test_pyvista_reads_every_step_of_results_vtkhdf(plate: paradyn.Results) -> None:
    """pyvista's own reader (``pyvista.get_reader``: ParaDyn's VTKHDFReader through its entry point)
    has the time of every frame, and each step holds the frame's positions and fields exactly."""
    import pyvista

    path = plate.outputs["vtkhdf"]
    reader = pyvista.get_reader(path)
    assert isinstance(reader, pyvista.TimeReader)
    assert reader.time_values == [float(t) for t in plate.time_values] and reader.number_time_points == plate.n_frames
    for k in [*range(plate.n_frames), 2]:   # and back to an earlier step
        reader.set_active_time_point(k)
        grid, arrays = reader.read(), plate.frame_arrays(k)
        assert reader.active_time_value == plate.time_values[k]
        assert np.array_equal(grid.point_data["displacement"], arrays.displacement)
        assert np.array_equal(grid.points, plate.coordinates + arrays.displacement)
        for name in ("velocity", "acceleration", "nodal_contact_force"):
            assert np.array_equal(grid.point_data[name], getattr(arrays, name)), name
        for name in ("membrane_stress", "von_mises", "plastic_strain", "membrane_strain", "internal_energy_density",
                     "thickness"):
            assert np.array_equal(grid.cell_data[name], getattr(arrays, name)), name
        assert np.array_equal(grid.cell_data["layer_stress"], arrays.layer_stress.reshape(plate.n_elements, 15))
        assert np.array_equal(grid.cell_data["surface_strain"], arrays.surface_strain.reshape(plate.n_elements, 6))
    reader.set_active_time_value(plate.time_values[-1])
    assert np.array_equal(reader.read().point_data["displacement"], plate.frame_arrays(-1).displacement)
    with pytest.raises(ValueError, match="no step at time"):
        reader.set_active_time_value(1.5 * plate.time_values[-1])
    first = pyvista.read(path)   # pyvista.read: the first step, as for a .pvd series
    assert np.array_equal(first.point_data["displacement"], plate.frame_arrays(0).displacement)


def test_a_vtkhdf_file_without_steps_reads_as_with_pyvistas_reader(tmp_path: Path) -> None:
    """ParaDyn's reader takes every .vtkhdf file in pyvista: one without time steps (here written by
    VTK's own writer through pyvista) reads as pyvista's HDFReader reads it, with no time values."""
    import pyvista

    grid = pyvista.ImageData(dimensions=(3, 4, 5)).cast_to_unstructured_grid()
    grid.point_data["a"] = np.arange(grid.n_points, dtype=float)
    grid.save(tmp_path / "static.vtkhdf")
    reader = pyvista.get_reader(tmp_path / "static.vtkhdf")
    assert reader.time_values == [] and reader.number_time_points == 0
    mine, theirs = reader.read(), pyvista.HDFReader(tmp_path / "static.vtkhdf").read()
    assert np.array_equal(mine.points, theirs.points) and np.array_equal(mine.point_data["a"], grid.point_data["a"])
    sphere = pyvista.Sphere()
    sphere.save(tmp_path / "sphere.vtkhdf")
    assert pyvista.read(tmp_path / "sphere.vtkhdf").n_points == sphere.n_points


def test_vtkhdf_written_a_frame_at_a_time_is_the_same_file(plate: paradyn.Results, tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """The export copies blocks of frames; blocks of one frame must give the same datasets."""
    import h5py

    from paradyn.results import vtkhdf_export

    monkeypatch.setattr(vtkhdf_export, "_BLOCK_BYTES", 1)
    path = write_vtkhdf(plate, tmp_path / "one_by_one.vtkhdf")
    with h5py.File(path, "r") as mine, h5py.File(plate.outputs["vtkhdf"], "r") as whole:
        for name in ("Points", "PointData/displacement", "PointData/velocity", "CellData/von_mises",
                     "CellData/membrane_stress", "CellData/plastic_strain"):
            assert np.array_equal(mine["VTKHDF/" + name][()], whole["VTKHDF/" + name][()]), name


def test_vtkhdf_keeps_parts_apart(tmp_path: Path) -> None:
    from test_results import write_synthetic

    synthetic = write_synthetic(tmp_path)
    results = paradyn.read(synthetic.results)
    path = write_vtkhdf(results, tmp_path / "two.vtkhdf")
    last = read_step(path, results.n_frames - 1)
    assert sorted(set(last.cell_data["part"])) == [0, 1]
    assert np.array_equal(last.cell_data["part"], results.element_part)


@pytest.mark.parametrize(("peak", "factor"), [(1e-3, 100.0), (3e-3, 50.0), (7e-3, 20.0), (0.2, 1.0), (0.0, 1.0)])
def test_displacement_scale_makes_the_largest_one_visible(peak: float, factor: float) -> None:
    """The 2 m long model's diagonal is 2 m: the largest displacement must show as at least 5 %
    of it (0.1 m), with the smallest factor of 1, 2, 5 x 10^k that does it."""
    coordinates = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    displacement = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, peak]])
    assert figures.displacement_scale(coordinates, displacement) == factor
    assert peak == 0.0 or factor == 1.0 or peak * factor >= 0.1 > peak * factor / 2.5


def test_deformed_picture_states_its_factor(plate: paradyn.Results) -> None:
    picture = figures.deformed_picture(plate, -1)
    factor = figures.displacement_scale(plate.coordinates, plate.displacement[-1])
    assert factor > 1.0  # the plate's tip moves a fraction of a millimetre
    assert picture.caption.endswith(f"displacements x {factor:g}")
    assert_allclose(picture.grid.points - plate.coordinates[picture.grid.point_data["node_id"]],
                    factor * picture.grid.point_data["displacement"], atol=1e-12)
    assert figures.deformed_picture(plate, -1, scale=1.0).caption.endswith("true scale")


def test_edges_only_on_coarse_meshes() -> None:
    import pyvista as pv

    assert rendering.edges_shown(pv.Plane(i_resolution=10, j_resolution=10), None)
    assert not rendering.edges_shown(pv.Plane(i_resolution=100, j_resolution=100), None)
    assert rendering.edges_shown(pv.Plane(i_resolution=100, j_resolution=100), True)


def test_rendering_off_screen_prints_no_display_warning(tmp_path: Path) -> None:
    code = ("import pyvista as pv; from paradyn.results import rendering; "
            "rendering.render(rendering.Picture(pv.Plane().cast_to_unstructured_grid(), 'Normals', 'x'), 'p.png')")
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                          check=True)
    assert (tmp_path / "p.png").stat().st_size > 1000
    assert "X server" not in done.stderr and "WARN" not in done.stderr
