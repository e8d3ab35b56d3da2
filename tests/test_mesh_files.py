"""Meshes read from files (issue 18, docs/scene.md ``kind = "file"``): a gmsh file's physical
groups become parts through ``group``, its node and element tags are kept as the model's ids; a
meshio format's named cell sets select parts too."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest

from paradyn import scene
from paradyn.mesh import files as mesh_files
from paradyn.mesh import geometry

SCENE = """
[run]
end_time = 1e-5
output_interval = 1e-5

[[material]]
name = "steel"
model = "elastic"
density = 7800.0
youngs_modulus = 2e11
poisson_ratio = 0.3

[[part]]
name = "left"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "file"
path = "{file}"
group = "left"

[[part]]
name = "right"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "file"
path = "{file}"
group = "right"

[[part]]
name = "plate"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "plate"
size = [1.0, 1.0]
elements = [1, 1]
origin = [0.0, 0.0, 1.0]
"""


@pytest.fixture
def two_groups(tmp_path: Path) -> Path:
    """Two unit squares side by side, physical groups 'left' (tag 11) and 'right' (tag 12), with
    node and element tags offset so that they are not row numbers."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("two")
        occ = gmsh.model.occ
        a, b = occ.addRectangle(0, 0, 0, 1, 1), occ.addRectangle(1, 0, 0, 1, 1)
        occ.fragment([(2, a)], [(2, b)])
        occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [a], tag=11, name="left")
        gmsh.model.addPhysicalGroup(2, [b], tag=12, name="right")
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.renumberNodes()
        gmsh.model.mesh.renumberElements()
        node_tags = gmsh.model.mesh.getNodes()[0]
        gmsh.model.mesh.renumberNodes(node_tags, node_tags + 1000)
        path = tmp_path / "two.msh"
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def test_gmsh_groups_are_parts_with_the_file_ids(two_groups: Path, tmp_path: Path) -> None:
    left, right = mesh_files.load_mesh(two_groups, "left"), mesh_files.load_mesh(two_groups, "right")
    assert (left.part_id, right.part_id) == (11, 12)
    assert left.node_ids.min() > 1000 and len(set(left.element_ids) & set(right.element_ids)) == 0
    assert left.coordinates[:, 0].max() == pytest.approx(1.0) and right.coordinates[:, 0].min() == pytest.approx(1.0)
    whole = mesh_files.load_mesh(two_groups)
    assert whole.n_elements == left.n_elements + right.n_elements and whole.part_id is None
    path = tmp_path / "scene.toml"
    path.write_text(SCENE.format(file=two_groups.name))
    model = scene.build_model(scene.load_scene(path))
    assert model.part_ids.tolist() == [11, 12, 0]
    np.testing.assert_array_equal(model.node_ids[:left.n_nodes], left.node_ids)
    np.testing.assert_array_equal(model.element_ids[left.n_elements:-1], right.element_ids)
    assert model.node_ids[-4:].tolist() == [0, 0, 0, 0]     # the plate ParaDyn meshed has no file ids


def test_gmsh_group_that_does_not_exist_names_the_groups(two_groups: Path) -> None:
    with pytest.raises(geometry.GeometryError, match=r"no surface physical group named 'middle'.*'left', 'right'"):
        mesh_files.load_mesh(two_groups, "middle")


def test_meshio_cell_sets_select_parts(tmp_path: Path) -> None:
    """An Abaqus file's ELSETs are cell sets: ``group`` takes one of them."""
    points = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], dtype=float)
    quads = np.array([[0, 1, 4, 3], [1, 2, 5, 4]])
    path = tmp_path / "two.inp"
    meshio.write(path, meshio.Mesh(points, [("quad", quads)], cell_sets={"lid": [np.array([1])],
                                                                          "base": [np.array([0])]}))
    lid = mesh_files.load_mesh(path, "lid")
    assert lid.n_elements == 1 and lid.coordinates[:, 0].min() == 1.0 and lid.node_ids is None
    with pytest.raises(geometry.GeometryError, match=r"no cell set named 'top'; the file has \['base', 'lid'\]"):
        mesh_files.load_mesh(path, "top")


@pytest.mark.parametrize("recombine", [0, 1])
def test_gmsh_triangles_are_read(tmp_path: Path, recombine: int) -> None:
    """Triangles of a gmsh mesh (issue 33): a disk meshed with triangles only, or recombined into
    quads with the triangles gmsh leaves, reads as rows whose third node is repeated as the fourth,
    with their element tags; every element's normal is the disk's (counter-clockwise kept)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("disk")
        gmsh.model.occ.addDisk(0, 0, 0, 1.0, 1.0)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.RecombineAll", recombine)
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 0)   # simple: leaves triangles
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(2)
        counts = {int(k): len(t) for k, t in zip(*gmsh.model.mesh.getElements(2)[:2], strict=True)}
        path = tmp_path / "disk.msh"
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    mesh = mesh_files.load_mesh(path)
    assert int(mesh.triangles.sum()) == counts.get(2, 0) > 0
    assert int((~mesh.triangles).sum()) == counts.get(3, 0)
    assert (counts.get(3, 0) > 0) == bool(recombine)
    assert len(set(mesh.element_ids.tolist())) == mesh.n_elements
    np.testing.assert_allclose(mesh.normals()[:, 2], 1.0, atol=1e-12)
