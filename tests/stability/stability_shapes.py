"""Shapes and measures of the stability suite's newer cases (issue 35 item 4), apart from the
scene tables of stability_scenes: the square tube (a cylinder's rings flattened onto a square) and
its mean crush force against Abramowicz and Jones's estimate, the cubed-sphere ball, and the plate
with half its quads cut into triangles."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from paradyn import deck

# the square tube (issue 35 item 4): side C, wall t, length L, the paper's steel (sigma_0 = 250 MPa,
# perfectly plastic), crushed by a rigid wall at 10 m/s
TUBE_SIDE, TUBE_WALL, TUBE_LENGTH, TUBE_SPEED = 0.05, 1.5e-3, 0.2, 10.0
PLATEN_FRICTION = 0.3   # the crushing wall's Coulomb coefficient (dry steel on steel)


SPHERE_RADIUS = 0.05   # the rigid ball (m)


def cubed_sphere(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A sphere of SPHERE_RADIUS centred on the origin, as quads: a cube's six faces, n x n each,
    pushed out onto the sphere (the corners and edges shared), normals outward."""
    grid = np.linspace(-1.0, 1.0, n + 1)
    points: dict[tuple[int, ...], int] = {}
    coords, quads = [], []

    def node(p: np.ndarray) -> int:
        key = tuple(np.round(p * n).astype(int))
        if key not in points:
            points[key] = len(coords)
            coords.append(SPHERE_RADIUS * p / np.linalg.norm(p))
        return points[key]

    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            for i in range(n):
                for j in range(n):
                    corners = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis], p[u], p[v] = sign, grid[i + di], grid[j + dj]
                        corners.append(node(p))
                    quads.append(corners if sign > 0 else corners[::-1])
    return np.array(coords), np.array(quads, dtype=np.int64)


def sphere_file(n: int) -> Path:
    """The cubed sphere written once as a .vtu file in a cache folder (a scene's mesh is a file)."""
    import meshio
    path = Path(tempfile.gettempdir()) / "paradyn-stability" / f"sphere_{n}.vtu"
    if not path.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
        coords, quads = cubed_sphere(n)
        meshio.write(path, meshio.Mesh(coords, [("quad", quads)]))
    return path


def mix_triangles(model: deck.Model) -> None:
    """Cut every other quad of the plate (part 0, a checkerboard) into two triangles (N3 = N4) along the
    diagonal that points at the plate's centre; the other elements keep their order after them."""
    conn, part = np.asarray(model.connectivity), np.asarray(model.element_part)
    xy = np.asarray(model.coordinates)[:, :2]
    rows, parts = [], []
    for k, (quad, p) in enumerate(zip(conn, part, strict=True)):
        if p != 0 or k % 2:
            rows.append(quad)
            parts.append(p)
            continue
        a, b, c, d = quad
        centre = xy[quad].mean(axis=0)
        rows += [[a, b, c, c], [a, c, d, d]] if centre[0] * centre[1] > 0 else [[a, b, d, d], [b, c, d, d]]
        parts += [p, p]
    model.connectivity = np.array(rows, dtype=np.int64)
    model.element_part = np.array(parts, dtype=np.int32)
    model.element_ids = None


def to_square(model: deck.Model) -> None:
    """Map the cylinder's rings onto a square of side TUBE_SIDE: the node at angle theta from the first
    node goes to the point at the same fraction of the square's perimeter, so corners are nodes (the
    count around is a multiple of 4) and each side keeps equal elements."""
    x = np.asarray(model.coordinates)
    theta = np.arctan2(x[:, 1], x[:, 0])
    phase = np.mod(theta - theta[0], 2.0 * np.pi)
    side = np.floor(phase / (0.5 * np.pi) + 1e-9).astype(int) % 4
    fraction = phase / (0.5 * np.pi) - side
    half = TUBE_SIDE / math.sqrt(2.0)          # the corners lie on this circle
    a0 = theta[0] + 0.5 * np.pi * side
    corner0 = half * np.stack([np.cos(a0), np.sin(a0)], axis=1)
    corner1 = half * np.stack([np.cos(a0 + 0.5 * np.pi), np.sin(a0 + 0.5 * np.pi)], axis=1)
    x[:, :2] = corner0 + fraction[:, None] * (corner1 - corner0)
    model.coordinates = x


def mean_crush_force(results: Any) -> tuple[float, float]:
    """The moving wall's mean force on the tube over the run (its impulse over the time: the wall moves
    at a constant speed, so this is the work over the crush distance) and the crush distance (m)."""
    h = results.history
    force = -np.asarray(h["rigid_wall_force"])[:, 0, 2]       # the wall pushes the tube down: -fz
    t = np.asarray(h["time"])
    mean = float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(t)) / (t[-1] - t[0]))
    return mean, TUBE_SPEED * float(t[-1] - t[0])


def abramowicz_jones_force() -> float:
    """Mean crush force of a square tube in progressive folding, P_m = 13.06 sigma_0 t^2 (C / t)^(1/3)
    (Abramowicz and Jones 1984, Int. J. Impact Eng. 2(2), from Wierzbicki and Abramowicz's
    super-folding element with the effective crush distance 0.73 of the fold length)."""
    return 13.06 * 250e6 * TUBE_WALL**2 * (TUBE_SIDE / TUBE_WALL) ** (1.0 / 3.0)
