"""What the kernel tests (tests/test_kernels_*.py) share: the array layout of the f2py wrappers,
steel, the J2 hardening constants, the shell thickness and a rotation matrix."""

from __future__ import annotations

import math

import numpy as np

F = np.asfortranarray

# steel
E = 200e9
NU = 0.3
RHO = 7860.0
C_PLANE = E / (1.0 - NU**2)        # plane-stress modulus
G = E / (2.0 * (1.0 + NU))

# J2 plasticity: bilinear hardening
SY0 = 250e6     # initial yield stress
ET = 2e9        # tangent modulus
H = E * ET / (E - ET)   # plastic modulus dsigma / deps_p of the uniaxial curve

# BLT shell element
T = 0.01          # thickness


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    a = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)
