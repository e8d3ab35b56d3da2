"""The rigid walls' surfaces as the engine sees them (fortran/src/nodal_effects/rigid_wall.f90):
the signed gap of points to a wall, for the deck's check that no node starts inside one, and what
a wall of each shape needs of its geometry (the relation rigid_wall_geometry).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from paradyn._schema import ENUMS

SHAPES = ENUMS["rigid_wall_shape"]
NO_CONTACT = np.inf   # a gap no node reaches: beyond a finite wall's edges


@dataclass(frozen=True)
class Wall:
    """One wall of a deck: its shape code and geometry as the deck holds them."""

    shape: int
    point: np.ndarray
    normal: np.ndarray
    edge: np.ndarray
    size: np.ndarray
    radius: float
    length: float

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The unit normal, the unit edge (its part along the normal dropped) and normal x edge;
        zero vectors where the deck's are zero."""
        n = _unit(self.normal)
        edge = _unit(self.edge - (self.edge @ n) * n)
        return n, edge, np.cross(n, edge)

    def gaps(self, x: np.ndarray) -> np.ndarray:
        """The signed gap of each point x (k, 3) at time 0: negative inside or behind the wall,
        ``inf`` where the wall does not act (beyond a finite plane's edges or a finite cylinder's
        ends, on a cylinder's axis or a sphere's centre)."""
        y = np.asarray(x, dtype=float) - self.point
        n, edge, side = self.axes()
        gap = np.full(len(y), NO_CONTACT)
        if self.shape == SHAPES["plane"]:
            gap = y @ n
        elif self.shape == SHAPES["finite_plane"]:
            a, b = y @ edge, y @ side
            inside = (a >= 0) & (a <= self.size[0]) & (b >= 0) & (b <= self.size[1])
            gap[inside] = (y @ n)[inside]
        elif self.shape == SHAPES["cylinder"]:
            c = y @ n
            r = np.linalg.norm(y - c[:, None] * n, axis=1)
            acts = (r > 0) & ((self.length <= 0) | ((c >= 0) & (c <= self.length)))
            gap[acts] = r[acts] - self.radius
        elif self.shape == SHAPES["sphere"]:
            r = np.linalg.norm(y, axis=1)
            gap[r > 0] = r[r > 0] - self.radius
        elif self.shape == SHAPES["box"]:
            a, b, c = y @ edge, y @ side, y @ n
            faces = np.stack([c, -self.size[2] - c, -a, a - self.size[0], -b, b - self.size[1]], axis=1)
            deepest = faces.max(axis=1)
            gap[deepest < 0] = deepest[deepest < 0]
        return gap

    def requirement(self) -> str:
        """What the wall lacks of its geometry (the words after '= ' of rigid_wall_geometry), '' if nothing."""
        across = np.linalg.norm(np.cross(self.normal, self.edge)) > 1e-9 * np.linalg.norm(self.normal) * \
            np.linalg.norm(self.edge)
        if self.shape == SHAPES["finite_plane"] and not (across and self.size[0] > 0 and self.size[1] > 0):
            return "finite_plane needs an edge not parallel to its normal and sides size[0], size[1] > 0"
        if self.shape == SHAPES["box"] and not (across and np.all(self.size > 0)):
            return "box needs an edge not parallel to its normal and size > 0 (both sides and the depth)"
        if self.shape in (SHAPES["cylinder"], SHAPES["sphere"]) and not self.radius > 0:
            name = "cylinder" if self.shape == SHAPES["cylinder"] else "sphere"
            return f"{name} needs a radius > 0"
        return ""


def _unit(v: np.ndarray) -> np.ndarray:
    length = float(np.linalg.norm(v))
    return v / length if length > 0 else np.zeros(3)


def walls_of(shape: np.ndarray, point: np.ndarray, normal: np.ndarray, edge: np.ndarray, size: np.ndarray,
             radius: np.ndarray, length: np.ndarray) -> list[Wall]:
    """The deck's walls from its /rigid_walls arrays."""
    return [Wall(int(shape[w]), np.asarray(point[w], float), np.asarray(normal[w], float),
                 np.asarray(edge[w], float), np.asarray(size[w], float), float(radius[w]), float(length[w]))
            for w in range(len(point))]


__all__ = ["NO_CONTACT", "SHAPES", "Wall", "walls_of"]
