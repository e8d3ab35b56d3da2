"""The keyword subset ParaDyn reads (docs/keyword.md): each keyword's card layout and the records read.

:func:`collect` walks the blocks of a :class:`paradyn.keyword.reader.KeywordFile` and fills a
:class:`KeywordData` with what each supported keyword says, in the deck's own units and ids;
:mod:`paradyn.keyword.scene` turns that into a model. A keyword outside the subset, or a field
that is read but has no ParaDyn counterpart and holds a value other than its default, becomes a
warning naming the keyword, the field and the line.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

from .defaults import apply_zero_defaults
from .erosion import EROSION_READERS
from .reader import Block, Field, KeywordError, KeywordFile, Line, Value, fields, layout
from .rigid_cards import WELD_READERS, part_inertia_reader
from .walls import WALL_READERS

NODE = (Field("NID", "int", None, 8), Field("X", "float", 0.0, 16), Field("Y", "float", 0.0, 16),
        Field("Z", "float", 0.0, 16), Field("TC", "int", 0, 8), Field("RC", "int", 0, 8))
ELEMENT_SHELL = tuple(Field(n, "int", None if n in ("EID", "N1", "N2", "N3") else 0, 8)
                      for n in ("EID", "PID", "N1", "N2", "N3", "N4", "N5", "N6", "N7", "N8"))
PART = (Field("HEADING", "text", "", 70),), layout("int:PID int:SECID int:MID int:EOSID int:HGID int:GRAV "
                                                   "int:ADPOPT int:TMID", eosid=0, hgid=0, grav=0, adpopt=0, tmid=0)
SECTION_SHELL = (layout("int:SECID int:ELFORM SHRF int:NIP PROPT int:QR/IRID int:ICOMP int:SETYP",
                        elform=2, shrf=1.0, nip=2, propt=1.0, **{"qr/irid": 0}, icomp=0, setyp=1),
                 layout("T1 T2 T3 T4 NLOC MAREA IDOF int:EDGSET", t1=0.0, t2=0.0, t3=0.0, t4=0.0, nloc=0.0,
                        marea=0.0, idof=0.0, edgset=0))
MAT_ELASTIC = (layout("int:MID RO E PR DA DB K", da=0.0, db=0.0, k=0.0),)
MAT_PLASTIC_KINEMATIC = (layout("int:MID RO E PR SIGY ETAN BETA", etan=0.0, beta=0.0),
                         layout("SRC SRP FS VP", src=0.0, srp=0.0, fs=0.0, vp=0.0))
# MAT 24 and MAT 81 share cards 2 to 4 (C, P, LCSS, LCSR; EPS1..8; ES1..8); MAT 81's card 1 has the
# damage's EPPF where MAT 24 has FAIL, its card 2 EPPFR, LCDM, NUMINT after LCSR
_EPS_ES = (layout(" ".join(f"EPS{k}" for k in range(1, 9)), **{f"eps{k}": 0.0 for k in range(1, 9)}),
           layout(" ".join(f"ES{k}" for k in range(1, 9)), **{f"es{k}": 0.0 for k in range(1, 9)}))
MAT_PIECEWISE_LINEAR_PLASTICITY = (layout("int:MID RO E PR SIGY ETAN FAIL TDEL", sigy=0.0, etan=0.0, fail=1e21,
                                          tdel=0.0),
                                   layout("C P int:LCSS int:LCSR VP", c=0.0, p=0.0, lcss=0, lcsr=0, vp=0.0), *_EPS_ES)
MAT_PLASTICITY_WITH_DAMAGE = (layout("int:MID RO E PR SIGY ETAN EPPF TDEL", sigy=0.0, etan=0.0, eppf=0.0, tdel=0.0),
                              layout("C P int:LCSS int:LCSR EPPFR VP int:LCDM int:NUMINT", c=0.0, p=0.0, lcss=0,
                                     lcsr=0, eppfr=0.0, vp=0.0, lcdm=0, numint=0), *_EPS_ES)
SPC = layout("int:ID int:CID int:DOFX int:DOFY int:DOFZ int:DOFRX int:DOFRY int:DOFRZ", cid=0, dofx=0, dofy=0,
             dofz=0, dofrx=0, dofry=0, dofrz=0)
VELOCITY_GENERATION = (layout("int:ID int:STYP OMEGA VX VY VZ int:IVATN int:ICID", id=0, styp=1, omega=0.0,
                              vx=0.0, vy=0.0, vz=0.0, ivatn=0, icid=0),
                       layout("XC YC ZC NX NY NZ int:PHASE int:IRIGID", xc=0.0, yc=0.0, zc=0.0, nx=0.0, ny=0.0,
                              nz=0.0, phase=0, irigid=0))
VELOCITY_NODE = layout("int:NID VX VY VZ VXR VYR VZR int:ICID", vx=0.0, vy=0.0, vz=0.0, vxr=0.0, vyr=0.0,
                       vzr=0.0, icid=0)
SET_HEAD = layout("int:SID DA1 DA2 DA3 DA4 text:SOLVER", da1=0.0, da2=0.0, da3=0.0, da4=0.0, solver="MECH")
ID_LIST = layout("K1 K2 K3 K4 K5 K6 K7 K8", "int")
CONTROL_TERMINATION = layout("ENDTIM int:ENDCYC DTMIN ENDENG ENDMAS int:NOSOL", endtim=0.0, endcyc=0, dtmin=0.0,
                             endeng=0.0, endmas=1e8, nosol=0)
CONTROL_TIMESTEP = layout("DTINIT TSSFAC int:ISDO TSLIMT DT2MS int:LCTM int:ERODE int:MS1ST", dtinit=0.0,
                          tssfac=0.9, isdo=0, tslimt=0.0, dt2ms=0.0, lctm=0, erode=0, ms1st=0)
ELEMENT_SOLID = tuple(Field(n, "int", None if n in ("EID", "PID", "N1", "N2", "N3", "N4") else 0, 8)
                      for n in ("EID", "PID", "N1", "N2", "N3", "N4", "N5", "N6", "N7", "N8"))
SECTION_SOLID = layout("int:SECID int:ELFORM int:AET", elform=1, aet=0)
MAT_RIGID = (layout("int:MID RO E PR N COUPLE M ALIAS", n=0.0, couple=0.0, m=0.0, alias=0.0),
             layout("CMO CON1 CON2", cmo=0.0, con1=0.0, con2=0.0),
             layout("A1 A2 A3 V1 V2 V3", a1=0.0, a2=0.0, a3=0.0, v1=0.0, v2=0.0, v3=0.0))
DEFORMABLE_TO_RIGID = layout("int:PID int:MRB text:PTYPE", mrb=0, ptype="PART")
CONSTRAINED_RIGID_BODIES = layout("int:PIDL int:PIDC int:IFLAG", iflag=0)
EXTRA_NODES = layout("int:PID int:ID int:IFLAG", iflag=0)
RIGID_BODY_VELOCITY = layout("int:PID VX VY VZ VXR VYR VZR", vx=0.0, vy=0.0, vz=0.0, vxr=0.0, vyr=0.0, vzr=0.0)
CONTROL_HOURGLASS = layout("int:IHQ QH", ihq=1, qh=0.1)
# only ISTUPD is read (1: the thickness update of keyword/parts.py); the other fields of card 1 are
# warned when not LS-DYNA's defaults, cards 2 and after (ROTASCL ...) are not read
CONTROL_SHELL = layout("WRPANG int:ESORT int:IRNXX int:ISTUPD int:THEORY int:BWC int:MITER int:PROJ", wrpang=20.0,
                       esort=0, irnxx=-1, istupd=0, theory=2, bwc=2, miter=1, proj=0)
# only IMFLAG is read: a value other than 0 asks for an implicit analysis, which ParaDyn refuses
CONTROL_IMPLICIT_GENERAL = layout("int:IMFLAG DT0 int:IMFORM int:NSBS int:IGS int:CNSTN int:FORM int:ZERO_V",
                                  imflag=0, dt0=0.0, imform=2, nsbs=1, igs=2, cnstn=0, form=0, zero_v=0)
CONTROL_UNITS = layout("text:LENGTH text:TIME text:MASS text:TEMP", length="m", time="sec", mass="kg", temp="k")
HOURGLASS = layout("int:HGID int:IHQ QM int:IBQ Q1 Q2 QB/VDC QW", hgid=0, ihq=1, qm=0.1, ibq=0, q1=1.5, q2=0.06,
                   **{"qb/vdc": 0.1}, qw=0.1)
DATABASE_DT = layout("DT int:LCDT int:BEAM int:NPLTC int:PSETID", dt=0.0, lcdt=0, beam=0, npltc=0, psetid=0)
DEFINE_CURVE = layout("int:LCID int:SIDR SFA SFO OFFA OFFO int:DATTYP int:LCINT", sidr=0, sfa=1.0, sfo=1.0,
                      offa=0.0, offo=0.0, dattyp=0, lcint=0)
CURVE_POINT = (Field("A", "float", 0.0, 20), Field("O", "float", 0.0, 20))
LOAD_BODY = layout("int:LCID SF int:LCIDDR XC YC ZC int:CID", lcid=0, sf=1.0, lciddr=0, xc=0.0, yc=0.0, zc=0.0, cid=0)
TITLE_CARD = (Field("TITLE", "text", "", 80),)
ID_CARD = (Field("ID", "int", 0), Field("HEADING", "text", "", 70))


@dataclass
class Record:
    """One card's values, with the line it came from (for messages)."""

    values: dict[str, Value]
    where: str

    def __getitem__(self, name: str) -> Value:
        return self.values[name]


