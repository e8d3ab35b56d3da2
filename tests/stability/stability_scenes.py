"""The stability suite's cases (issue 15 item 4), built as scene tables in Python.

Every case starts from the scene of ``cases/pipe_whip`` (the paper's case-1 geometry and steel) read
with ``tomllib``, edits the tables (thickness, velocities, positions, meshes, extra parts, rigid
walls), writes them as a scene file, and builds the deck with ``paradyn.scene.load_scene`` and
``build_model``; the model's arrays are then edited where a scene cannot say it (the skewed mesh's
coordinates) and every part gets the element a user picks for a hard case: the fully integrated
element with the warping correction (``build_model(element="blt")``: the one-point element with the
physical hourglass form; ``Case.paper_element`` keeps the scene's element instead).

``Case.short`` gives the coarse, short variant that ``make test`` runs (tests/stability/test_stability_short.py).
"""

from __future__ import annotations

import copy
import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from stability_shapes import (
    PLATEN_FRICTION,
    SPHERE_RADIUS,
    TUBE_LENGTH,
    TUBE_SPEED,
    TUBE_WALL,
    abramowicz_jones_force,
    mean_crush_force,
    mix_triangles,
    sphere_file,
    to_square,
)

from paradyn import deck, scene
from paradyn._schema import ENUMS

ROOT = Path(__file__).resolve().parents[2]
PIPE_WHIP = ROOT / "cases" / "pipe_whip" / "scene.toml"
FIG3 = ROOT / "cases" / "pipe_whip_fig3" / "scene.toml"
RADIUS = 0.08          # mid-surface radius of the paper's pipes (m)
THICKNESS = 0.003      # the paper's wall (m)

Table = dict[str, Any]


@dataclass(frozen=True)
class Variant:
    """What the short variant changes: mesh refinement divisor and end time (s)."""

    coarsen: int
    end_time: float


@dataclass(frozen=True)
class Case:
    """A stability case: its name, what it is, how its scene tables are built (``build(coarsen)``, 1 = full
    mesh), the full run's end time, the short variant, and whether it keeps the paper's element."""

    name: str
    what: str
    build: Callable[[int], Table]
    end_time: float
    short: Variant
    paper_element: bool = False
    edit: Callable[[deck.Model], None] | None = None   # edits of the built model's arrays
    probe: Callable[[Any, deck.Model], str] | None = None   # what the criteria do not measure (a note)
    element: str | None = None   # the shell element this case needs, whatever the suite's (None: the suite's)


# ---------------------------------------------------------------------------------------------------
# scene tables -> TOML -> model


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, int | float):
        return repr(float(v)) if isinstance(v, float) else str(v)
    return "[" + ", ".join(_value(x) for x in v) + "]"


def to_toml(table: Table, prefix: str = "") -> str:
    """The TOML text of a scene table (scalars, lists, sub-tables and arrays of tables)."""
    lines = [f"{k} = {_value(v)}" for k, v in table.items()
             if not isinstance(v, dict) and not (isinstance(v, list) and v and isinstance(v[0], dict))]
    for k, v in table.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict):
            lines += ["", f"[{name}]", to_toml(v, f"{name}.")]
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                lines += ["", f"[[{name}]]", to_toml(item, f"{name}.")]
    return "\n".join(lines)


