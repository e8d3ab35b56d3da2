"""Scenes of rigid bodies for the tests (tests/test_rigid_bodies.py) and their references."""

from __future__ import annotations

import numpy as np

import paradyn
from models import lumped_masses

STEEL = {"density": 7800.0, "youngs_modulus": 200e9, "poisson_ratio": 0.3}
SIDES = (0.3, 0.1)        # a x b of the spinning plate (m)
THICKNESS = 0.01


def spinning_plate(end_time: float, omega: tuple[float, float, float], velocity=(0.0, 0.0, 0.0),
                   fixed=(0, 0, 0, 0, 0, 0)) -> paradyn.deck.Model:
    """A rigid plate a x b x t in the x-y plane (centre at its middle) spinning at omega (rad/s)
    about its centre and moving at velocity; three corners tracked (origin, +x, +y)."""
    a, b = SIDES
    scene = paradyn.Scene("rigid plate", end_time=end_time, output_interval=end_time / 10, history_interval=2e-4)
    scene.add_material("rigid_steel", model="rigid", **STEEL)
    scene.add_part("plate", material="rigid_steel", thickness=THICKNESS,
                   geometry=paradyn.Plate(size=(a, b), elements=(12, 4)))
    scene.add("rigid_body", part="plate", fixed=list(fixed))
    for name, point in (("o", (0.0, 0.0, 0.0)), ("x", (a, 0.0, 0.0)), ("y", (0.0, b, 0.0))):
        scene.add_track(name, part="plate", point=list(point))
    model = scene.build()
    centre = np.array([a / 2, b / 2, 0.0])
    model.initial_velocity = np.asarray(velocity) + np.cross(omega, model.coordinates - centre)
    model.initial_angular_velocity = np.tile(omega, (len(model.coordinates), 1))
    return model


def lumped_inertia(model: paradyn.deck.Model) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre and inertia tensor of a one-part rigid shell model as the engine takes them
    (docs/theory.md, "Rigid bodies"): the lumped masses of its nodes (models.lumped_masses: a
    quarter of each element's rho t A at its corners) as points, and each node's rotary inertia
    m t^2 / 12 about every axis."""
    mass = lumped_masses(model)
    total = float(mass.sum())
    centre = mass @ model.coordinates / total
    r = model.coordinates - centre
    inertia = (mass * (r * r).sum(axis=1)).sum() * np.eye(3) - np.einsum("i,ij,ik->jk", mass, r, r)
    inertia += total * float(model.thickness[0]) ** 2 / 12 * np.eye(3)
    return total, centre, inertia


def euler_free_spin(inertia: np.ndarray, omega0: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Body-axis angular velocity of a torque-free body (Euler's equations), by RK4 at 1e-5 s."""
    def rate(w: np.ndarray) -> np.ndarray:
        i1, i2, i3 = inertia
        return np.array([(i2 - i3) * w[1] * w[2] / i1, (i3 - i1) * w[2] * w[0] / i2, (i1 - i2) * w[0] * w[1] / i3])
    h = 1e-5
    out = np.empty((len(times), 3))
    w = np.array(omega0, dtype=float)
    t = 0.0
    for k, target in enumerate(times):
        while t < target - 1e-12:
            step = min(h, target - t)
            k1 = rate(w)
            k2 = rate(w + 0.5 * step * k1)
            k3 = rate(w + 0.5 * step * k2)
            k4 = rate(w + step * k3)
            w = w + step / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            t += step
        out[k] = w
    return out


def body_omega(displacement: np.ndarray, velocity: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Body-axis angular velocity from three tracked corners (o, +x, +y: history arrays of shape
    (records, 3 tracks, 3)): the body axes from their positions, omega from their velocities."""
    x = start[None, :, :] + displacement
    e1 = x[:, 1] - x[:, 0]
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = x[:, 2] - x[:, 0]
    e2 /= np.linalg.norm(e2, axis=1)[:, None]
    e3 = np.cross(e1, e2)
    dv1 = velocity[:, 1] - velocity[:, 0]    # omega x (x1 - x0): along e2 and e3
    dv2 = velocity[:, 2] - velocity[:, 0]
    a, b = SIDES
    w3 = np.einsum("ij,ij->i", dv1, e2) / a
    w2 = -np.einsum("ij,ij->i", dv1, e3) / a
    w1 = np.einsum("ij,ij->i", dv2, e3) / b
    return np.stack([w1, w2, w3], axis=1)


def impact(end_time: float) -> paradyn.deck.Model:
    """A rigid plate (0.1 m square, 5 mm, the impactor) falling at 20 m/s onto a free steel plate
    (0.2 m square, 2 mm) 1 mm below it, node-to-segment contact; nothing holds either."""
    scene = paradyn.Scene("rigid impact", end_time=end_time, output_interval=end_time / 4,
                          history_interval=end_time / 40)
    scene.add_material("steel", model="elastic", **STEEL)
    scene.add_material("rigid_steel", model="rigid", **STEEL)
    scene.add_part("target", material="steel", thickness=0.002,
                   geometry=paradyn.Plate(size=(0.2, 0.2), elements=(16, 16)))
    scene.add_part("impactor", material="rigid_steel", thickness=0.005, initial_velocity=[0.0, 0.0, -20.0],
                   geometry=paradyn.Plate(size=(0.1, 0.1), elements=(5, 5), origin=[0.05, 0.05, 0.0045]))
    scene.add("rigid_body", part="impactor")
    scene.add_contact("impactor", "target")
    return scene.build()