@dataclass
class KeywordData:
    """What the supported keywords of a deck say, in the deck's units and ids (docs/keyword.md)."""

    nodes: list[Record] = field(default_factory=list)
    elements: list[Record] = field(default_factory=list)
    parts: list[Record] = field(default_factory=list)                # HEADING and card 2, merged
    sections: dict[int, list[Record]] = field(default_factory=dict)
    materials: dict[int, tuple[str, list[Record]]] = field(default_factory=dict)   # mid -> (model, cards)
    hourglasses: dict[int, Record] = field(default_factory=dict)
    node_sets: dict[int, list[int]] = field(default_factory=dict)
    part_sets: dict[int, list[int]] = field(default_factory=dict)
    spcs: list[tuple[str, Record]] = field(default_factory=list)     # ("NODE" | "SET", record)
    velocity_generation: list[list[Record]] = field(default_factory=list)
    node_velocities: list[Record] = field(default_factory=list)
    contacts: list[tuple[str, list[Record]]] = field(default_factory=list)  # (kind, cards)
    control: dict[str, Record] = field(default_factory=dict)         # CONTROL_* and DATABASE_* by name
    curves: dict[int, tuple[Record, list[tuple[float, float]]]] = field(default_factory=dict)
    history_nodes: list[tuple[int, str, str]] = field(default_factory=list)   # (nid, name, where)
    body_loads: list[tuple[str, Record]] = field(default_factory=list)        # ("X" | "Y" | "Z", record)
    solids: list[Record] = field(default_factory=list)                       # *ELEMENT_SOLID (rigid geometry)
    beams: list[Record] = field(default_factory=list)                        # *ELEMENT_BEAM (trusses)
    beam_sections: dict[int, list[Record]] = field(default_factory=dict)     # *SECTION_BEAM cards 1 and 2
    solid_sections: dict[int, Record] = field(default_factory=dict)
    deformable_to_rigid: list[Record] = field(default_factory=list)
    merged_bodies: list[Record] = field(default_factory=list)               # *CONSTRAINED_RIGID_BODIES
    extra_nodes: list[tuple[str, Record]] = field(default_factory=list)     # ("NODE" | "SET", record)
    welds: list[tuple[str, Record]] = field(default_factory=list)           # nodal rigid bodies, spot welds
    body_velocities: list[Record] = field(default_factory=list)             # *INITIAL_VELOCITY_RIGID_BODY
    part_inertia: dict[int, Record] = field(default_factory=dict)           # PID -> *PART_INERTIA cards 3-5a
    rigid_motions: list[tuple[int, int, float, int, str]] = field(default_factory=list)  # PID, dof, SI scale, curve
    added_masses: list[tuple[str, Record]] = field(default_factory=list)    # *ELEMENT_MASS(_PART): (target, card)
    # loads, motions and boxes (keyword/loads.py); parts with contact data (keyword/contacts.py)
    point_loads: list[tuple[str, Record]] = field(default_factory=list)       # ("NODE" | "SET", record)
    motions: list[tuple[str, Record]] = field(default_factory=list)           # ("NODE" | "SET", record)
    set_velocities: list[list[Record]] = field(default_factory=list)          # *INITIAL_VELOCITY cards
    boxes: dict[int, Record] = field(default_factory=dict)
    part_contacts: dict[int, Record] = field(default_factory=dict)           # PID -> *PART_CONTACT card
    shell_edges: list[tuple[str, str]] = field(default_factory=list)       # tied shell edge -> surface parts
    title: str = ""
    warnings: list[str] = field(default_factory=list)

    def warn(self, message: str) -> None:
        self.warnings.append(message)


