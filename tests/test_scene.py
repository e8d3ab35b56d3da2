"""Scene parsing (strict keys, clear errors) and model building, incl. the pipe whip case."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest

from paradyn import deck, scene

ROOT = Path(__file__).resolve().parents[1]
PIPE_WHIP = ROOT / "cases" / "pipe_whip" / "scene.toml"
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"

MINIMAL = """
title = "strip"
[run]
end_time = 1e-3
output_interval = 1e-4
[[material]]
name = "steel"
model = "elastic"
density = 7860.0
youngs_modulus = 200e9
poisson_ratio = 0.3
[[part]]
name = "strip"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "plate"
size = [0.2, 0.1]
elements = [4, 2]
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _error(tmp_path: Path, text: str) -> str:
    path = _write(tmp_path, text)
    with pytest.raises(scene.SceneError) as info:
        scene.build_model(scene.load_scene(path))
    message = str(info.value)
    assert message.startswith(str(path))
    return message


@pytest.fixture(scope="module")
def pipe_whip() -> deck.Model:
    return scene.build_model(scene.load_scene(PIPE_WHIP))


def test_pipe_whip_sizes_and_fixes(pipe_whip: deck.Model) -> None:
    assert pipe_whip.n_elements == 1024
    assert pipe_whip.n_nodes == 2 * 16 * 33  # 1056: 33 rings of 16 nodes per pipe
    fixed_nodes = np.flatnonzero(pipe_whip.fixed_dofs.any(axis=1))
    assert fixed_nodes.size == 2 * 16
    assert np.all(pipe_whip.fixed_dofs[fixed_nodes] == 1)
    np.testing.assert_allclose(np.abs(pipe_whip.coordinates[fixed_nodes, 0]), 1.0, atol=1e-12)
    assert pipe_whip.part_names == ["lower_pipe", "upper_pipe"]
    np.testing.assert_array_equal(np.bincount(pipe_whip.element_part), [512, 512])


def test_pipe_whip_gap_velocity_and_tracks(pipe_whip: deck.Model) -> None:
    lower = np.unique(pipe_whip.connectivity[pipe_whip.element_part == 0])
    upper = np.unique(pipe_whip.connectivity[pipe_whip.element_part == 1])
    assert np.intersect1d(lower, upper).size == 0
    thickness = 0.003
    mid_surface_gap = pipe_whip.coordinates[upper, 2].min() - pipe_whip.coordinates[lower, 2].max()
    assert mid_surface_gap - thickness == pytest.approx(1e-4, abs=1e-12)
    np.testing.assert_allclose(pipe_whip.initial_velocity[upper], np.tile([0, 0, -2.0], (upper.size, 1)))
    np.testing.assert_allclose(pipe_whip.initial_velocity[lower], 0.0)
    expected = {
        "lower_contact": [0, 0, 0.08], "lower_bottom": [0, 0, -0.08], "lower_quarter": [0.5, 0, 0.08],
        "upper_contact": [0, 0, 0.0831], "upper_top": [0, 0, 0.2431], "upper_quarter": [0, 0.5, 0.0831],
    }
    assert pipe_whip.tracked_names == list(expected)
    np.testing.assert_allclose(pipe_whip.coordinates[pipe_whip.tracked_nodes], list(expected.values()),
                               atol=1e-12)
    assert pipe_whip.control.time_step == 1e-6 and pipe_whip.control.end_time == 2.5e-3


def test_small_plate_builds_and_writes(tmp_path: Path) -> None:
    model = scene.build_model(scene.load_scene(SMALL_PLATE))
    assert (model.n_nodes, model.n_elements) == (45, 32)
    clamped = np.flatnonzero(model.fixed_dofs.any(axis=1))
    np.testing.assert_allclose(model.coordinates[clamped, 0], 0.0)
    assert clamped.size == 5
    np.testing.assert_allclose(model.initial_velocity[clamped], 0.0)  # zeroed on fixed translations
    back = deck.read_deck(deck.write_deck(model, tmp_path / "deck.h5"))
    assert back.tracked_names == ["tip_corner", "tip_middle", "middle"]
    np.testing.assert_array_equal(back.load_dof, [3])


def test_minimal_scene_defaults(tmp_path: Path) -> None:
    s = scene.load_scene(_write(tmp_path, MINIMAL))
    assert s.title == "strip"
    assert s.run.time_step == 0.0 and s.run.time_step_safety == 0.9 and s.run.history_interval is None
    part = s.part("strip")
    assert (part.integration_points, part.hourglass_coefficient) == (5, 0.1)
    model = scene.build_model(s)
    assert model.n_tracked == 0 and model.n_loads == 0


@pytest.mark.parametrize("line, partition", [("", None), ('partition = "blocks"', "blocks"),
                                             ('partition = "rcb"', "rcb")])
def test_run_partition_reaches_the_deck(tmp_path: Path, line: str, partition: str | None) -> None:
    """docs/scene.md [run] partition: written to the deck's /control partition; absent leaves
    the attribute out (the engine's default). contact_sort_interval reaches the deck too."""
    text = MINIMAL.replace("end_time = 1e-3", f"end_time = 1e-3\n{line}\ncontact_sort_interval = 7", 1)
    model = scene.build_model(scene.load_scene(_write(tmp_path, text)))
    assert model.control.partition == partition
    assert model.control.contact_sort_interval == 7
    back = deck.read_deck(deck.write_deck(model, tmp_path / "deck.h5"))
    assert back.control.partition == partition and back.control.contact_sort_interval == 7