def build_model(case: Case, folder: Path, short: bool, refine: int = 1, element: str = "full") -> deck.Model:
    """The deck model of ``case`` (its short variant when ``short``), its scene written into ``folder``;
    ``refine`` multiplies every generated part's element counts (a mesh study of the full case);
    ``element`` is every part's shell element unless the case keeps the paper's ("full": the fully
    integrated element a user picks for a hard case; "blt": the one-point element)."""
    tables = case.build(case.short.coarsen if short else 1)
    for part in tables["part"]:
        g = part["geometry"]
        if g["kind"] == "cylinder":
            g["elements_around"], g["elements_along"] = refine * g["elements_around"], refine * g["elements_along"]
        elif g["kind"] == "plate":
            g["elements"] = [refine * n for n in g["elements"]]
    tables["run"]["end_time"] = case.short.end_time if short else case.end_time
    tables["run"].pop("time_step", None)   # the automatic step that follows the mesh (the default)
    frames = 10 if short else 40
    tables["run"]["output_interval"] = tables["run"]["end_time"] / frames
    tables["run"]["history_interval"] = tables["run"]["end_time"] / (10 * frames)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "scene.toml"
    path.write_text(to_toml(tables) + "\n")
    model = scene.build_model(scene.load_scene(path))
    if case.edit is not None:
        case.edit(model)
    if not case.paper_element:
        n_parts = len(model.thickness)
        model.hourglass_form = np.full(n_parts, ENUMS["hourglass_form"]["physical"], dtype=np.int32)
        model.warping_correction = np.ones(n_parts, dtype=np.int32)
        model.shell_element = np.full(n_parts, ENUMS["shell_element"][case.element or element], dtype=np.int32)
    return model


# ---------------------------------------------------------------------------------------------------
# the pieces


def pipe_whip(source: Path = PIPE_WHIP) -> Table:
    """The tables of a pipe-whip scene, without its tracked points (cases move the pipes)."""
    tables = tomllib.loads(source.read_text())
    tables.pop("track", None)
    return copy.deepcopy(tables)


