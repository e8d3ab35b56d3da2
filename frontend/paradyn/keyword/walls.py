"""LS-DYNA rigid walls (docs/keyword.md): *RIGIDWALL_PLANAR (_FINITE, _MOVING, _FORCES, _ID) and
*RIGIDWALL_GEOMETRIC_FLAT, PRISM, CYLINDER and SPHERE (_MOTION, _DISPLAY, _ID), read into the
deck's /rigid_walls rows and the node lists of /rigid_wall_nodes.

:data:`WALL_READERS` maps each keyword to its card reader (registered in
:data:`paradyn.keyword.cards.READERS`); :func:`apply_rigid_walls` turns what they read into the
model (called from :mod:`paradyn.keyword.scene`). The cards read are kept on the deck's
:class:`~paradyn.keyword.cards.KeywordData` under ``rigid_walls`` (see :func:`read_walls`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from itertools import permutations
from typing import TYPE_CHECKING, Any

import numpy as np

from paradyn._schema import DATASETS, ENUMS
from paradyn.deck.walls import Wall

from .reader import Field, KeywordError, layout

if TYPE_CHECKING:
    from paradyn import deck

    from .units import Units

# cards.py imports this module (its READERS take WALL_READERS), so neither its types nor those of
# mesh.py (which imports cards.py) are imported back: a reader gets cards.py's _Reading, the data
# is its KeywordData, a card its Record, the mesh mesh.py's KeywordMesh
_Reading = Any
KeywordData = Any
Record = Any
KeywordMesh = Any

SHAPES = ENUMS["rigid_wall_shape"]
DEFAULT_SCALE = float(next(d.default for d in DATASETS if d.python == "rigid_wall_penalty_scale"))
MAX_SCALE = float(next(d.upper.value for d in DATASETS if d.python == "rigid_wall_penalty_scale"))
STICKING = 1.0e6   # FRIC = 1 (no sliding): a Coulomb limit no node reaches, so the stick force holds

ID_CARD = (Field("RWID", "int", 0), Field("HEADING", "text", "", 70))
PLANAR = (layout("int:NSID int:NSIDEX int:BOXID OFFSET BIRTH DEATH RWKSF", nsid=0, nsidex=0, boxid=0,
                 offset=0.0, birth=0.0, death=1e20, rwksf=1.0),
          layout("XT YT ZT XH YH ZH FRIC WVEL", xt=0.0, yt=0.0, zt=0.0, xh=0.0, yh=0.0, zh=0.0, fric=0.0,
                 wvel=0.0))
GEOMETRIC = (layout("int:NSID int:NSIDEX int:BOXID BIRTH DEATH", nsid=0, nsidex=0, boxid=0, birth=0.0, death=1e20),
             layout("XT YT ZT XH YH ZH FRIC", xt=0.0, yt=0.0, zt=0.0, xh=0.0, yh=0.0, zh=0.0, fric=0.0))
FINITE = layout("XHEV YHEV ZHEV LENL LENM", xhev=0.0, yhev=0.0, zhev=0.0, lenl=0.0, lenm=0.0)
SHAPE_CARDS = {
    "FLAT": FINITE,
    "PRISM": layout("XHEV YHEV ZHEV LENL LENM LENP", xhev=0.0, yhev=0.0, zhev=0.0, lenl=0.0, lenm=0.0, lenp=0.0),
    "CYLINDER": layout("RADCYL LENCYL int:NSEGS", radcyl=0.0, lencyl=0.0, nsegs=0),
    "SPHERE": layout("RADSPH", radsph=0.0),
}
MOVING = layout("MASS V0", mass=0.0, v0=0.0)
MOTION = layout("int:LCID int:OPT VX VY VZ", lcid=0, opt=0, vx=0.0, vy=0.0, vz=0.0)
OPTIONAL = {"PLANAR": ("ORTHO", "FINITE", "MOVING", "FORCES", "ID"), "GEOMETRIC": ("MOTION", "DISPLAY", "ID")}


@dataclass
class WallCards:
    """One rigid wall's cards as read: its keyword's kind and options and its records by name."""

    kind: str                    # "PLANAR" or a geometric shape: "FLAT", "PRISM", "CYLINDER", "SPHERE"
    options: set[str]
    cards: dict[str, Record]     # "main", "point", "shape" (FINITE or the shape's card), "motion"
    where: str
    keyword: str


def read_walls(data: KeywordData) -> list[WallCards]:
    """The walls read so far. They live on the deck's data object under ``rigid_walls``, set here
    rather than declared in cards.py, which other readers edit."""
    walls: list[WallCards] = data.__dict__.setdefault("rigid_walls", [])
    return walls


def _planar(r: _Reading) -> None:
    options = set(r.keyword[len("RIGIDWALL_PLANAR"):].strip("_").split("_")) - {""}
    if "ORTHO" in options:
        raise KeywordError(f"{r.block.where}: *{r.keyword}: the orthotropic friction of _ORTHO is not read; "
                           f"drop the option and its two cards (FRIC gives isotropic Coulomb friction)")
    lines = r.lines(skip_blank=False)
    if "ID" in options and lines:
        lines = lines[1:]
    names = ["main", "point", *(["shape"] if "FINITE" in options else []),
             *(["motion"] if "MOVING" in options else []), *(["forces"] if "FORCES" in options else [])]
    layouts = {"main": PLANAR[0], "point": PLANAR[1], "shape": FINITE, "motion": MOVING}
    _store(r, "PLANAR", options, names, layouts, lines)


def _geometric(shape: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        options = set(r.keyword[len(f"RIGIDWALL_GEOMETRIC_{shape}"):].strip("_").split("_")) - {""}
        lines = r.lines(skip_blank=False)
        if "ID" in options and lines:
            lines = lines[1:]
        names = ["main", "point", "shape", *(["motion"] if "MOTION" in options else []),
                 *(["display"] if "DISPLAY" in options else [])]
        layouts = {"main": GEOMETRIC[0], "point": GEOMETRIC[1], "shape": SHAPE_CARDS[shape], "motion": MOTION}
        _store(r, shape, options, names, layouts, lines)
    return read


def _store(r: _Reading, kind: str, options: set[str], names: list[str], layouts: dict[str, tuple[Field, ...]],
           lines: list[Any]) -> None:
    while len(lines) > len(names) and not lines[-1].text.strip():
        lines = lines[:-1]
    if len(lines) < 2:
        raise KeywordError(f"{r.block.where}: *{r.keyword} needs its cards {', '.join(names)}; complete it")
    cards: dict[str, Record] = {}
    for name, line in zip(names, lines, strict=False):
        if name in ("forces", "display"):
            r.data.warn(f"{line.where}: *{r.keyword}: the {name} card is not read (docs/keyword.md)")
            continue
        cards[name] = r.card(line, layouts[name])
    for name in names[len(lines):]:   # trailing blank cards take their defaults
        if name in layouts:
            cards[name] = r.card(type(lines[-1])("", lines[-1].path, lines[-1].number), layouts[name])
    read_walls(r.data).append(WallCards(kind, options, cards, r.block.where, r.keyword))


def _names() -> dict[str, Callable[[_Reading], None]]:
    """Every spelling of the wall keywords: the options in any order."""
    readers: dict[str, Callable[[_Reading], None]] = {}
    for family, options in OPTIONAL.items():
        bases = ["RIGIDWALL_PLANAR"] if family == "PLANAR" else [f"RIGIDWALL_GEOMETRIC_{s}" for s in SHAPE_CARDS]
        for base in bases:
            read = _planar if family == "PLANAR" else _geometric(base.rsplit("_", 1)[1])
            for n in range(len(options) + 1):
                for chosen in permutations(options, n):
                    readers["_".join([base, *chosen])] = read
    return readers


WALL_READERS: dict[str, Callable[[_Reading], None]] = _names()


# ----------------------------------------------------------------------------------------------
# the model


def apply_rigid_walls(data: KeywordData, unit: Units, mesh: KeywordMesh, model: deck.Model) -> None:
    """The walls read into the model's /rigid_walls rows, in SI, and their node lists."""
    walls = read_walls(data)
    if not walls:
        return
    rows = [_row(data, unit, wall) for wall in walls]
    for key in ("shape", "point", "normal", "edge", "size", "radius", "length", "velocity", "penalty_scale",
                "friction", "birth_time", "death_time"):
        values = np.array([row[key] for row in rows])
        setattr(model, f"rigid_wall_{key}", values.astype(np.int32) if key == "shape" else values.astype(float))
    listed, nodes = [], []
    for w, wall in enumerate(walls):
        chosen = _nodes(data, unit, mesh, wall, rows[w])
        if chosen is not None:
            listed += [w] * len(chosen)
            nodes += chosen.tolist()
    if nodes:
        model.rigid_wall_node_wall = np.array(listed, dtype=np.int32)
        model.rigid_wall_node = np.array(nodes, dtype=np.int32)