def test_plasticity_and_damping_effects(tmp_path: Path) -> None:
    text = MINIMAL.replace('model = "elastic"', 'model = "j2_plasticity"\nyield_stress = 250e6')
    text = text.replace("output_interval = 1e-4", "output_interval = 1e-4\nmass_damping = 10.0")
    model = scene.build_model(scene.load_scene(_write(tmp_path, text)))
    assert model.control.mass_damping == 10.0
    np.testing.assert_array_equal(model.material_model, [2])
    np.testing.assert_array_equal(model.hardening_mixing, [1.0])


def test_dof_groups(tmp_path: Path) -> None:
    text = MINIMAL + '[[fix]]\npart = "strip"\nbox = [[0, 0, 0], [0, 0.1, 0]]\ndofs = ["translations", "rz"]\n'
    model = scene.build_model(scene.load_scene(_write(tmp_path, text)))
    np.testing.assert_array_equal(model.fixed_dofs[0], [1, 1, 1, 0, 0, 1])
    assert np.count_nonzero(model.fixed_dofs.any(axis=1)) == 3


def test_file_geometry_relative_to_scene(tmp_path: Path) -> None:
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    (tmp_path / "meshes").mkdir()
    meshio.write(tmp_path / "meshes" / "square.vtu", meshio.Mesh(points, [("quad", np.array([[0, 1, 2, 3]]))]))
    text = MINIMAL.replace('kind = "plate"\nsize = [0.2, 0.1]\nelements = [4, 2]',
                           'kind = "file"\npath = "meshes/square.vtu"')
    model = scene.build_model(scene.load_scene(_write(tmp_path, text)))
    assert (model.n_nodes, model.n_elements) == (4, 1)


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        ("end_time = 1e-3", "end_tme = 1e-3",
         r"unknown key 'end_tme' in \[run\]; did you mean 'end_time'\? allowed keys are: end_time"),
        ("thickness = 0.002", "thicknes = 0.002", r"unknown key 'thicknes' in \[\[part\]\] #1 'strip'"),
        ('kind = "plate"', 'kind = "plate"\nradius = 1.0', r"unknown key 'radius' in \[part.geometry\]"),
        ("density = 7860.0", "", r"missing required key 'density' in \[\[material\]\] #1 'steel'"),
        ("end_time = 1e-3", "", r"missing required key 'end_time' in \[run\]"),
        ('title = "strip"', 'title = "strip"\ncolour = "red"', r"unknown key 'colour' in the top level"),
        ("thickness = 0.002", "thickness = -0.002", r"'thickness' in \[\[part\]\] #1 'strip' must be > 0"),
        ("thickness = 0.002", 'thickness = "thin"', r"'thickness' .* must be a finite number"),
        ('material = "steel"', 'material = "stee"', r"material 'stee', which is not defined"),
        ('model = "elastic"', 'model = "plastic"', r"'model' = 'plastic' .* not one of: elastic, j2_plasticity"),
        ("poisson_ratio = 0.3", "poisson_ratio = 0.3\nyield_stress = 1e6", r"only applies to model"),
        ("elements = [4, 2]", "elements = [4.0, 2]", r"'elements' .* two positive integers"),
        ("[[part]]", "[part]", r"write \[\[part\]\] instead of \[part\]"),
        ("end_time = 1e-3", 'end_time = 1e-3\npartition = "metis"',
         r"'partition' = 'metis' in \[run\] is not one of: blocks, rcb"),
        ("end_time = 1e-3", "end_time = 1e-3\npartition = 2", r"'partition' in \[run\] must be a non-empty string"),
        ("end_time = 1e-3", "end_time = 1e-3\ncontact_sort_interval = -1",
         r"'contact_sort_interval' in \[run\] must be >= 0"),
    ],
)
def test_scene_errors(tmp_path: Path, old: str, new: str, pattern: str) -> None:
    assert old in MINIMAL
    with pytest.raises(scene.SceneError, match=pattern) as info:
        scene.load_scene(_write(tmp_path, MINIMAL.replace(old, new, 1)))
    assert str(info.value).startswith(str(tmp_path / "scene.toml"))


def test_contact_with_itself_is_rejected(tmp_path: Path) -> None:
    message = _error(tmp_path, MINIMAL + '[[contact]]\nparts = ["strip", "strip"]\n')
    assert "'parts' in [[contact]] #1 must name two different parts" in message


def test_contact_with_unknown_part_is_rejected(tmp_path: Path) -> None:
    message = _error(tmp_path, MINIMAL + '[[contact]]\nparts = ["strip", "other"]\n')
    assert "[[contact]] #1 names part 'other', which is not defined" in message


def test_pipe_whip_contact_reaches_the_deck() -> None:
    model = scene.build_model(scene.load_scene(PIPE_WHIP))
    np.testing.assert_array_equal(model.contact_pairs, [[0, 1]])
    assert model.contact_penalty_scale.tolist() == [0.1] and model.contact_passes.tolist() == [2]


def test_fix_box_missing_the_part(tmp_path: Path) -> None:
    message = _error(tmp_path, MINIMAL + '[[fix]]\npart = "strip"\nbox = [[5, 5, 5], [6, 6, 6]]\n')
    assert "contains no node of part 'strip'" in message


def test_track_far_from_part(tmp_path: Path) -> None:
    message = _error(tmp_path, MINIMAL + '[[track]]\nname = "x"\npart = "strip"\npoint = [0.1, 0.05, 1.0]\n')
    assert "[[track]] 'x'" in message and "from the nearest node" in message


def test_unknown_dof_and_bad_toml(tmp_path: Path) -> None:
    message = _error(tmp_path, MINIMAL + '[[load]]\npart = "strip"\npoint = [0.2, 0.1, 0]\ndof = "uw"\nvalue = 1.0\n')
    assert "'dof' = 'uw'" in message
    message = _error(tmp_path, MINIMAL + "[run\n")
    assert "not valid TOML" in message
