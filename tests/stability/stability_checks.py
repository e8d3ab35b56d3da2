"""The stability suite's criteria (issue 15 item 4) and how one case is run and measured.

Criteria, each pass or fail (``None``: does not apply to the case):

- ``finishes``: the engine ran to the end time (exit status 0, a complete results file);
- ``finite``: no NaN or Inf in any history column;
- ``balance``: energy balance error (``paradyn.results.reports.energy_report``) under 1 %;
- ``hourglass``: the largest hourglass / internal energy over the history records whose internal
  energy exceeds 0.1 % of the initial total energy, under 10 %;
- ``penetration``: the deepest contact penetration (history ``contact_penetration``) under 20 % of the
  thinnest wall of the contact pairs (cases with contact pairs; a rigid wall's penetration is not in
  that column);
- ``momentum``: for a free body (no fixed dof, rigid wall, load, gravity or prescribed motion) the
  total momentum of every frame, ``sum_i m_i v_i``, within 1e-10 of the first frame's, relative to
  ``|P(0)|``. The frames hold the nodal velocities; the masses are the engine's lumped masses
  rebuilt from the deck (docs/theory.md: each element gives a quarter of rho t A, A its area at the
  initial coordinates), and their sum is checked against the engine's ``/run model_mass_kg``.

The angular momentum about the centre of mass, ``sum_i m_i (x_i - x_c) x v_i``, is reported for the
free cases (its largest change over the frames relative to ``sum_i m_i |x_i - x_c| |v_i|`` at the first
frame, a scale that is not zero where the angular momentum itself starts at zero) but not judged: the
frames hold no rotation rates, so the nodal rotational inertia's part is missing from it and it is
not a conserved quantity by itself.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import paradyn
from paradyn import deck
from paradyn.results import reports

LIMITS = {"balance": 0.01, "hourglass": 0.10, "penetration": 0.20, "momentum": 1e-10}
CRITERIA = ("finishes", "finite", "balance", "hourglass", "penetration", "momentum")
THREADS = 2


@dataclass
class Outcome:
    """What one run of a case measured, and the pass (True) / fail (False) / n.a. (None) per criterion."""

    name: str
    balance_error: float | None = None
    peak_hourglass: float | None = None
    penetration: float | None = None
    momentum_error: float | None = None
    angular_momentum_error: float | None = None
    dt_min: float | None = None
    dt_max: float | None = None
    wall_s: float = 0.0
    cycles: int = 0
    message: str = ""
    probe: str = ""          # what the case's own probe measured (Case.probe), for the notes
    passed: dict[str, bool | None] = field(default_factory=dict)

    @property
    def overall(self) -> bool:
        return all(v is not False for v in self.passed.values())


def lumped_masses(model: deck.Model) -> np.ndarray:
    """The engine's lumped nodal masses (kg): a quarter of rho t A of each element to each node."""
    c = model.coordinates[model.connectivity]
    area = 0.5 * np.linalg.norm(np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]), axis=1)
    part = model.element_part
    rho_t = np.asarray(model.density)[np.asarray(model.part_material)[part]] * np.asarray(model.thickness)[part]
    mass = np.zeros(len(model.coordinates))
    np.add.at(mass, model.connectivity.ravel(), np.repeat(0.25 * rho_t * area, 4))
    return mass


def is_free(model: deck.Model) -> bool:
    """No constraint or external force: total momentum must stay as it started."""
    control = model.control
    return bool((model.fixed_dofs is None or not np.any(model.fixed_dofs)) and len(model.rigid_wall_point) == 0
                and len(model.load_node) == 0 and len(model.pressure_part) == 0 and len(model.prescribed_node) == 0
                and control.gravity_x == control.gravity_y == control.gravity_z == 0.0)


def peak_hourglass(history: dict[str, np.ndarray]) -> float | None:
    """Largest hourglass / internal energy over the records whose internal energy exceeds 0.1 % of the
    initial total energy (None when no record does)."""
    internal, hourglass = history["internal_energy"], history["hourglass_energy"]
    total0 = float(history["kinetic_energy"][0] + internal[0] + hourglass[0] + history["contact_energy"][0]
                   - history["external_work"][0])
    keep = internal > 1e-3 * abs(total0)
    return float(np.max(hourglass[keep] / internal[keep])) if np.any(keep) else None


