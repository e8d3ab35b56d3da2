"""What a run will cost and what looks wrong in it, before it starts (``paradyn-run --check``).

From the deck model alone (no engine): the mass of every part, the stable time step and the
element that controls it (the engine's formula, docs/theory.md "Mass and time step"), the cycles,
an estimate of the wall time and of the memory, and warnings for values that look like another
unit system's habits (a thickness of 2 meaning millimetres, a density of 2.7e-9 meaning
tonne/mm^3). ``paradyn-run`` prints these lines at the start of every run; ``--check`` adds the
engine's own set-up (:func:`engine_check`: its refusals and the initial contact penetrations) and
stops there. docs/scene.md, "Checking a scene before a run", lists the warnings.
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from paradyn import _schema, deck
from paradyn.deck.model import trait_codes

from . import launch
from .engine_process import EngineError, follow_engine
from .machine_rate import MachineRate, cache_path, cached_rate, measure_rate

# Element-cycles per second on one core before this machine's is measured (paradyn-run --check
# measures it once and caches it: machine_rate.py): the pipe whip (1024 elements, contact, J2) on
# the development machine, docs/performance.md "Scaling" (2.2e6 at 1 x 1 on both meshes). A run on
# more cores is estimated at 75 % parallel efficiency (the 1 x 2 and 2 x 1 rows there: 74 to 89 %).
RATE_PER_CORE = 2.2e6
RATE_SOURCE = "2.2e6 per core of the development machine, docs/performance.md; paradyn-run --check measures this one's"
RATE_ENV = "PARADYN_ELEMENT_RATE"   # this machine's figure (summary.json element_cycles_per_s) overrides it
PARALLEL_EFFICIENCY = 0.75
# the engine's memory estimate per rank (app/machine_memory.f90): a base plus so much per element or node
MEMORY_BASE_MB, MEMORY_PER_ENTITY_MB = 40.0, 2.0e-3
# a stored point beyond those (9 doubles), counted 3 x integration_points per element with a fully
# integrated part (its 4 in-plane points): the engine's upper bound
MEMORY_PER_POINT_MB = 9 * 8 / 2**20
# plausible engineering materials in SI units (kg/m^3, Pa, m/s): outside these a unit slip is likelier
DENSITY_RANGE = (30.0, 3.0e4)          # foams of 30 kg/m^3 to the densest metals (osmium 22 600)
YOUNG_RANGE = (1.0e5, 1.2e12)          # soft rubbers and foams to diamond
WAVE_SPEED_RANGE = (20.0, 2.0e4)       # sqrt(E / rho): soft rubber to beryllium and diamond
THICKNESS_FRACTION = 0.25              # a shell thicker than this fraction of its part's smallest extent
LARGE_EXTENT_M = 100.0                 # a part larger than this, in metres, looks drawn in millimetres
CYCLE_LIMIT = 1.0e7                    # more cycles than this get a warning (the engine refuses 1e9 and up)


@dataclass(frozen=True)
class PartMass:
    """One part: its name, elements, mass (kg), the mass scaling adds (kg), thickness and extent (m)."""

    name: str
    elements: int
    mass_kg: float
    added_kg: float
    thickness: float
    smallest_extent: float
    largest_extent: float


@dataclass(frozen=True)
class StableStep:
    """The stable step (s, safety factor included) and the element that controls it."""

    dt: float
    element: int        # 0-based global element id (the smallest id among equal steps, as the engine)
    part: str
    length: float       # L = area / longest side (m)
    wave_speed: float   # c = sqrt(E / (rho (1 - nu^2))) of the element's part (m/s)


@dataclass
class Preflight:
    """Everything the check says about a model on a layout."""

    parts: list[PartMass]
    step: StableStep
    dt: float                  # the engine's first step: the stable one, or a smaller requested one
    cycles: int
    end_time: float
    n_elements: int
    n_nodes: int
    ranks: int
    threads: int
    rate: float                # element-cycles per second assumed for the wall time
    rate_source: str
    warnings: list[str] = field(default_factory=list)
    extra_points: int = 0      # stored points per element beyond the one-point element's

    @property
    def wall_s(self) -> float:
        return self.cycles * self.n_elements / self.rate

    @property
    def memory_mb(self) -> float:
        """The engine's estimate per rank times the ranks (each rank holds its share of the mesh)."""
        share = max(-(-self.n_elements // self.ranks), -(-self.n_nodes // self.ranks))
        elements = -(-self.n_elements // self.ranks)
        return self.ranks * (MEMORY_BASE_MB + MEMORY_PER_ENTITY_MB * share
                             + MEMORY_PER_POINT_MB * self.extra_points * elements)

    def lines(self) -> list[str]:
        """The check's report, one line each (the warnings last, starting with ``warning:``)."""
        out = [f"{len(self.parts)} part(s), {self.n_elements} elements, {self.n_nodes} nodes"]
        for p in self.parts:
            added = f" (+{p.added_kg:.4g} kg mass scaling)" if p.added_kg > 0 else ""
            out.append(f"  part {p.name}: {p.elements} elements, mass {p.mass_kg:.4g} kg{added}, "
                       f"thickness {p.thickness:.4g} m")
        s = self.step
        out.append(f"stable step {s.dt:.4e} s, set by element {s.element} of part {s.part} "
                   f"(L = {s.length:.4g} m, c = {s.wave_speed:.4g} m/s)")
        if self.dt < s.dt:
            out.append(f"requested step {self.dt:.4e} s (fixed)")
        out.append(f"about {self.cycles} cycles to end_time {self.end_time:.4g} s, wall time about "
                   f"{_duration(self.wall_s)} on {self.ranks} x {self.threads}")
        out.append(f"  (at {self.rate:.3g} element-cycles/s: {self.rate_source})")
        out.append(f"memory about {self.memory_mb:.0f} MiB ({self.ranks} rank(s))")
        return out + [f"warning: {w}" for w in self.warnings]


def element_steps(model: deck.Model) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per element: the stable step L / c (no safety factor, no mass scaling), L, the area and c.

    The engine's ``blt_stable_time_step``: the area is that of the element's co-rotational frame,
    half the norm of the cross product of the diagonals, and L is the area over the longest side. A
    truss's (``truss_stable_time_step``): L its length, c = sqrt(E / rho), and as its area the
    volume A L over the part's thickness (so that rho t area is its mass, as for a shell)."""
    x = np.asarray(model.coordinates, dtype=float)[np.asarray(model.connectivity)]   # (n, 4, 3)
    area = 0.5 * np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1]), axis=1)
    longest = np.linalg.norm(np.roll(x, -1, axis=1) - x, axis=2).max(axis=1)
    material = np.asarray(model.part_material)[np.asarray(model.element_part)]
    rho, young = np.asarray(model.density, float), np.asarray(model.youngs_modulus, float)
    nu = np.asarray(model.poisson_ratio, float)
    c = np.sqrt(young / (rho * (1.0 - nu**2)))[material]
    length = area / longest
    truss = _truss_elements(model)
    if truss.any():   # element/truss_element: L the length, c the bar wave speed sqrt(E / rho)
        length = np.where(truss, np.linalg.norm(x[:, 1] - x[:, 0], axis=1), length)
        c = np.where(truss, np.sqrt(young / rho)[material], c)
        # the volume A L as the "area" whose rho t area is the element's mass
        area = np.where(truss, _truss_area(model) * length / np.asarray(model.thickness, float)[
            np.asarray(model.element_part)], area)
    dt = length / c
    rigid = np.isin(np.asarray(model.material_model), trait_codes("material_model", "rigid"))[material]
    if rigid.any() and not rigid.all():   # a rigid body's elements set no step (engine: mass_scaling_setup)
        dt = np.where(rigid, np.inf, dt)
    return dt, length, area, c


