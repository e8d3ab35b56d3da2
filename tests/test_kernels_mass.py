"""Lumped mass and stable time step of the BLT shell element, called through the f2py wrappers
(``paradyn._kernels``).

Each test names the reference it checks against in its docstring. Real arrays passed to the
wrappers are float64 and Fortran-ordered; ``intent(inout)`` arrays are updated in place.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel_cases import RHO, E, F, T, _rotation
from paradyn import _kernels as K

# ------------------------------------------------------------------------------------------------
# mass and stable time step


def _pipe_elements(radius: float = 0.08, length: float = 2.0, around: int = 16,
                   along: int = 32) -> np.ndarray:
    """The pipe whip mesh built analytically: (n, 4, 3) node rows, outward normals."""
    angles = 2 * np.pi * np.arange(around + 1) / around
    xs = np.linspace(-length / 2, length / 2, along + 1)
    elements = []
    for i in range(along):
        for j in range(around):
            p = [(xs[i], angles[j]), (xs[i + 1], angles[j]), (xs[i + 1], angles[j + 1]),
                 (xs[i], angles[j + 1])]
            elements.append([[x, radius * math.cos(a), radius * math.sin(a)] for x, a in p])
    return np.array(elements)


def _layout(elements: np.ndarray) -> np.ndarray:
    return F(np.transpose(elements, (0, 2, 1)))


def _plate_elements(rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """A 6 x 4 plate with jiggled interior nodes (general convex quads), tilted in 3D; area."""
    nx, ny = 6, 4
    gx, gy = np.meshgrid(np.linspace(0, 0.3, nx + 1), np.linspace(0, 0.2, ny + 1), indexing="ij")
    gx[1:-1, 1:-1] += rng.uniform(-0.01, 0.01, (nx - 1, ny - 1))
    gy[1:-1, 1:-1] += rng.uniform(-0.01, 0.01, (nx - 1, ny - 1))
    rotation = _rotation(np.array([1.0, 2.0, -0.5]), 0.9)
    elements, area = [], 0.0
    for i in range(nx):
        for j in range(ny):
            q = np.array([[gx[i, j], gy[i, j]], [gx[i + 1, j], gy[i + 1, j]],
                          [gx[i + 1, j + 1], gy[i + 1, j + 1]], [gx[i, j + 1], gy[i, j + 1]]])
            area += 0.5 * np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1])
            elements.append(np.c_[q, np.zeros(4)] @ rotation.T)
    return np.array(elements), area


def test_blt_lumped_mass_adds_up_to_the_total_mass() -> None:
    """Reference: mass conservation of the lumped mass, sum over elements of 4 * node_mass =
    rho t (total area), on a tilted plate of general quadrilaterals (shoelace area) and on the
    pipe whip's 16 x 32 polygonal cylinder (512 rectangles 2 R sin(pi/16) x 0.0625); and the
    documented rotary inertia I = m (t^2 + A) / 4."""
    rng = np.random.default_rng(3)
    plate, area = _plate_elements(rng)
    mass, inertia = K.blt_mass(_layout(plate), T, RHO)
    assert 4.0 * mass.sum() == pytest.approx(RHO * T * area, rel=1e-12)
    element_area = 4.0 * mass / (RHO * T)
    np.testing.assert_allclose(inertia, mass * (T**2 + element_area) / 4.0, rtol=1e-12)

    pipe = _pipe_elements()
    t_pipe = 0.003
    mass, _ = K.blt_mass(_layout(pipe), t_pipe, RHO)
    side = 2 * 0.08 * math.sin(math.pi / 16)
    assert 4.0 * mass.sum() == pytest.approx(RHO * t_pipe * 512 * side * 0.0625, rel=1e-12)


def test_blt_time_step_of_the_pipe_element() -> None:
    """Reference: LS-DYNA Theory Manual shell time step dt = L / c, L = area / longest side,
    c = sqrt(E / (rho (1 - nu^2))). Pipe whip (R = 0.08, 16 around, 32 along, nu = 0.28): the
    element is 2 R sin(pi/16) x 0.0625, so dt = 2 R sin(pi/16) / c = 5.94 us; a true circle's
    arc 2 pi R / 16 would give the benchmark's ~5.98 us (before the 0.9 safety factor)."""
    nu = 0.28
    pipe = _pipe_elements()
    dt = K.blt_time_step(_layout(pipe), 0.003, RHO, E, nu)
    c = math.sqrt(E / (RHO * (1 - nu**2)))
    side, length = 2 * 0.08 * math.sin(math.pi / 16), 0.0625
    expected = side * length / max(side, length) / c
    np.testing.assert_allclose(dt, expected, rtol=1e-12)
    arc = 2 * math.pi * 0.08 / 16
    assert arc / c == pytest.approx(5.98e-6, rel=2e-3)
    assert dt.min() == pytest.approx(5.98e-6 * side / arc, rel=2e-3)
