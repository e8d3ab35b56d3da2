"""Meshing: cylinders and plates (by formula), mesh files and node selection."""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np
import pytest

from paradyn.mesh import files as mesh_files
from paradyn.mesh import geometry


def _radial_dot_normal(mesh: geometry.Mesh, axis: np.ndarray, center: np.ndarray) -> np.ndarray:
    centroid = mesh.coordinates[mesh.quads].mean(axis=1) - center
    radial = centroid - np.outer(centroid @ axis, axis)
    return np.einsum("ij,ij->i", mesh.normals(), radial)


@pytest.mark.parametrize("axis", [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 1.0)])
def test_cylinder_counts_radius_and_outward_normals(axis: tuple[float, float, float]) -> None:
    center = np.array([0.1, -0.2, 0.3])
    mesh = geometry.cylinder(0.08, 2.0, axis=axis, center=center, elements_around=16, elements_along=32)
    assert mesh.quads.shape == (16 * 32, 4)
    assert mesh.coordinates.shape == (16 * 33, 3)
    assert mesh.coordinates.dtype == np.float64 and mesh.quads.dtype == np.int64
    a = np.asarray(axis) / np.linalg.norm(axis)
    rel = mesh.coordinates - center
    along = rel @ a
    radial = np.linalg.norm(rel - np.outer(along, a), axis=1)
    np.testing.assert_allclose(radial, 0.08, rtol=1e-12)
    np.testing.assert_allclose([along.min(), along.max()], [-1.0, 1.0], atol=1e-12)
    assert np.all(_radial_dot_normal(mesh, a, center) > 0)


def test_cylinder_has_no_duplicate_or_unused_nodes() -> None:
    mesh = geometry.cylinder(0.05, 0.4, elements_around=8, elements_along=4)
    rounded = np.round(mesh.coordinates, 12)
    assert len(np.unique(rounded, axis=0)) == mesh.n_nodes
    assert set(np.unique(mesh.quads)) == set(range(mesh.n_nodes))
    assert np.all([len(set(q)) == 4 for q in mesh.quads.tolist()])


def test_cylinder_node_numbering_is_ring_by_ring() -> None:
    mesh = geometry.cylinder(0.08, 2.0, elements_around=16, elements_along=32)
    x = mesh.coordinates[:, 0].reshape(33, 16)
    np.testing.assert_allclose(x, np.repeat(np.linspace(-1, 1, 33)[:, None], 16, axis=1), atol=1e-12)
    np.testing.assert_allclose(mesh.coordinates[16 * 16], [0.0, 0.0, 0.08], atol=1e-12)  # top, mid ring


def test_cylinder_rejects_elements_around_not_multiple_of_four() -> None:
    with pytest.raises(geometry.GeometryError, match="multiple of 4"):
        geometry.cylinder(0.08, 2.0, elements_around=10)


