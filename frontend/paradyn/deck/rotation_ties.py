"""Rotation ties of a deck model (/rotation_ties; docs/theory.md, "Rotation ties"): a shell edge
tied to a surface (LS-DYNA *CONTACT_TIED_SHELL_EDGE_TO_SURFACE) turns with it.

The tied contact (a ``tied`` contact pair) holds the slave nodes' places on the master surface;
:func:`add_rotation_ties` ties their rotations too: each slave node within the tie's reach of a
master segment, (t_slave + t_master) / 2 plus 1 % as the engine's tie (contact/kinds/tied_contact.f90),
gets the segment's four nodes and their bilinear shape functions at its closest point, and the
engine holds its angular velocity to the weighted mean of theirs.
"""

from __future__ import annotations

import numpy as np

from .model import Model

# as tied_contact.f90's tie_slack: a node within (1 + TIE_SLACK) (t_s + t_m) / 2 of a segment is tied
TIE_SLACK = 0.01


def add_rotation_ties(model: Model, slave_part: int, master_part: int) -> int:
    """Append to /rotation_ties a tie of every node of ``slave_part`` (0-based) within reach of a
    segment of ``master_part``, to the nearest such segment (the lowest element among equals);
    returns how many were added."""
    x = np.asarray(model.coordinates, dtype=float)
    conn, part = np.asarray(model.connectivity), np.asarray(model.element_part)
    thickness = np.asarray(model.thickness, dtype=float)
    reach = (1.0 + TIE_SLACK) * 0.5 * (thickness[slave_part] + thickness[master_part])
    masters = np.flatnonzero(part == master_part)
    corners = x[conn[masters]]                          # (segments, 4, 3)
    low, high = corners.min(axis=1) - reach, corners.max(axis=1) + reach
    nodes, segments, weights = [], [], []
    for node in np.unique(conn[part == slave_part]):
        p = x[node]
        near = np.flatnonzero(np.all((p >= low) & (p <= high), axis=1))
        best: tuple[float, int, np.ndarray] | None = None
        for k in near:
            if node in conn[masters[k]]:
                continue
            shape, distance = _closest(corners[k], p)
            if distance <= reach and (best is None or distance < best[0]):
                best = (distance, k, shape)
        if best is not None:
            nodes.append(node)
            segments.append(conn[masters[best[1]]])
            weights.append(best[2])
    if nodes:
        _append(model, np.array(nodes), np.array(segments), np.array(weights))
    return len(nodes)


def _closest(corners: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, float]:
    """The shape functions (4,) at the point of the bilinear segment nearest p, and its distance
    (Newton steps on the squared distance in (xi, eta), kept in the square; a triangle, N3 = N4,
    gets its fourth function folded into the third)."""
    xi = eta = 0.0
    for _ in range(20):
        shape, dxi, deta = _shape(xi, eta)
        r = shape @ corners - p
        a, b = dxi @ corners, deta @ corners
        jacobian = np.array([[a @ a, a @ b], [a @ b, b @ b]])
        step = np.linalg.solve(jacobian + 1e-30 * np.eye(2), [r @ a, r @ b])
        xi, eta = float(np.clip(xi - step[0], -1.0, 1.0)), float(np.clip(eta - step[1], -1.0, 1.0))
    shape = _shape(xi, eta)[0]
    if np.array_equal(corners[2], corners[3]):
        shape = np.array([shape[0], shape[1], shape[2] + shape[3], 0.0])
    return shape, float(np.linalg.norm(shape @ corners - p))


def _shape(xi: float, eta: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    s, t = np.array([-1.0, 1.0, 1.0, -1.0]), np.array([-1.0, -1.0, 1.0, 1.0])
    return (0.25 * (1 + s * xi) * (1 + t * eta), 0.25 * s * (1 + t * eta), 0.25 * t * (1 + s * xi))


def _append(model: Model, nodes: np.ndarray, masters: np.ndarray, weights: np.ndarray) -> None:
    if model.rotation_tie_node is not None:
        nodes = np.concatenate([np.asarray(model.rotation_tie_node), nodes])
        masters = np.concatenate([np.asarray(model.rotation_tie_masters), masters])
        weights = np.concatenate([np.asarray(model.rotation_tie_weights), weights])
    model.rotation_tie_node = nodes.astype(np.int32)
    model.rotation_tie_masters = masters.astype(np.int32)
    model.rotation_tie_weights = np.clip(weights, 0.0, 1.0)
