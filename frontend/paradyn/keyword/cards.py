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

from .reader import Block, Field, KeywordError, KeywordFile, Line, Value, fields, layout
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
CONTACT = (layout("int:SSID int:MSID int:SSTYP int:MSTYP int:SBOXID int:MBOXID int:SPR int:MPR",
                  ssid=0, msid=0, sstyp=0, mstyp=0, sboxid=0, mboxid=0, spr=0, mpr=0),
           layout("FS FD DC VC VDC int:PENCHK BT DT", fs=0.0, fd=0.0, dc=0.0, vc=0.0, vdc=0.0, penchk=0,
                  bt=0.0, dt=1e20),
           layout("SFS SFM SST MST SFST SFMT FSF VSF", sfs=1.0, sfm=1.0, sst=0.0, mst=0.0, sfst=1.0, sfmt=1.0,
                  fsf=1.0, vsf=1.0))
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
CONTROL_CONTACT = layout("SLSFAC RWPNAL int:ISLCHK int:SHLTHK int:PENOPT int:THKCHG int:ORIEN int:ENMASS",
                         slsfac=0.1, rwpnal=0.0, islchk=1, shlthk=0, penopt=1, thkchg=0, orien=1, enmass=0)
CONTROL_HOURGLASS = layout("int:IHQ QH", ihq=1, qh=0.1)
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
    return read


def _contact(kind: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        options = _options(r.keyword, f"CONTACT_AUTOMATIC_{kind.upper()}")
        lines = r.head_and_rest(bool(options & {"ID", "TITLE"}))
        ignored = [{"SBOXID": 0, "MBOXID": 0, "SPR": 0, "MPR": 0},
                   {"VC": 0.0, "VDC": 0.0, "PENCHK": 0, "BT": 0.0, "DT": 1e20},
                   {"SST": 0.0, "MST": 0.0, "SFST": 1.0, "SFMT": 1.0, "FSF": 1.0, "VSF": 1.0}]
        records = [r.card(line, card, skip) for line, card, skip in zip(lines, CONTACT, ignored, strict=False)]
        records += [Record({f.name: f.default for f in card}, lines[-1].where) for card in CONTACT[len(records):]]
        if any(line.text.strip() for line in lines[3:]):
            r.data.warn(f"{lines[3].where}: *{r.keyword}: the optional cards A and after are not read "
                        f"(docs/keyword.md)")
        r.data.contacts.append((kind, records))
    return read


def _spc(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        options = _options(r.keyword, f"BOUNDARY_SPC_{target}")
        lines = r.head_and_rest(bool(options & {"ID", "TITLE"}))
        for line in lines:
            if line.text.strip():
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
    "PART": _part,
    "SECTION_SHELL": _section_shell, "SECTION_SHELL_TITLE": _section_shell,
    "BOUNDARY_SPC_NODE": _spc("NODE"), "BOUNDARY_SPC_NODE_ID": _spc("NODE"),
    "BOUNDARY_SPC_SET": _spc("SET"), "BOUNDARY_SPC_SET_ID": _spc("SET"),
    "INITIAL_VELOCITY_GENERATION": _velocity_generation,
    "INITIAL_VELOCITY_NODE": _velocity_node,
    "CONTROL_TERMINATION": _control(CONTROL_TERMINATION, {"ENDCYC": 0, "ENDENG": 0.0, "ENDMAS": 1e8, "NOSOL": 0}),
    "CONTROL_TIMESTEP": _control(CONTROL_TIMESTEP, {"DTINIT": 0.0, "ISDO": 0, "TSLIMT": 0.0, "ERODE": 0,
                                                    "MS1ST": 0}),
    "CONTROL_CONTACT": _control(CONTROL_CONTACT, {"RWPNAL": 0.0, "ISLCHK": 1, "SHLTHK": 0, "PENOPT": 1,
                                                  "THKCHG": 0, "ORIEN": 1, "ENMASS": 0}),
    "CONTROL_HOURGLASS": _control(CONTROL_HOURGLASS),
    "CONTROL_IMPLICIT_GENERAL": _control(CONTROL_IMPLICIT_GENERAL),
    "CONTROL_UNITS": _control(CONTROL_UNITS, {"TEMP": "k"}),
    "DATABASE_BINARY_D3PLOT": _control(DATABASE_DT, {"LCDT": 0, "BEAM": 0, "NPLTC": 0, "PSETID": 0}),
    "DATABASE_GLSTAT": _control(DATABASE_DT[:1]),
    "DATABASE_NODOUT": _control(DATABASE_DT[:1]),
    "DATABASE_HISTORY_NODE": _history_node, "DATABASE_HISTORY_NODE_ID": _history_node,
    "HOURGLASS": _hourglass, "HOURGLASS_TITLE": _hourglass,
    "DEFINE_CURVE": _define_curve, "DEFINE_CURVE_TITLE": _define_curve,
    "LOAD_BODY_X": _load_body, "LOAD_BODY_Y": _load_body, "LOAD_BODY_Z": _load_body,
}
for _title in ("", "_TITLE"):
    for _name in ("MAT_ELASTIC", "MAT_001"):
        READERS[_name + _title] = _material("elastic", MAT_ELASTIC, {"DA": 0.0, "DB": 0.0, "K": 0.0})
    for _name in ("MAT_PLASTIC_KINEMATIC", "MAT_003"):
        READERS[_name + _title] = _material("j2_plasticity", MAT_PLASTIC_KINEMATIC, {"FS": 0.0, "VP": 0.0})
    for _kind in ("SURFACE_TO_SURFACE", "SINGLE_SURFACE"):
        for _option in ("", "_ID"):
            READERS[f"CONTACT_AUTOMATIC_{_kind}{_option or _title}"] = _contact(_kind.lower())
    for _target in ("NODE", "PART"):
        for _list in ("", "_LIST", "_LIST_GENERATE"):
            READERS[f"SET_{_target}{_list}{_title}"] = _set(_target)
READERS.update(WALL_READERS)   # *RIGIDWALL_PLANAR and _GEOMETRIC (keyword/walls.py)


def collect(deck: KeywordFile) -> KeywordData:
    """Read every block of ``deck``; unsupported keywords are named in ``warnings`` and skipped. An
    error carries the warnings collected before it (a skipped keyword is often its cause)."""
    data = KeywordData(title=deck.title, warnings=list(deck.warnings))
    try:
        for block in deck.blocks:
            reader = READERS.get(block.name)
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