def momentum_errors(results: paradyn.Results, mass: np.ndarray) -> tuple[float, float]:
    """Largest relative change of the total momentum and of the (translational) angular momentum about
    the centre of mass over the frames."""
    x0 = results.coordinates
    p, h, scale = [], [], 0.0
    for k in range(results.n_frames):
        v = results.velocity[k]
        x = x0 + results.displacement[k]
        p.append(mass @ v)
        arm = x - mass @ x / mass.sum()
        h.append(np.sum(mass[:, None] * np.cross(arm, v), axis=0))
        if k == 0:   # sum m |r| |v|: the scale of the angular momentum, also where it starts at zero
            scale = float(np.sum(mass * np.linalg.norm(arm, axis=1) * np.linalg.norm(v, axis=1)))
    p, h = np.array(p), np.array(h)
    momentum = float(np.max(np.linalg.norm(p - p[0], axis=1)) / np.linalg.norm(p[0]))
    angular = float(np.max(np.linalg.norm(h - h[0], axis=1)) / max(scale, 1e-300))
    return momentum, angular


def run_case(name: str, model: deck.Model, folder: Path,
             probe: Callable[[paradyn.Results, deck.Model], str] | None = None) -> Outcome:
    """Run ``model`` into ``folder`` (one rank, two threads, no post-processing) and judge it; a
    case's ``probe`` measures what the criteria do not (its text goes into ``Outcome.probe``)."""
    out = Outcome(name)
    start = time.perf_counter()
    try:
        results = paradyn.run(model, folder, ranks=1, threads=THREADS, post=False)
        finished = bool(results.complete)
    except Exception as exc:   # the engine stopped early: judge what it wrote
        out.message = f"{type(exc).__name__}: {str(exc).splitlines()[0][:160]}"
        finished = False
        try:
            results = paradyn.read(folder / "results.h5", allow_incomplete=True)
        except Exception as read_exc:
            out.message += f"; no results: {str(read_exc).splitlines()[0][:120]}"
            out.wall_s = time.perf_counter() - start
            out.passed = {c: False if c == "finishes" else None for c in CRITERIA}
            return out
    out.wall_s = time.perf_counter() - start
    _judge(out, results, model, finished)
    if probe is not None and results.n_frames > 0:
        out.probe = probe(results, model)
    return out


def _judge(out: Outcome, results: paradyn.Results, model: deck.Model, finished: bool) -> None:
    h = results.history
    out.cycles = int(results.run.get("cycles", 0) or 0)
    finite = all(np.all(np.isfinite(np.asarray(v, dtype=np.float64))) for v in h.values())
    out.balance_error = reports.energy_report(results)["balance_error"]
    out.peak_hourglass = peak_hourglass(h) if results.n_records else None
    if results.n_records and "dt" in h:
        out.dt_min, out.dt_max = float(np.min(h["dt"])), float(np.max(h["dt"]))
    if model.n_contacts and results.n_records:
        thinnest = float(np.min(np.asarray(model.thickness)[np.asarray(model.contact_pairs).ravel()]))
        out.penetration = float(np.max(h["contact_penetration"])) / thinnest
    if is_free(model) and results.n_frames > 1:
        mass = lumped_masses(model)
        engine_mass = results.run.get("model_mass_kg")
        if engine_mass is not None and abs(mass.sum() - engine_mass) > 1e-9 * engine_mass:
            out.message += f" lumped masses sum to {mass.sum():.6g} kg, the engine's {engine_mass:.6g} kg;"
        out.momentum_error, out.angular_momentum_error = momentum_errors(results, mass)
    out.passed = {
        "finishes": finished,
        "finite": finite,
        "balance": _below(out.balance_error, LIMITS["balance"]),
        "hourglass": _below(out.peak_hourglass, LIMITS["hourglass"], missing=None),
        "penetration": _below(out.penetration, LIMITS["penetration"], missing=None),
        "momentum": _below(out.momentum_error, LIMITS["momentum"], missing=None),
    }


def _below(value: float | None, limit: float, missing: bool | None = False) -> bool | None:
    """value < limit; ``missing`` where there is no value (False: a value was due, e.g. NaN energies)."""
    if value is None:
        return missing
    return bool(np.isfinite(value) and value < limit)