def _row(data: KeywordData, unit: Units, wall: WallCards) -> dict[str, Any]:
    main, point, shape = wall.cards["main"], wall.cards["point"], wall.cards.get("shape")
    tail = np.array([float(point["XT"]), float(point["YT"]), float(point["ZT"])])
    head = np.array([float(point["XH"]), float(point["YH"]), float(point["ZH"])])
    name = f"*{wall.keyword} ({wall.where})"
    _warn_unread(data, wall, name)
    row: dict[str, Any] = {"point": tail * unit.length, "normal": head - tail, "edge": np.zeros(3),
                           "size": np.zeros(3), "radius": 0.0, "length": 0.0, "velocity": np.zeros(3),
                           "friction": _friction(data, point, name), **_life(main, unit, name),
                           "penalty_scale": _scale(data, main, name) if wall.kind == "PLANAR" else DEFAULT_SCALE}
    if wall.kind == "PLANAR":
        row["shape"] = SHAPES["finite_plane" if shape is not None else "plane"]
    else:
        row["shape"] = SHAPES[{"FLAT": "finite_plane", "PRISM": "box", "CYLINDER": "cylinder", "SPHERE": "sphere"}[
            wall.kind]]
    if wall.kind in ("PLANAR", "FLAT", "PRISM") and shape is not None:
        edge_head = np.array([float(shape["XHEV"]), float(shape["YHEV"]), float(shape["ZHEV"])])
        row["edge"] = edge_head - tail
        depth = float(shape["LENP"]) if wall.kind == "PRISM" else 0.0
        row["size"] = np.array([float(shape["LENL"]), float(shape["LENM"]), depth]) * unit.length
    elif wall.kind == "CYLINDER" and shape is not None:
        row["radius"], row["length"] = float(shape["RADCYL"]) * unit.length, float(shape["LENCYL"]) * unit.length
        if int(shape["NSEGS"] or 0):
            data.warn(f"{shape.where}: {name} NSEGS = {shape['NSEGS']}: the cylinder's segments are not read; one "
                      f"cylinder of radius RADCYL is used")
    elif wall.kind == "SPHERE" and shape is not None:
        row["radius"] = float(shape["RADSPH"]) * unit.length
    motion = wall.cards.get("motion")
    if motion is not None:
        row["velocity"] = _velocity(data, unit, wall, motion, head - tail, name)
    return row


