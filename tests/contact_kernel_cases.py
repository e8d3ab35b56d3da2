"""What the contact kernel tests (tests/test_contact_*_search.py, tests/test_contact_penalty.py)
share: the array layout of the f2py wrappers, a brute-force nearest node, the bilinear segment
and random quadrilaterals.

Node and segment numbers returned by the wrappers are 1-based. A segment is ``xseg[:, I]`` for
its nodes I = 0..3 at (xi, eta) = (-1, -1), (1, -1), (1, 1), (-1, 1).
"""

from __future__ import annotations

import numpy as np

F = np.asfortranarray


def brute_nearest(master: np.ndarray, points: np.ndarray) -> np.ndarray:
    """1-based index of the nearest master node of each point; np.argmin keeps the first (lowest)."""
    d2 = ((points.T[:, None, :] - master.T[None, :, :]) ** 2).sum(axis=2)
    return np.argmin(d2, axis=1) + 1


SHAPE_SIGNS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)


def shape(xi: float, eta: float) -> np.ndarray:
    return 0.25 * (1 + SHAPE_SIGNS[:, 0] * xi) * (1 + SHAPE_SIGNS[:, 1] * eta)


def surface(xseg: np.ndarray, xi, eta):
    """x(xi, eta) and its two tangents dx/dxi, dx/deta (numpy reference of the bilinear map)."""
    n = shape(xi, eta)
    dxi = 0.25 * SHAPE_SIGNS[:, 0] * (1 + SHAPE_SIGNS[:, 1] * eta)
    deta = 0.25 * SHAPE_SIGNS[:, 1] * (1 + SHAPE_SIGNS[:, 0] * xi)
    return xseg @ n, xseg @ dxi, xseg @ deta


def rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def flat_quad(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A convex, non-parallelogram flat quadrilateral in a random orientation, and its normal."""
    local = np.array([[0.0, 0.0], [2.0, 0.2], [2.3, 1.7], [-0.2, 1.5]]) + rng.uniform(-0.15, 0.15, (4, 2))
    rot = rotation(rng)
    xseg = rot @ np.vstack([local.T, np.zeros(4)]) + rng.uniform(-3, 3, size=(3, 1))
    return F(xseg), rot[:, 2]


def warped_quad(rng: np.random.Generator, warp: float) -> np.ndarray:
    local = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) + rng.uniform(-0.15, 0.15, (4, 2))
    z = warp * np.array([1.0, -1.0, 1.0, -1.0]) + rng.uniform(-0.05, 0.05, 4)
    return F(rotation(rng) @ np.vstack([local.T, z]))