# ----------------------------------------------------------------------------------------------
# reading the blocks


class _Reading:
    """Reads the cards of one block, with the deck's parameters and the block's format."""

    def __init__(self, deck: KeywordFile, block: Block, data: KeywordData) -> None:
        self.deck, self.block, self.data = deck, block, data
        self.keyword = block.name

    def card(self, line: Line, card: tuple[Field, ...], ignored: dict[str, Value] | None = None) -> Record:
        values = fields(line, card, long=self.block.long, parameters=self.deck.parameters, keyword=self.keyword)
        apply_zero_defaults(self.keyword, values)     # a 0 that means LS-DYNA's default (keyword/defaults.py)
        record = Record(values, line.where)
        for name, default in (ignored or {}).items():
            if values.get(name) is not None and values[name] != default:
                self.data.warn(f"{line.where}: *{self.keyword} {name} = {values[name]} is not supported and "
                               f"ignored (docs/keyword.md)")
        return record

    def lines(self, skip_blank: bool = True) -> list[Line]:
        """The block's data lines, without trailing blank ones (and without any blank line when asked)."""
        lines = list(self.block.lines)
        while lines and not lines[-1].text.strip():
            lines.pop()
        return [line for line in lines if line.text.strip()] if skip_blank else lines

    def groups(self, size: int, optional_last: bool = False) -> Iterator[list[Line]]:
        """The lines in groups of ``size`` cards (a keyword may repeat its group); with
        ``optional_last`` a missing last card of the last group is a blank one (its defaults)."""
        lines = self.lines(skip_blank=False)
        if optional_last and lines and len(lines) % size == size - 1:
            lines.append(Line("", lines[-1].path, lines[-1].number + 1))
        if len(lines) % size:
            raise KeywordError(f"{self.block.where}: *{self.keyword} takes groups of {size} cards, its "
                               f"{len(lines)} lines are not a whole number of groups; complete the last one")
        for start in range(0, len(lines), size):
            yield lines[start:start + size]

    def head_and_rest(self, titled: bool) -> list[Line]:
        lines = self.lines(skip_blank=False)
        if titled and lines:
            lines = lines[1:]
        if not lines:
            raise KeywordError(f"{self.block.where}: *{self.keyword} has no data card; complete it")
        return lines