def _warn_unread(data: KeywordData, wall: WallCards, name: str) -> None:
    main, point = wall.cards["main"], wall.cards["point"]
    if int(main["BOXID"] or 0):
        data.warn(f"{main.where}: {name} BOXID = {main['BOXID']} is not read; the wall acts on its whole node set")
    if wall.kind == "PLANAR" and float(point["WVEL"] or 0.0) != 0.0:
        data.warn(f"{point.where}: {name} WVEL = {point['WVEL']} (welding) is not supported and ignored")


def _life(main: Record, unit: Units, name: str) -> dict[str, float]:
    """BIRTH and DEATH (deck time units) as the wall's birth_time and death_time in s (DEATH 0 or
    blank: LS-DYNA's 1e20, never); a DEATH not after BIRTH is an error."""
    birth = float(main["BIRTH"] or 0.0)
    death = float(main["DEATH"] or 0.0) or 1e20
    if birth < 0.0 or death <= birth:
        raise KeywordError(f"{main.where}: {name} BIRTH = {birth:g}, DEATH = {death:g}: give BIRTH >= 0 and a DEATH "
                           f"after it (0: never)")
    return {"birth_time": birth * unit.time, "death_time": death * unit.time if death < 1e20 else 1e20}


def _friction(data: KeywordData, point: Record, name: str) -> float:
    """FRIC: a Coulomb coefficient below 1; 1 is no sliding (stick); 2 and above (welding) stick too."""
    fric = float(point["FRIC"] or 0.0)
    if fric < 1.0:
        return max(fric, 0.0)
    if fric >= 2.0:
        data.warn(f"{point.where}: {name} FRIC = {fric:g} (a node welded after contact) is not supported; the node "
                  f"sticks while pressed on the wall, and may leave it")
    return STICKING