def _truss_elements(model: deck.Model) -> np.ndarray:
    """Whether each element is of a truss part."""
    kinds = np.asarray(model.element_kind if model.element_kind is not None else np.ones(len(model.thickness)))
    return np.isin(kinds, trait_codes("element_kind", "truss"))[np.asarray(model.element_part)]


def _truss_area(model: deck.Model) -> np.ndarray:
    """Each element's part's cross-section area (0 where none is given)."""
    area = np.zeros(len(np.asarray(model.thickness))) if model.cross_section_area is None \
        else np.asarray(model.cross_section_area, float)
    return area[np.asarray(model.element_part)]


def _part_names(model: deck.Model) -> list[str]:
    n = len(np.asarray(model.thickness))
    names = list(model.part_names)[:n]
    return [*names, *(f"part_{i}" for i in range(len(names), n))]


def _parts(model: deck.Model, area: np.ndarray, added: np.ndarray) -> list[PartMass]:
    element_part = np.asarray(model.element_part)
    thickness = np.asarray(model.thickness, float)
    rho = np.asarray(model.density, float)[np.asarray(model.part_material)]
    coords, conn = np.asarray(model.coordinates, float), np.asarray(model.connectivity)
    parts = []
    for p, name in enumerate(_part_names(model)):
        mine = element_part == p
        nodes = np.flatnonzero(np.bincount(conn[mine].ravel(), minlength=len(coords)))  # np.unique: +20 ms
        extent = np.ptp(coords[nodes], axis=0) if nodes.size else np.zeros(3)
        nonzero = extent[extent > 0]
        surface_only = model.surface_only is not None and bool(np.asarray(model.surface_only)[p])
        mass = (float(np.asarray(model.added_mass)[nodes].sum()) if surface_only   # a rigid solid's faces
                else float(rho[p] * thickness[p] * area[mine].sum()))
        parts.append(PartMass(name=name, elements=int(mine.sum()), mass_kg=mass,
                              added_kg=float(added[p]), thickness=float(thickness[p]),
                              smallest_extent=float(nonzero.min()) if nonzero.size else 0.0,
                              largest_extent=float(extent.max())))
    return parts