def _options(name: str, base: str) -> set[str]:
    return set(name[len(base):].strip("_").split("_")) - {""}


def _node(r: _Reading) -> None:
    for line in r.lines():
        r.data.nodes.append(r.card(line, NODE))


def _element_shell(r: _Reading) -> None:
    for line in r.lines():
        record = r.card(line, ELEMENT_SHELL)
        if any(record[f"N{k}"] not in (0, None) for k in range(5, 9)):
            raise KeywordError(f"{line.where}: *ELEMENT_SHELL {record['EID']} has nodes N5..N8; ParaDyn reads "
                               f"4-node shells only")
        r.data.elements.append(record)


def _element_solid(r: _Reading) -> None:
    for line in r.lines():
        r.data.solids.append(r.card(line, ELEMENT_SOLID))


def _section_solid(r: _Reading) -> None:
    for line in r.head_and_rest("TITLE" in _options(r.keyword, "SECTION_SOLID")):
        if line.text.strip():
            record = r.card(line, SECTION_SOLID, {"AET": 0})
            r.data.solid_sections[int(record["SECID"])] = record


def _deformable_to_rigid(r: _Reading) -> None:
    for line in r.lines():
        record = r.card(line, DEFORMABLE_TO_RIGID)
        if str(record["PTYPE"] or "PART").strip().upper() not in ("PART", ""):
            raise KeywordError(f"{line.where}: *DEFORMABLE_TO_RIGID PTYPE = {record['PTYPE']} is not read; name "
                               f"a part (PTYPE PART)")
        r.data.deformable_to_rigid.append(record)