def _scale(data: KeywordData, main: Record, name: str) -> float:
    """RWKSF scales ParaDyn's default penalty scale (0 meaning 1), up to the schema's bound."""
    factor = float(main["RWKSF"] or 0.0) or 1.0
    scale = DEFAULT_SCALE * factor
    if scale > MAX_SCALE:
        data.warn(f"{main.where}: {name} RWKSF = {factor:g} gives a penalty scale {scale:g} above the stable "
                  f"{MAX_SCALE:g}; {MAX_SCALE:g} is used")
        scale = MAX_SCALE
    return scale


def _velocity(data: KeywordData, unit: Units, wall: WallCards, motion: Record, normal: np.ndarray,
              name: str) -> np.ndarray:
    """_MOVING: V0 along the normal, the wall's mass taken as infinite; _MOTION: a curve of constant
    velocity (OPT 0) or of displacement at a constant rate (OPT 1) along (VX, VY, VZ)."""
    if wall.kind == "PLANAR":
        if float(motion["MASS"] or 0.0) > 0.0:
            data.warn(f"{motion.where}: {name} MASS = {motion['MASS']}: the wall moves at V0 throughout, as if its "
                      f"mass were infinite")
        length = float(np.linalg.norm(normal))
        return float(motion["V0"] or 0.0) * unit.velocity * (normal / length if length > 0 else normal)
    direction = np.array([float(motion["VX"]), float(motion["VY"]), float(motion["VZ"])])
    lcid, opt = int(motion["LCID"] or 0), int(motion["OPT"] or 0)
    if lcid not in data.curves or not np.linalg.norm(direction) > 0:
        raise KeywordError(f"{motion.where}: {name} _MOTION needs a *DEFINE_CURVE LCID and a direction VX, VY, VZ; "
                           f"give them")
    head, points = data.curves[lcid]
    sfa, sfo = float(head["SFA"]) or 1.0, float(head["SFO"]) or 1.0
    t = np.array([a * sfa + float(head["OFFA"]) for a, _ in points])
    y = np.array([o * sfo + float(head["OFFO"]) for _, o in points])
    rate = np.diff(y) / np.diff(t) if opt == 1 and len(t) > 1 else y
    if opt not in (0, 1) or not np.allclose(rate, rate[0], rtol=1e-9, atol=0.0):
        raise KeywordError(f"{motion.where}: {name} moves by curve {lcid} (OPT = {opt}) at a varying speed; ParaDyn's "
                           f"walls move at a constant velocity: give a constant velocity curve (OPT 0) or a linear "
                           f"displacement (OPT 1)")
    speed = float(rate[0]) * (unit.length if opt == 1 else unit.velocity) / (unit.time if opt == 1 else 1.0)
    return speed * direction / np.linalg.norm(direction)


def _nodes(data: KeywordData, unit: Units, mesh: KeywordMesh, wall: WallCards,
           row: dict[str, Any]) -> np.ndarray | None:
    """The mesh rows of the nodes the wall acts on: NSID (0 = all) less NSIDEX, within OFFSET of a
    planar wall if given; None for every node."""
    main = wall.cards["main"]
    nsid, nsidex = int(main["NSID"] or 0), int(main["NSIDEX"] or 0)
    offset = float(main["OFFSET"] or 0.0) if wall.kind == "PLANAR" else 0.0
    if not (nsid or nsidex or offset > 0.0):
        return None
    rows = np.arange(len(mesh.coordinates)) if nsid == 0 else _set_rows(data, mesh, nsid, main)
    if nsidex:
        rows = np.setdiff1d(rows, _set_rows(data, mesh, nsidex, main))
    if offset > 0.0:
        surface = Wall(int(row["shape"]), row["point"], row["normal"], row["edge"], row["size"], row["radius"],
                       row["length"])
        rows = rows[np.abs(surface.gaps(mesh.coordinates[rows])) <= offset * unit.length]
    return rows


def _set_rows(data: KeywordData, mesh: KeywordMesh, sid: int, main: Record) -> np.ndarray:
    if sid not in data.node_sets:
        raise KeywordError(f"{main.where}: the rigid wall names node set {sid}, which no *SET_NODE defines; define it")
    nids = data.node_sets[sid]
    rows = np.array(sorted({mesh.node_index[n] for n in nids if n in mesh.node_index}), dtype=np.int64)
    if len(rows) < len(set(nids)):
        data.warn(f"{main.where}: node set {sid} of the rigid wall has {len(set(nids)) - len(rows)} nodes that no "
                  f"shell element uses; the wall acts on the others")
    return rows


__all__ = ["WALL_READERS", "WallCards", "apply_rigid_walls", "read_walls"]