def _gmsh_cylinder_nodes(radius: float, length: float, n_around: int, n_along: int) -> np.ndarray:
    """The nodes of gmsh's transfinite mesh of the cylinder along x from x = -length / 2: four
    quarter arcs of n_around / 4 elements each, extruded in n_along layers (an independent mesher)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        geo = gmsh.model.geo
        x0 = -0.5 * length
        centre = geo.addPoint(x0, 0.0, 0.0)
        corners = [geo.addPoint(x0, -radius * np.sin(0.5 * np.pi * k), radius * np.cos(0.5 * np.pi * k))
                   for k in range(4)]
        arcs = [geo.addCircleArc(corners[k], centre, corners[(k + 1) % 4]) for k in range(4)]
        for arc in arcs:
            geo.mesh.setTransfiniteCurve(arc, n_around // 4 + 1)
        extruded = geo.extrude([(1, arc) for arc in arcs], length, 0.0, 0.0, numElements=[n_along], recombine=True)
        geo.synchronize()
        group = gmsh.model.addPhysicalGroup(2, [tag for dim, tag in extruded if dim == 2])
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.removeDuplicateNodes()
        return np.asarray(gmsh.model.mesh.getNodesForPhysicalGroup(2, group)[1]).reshape(-1, 3)
    finally:
        gmsh.finalize()


def test_cylinder_nodes_are_those_of_gmsh_transfinite_mesh() -> None:
    """The formula's nodes are gmsh's (its geo kernel's arcs, meshed transfinite, extruded): each
    within 1e-9 m of one of gmsh's, one to one. gmsh's arc points lie up to 1.3e-10 m off the
    circle (measured with radius 0.08 m); the formula's are on it to round-off."""
    mesh = geometry.cylinder(0.08, 2.0, elements_around=16, elements_along=32)
    theirs = _gmsh_cylinder_nodes(0.08, 2.0, 16, 32)
    assert theirs.shape == mesh.coordinates.shape
    distance = np.linalg.norm(mesh.coordinates[:, None, :] - theirs[None, :, :], axis=2)
    nearest = distance.argmin(axis=1)
    assert len(set(nearest.tolist())) == mesh.n_nodes
    assert distance.min(axis=1).max() < 1e-9
    radial = np.linalg.norm(mesh.coordinates[:, 1:], axis=1)
    np.testing.assert_allclose(radial, 0.08, rtol=1e-15)


def test_cylinder_elements_go_ring_by_ring_around_the_axis() -> None:
    mesh = geometry.cylinder(0.05, 0.4, elements_around=8, elements_along=4)
    np.testing.assert_array_equal(mesh.quads[:2], [[0, 1, 9, 8], [1, 2, 10, 9]])
    np.testing.assert_array_equal(mesh.quads[7], [7, 0, 8, 15])   # the ring closes
    np.testing.assert_array_equal(mesh.quads[8], [8, 9, 17, 16])


def test_plate_counts_and_normal() -> None:
    mesh = geometry.plate((0.2, 0.1), (8, 4), origin=(1.0, 0.0, 0.0), u_axis=(0, 1, 0), v_axis=(0, 0, 2))
    assert mesh.quads.shape == (32, 4)
    assert mesh.coordinates.shape == (45, 3)
    np.testing.assert_allclose(mesh.normals(), np.tile([1.0, 0.0, 0.0], (32, 1)), atol=1e-12)
    np.testing.assert_allclose(mesh.coordinates.max(axis=0), [1.0, 0.2, 0.1])
    np.testing.assert_allclose(mesh.edge_lengths()[0], [0.025, 0.025, 0.025, 0.025])


def test_plate_rejects_parallel_axes() -> None:
    with pytest.raises(geometry.GeometryError, match="perpendicular"):
        geometry.plate((1, 1), (2, 2), u_axis=(1, 0, 0), v_axis=(1, 1, 0))


def test_load_mesh_reads_quads_and_drops_unused_nodes(tmp_path: Path) -> None:
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5]], dtype=float)
    path = tmp_path / "quad.vtu"
    meshio.write(path, meshio.Mesh(points, [("quad", np.array([[0, 1, 2, 3]]))]))
    mesh = mesh_files.load_mesh(path)
    assert mesh.n_nodes == 4 and mesh.n_elements == 1
    np.testing.assert_allclose(mesh.normals(), [[0, 0, 1]])


def test_load_mesh_reads_triangles_as_degenerate_quads(tmp_path: Path) -> None:
    """Triangles (issue 33) become rows whose third node is repeated as the fourth, after the quads."""
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], dtype=float)
    path = tmp_path / "tri.vtu"
    meshio.write(path, meshio.Mesh(points, [("quad", np.array([[0, 1, 2, 3]])),
                                            ("triangle", np.array([[1, 4, 5], [1, 5, 2]]))]))
    mesh = mesh_files.load_mesh(path)
    assert mesh.n_elements == 3
    assert mesh.triangles.tolist() == [False, True, True]
    np.testing.assert_allclose(mesh.normals(), [[0, 0, 1]] * 3)


def test_load_mesh_rejects_quadratic_triangles_with_count(tmp_path: Path) -> None:
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, 0, 0], [0.5, 0.5, 0], [0, 0.5, 0]], dtype=float)
    path = tmp_path / "tri6.vtu"
    meshio.write(path, meshio.Mesh(points, [("triangle6", np.array([[0, 1, 2, 3, 4, 5]]))]))
    with pytest.raises(geometry.GeometryError, match=r"1 triangle6 cells.*triangles"):
        mesh_files.load_mesh(path)


def test_load_mesh_without_quads(tmp_path: Path) -> None:
    points = np.array([[0, 0, 0], [1, 0, 0]], dtype=float)
    path = tmp_path / "line.vtu"
    meshio.write(path, meshio.Mesh(points, [("line", np.array([[0, 1]]))]))
    with pytest.raises(geometry.GeometryError, match="no quadrilateral or triangle cells"):
        mesh_files.load_mesh(path)


def test_node_selection() -> None:
    coords = np.array([[0.0, 0, 0], [1.0, 0, 0], [1.0 + 1e-12, 1, 0], [2.0, 0, 0]])
    np.testing.assert_array_equal(geometry.nodes_in_box(coords, (1, -1, -1), (1, 1, 1), tol=1e-9), [1, 2])
    np.testing.assert_array_equal(geometry.nodes_in_box(coords, (1, -1, -1), (1, 1, 1)), [1])
    assert geometry.nearest_node(coords, (1.9, 0.1, 0.0)) == 3
    with pytest.raises(geometry.GeometryError, match="must not exceed"):
        geometry.nodes_in_box(coords, (1, 1, 1), (0, 0, 0))