def _merged_bodies(r: _Reading) -> None:
    for line in r.lines():
        r.data.merged_bodies.append(r.card(line, CONSTRAINED_RIGID_BODIES, {"IFLAG": 0}))


def _extra_nodes(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        for line in r.lines():
            r.data.extra_nodes.append((target, r.card(line, EXTRA_NODES, {"IFLAG": 0})))
    return read


def _body_velocity(r: _Reading) -> None:
    for line in r.lines():
        r.data.body_velocities.append(r.card(line, RIGID_BODY_VELOCITY))


def _part(r: _Reading) -> None:
    for heading, card in r.groups(2):
        record = r.card(card, PART[1], {"EOSID": 0, "GRAV": 0, "ADPOPT": 0, "TMID": 0})
        record.values["HEADING"] = heading.text.strip()
        r.data.parts.append(record)


def _section_shell(r: _Reading) -> None:
    titled = "TITLE" in _options(r.keyword, "SECTION_SHELL")
    for group in r.groups(3 if titled else 2):
        first = r.card(group[-2], SECTION_SHELL[0], {"SHRF": 1.0, "PROPT": 1.0, "QR/IRID": 0, "ICOMP": 0, "SETYP": 1})
        second = r.card(group[-1], SECTION_SHELL[1], {"NLOC": 0.0, "MAREA": 0.0, "IDOF": 0.0, "EDGSET": 0})
        r.data.sections[int(first["SECID"])] = [first, second]


def _material(model: str, cards: tuple[tuple[Field, ...], ...],
              ignored: dict[str, Value]) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        _read_material(r, model, cards, ignored)
    return read


def _read_material(r: _Reading, model: str, cards: tuple[tuple[Field, ...], ...],
                   ignored: dict[str, Value]) -> list[Record]:
    """A *MAT block's cards (missing trailing cards at their defaults) into ``materials``."""
    titled = "TITLE" in r.keyword.split("_")
    lines = r.head_and_rest(titled)
    records = [r.card(line, card, ignored) for line, card in zip(lines, cards, strict=False)]
    records[0].values["TITLE"] = r.block.lines[0].text.strip() if titled else ""
    for line in lines[len(cards):]:
        if line.text.strip():
            r.data.warn(f"{line.where}: *{r.keyword}: this card is not read (docs/keyword.md)")
    if len(records) < len(cards):
        records += [Record({f.name: f.default for f in card}, lines[-1].where) for card in cards[len(records):]]
    r.data.materials[int(records[0]["MID"])] = (model, records)
    return records


def _piecewise_material(cards: tuple[tuple[Field, ...], ...]) -> Callable[[_Reading], None]:
    """MAT 24 (and MAT 81, read as MAT 24): the cards as _material reads them, with a warning for
    what ParaDyn does not model, naming the material: VP other than 0, MAT 81's damage. FAIL is
    the failure strain (materials.py)."""
    def read(r: _Reading) -> None:
        first, second = _read_material(r, "piecewise_linear", cards, {"TDEL": 0.0})[:2]
        mid = int(first["MID"])
        if float(second["VP"] or 0.0) != 0.0:
            r.data.warn(f"{second.where}: *{r.keyword} {mid} VP = {second['VP']} is not modelled; the yield stress "
                        f"is scaled by the total strain rate as with VP = 0")
        if "EPPF" in first.values:
            r.data.warn(f"{first.where}: *{r.keyword} {mid} is read as *MAT_PIECEWISE_LINEAR_PLASTICITY: its damage "
                        f"(EPPF, EPPFR, LCDM) is not modelled; material {mid} hardens along its curve and never "
                        f"softens or fails")
    return read


def _spc(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        options = _options(r.keyword, f"BOUNDARY_SPC_{target}")
        if not options & {"ID", "TITLE"}:
            for line in r.lines():
                r.data.spcs.append((target, r.card(line, SPC)))
            return
        for head, line in r.groups(2):     # _ID: each constraint is an ID card (ID, HEADING) and its card
            r.card(head, ID_CARD)
            r.data.spcs.append((target, r.card(line, SPC)))
    return read


def _velocity_generation(r: _Reading) -> None:
    for group in r.groups(2, optional_last=True):
        first = r.card(group[0], VELOCITY_GENERATION[0], {"IVATN": 0, "ICID": 0})
        second = r.card(group[1], VELOCITY_GENERATION[1], {"PHASE": 0, "IRIGID": 0})
        r.data.velocity_generation.append([first, second])


def _velocity_node(r: _Reading) -> None:
    for line in r.lines():
        r.data.node_velocities.append(r.card(line, VELOCITY_NODE, {"ICID": 0}))


def _set(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        options = _options(r.keyword, f"SET_{target}") - {"LIST"}
        if options - {"TITLE", "GENERATE"}:
            raise KeywordError(f"{r.block.where}: *{r.keyword} is not read (only *SET_{target}, _LIST, "
                               f"_LIST_GENERATE and _TITLE); list the ids")
        lines = [line for line in r.head_and_rest("TITLE" in options) if line.text.strip()]
        head = r.card(lines[0], SET_HEAD, {"DA1": 0.0, "DA2": 0.0, "DA3": 0.0, "DA4": 0.0})
        ids: list[int] = []
        for line in lines[1:]:
            values = [v for v in r.card(line, ID_LIST).values.values() if v not in (None, 0)]
            if "GENERATE" in options:
                pairs = zip(values[::2], values[1::2], strict=False)
                ids += [i for lo, hi in pairs for i in range(int(lo), int(hi) + 1)]
            else:
                ids += [int(v) for v in values]
        sets = r.data.node_sets if target == "NODE" else r.data.part_sets
        sets[int(head["SID"])] = ids
    return read


def _control(card: tuple[Field, ...], ignored: dict[str, Value] | None = None) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        lines = r.head_and_rest(False)
        r.data.control[r.keyword] = r.card(lines[0], card, ignored)
        if any(line.text.strip() for line in lines[1:]):
            r.data.warn(f"{lines[1].where}: *{r.keyword}: the cards after the first are not read "
                        f"(docs/keyword.md)")
    return read


def _load_body(r: _Reading) -> None:
    record = r.card(r.head_and_rest(False)[0], LOAD_BODY, {"LCIDDR": 0, "XC": 0.0, "YC": 0.0, "ZC": 0.0, "CID": 0})
    r.data.body_loads.append((r.keyword[-1], record))


def _history_node(r: _Reading) -> None:
    if r.keyword == "DATABASE_HISTORY_NODE_ID":
        for line in r.lines():
            record = r.card(line, ID_CARD)
            r.data.history_nodes.append((int(record["ID"]), str(record["HEADING"]), line.where))
        return
    for line in r.lines():
        for value in r.card(line, ID_LIST).values.values():
            if value not in (None, 0):
                r.data.history_nodes.append((int(value), "", line.where))


def _hourglass(r: _Reading) -> None:
    for line in r.head_and_rest("TITLE" in _options(r.keyword, "HOURGLASS")):
        if line.text.strip():
            record = r.card(line, HOURGLASS, {"IBQ": 0, "Q1": 1.5, "Q2": 0.06, "QB/VDC": 0.1, "QW": 0.1})
            r.data.hourglasses[int(record["HGID"])] = record


def _define_curve(r: _Reading) -> None:
    lines = [line for line in r.head_and_rest("TITLE" in _options(r.keyword, "DEFINE_CURVE")) if line.text.strip()]
    head = r.card(lines[0], DEFINE_CURVE, {"SIDR": 0, "DATTYP": 0, "LCINT": 0})
    points = [r.card(line, CURVE_POINT) for line in lines[1:]]
    r.data.curves[int(head["LCID"])] = (head, [(float(p["A"]), float(p["O"])) for p in points])


READERS: dict[str, Callable[[_Reading], None]] = {
    "NODE": _node,
    "ELEMENT_SHELL": _element_shell,
    "PART": _part, "PART_INERTIA": part_inertia_reader(PART[1]),
    "SECTION_SHELL": _section_shell, "SECTION_SHELL_TITLE": _section_shell,
    "BOUNDARY_SPC_NODE": _spc("NODE"), "BOUNDARY_SPC_NODE_ID": _spc("NODE"),
    "BOUNDARY_SPC_SET": _spc("SET"), "BOUNDARY_SPC_SET_ID": _spc("SET"),
    "INITIAL_VELOCITY_GENERATION": _velocity_generation,
    "INITIAL_VELOCITY_NODE": _velocity_node,
    "CONTROL_TERMINATION": _control(CONTROL_TERMINATION, {"ENDCYC": 0, "ENDENG": 0.0, "ENDMAS": 1e8, "NOSOL": 0}),
    "CONTROL_TIMESTEP": _control(CONTROL_TIMESTEP, {"DTINIT": 0.0, "ISDO": 0, "TSLIMT": 0.0, "ERODE": 0,
                                                    "MS1ST": 0}),
    "CONTROL_HOURGLASS": _control(CONTROL_HOURGLASS),
    "CONTROL_SHELL": _control(CONTROL_SHELL, {"WRPANG": 20.0, "ESORT": 0, "IRNXX": -1, "THEORY": 2, "BWC": 2,
                                              "MITER": 1, "PROJ": 0}),
    "CONTROL_IMPLICIT_GENERAL": _control(CONTROL_IMPLICIT_GENERAL),
    "CONTROL_UNITS": _control(CONTROL_UNITS, {"TEMP": "k"}),
    "DATABASE_BINARY_D3PLOT": _control(DATABASE_DT, {"LCDT": 0, "BEAM": 0, "NPLTC": 0, "PSETID": 0}),
    "DATABASE_GLSTAT": _control(DATABASE_DT[:1]),
    "DATABASE_NODOUT": _control(DATABASE_DT[:1]),
    "DATABASE_HISTORY_NODE": _history_node, "DATABASE_HISTORY_NODE_ID": _history_node,
    "HOURGLASS": _hourglass, "HOURGLASS_TITLE": _hourglass,
    "DEFINE_CURVE": _define_curve, "DEFINE_CURVE_TITLE": _define_curve,
    "LOAD_BODY_X": _load_body, "LOAD_BODY_Y": _load_body, "LOAD_BODY_Z": _load_body,
    "ELEMENT_SOLID": _element_solid,
    "SECTION_SOLID": _section_solid, "SECTION_SOLID_TITLE": _section_solid,
    "DEFORMABLE_TO_RIGID": _deformable_to_rigid,
    "CONSTRAINED_RIGID_BODIES": _merged_bodies,
    "CONSTRAINED_EXTRA_NODES_NODE": _extra_nodes("NODE"), "CONSTRAINED_EXTRA_NODES_SET": _extra_nodes("SET"),
    "INITIAL_VELOCITY_RIGID_BODY": _body_velocity,
    **WELD_READERS,
}
for _title in ("", "_TITLE"):
    for _name in ("MAT_ELASTIC", "MAT_001"):
        READERS[_name + _title] = _material("elastic", MAT_ELASTIC, {"DA": 0.0, "DB": 0.0, "K": 0.0})
    for _name in ("MAT_RIGID", "MAT_020"):
        READERS[_name + _title] = _material("rigid", MAT_RIGID, {"N": 0.0, "COUPLE": 0.0, "M": 0.0, "ALIAS": 0.0,
                                                                "A1": 0.0, "A2": 0.0, "A3": 0.0, "V1": 0.0,
                                                                "V2": 0.0, "V3": 0.0})
    for _name in ("MAT_PLASTIC_KINEMATIC", "MAT_003"):
        READERS[_name + _title] = _material("j2_plasticity", MAT_PLASTIC_KINEMATIC, {"VP": 0.0})
    for _name in ("MAT_PIECEWISE_LINEAR_PLASTICITY", "MAT_024"):
        READERS[_name + _title] = _piecewise_material(MAT_PIECEWISE_LINEAR_PLASTICITY)
    for _name in ("MAT_PLASTICITY_WITH_DAMAGE", "MAT_081"):
        READERS[_name + _title] = _piecewise_material(MAT_PLASTICITY_WITH_DAMAGE)
    for _target in ("NODE", "PART"):
        for _list in ("", "_LIST", "_LIST_GENERATE"):
            READERS[f"SET_{_target}{_list}{_title}"] = _set(_target)
READERS.update(WALL_READERS)   # *RIGIDWALL_PLANAR and _GEOMETRIC (keyword/walls.py)
READERS.update(EROSION_READERS)   # *MAT_ADD_EROSION (keyword/erosion.py)


def collect(deck: KeywordFile, readers: dict[str, Callable[[_Reading], None]] | None = None) -> KeywordData:
    """Read every block of ``deck`` with ``readers`` (by keyword; this module's :data:`READERS` by
    default, every keyword read with :func:`paradyn.keyword.keywords.collect`); unsupported
    keywords are named in ``warnings`` and skipped. An error carries the warnings collected before
    it (a skipped keyword is often its cause)."""
    readers = READERS if readers is None else readers
    data = KeywordData(title=deck.title, warnings=list(deck.warnings))
    try:
        for block in deck.blocks:
            reader = readers.get(block.name)
            if reader is None:
                data.warn(f"{block.where}: *{block.name} is not supported by ParaDyn and is ignored "
                          f"(docs/keyword.md lists the keywords read)")
                continue
            reader(_Reading(deck, block, data))
        _refuse_implicit(deck, data)
    except KeywordError as exc:
        raise with_warnings(exc, data.warnings) from exc
    return data


def _refuse_implicit(deck: KeywordFile, data: KeywordData) -> None:
    """An implicit analysis (*CONTROL_IMPLICIT_GENERAL IMFLAG not 0) is refused, naming what to drop."""
    general = data.control.get("CONTROL_IMPLICIT_GENERAL")
    if general is None or general["IMFLAG"] == 0:
        return
    cards = ", ".join(f"*{b.name} ({b.where})" for b in deck.blocks if b.name.startswith("CONTROL_IMPLICIT"))
    raise KeywordError(f"{general.where}: *CONTROL_IMPLICIT_GENERAL IMFLAG = {general['IMFLAG']} asks for an implicit "
                       f"analysis; ParaDyn is explicit (central differences). To run the deck explicitly, remove "
                       f"{cards} or set IMFLAG = 0, with loads and an end time meant for an explicit run")


def with_warnings(error: KeywordError, warnings: list[str]) -> KeywordError:
    """The error with the warnings collected before it, which often say why it happened."""
    if not warnings:
        return error
    listed = "\n".join(f"  warning: {w}" for w in warnings)
    return KeywordError(f"{error}\nwarnings before this error ({len(warnings)}):\n{listed}")
