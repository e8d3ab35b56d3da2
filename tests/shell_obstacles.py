"""Decks of the two warped-element problems of MacNeal & Harder's shell obstacle course
(tests/test_warping.py): the twisted beam and the closed pinched hemisphere, built in numpy.

Both meshes are made of warped quadrilaterals: the four nodes of an element do not lie in a plane,
which is what the warping correction of the element (docs/theory.md) is about. Nothing here knows
a reference value: the tests hold those.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import models as M
from paradyn.deck import Control, Model
from paradyn.mesh import geometry


def _grid_quads(n_u: int, n_v: int) -> np.ndarray:
    """Quads of a structured (n_u + 1) x (n_v + 1) node grid, node ``j * (n_u + 1) + i``."""
    i, j = np.meshgrid(np.arange(n_u), np.arange(n_v))
    first = (j * (n_u + 1) + i).ravel()
    return np.stack([first, first + 1, first + n_u + 2, first + n_u + 1], axis=1)


# ----------------------------------------------------------------------------------------------
# twisted beam


@dataclass
class TwistedBeam:
    """MacNeal & Harder's twisted beam: L = 12 along x, width 1.1, pretwisted 90 deg from the root
    (width along y) to the tip (width along z), t = 0.32, E = 29e6, nu = 0.22; clamped root, a
    tip load of 1 spread on the tip nodes as a consistent line load."""

    mesh: geometry.Mesh
    root: np.ndarray
    tip: np.ndarray

    LENGTH = 12.0
    WIDTH = 1.1
    THICKNESS = 0.32
    YOUNG = 29.0e6
    POISSON = 0.22

    @property
    def tip_weights(self) -> np.ndarray:
        return M.edge_weights(len(self.tip))

    def model(self, control: Control, direction: int, density: float, ramp_time: float,
              **kwargs: object) -> Model:
        """Tip load 1 along global ``direction`` (1 = y: normal to the tip's plane, 2 = z: in the
        tip's plane), ramped over ``ramp_time``."""
        material = M.Material(self.YOUNG, self.POISSON, density)
        load = M.Load(self.tip, direction + 1, self.tip_weights, ramp_time)
        return M.shell_model(self.mesh, self.THICKNESS, material, control, loads=[load],
                             fixed={int(n): M.ALL_DOFS for n in self.root}, tracked=self.tip, **kwargs)


def twisted_beam(n_width: int, n_length: int) -> TwistedBeam:
    """n_width elements across, n_length along; the width turns linearly with x."""
    B = TwistedBeam
    s = np.linspace(-0.5 * B.WIDTH, 0.5 * B.WIDTH, n_width + 1)
    x = np.linspace(0.0, B.LENGTH, n_length + 1)
    ss, xx = np.meshgrid(s, x)
    angle = 0.5 * np.pi * xx / B.LENGTH
    coordinates = np.column_stack([xx.ravel(), (ss * np.cos(angle)).ravel(), (ss * np.sin(angle)).ravel()])
    mesh = geometry.Mesh(coordinates=coordinates, quads=_grid_quads(n_width, n_length))
    root = np.arange(n_width + 1)
    return TwistedBeam(mesh=mesh, root=root, tip=root + n_length * (n_width + 1))


# ----------------------------------------------------------------------------------------------
# closed pinched hemisphere


@dataclass
class Hemisphere:
    """MacNeal & Harder's hemisphere without the polar hole: R = 10, t = 0.04, E = 6.825e7,
    nu = 0.3, four radial loads of 1 on the equator, outward along +-x and inward along +-y.

    Cubed-sphere mesh: the top face of the cube [-1, 1]^3 and the upper halves of its four side
    faces, equiangular (n x n elements on the top face, n x n/2 on each side half), projected
    onto the sphere; the equator is free. The pole node has all six dofs fixed: by the symmetry
    of the loads its displacement and rotation are zero, and this takes out the rigid motions.
    """

    mesh: geometry.Mesh
    pole: int
    loaded: np.ndarray       # nodes at +x, -x (outward loads), +y, -y (inward loads)
    directions: np.ndarray   # unit radial direction of each load, (4, 3), outward positive
    signs: np.ndarray        # +1 outward, -1 inward

    RADIUS = 10.0
    THICKNESS = 0.04
    YOUNG = 6.825e7
    POISSON = 0.3

    def model(self, control: Control, load: float, density: float, ramp_time: float,
              **kwargs: object) -> Model:
        material = M.Material(self.YOUNG, self.POISSON, density)
        loads = [M.Load(np.array([node]), 1 + int(np.argmax(np.abs(d))), np.array([load * s * d.sum()]), ramp_time)
                 for node, d, s in zip(self.loaded, self.directions, self.signs, strict=True)]
        return M.shell_model(self.mesh, self.THICKNESS, material, control, loads=loads,
                             fixed={self.pole: M.ALL_DOFS}, tracked=self.loaded, **kwargs)


def _face(n_u: int, n_v: int, v_range: tuple[float, float], point) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (on the unit sphere) and quads of one equiangular cube face patch: angles a in
    [-pi/4, pi/4] (n_u elements) and b in v_range (n_v elements); point(ta, tb) gives the cube
    point for the tangents of the two angles."""
    a = np.linspace(-0.25 * np.pi, 0.25 * np.pi, n_u + 1)
    b = np.linspace(v_range[0], v_range[1], n_v + 1)
    aa, bb = np.meshgrid(a, b)
    cube = point(np.tan(aa.ravel()), np.tan(bb.ravel()))
    return cube / np.linalg.norm(cube, axis=1)[:, None], _grid_quads(n_u, n_v)


def hemisphere(n: int) -> Hemisphere:
    """Cubed-sphere hemisphere with n x n elements per face (n even)."""
    if n % 2:
        raise ValueError("hemisphere: n must be even (a node at the pole and on the load lines)")
    one = np.ones
    half = (0.0, 0.25 * np.pi)
    faces = [
        _face(n, n, (-0.25 * np.pi, 0.25 * np.pi), lambda u, v: np.column_stack([u, v, one(len(u))])),
        _face(n, n // 2, half, lambda u, v: np.column_stack([one(len(u)), u, v])),
        _face(n, n // 2, half, lambda u, v: np.column_stack([-one(len(u)), u, v])),
        _face(n, n // 2, half, lambda u, v: np.column_stack([u, one(len(u)), v])),
        _face(n, n // 2, half, lambda u, v: np.column_stack([u, -one(len(u)), v])),
    ]
    points = np.concatenate([p for p, _ in faces])
    offsets = np.cumsum([0] + [len(p) for p, _ in faces])
    quads = np.concatenate([q + offsets[k] for k, (_, q) in enumerate(faces)])
    # merge the nodes that the faces share (their edges coincide exactly up to rounding)
    _, first, inverse = np.unique(np.round(points, 12), axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)
    renumber = np.empty_like(order)
    renumber[order] = np.arange(len(order))
    coordinates = Hemisphere.RADIUS * points[first[order]]
    quads = renumber[inverse.ravel()][quads]
    # counter-clockwise seen from outside
    outward = np.einsum("ij,ij->i", geometry.quad_normals(coordinates, quads), coordinates[quads].mean(axis=1))
    quads[outward < 0.0] = quads[outward < 0.0][:, ::-1]
    R = Hemisphere.RADIUS
    directions = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]])
    loaded = np.array([geometry.nearest_node(coordinates, R * d) for d in directions])
    if not np.allclose(coordinates[loaded], R * directions, atol=1e-9 * R):
        raise AssertionError("hemisphere: no node at a load point")
    pole = geometry.nearest_node(coordinates, (0.0, 0.0, R))
    return Hemisphere(mesh=geometry.Mesh(coordinates=coordinates, quads=quads), pole=pole, loaded=loaded,
                      directions=directions, signs=np.array([1.0, 1.0, -1.0, -1.0]))


def warp(mesh: geometry.Mesh) -> np.ndarray:
    """Warp of every element: the distance of its nodes from the plane normal to the diagonals
    through their centroid, over the square root of its area (0 for a flat element)."""
    c = mesh.coordinates[mesh.quads]
    normal = mesh.normals()
    z = np.einsum("ekj,ej->ek", c - c.mean(axis=1, keepdims=True), normal)
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    return np.abs(z[:, 0]) / np.sqrt(area)