def _coarsen_pipes(tables: Table, coarsen: int) -> None:
    for part in tables["part"]:
        g = part["geometry"]
        if g["kind"] == "cylinder":
            g["elements_around"] = max(8, 4 * round(g["elements_around"] / coarsen / 4))
            g["elements_along"] = max(4, g["elements_along"] // coarsen)


def _part(tables: Table, name: str) -> Table:
    return next(p for p in tables["part"] if p["name"] == name)


def _plate_part(name: str, size: tuple[float, float], elements: tuple[int, int], origin: list[float],
                u: list[float], v: list[float], velocity: list[float] | None = None) -> Table:
    part: Table = {"name": name, "material": "steel", "thickness": THICKNESS, "integration_points": 5,
                   "geometry": {"kind": "plate", "size": list(size), "elements": list(elements), "origin": origin,
                                "u_axis": u, "v_axis": v}}
    if velocity is not None:
        part["initial_velocity"] = velocity
    return part


def _pipe_part(name: str, length: float, axis: list[float], center: list[float], around: int, along: int,
               velocity: list[float] | None = None) -> Table:
    part: Table = {"name": name, "material": "steel", "thickness": THICKNESS, "integration_points": 5,
                   "geometry": {"kind": "cylinder", "radius": RADIUS, "length": length, "axis": axis,
                                "center": center, "elements_around": around, "elements_along": along}}
    if velocity is not None:
        part["initial_velocity"] = velocity
    return part


def _contact(a: str, b: str, friction: float = 0.0) -> Table:
    table: Table = {"parts": [a, b], "penalty_scale": 0.1, "symmetric": True}
    if friction:
        table["static_friction"] = friction
    return table


def _edge_clamps(part: str, lo: tuple[float, float], hi: tuple[float, float], z: float) -> list[Table]:
    """Clamp boxes over the four edges of a plate in the plane z, spanning lo..hi in x and y."""
    e = 1e-6
    (x0, y0), (x1, y1) = lo, hi
    boxes = [((x0 - e, y0 - e), (x0 + e, y1 + e)), ((x1 - e, y0 - e), (x1 + e, y1 + e)),
             ((x0 - e, y0 - e), (x1 + e, y0 + e)), ((x0 - e, y1 - e), (x1 + e, y1 + e))]
    return [{"part": part, "box": [[a[0], a[1], z - e], [b[0], b[1], z + e]], "dofs": ["all"]} for a, b in boxes]


# ---------------------------------------------------------------------------------------------------
# the cases


def thin_walls(ratio: float, edges: bool = True) -> Callable[[int], Table]:
    """Case 1 with walls t = R / ratio and the upper pipe at 20 m/s (x10); the gap kept at 0.1 mm. A
    node moves about 0.1 mm a step at the elements' stable step, more than the thinner wall: the
    automatic contact limit (contact_closing_limit, 0.05 by default) cuts the step while the pipes
    are near and closing, the contact checks element edges
    against edges (``edges``: walls that cross between their nodes; docs/contact-edges.md), and its
    penalty scale is 1.0 (a thin wall's bulk-modulus penalty K A / d does not shrink with the wall,
    its nodes' masses do: at 0.1 the spring is weak next to them; the stability cap still bounds
    it at m / (4 dt^2); docs/theory.md)."""
    def build(coarsen: int) -> Table:
        tables = pipe_whip()
        tables["contact"][0]["edges"] = edges
        tables["contact"][0]["penalty_scale"] = 1.0
        t = RADIUS / ratio
        for part in tables["part"]:
            part["thickness"] = t
        upper = _part(tables, "upper_pipe")
        upper["initial_velocity"] = [10.0 * x for x in upper["initial_velocity"]]
        upper["geometry"]["center"] = [0.0, 0.0, 2.0 * RADIUS + t + 1e-4]
        _coarsen_pipes(tables, coarsen)
        return tables
    return build


def crush_100(coarsen: int, self_contact: bool = True) -> Table:
    """Case 1 with the upper pipe at 100 m/s (x50); the pipes' pair contact becomes one
    single-surface contact of both (each pipe against itself and the other), unless not
    ``self_contact``."""
    tables = pipe_whip()
    upper = _part(tables, "upper_pipe")
    upper["initial_velocity"] = [50.0 * x for x in upper["initial_velocity"]]
    if self_contact:
        tables["contact"] = [{"kind": "single_surface", "penalty_scale": 0.1}]
    _coarsen_pipes(tables, coarsen)
    return tables


def mid_ring_heights(results: Any, model: deck.Model) -> dict[str, float]:
    """Per pipe of case 1, the smallest distance over the frames between the nodes that started at
    the top and at the bottom of its middle ring, in wall thicknesses (below 0: the crushed walls
    passed through each other)."""
    x0 = np.asarray(model.coordinates)
    heights = {}
    for part, centre in ((0, (0.0, 0.0, 0.0)), (1, (0.0, 0.0, 2.0 * RADIUS + THICKNESS + 1e-4))):
        nodes = np.unique(np.asarray(model.connectivity)[np.asarray(model.element_part) == part])
        ends = []
        for sign in (1.0, -1.0):
            target = np.array(centre) + sign * np.array([0.0, 0.0, RADIUS])
            ends.append(nodes[np.argmin(np.linalg.norm(x0[nodes] - target, axis=1))])
        z = x0[ends, 2][None, :] + np.asarray(results.displacement)[:, ends, 2]
        heights[("lower_pipe", "upper_pipe")[part]] = float(np.min(z[:, 0] - z[:, 1])) / float(model.thickness[part])
    return heights


def crush_probe(results: Any, model: deck.Model) -> str:
    h = mid_ring_heights(results, model)
    return ("middle ring's top over its bottom, least over the frames: "
            + ", ".join(f"{name} {value:.3f} t" for name, value in h.items())
            + " (below 0: the walls passed through each other; the issue asks at least 1 t)")


def impact_probe(results: Any, model: deck.Model) -> str:
    """How much the contact did: the kinetic energy each moving part keeps, the contact impulse, the peak force."""
    h = results.history
    ke = h["part_kinetic_energy"]
    kept = ", ".join(f"{results.part_names[i]} keeps {100.0 * ke[-1, i] / ke[0, i]:.0f} % of its kinetic energy"
                     for i in range(ke.shape[1]) if ke[0, i] > 0.0)
    force = np.linalg.norm(h["contact_force"].sum(axis=1), axis=1)
    impulse = float(np.sum(force[1:] * np.diff(h["time"])))
    return (f"{kept}; contact impulse {impulse:.3g} N s, peak contact force {force.max():.3g} N at "
            f"{1e3 * h['time'][force.argmax()]:.3g} ms")


def fig3(coarsen: int) -> Table:
    """The paper's Figure 3 (free pipes, 20 m/s)."""
    tables = pipe_whip(FIG3)
    _coarsen_pipes(tables, coarsen)
    return tables


def sliding(coarsen: int) -> Table:
    """Two free pipes, the upper one crossing 0.4 m off the lower one's middle and moving obliquely
    (10 m/s along the lower pipe, 5 m/s along its own axis, 20 m/s down), Coulomb friction 0.3."""
    tables = pipe_whip(FIG3)
    upper = _part(tables, "upper_pipe")
    upper["geometry"]["center"] = [0.4, 0.0, 2.0 * RADIUS + THICKNESS + 1e-4]
    upper["initial_velocity"] = [10.0, 5.0, -20.0]
    tables["contact"] = [_contact("lower_pipe", "upper_pipe", friction=0.3)]
    _coarsen_pipes(tables, coarsen)
    return tables


SPIN_RATE = 500.0                          # rad/s about the pipe's axis (y)
SPIN_VELOCITY = (3.0, 0.0, -2.0)           # m/s, translation


def spinning(coarsen: int) -> Table:
    """A free pipe (1 m, elastic-plastic steel) alone, no contact: the spin is set on the model."""
    tables = pipe_whip()
    tables["part"] = [_pipe_part("pipe", 1.0, [0.0, 1.0, 0.0], [0.0, 0.0, 0.0], 16, 16)]
    for key in ("fix", "contact"):
        tables.pop(key, None)
    _coarsen_pipes(tables, coarsen)
    return tables


def set_spin(model: deck.Model) -> None:
    """Rigid motion: v = V + w x r (r from the axis), and every node's rotation rate w."""
    omega = np.array([0.0, SPIN_RATE, 0.0])
    model.initial_velocity = np.asarray(SPIN_VELOCITY) + np.cross(omega, model.coordinates)
    model.initial_angular_velocity = np.tile(omega, (len(model.coordinates), 1))


PLATE = 0.6            # side of the clamped plates (m)
SKEW = math.radians(55.0)


def _plate_hit_by_pipe(elements: tuple[int, int], coarsen: int) -> Table:
    """A clamped steel plate 0.6 m x 0.6 m (z = 0, centre at the origin) hit by a free 0.5 m pipe at 20 m/s."""
    tables = pipe_whip()
    h = PLATE / 2.0
    nx, ny = (max(2, n // coarsen) for n in elements)
    plate = _plate_part("plate", (PLATE, PLATE), (nx, ny), [-h, -h, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    pipe = _pipe_part("pipe", 0.5, [1.0, 0.0, 0.0], [0.0, 0.0, RADIUS + THICKNESS + 1e-4],
                      max(8, 16 // coarsen), max(4, 16 // coarsen), velocity=[0.0, 0.0, -20.0])
    tables["part"] = [plate, pipe]
    tables["fix"] = _edge_clamps("plate", (-h, -h), (h, h), 0.0)
    tables["contact"] = [_contact("plate", "pipe")]
    return tables


def skewed_plate(coarsen: int) -> Table:
    """The plate meshed 24 x 24, to be sheared into 55-degree parallelograms (``skew``)."""
    return _plate_hit_by_pipe((24, 24), coarsen)


def skew(model: deck.Model) -> None:
    """Shear the plate (part 0, centred on the origin): x += y tan(55 deg); its quads' corners go from
    90 to 35 and 145 degrees. Its clamps (chosen on the rectangle) go with their nodes."""
    nodes = np.unique(model.connectivity[model.element_part == 0])
    model.coordinates[nodes, 0] += model.coordinates[nodes, 1] * math.tan(SKEW)


def elongated_plate(coarsen: int) -> Table:
    """The plate meshed 12 x 120: quads of 50 mm x 5 mm (aspect ratio 10)."""
    return _plate_hit_by_pipe((12, 120), coarsen)


def mixed_plate(coarsen: int) -> Table:
    """The plate meshed 24 x 24, to be cut half into triangles (``mix_triangles``)."""
    return _plate_hit_by_pipe((24, 24), coarsen)


def sphere_on_plate(coarsen: int) -> Table:
    """A rigid ball (a 5 mm shell sphere of steel's density, 0.05 m radius) thrown at 20 m/s onto the
    middle of the clamped 0.6 m plate, 0.1 mm above it."""
    tables = _plate_hit_by_pipe((24, 24), coarsen)
    tables["material"].append({"name": "rigid_steel", "model": "rigid", "density": 7860.0,
                               "youngs_modulus": 200e9, "poisson_ratio": 0.28})
    ball = {"name": "ball", "material": "rigid_steel", "thickness": 0.005, "initial_velocity": [0.0, 0.0, -20.0],
            "geometry": {"kind": "file", "path": str(sphere_file(max(2, 8 // coarsen)))}}
    tables["part"] = [_part(tables, "plate"), ball]
    tables["rigid_body"] = [{"part": "ball"}]
    tables["contact"] = [_contact("plate", "ball")]
    return tables


def lift_ball(model: deck.Model) -> None:
    """Move the ball (part 1) from the origin to just above the plate: its lowest point 0.1 mm over
    the plate's upper surface."""
    nodes = np.unique(np.asarray(model.connectivity)[np.asarray(model.element_part) == 1])
    x = np.asarray(model.coordinates)
    x[nodes, 2] += SPHERE_RADIUS + 0.5 * (THICKNESS + 0.005) + 1e-4
    model.coordinates = x


def edge_drop(coarsen: int) -> Table:
    """A 0.3 m x 0.3 m plate, vertical (the y-z plane), falling edge-first at 20 m/s onto the middle of
    case 1's clamped lower pipe; the lower edge starts 1 mm above the pipe's outer surface."""
    tables = pipe_whip()
    n = max(4, 12 // coarsen)
    bottom = RADIUS + THICKNESS + 1e-3
    plate = _plate_part("plate", (0.3, 0.3), (n, n), [0.0, -0.15, bottom], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0],
                        velocity=[0.0, 0.0, -20.0])
    tables["part"] = [_part(tables, "lower_pipe"), plate]
    tables["contact"] = [_contact("lower_pipe", "plate")]
    _coarsen_pipes(tables, coarsen)
    return tables


def wall_crush(coarsen: int) -> Table:
    """A free 1 m pipe between a floor under it and a rigid wall above it closing at 20 m/s."""
    tables = pipe_whip()
    outer = RADIUS + THICKNESS / 2.0
    tables["part"] = [_pipe_part("pipe", 1.0, [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 16, 16)]
    for key in ("fix", "contact"):
        tables.pop(key, None)
    tables["rigid_wall"] = [{"point": [0.0, 0.0, -outer - 1e-4], "normal": [0.0, 0.0, 1.0]},
                            {"point": [0.0, 0.0, outer + 1e-4], "normal": [0.0, 0.0, -1.0],
                             "velocity": [0.0, 0.0, -20.0]}]
    _coarsen_pipes(tables, coarsen)
    return tables


def square_tube(coarsen: int) -> Table:
    """A square tube along z (side TUBE_SIDE at the mid-surface, 16 elements a side, 64 along), its
    bottom ring clamped, crushed by a plane wall closing from the top at TUBE_SPEED with Coulomb
    friction PLATEN_FRICTION (a dry steel platen, as in the crush tests); single-surface contact of
    the tube. Built as a 64-element cylinder that ``to_square`` flattens. On a frictionless wall the
    top edge slides freely and the first fold curls over the corners, whose elements the fully
    integrated element then turns inside out at 0.96 ms."""
    tables = pipe_whip()
    around, along = max(16, 64 // coarsen), max(16, 64 // coarsen)
    part = _pipe_part("tube", TUBE_LENGTH, [0.0, 0.0, 1.0], [0.0, 0.0, TUBE_LENGTH / 2.0], around, along)
    part["thickness"] = TUBE_WALL
    tables["part"] = [part]
    e, h = 1e-6, 2.0 * RADIUS       # the box holds the bottom ring before and after to_square
    tables["fix"] = [{"part": "tube", "box": [[-h, -h, -e], [h, h, e]], "dofs": ["all"]}]
    tables["contact"] = [{"kind": "single_surface", "penalty_scale": 1.0}]
    tables["rigid_wall"] = [{"point": [0.0, 0.0, TUBE_LENGTH + 1e-4], "normal": [0.0, 0.0, -1.0],
                             "velocity": [0.0, 0.0, -TUBE_SPEED], "friction": PLATEN_FRICTION}]
    return tables


def tube_probe(results: Any, model: deck.Model) -> str:
    mean, crush = mean_crush_force(results)
    ref = abramowicz_jones_force()
    return (f"mean crush force {mean / 1e3:.2f} kN over {crush * 1e3:.0f} mm of crush, {mean / ref:.3f} of "
            f"the Abramowicz-Jones estimate {ref / 1e3:.2f} kN (the issue asks within 20 %)")


CASES: list[Case] = [
    Case("thin_270", "case 1, t/R = 1/270, 20 m/s, edge contact, penalty 1.0 (the automatic contact limit)",
         thin_walls(270.0), 2.5e-3, Variant(1, 0.5e-3), probe=impact_probe),
    Case("thin_1000", "case 1, t/R = 1/1000, 20 m/s, edge contact, penalty 1.0 (the automatic contact limit)",
         thin_walls(1000.0), 2.5e-3, Variant(1, 0.5e-3), probe=impact_probe),
    Case("skew_55", "clamped plate, quads skewed 55 deg, pipe at 20 m/s", skewed_plate, 3.0e-3,
         Variant(2, 0.5e-3), edit=skew),
    Case("aspect_10", "clamped plate, quads of aspect 10, pipe at 20 m/s", elongated_plate, 3.0e-3,
         Variant(2, 0.5e-3)),
    Case("sliding_friction", "free pipes, off-centre oblique impact, friction 0.3", sliding, 5.0e-3,
         Variant(2, 0.5e-3)),
    Case("spinning_pipe", "free pipe, 500 rad/s about its axis, translating, no contact", spinning, 20.0e-3,
         Variant(2, 2.0e-3), edit=set_spin),
    Case("fig3", "paper Fig. 3: free pipes, 20 m/s, 60 ms", fig3, 60.0e-3, Variant(2, 1.0e-3)),
    Case("edge_drop", "plate dropped edge-first onto case 1's lower pipe, 20 m/s", edge_drop, 5.0e-3,
         Variant(2, 0.5e-3)),
    Case("wall_crush", "pipe crushed between rigid walls closing at 20 m/s", wall_crush, 3.0e-3,
         Variant(2, 0.5e-3)),
    Case("crush_100", "case 1 at 100 m/s, 5 ms, single-surface contact of both pipes", crush_100, 5.0e-3,
         Variant(2, 0.5e-3), probe=crush_probe),
    Case("mixed_mesh", "clamped plate, half its quads cut into triangles, pipe at 20 m/s", mixed_plate, 3.0e-3,
         Variant(2, 0.5e-3), edit=mix_triangles),
    Case("sphere_plate", "rigid ball at 20 m/s onto a clamped plate", sphere_on_plate, 3.0e-3,
         Variant(2, 0.5e-3), edit=lift_ball, probe=impact_probe),
    Case("tube_crush", "square tube 50 x 1.5 mm crushed axially by a wall (friction 0.3) at 10 m/s, self-contact",
         square_tube,
         8.0e-3, Variant(2, 1.0e-3), edit=to_square, probe=tube_probe),
]
BY_NAME = {case.name: case for case in CASES}