def _mass_scaled(model: deck.Model, dt: np.ndarray, area: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The element steps after mass scaling to ``/control mass_scaling_step`` (as the engine's
    ``mass_scaling_setup``) and the mass it adds per part (kg)."""
    control = model.control
    n_parts = len(np.asarray(model.thickness))
    if control.mass_scaling_step <= 0:
        return dt, np.zeros(n_parts)
    wanted = control.mass_scaling_step / control.time_step_safety
    scale = np.where(dt < wanted, wanted / dt, 1.0)
    part = np.asarray(model.element_part)
    rho = np.asarray(model.density, float)[np.asarray(model.part_material)][part]
    mass = rho * np.asarray(model.thickness, float)[part] * area
    added = np.bincount(part, weights=(scale**2 - 1.0) * mass, minlength=n_parts)
    return dt * scale, added


def stable_step(model: deck.Model) -> tuple[StableStep, np.ndarray, np.ndarray]:
    """The model's stable step and controlling element; also the element areas and the mass
    scaling adds per part."""
    dt, length, area, c = element_steps(model)
    dt, added = _mass_scaled(model, dt, area)
    k = int(np.argmin(dt))
    part = int(np.asarray(model.element_part)[k])
    step = StableStep(dt=float(model.control.time_step_safety * dt[k]), element=k,
                      part=_part_names(model)[part], length=float(length[k]), wave_speed=float(c[k]))
    return step, area, added


def first_step(control: deck.Control, dt_stable: float) -> tuple[float, int]:
    """The engine's first step and its step count (``step_clock.clock_setup``): a requested step
    at or below the stable one is fixed, end_time / n for a whole n; otherwise the stable step."""
    end = control.end_time
    if 0 < control.time_step <= dt_stable:
        n = max(1, math.ceil(end / control.time_step - 1e-9))
        return end / n, n
    return dt_stable, max(1, math.ceil(end / dt_stable - 1e-9))


def element_rate(ranks: int, threads: int, machine: MachineRate | None = None) -> tuple[float, str]:
    """Element-cycles per second for the wall-time estimate, and where the figure comes from:
    $PARADYN_ELEMENT_RATE, else ``machine`` (this machine's, measured once and cached:
    :mod:`paradyn.running.machine_rate`), else the development machine's."""
    override = os.environ.get(RATE_ENV, "").strip()
    if override:
        try:
            rate = float(override)
        except ValueError:
            rate = 0.0
        if rate > 0:
            return rate, f"${RATE_ENV}"
    cores = ranks * threads
    efficiency = 1.0 if cores == 1 else PARALLEL_EFFICIENCY
    if machine is not None:
        per_core = machine.per_core
        source = (f"{per_core:.3g} per core, {'measured now' if machine.measured_now else 'measured'} on this "
                  f"machine ({machine.cpu}; cached in {cache_path()})")
    else:
        per_core, source = RATE_PER_CORE, RATE_SOURCE
    return per_core * cores * efficiency, source + (
        f" x {cores} cores at {PARALLEL_EFFICIENCY:.0%}" if cores > 1 else "") + f"; ${RATE_ENV} sets it"


def this_machine(precision: str | None, measure: bool = False) -> MachineRate | None:
    """The element rate of this machine's engine of ``precision``: cached, or with ``measure``
    measured now when it is not (about a second; ``paradyn-run --check``); None when there is none
    (not measured yet, or no engine)."""
    try:
        engine = launch.engine_path(precision)
        return cached_rate(engine) or (measure_rate(engine) if measure else None)
    except (EngineError, OSError, KeyError, ValueError):
        return None


def check_model(model: deck.Model, ranks: int = 1, threads: int = 1, machine: MachineRate | None = None) -> Preflight:
    """The check of a deck model on ``ranks`` x ``threads`` (see the module's description);
    ``machine``: this machine's rate (:func:`this_machine`), by default the cached one if any."""
    step, area, added = stable_step(model)
    dt, cycles = first_step(model.control, step.dt)
    rate, source = element_rate(ranks, threads, machine or this_machine(model.control.precision))
    result = Preflight(parts=_parts(model, area, added), step=step, dt=dt, cycles=cycles,
                       end_time=model.control.end_time, n_elements=len(np.asarray(model.element_part)),
                       n_nodes=len(np.asarray(model.coordinates)), ranks=ranks, threads=threads,
                       rate=rate, rate_source=source, extra_points=_extra_points(model))
    result.warnings = unit_warnings(model, result) + idle_warnings(model) + setting_warnings(model)
    return result


def _default_points() -> int:
    return int(next(d.default for d in _schema.DATASETS if d.path == "/parts/integration_points"))


def _extra_points(model: deck.Model) -> int:
    """3 x the most integration points of a fully integrated part (0 without one), as the engine's
    memory estimate (app/machine_memory.f90)."""
    if model.shell_element is None:
        return 0
    full = np.asarray(model.shell_element) == _schema.ENUMS["shell_element"]["full"]
    if not full.any():
        return 0
    points = np.asarray(model.integration_points if model.integration_points is not None
                        else np.full(full.shape, _default_points()))
    return 3 * int(points[full].max())


# coefficients far outside any sensible range (the usual values are 0.05 to 0.15 and 0.1)
HOURGLASS_COEFFICIENT_SUSPECT = 1.0
PENALTY_SCALE_SUSPECT = 10.0


def setting_warnings(model: deck.Model) -> list[str]:
    """Settings that run but rarely mean what was meant: an output or history interval longer
    than the run, and an hourglass coefficient or contact penalty scale far outside the usual."""
    out: list[str] = []
    c = model.control
    for name in ("output_interval", "history_interval"):
        value = getattr(c, name)
        if value is not None and value > c.end_time:
            out.append(f"{name} {value:g} s is longer than end_time {c.end_time:g} s: only the start and the end "
                       f"are recorded; give an interval below end_time")
    names = _part_names(model)
    for part, coefficient in enumerate(np.asarray(model.hourglass_coefficient, dtype=float)):
        if coefficient > HOURGLASS_COEFFICIENT_SUSPECT:
            out.append(f"part {names[part]}: hourglass coefficient {coefficient:g} is far above the usual 0.05 to "
                       f"0.15 (it stiffens the element against its own bending); use 0.1, or the physical form")
    scales = model.contact_penalty_scale
    for k, scale in enumerate(np.asarray(scales if scales is not None else [], dtype=float)):
        if scale > PENALTY_SCALE_SUSPECT:
            out.append(f"contact {k}: penalty scale {scale:g} is far above the usual 0.1 (1 for stiff contact): "
                       f"the contact springs may set a step the run does not take; use 0.1 to 1")
    return out


def idle_warnings(model: deck.Model) -> list[str]:
    """A warning when nothing in the model moves or is loaded: no initial velocity, point load,
    pressure, gravity, base acceleration, prescribed motion (of nodes or of a rigid body) or moving
    rigid wall (every energy would stay zero)."""
    velocities = (model.initial_velocity, model.initial_angular_velocity)
    moving = [np.any(np.asarray(v, dtype=float) != 0.0) for v in velocities if v is not None]
    walls = model.rigid_wall_velocity
    driven = model.rigid_body_prescribed is not None and model.rigid_body_velocity is not None and bool(
        np.any((np.asarray(model.rigid_body_prescribed) != 0) & (np.asarray(model.rigid_body_velocity) != 0.0)))
    acting = (any(moving) or driven or model.n_loads > 0 or model.n_pressures > 0 or model.n_prescribed > 0
              or model.n_base_accelerations > 0
              or any(g != 0.0 for g in model.gravity)
              or (walls is not None and bool(np.any(np.asarray(walls, dtype=float) != 0.0))))
    if acting:
        return []
    return ["nothing in this model moves or is loaded (no initial velocity, load, pressure, gravity, base "
            "acceleration, prescribed motion or moving rigid wall): every energy will stay zero; give the loading "
            "the model was made for"]


def unit_warnings(model: deck.Model, check: Preflight) -> list[str]:
    """Warnings for values that look like another unit system's, each naming the habit and the fix."""
    names = list(model.material_names) + [f"material_{i}" for i in range(len(model.material_names),
                                                                          len(np.asarray(model.density)))]
    out: list[str] = []
    for name, rho, young, nu in zip(names, np.asarray(model.density, float), np.asarray(model.youngs_modulus, float),
                                    np.asarray(model.poisson_ratio, float), strict=False):
        out += material_warnings(name, float(rho), float(young), float(nu))
    for part in check.parts:
        out += part_warnings(part)
    if check.cycles > CYCLE_LIMIT:
        out.append(f"{check.cycles:.3g} cycles (end_time {check.end_time:.4g} s / step {check.dt:.3g} s) will "
                   f"take about {_duration(check.wall_s)}: check the units of density (kg/m^3), Young's modulus "
                   f"(Pa), thickness and coordinates (m) above, end_time (s) and the smallest element (element "
                   f"{check.step.element}), or set [run] mass_scaling_step")
    return out


def material_warnings(name: str, rho: float, young: float, nu: float) -> list[str]:
    """A material's density, Young's modulus and wave speed against engineering materials in SI."""
    out = []
    label = f"material {name}"
    if rho < 1e-7:
        modulus = ", and Young's modulus in Pa, not MPa (x 1e6)" if young < 1e7 else ""
        out.append(f"{label}: density {rho:.4g} looks like tonne/mm^3 (the mm-t-s system: 2.7e-9 for aluminium); "
                   f"give kg/m^3 (x 1e12: {rho * 1e12:.4g}){modulus}")
    elif rho < 1e-3:
        out.append(f"{label}: density {rho:.4g} looks like kg/mm^3 (7.85e-6 for steel); give kg/m^3 "
                   f"(x 1e9: {rho * 1e9:.4g})")
    elif rho < DENSITY_RANGE[0]:
        out.append(f"{label}: density {rho:.4g} looks like g/cm^3 (7.85 for steel); give kg/m^3 "
                   f"(x 1000: {rho * 1e3:.4g})")
    elif rho > DENSITY_RANGE[1]:
        out.append(f"{label}: density {rho:.4g} kg/m^3 is above every engineering material (osmium: 22 600); "
                   f"give kg/m^3")
    if young < 1e4:
        out.append(f"{label}: Young's modulus {young:.4g} looks like GPa (210 for steel); give Pa "
                   f"(x 1e9: {young * 1e9:.4g})")
    elif young < YOUNG_RANGE[0] or (young < 1e7 and DENSITY_RANGE[0] <= rho <= DENSITY_RANGE[1]
                                    and math.sqrt(young / rho) < WAVE_SPEED_RANGE[0]):
        out.append(f"{label}: Young's modulus {young:.4g} looks like MPa (210000 for steel); give Pa "
                   f"(x 1e6: {young * 1e6:.4g})")
    elif young > YOUNG_RANGE[1]:
        out.append(f"{label}: Young's modulus {young:.4g} Pa is above every engineering material (diamond: "
                   f"1.2e12 Pa); give Pa")
    c = math.sqrt(young / (rho * (1.0 - nu**2))) if rho > 0 and nu < 1 else float("nan")
    if not out and not WAVE_SPEED_RANGE[0] <= c <= WAVE_SPEED_RANGE[1]:
        out.append(f"{label}: the wave speed sqrt(E / (rho (1 - nu^2))) = {c:.4g} m/s is outside "
                   f"{WAVE_SPEED_RANGE[0]:g} to {WAVE_SPEED_RANGE[1]:g} m/s of engineering materials; check that "
                   f"density is in kg/m^3 and Young's modulus in Pa")
    return out


def part_warnings(part: PartMass) -> list[str]:
    """A part's thickness against its size, and its size against a machine part in metres."""
    out = []
    if part.smallest_extent > 0 and part.thickness > THICKNESS_FRACTION * part.smallest_extent:
        out.append(f"part {part.name}: thickness {part.thickness:.4g} m is more than {THICKNESS_FRACTION:g} of "
                   f"the part's smallest extent ({part.smallest_extent:.4g} m), beyond a thin shell; if it is in "
                   f"millimetres, give metres ({part.thickness / 1e3:.4g})")
    if part.largest_extent > LARGE_EXTENT_M:
        out.append(f"part {part.name}: it spans {part.largest_extent:.4g} m; if the geometry is in millimetres, "
                   f"give metres (size, origin, radius, length, and a mesh file's scale)")
    return out


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    if seconds < 120:
        return f"{seconds:.2g} s"
    if seconds < 2 * 3600:
        return f"{seconds / 60:.3g} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 86400:.3g} days"


@dataclass(frozen=True)
class EngineCheck:
    """The engine's own set-up of a deck (``paradyn-engine --check``): its step and its warnings."""

    dt: float
    dt_stable: float
    steps: int
    warnings: list[str]


def engine_check(model: deck.Model, threads: int = 1) -> EngineCheck:
    """Set the run up in the engine on one rank and stop before it writes anything.

    Raises
    ------
    paradyn.running.launch.EngineError
        The engine refuses the deck (its message, status 2): the same refusal a run would get."""
    with tempfile.TemporaryDirectory(prefix="paradyn-check-") as folder:
        deck_path = deck.write_deck(model, Path(folder) / "deck.h5")
        command = [str(launch.engine_path(model.control.precision)), str(deck_path), "--check"]
        run = follow_engine(command, launch.engine_environment(threads), Path(folder), done_kind="CHECK")
    fields = run.done
    try:
        return EngineCheck(dt=float(fields["dt"]), dt_stable=float(fields["dt_stable"]), steps=int(fields["steps"]),
                           warnings=[w.removeprefix("paradyn-engine: ") for w in run.warnings])
    except (KeyError, ValueError) as error:
        raise EngineError(f"the engine's PARADYN-CHECK line lacks {error}; rebuild it (make install)", 1) from error
