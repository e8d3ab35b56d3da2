"""Contacts of a keyword deck (docs/keyword.md, "Contacts"): the ``*CONTACT_...`` variants, their
``_ID``/``_TITLE``/``_MORTAR`` options, ``*PART_CONTACT`` and ``*CONTROL_CONTACT``, read into
records (:data:`READERS`) and mapped onto ParaDyn's contact kinds as :class:`ContactSpec`\\ s
(:func:`contact_specs`): surface-to-surface and nodes-to-surface variants become symmetric
``node_to_segment`` pairs, single-surface variants one ``single_surface`` contact, tied variants
``tied`` pairs, tiebreak variants ``tiebreak`` pairs (OPTION 1 only); SOFT = 2 (segment-based
contact) adds the edge checks (``edges = true``). A part whose shells were split by thickness
(keyword/parts.py) stands for all its engine parts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from paradyn.scene.specs import ContactSpec

from . import cards
from .cards import KeywordData, Record, _Reading
from .reader import Field, KeywordError, layout
from .units import Units

CONTACT_ID = (Field("CID", "int", 0), Field("HEADING", "text", "", 70))
CONTACT = (layout("int:SSID int:MSID int:SSTYP int:MSTYP int:SBOXID int:MBOXID int:SPR int:MPR",
                  ssid=0, msid=0, sstyp=0, mstyp=0, sboxid=0, mboxid=0, spr=0, mpr=0),
           layout("FS FD DC VC VDC int:PENCHK BT DT", fs=0.0, fd=0.0, dc=0.0, vc=0.0, vdc=0.0, penchk=0,
                  bt=0.0, dt=1e20),
           layout("SFS SFM SST MST SFST SFMT FSF VSF", sfs=1.0, sfm=1.0, sst=0.0, mst=0.0, sfst=1.0, sfmt=1.0,
                  fsf=1.0, vsf=1.0),
           layout("int:SOFT SOFSCL int:LCIDAB MAXPAR SBOPT int:DEPTH int:BSORT int:FRCFRQ", soft=0, sofscl=0.1,
                  lcidab=0, maxpar=1.025, sbopt=2.0, depth=2, bsort=0, frcfrq=1),
           layout("PENMAX int:THKOPT int:SHLTHK int:SNLOG int:ISYM int:I2D3D SLDTHK SLDSTF", penmax=0.0, thkopt=0,
                  shlthk=0, snlog=0, isym=0, i2d3d=0, sldthk=0.0, sldstf=0.0),
           layout("int:IGAP int:IGNORE DPRFAC DTSTIF EDGEK UNUSED FLANGL int:CID_RCF", igap=1, ignore=0, dprfac=0.0,
                  dtstif=0.0, edgek=0.0, unused=0.0, flangl=0.0, cid_rcf=0))
IGNORED = ({"SBOXID": 0, "MBOXID": 0, "SPR": 0, "MPR": 0},
           {"VC": 0.0, "VDC": 0.0, "PENCHK": 0},
           {"SST": 0.0, "MST": 0.0, "FSF": 1.0, "VSF": 1.0},
           {"LCIDAB": 0, "MAXPAR": 1.025, "SBOPT": 2.0, "DEPTH": 2, "BSORT": 0, "FRCFRQ": 1},
           {"PENMAX": 0.0, "THKOPT": 0, "SHLTHK": 0, "SNLOG": 0, "ISYM": 0, "I2D3D": 0, "SLDTHK": 0.0, "SLDSTF": 0.0},
           {"IGAP": 1, "IGNORE": 0, "DPRFAC": 0.0, "DTSTIF": 0.0, "EDGEK": 0.0, "UNUSED": 0.0, "FLANGL": 0.0,
            "CID_RCF": 0})
CONTROL_CONTACT = (
    layout("SLSFAC RWPNAL int:ISLCHK int:SHLTHK int:PENOPT int:THKCHG int:ORIEN int:ENMASS",
           slsfac=0.1, rwpnal=0.0, islchk=1, shlthk=0, penopt=1, thkchg=0, orien=1, enmass=0),
    layout("int:USRSTR int:USRFRC int:NSBCS int:INTERM XPENE int:SSTHK int:ECDT int:TIEDPRJ", usrstr=0,
           usrfrc=0, nsbcs=0, interm=0, xpene=4.0, ssthk=0, ecdt=0, tiedprj=0),
    layout("SFRIC DFRIC EDC VFC TH TH_SF PEN_SF", sfric=0.0, dfric=0.0, edc=0.0, vfc=0.0, th=0.0, th_sf=0.0,
           pen_sf=0.0),
    layout("int:IGNORE int:FRCENG int:SKIPRWG int:OUTSEG int:SPOTSTP int:SPOTDEL SPOTHIN", ignore=0, frceng=0,
           skiprwg=0, outseg=0, spotstp=0, spotdel=0, spothin=0.0),
    layout("int:ISYM int:NSEROD int:RWGAPS RWGDTH RWKSF int:ICOV SWRADF int:ITHOFF", isym=0, nserod=0, rwgaps=1,
           rwgdth=0.0, rwksf=1.0, icov=0, swradf=0.0, ithoff=0),
    layout("int:SHLEDG int:PSTIFF int:ITHCNT int:TDCNOF int:FTALL UNUSED SHLTRW int:IGACTC", shledg=0, pstiff=0,
           ithcnt=0, tdcnof=0, ftall=0, unused=0.0, shltrw=0.0, igactc=0),
)
# warned when not the default; SFRIC, DFRIC, EDC are read (the friction of FS = -1 without *PART_CONTACT)
CONTROL_CONTACT_IGNORED = (
    {"RWPNAL": 0.0, "ISLCHK": 1, "SHLTHK": 0, "PENOPT": 1, "THKCHG": 0, "ORIEN": 1, "ENMASS": 0},
    {"USRSTR": 0, "USRFRC": 0, "NSBCS": 0, "INTERM": 0, "XPENE": 4.0, "SSTHK": 0, "ECDT": 0, "TIEDPRJ": 0},
    {"VFC": 0.0, "TH": 0.0, "TH_SF": 0.0, "PEN_SF": 0.0},
    {"IGNORE": 0, "FRCENG": 0, "SKIPRWG": 0, "OUTSEG": 0, "SPOTSTP": 0, "SPOTDEL": 0, "SPOTHIN": 0.0},
    {"ISYM": 0, "NSEROD": 0, "RWGAPS": 1, "RWGDTH": 0.0, "RWKSF": 1.0, "ICOV": 0, "SWRADF": 0.0, "ITHOFF": 0},
    {"SHLEDG": 0, "PSTIFF": 0, "ITHCNT": 0, "TDCNOF": 0, "FTALL": 0, "UNUSED": 0.0, "SHLTRW": 0.0, "IGACTC": 0},
)
# the tiebreak card after card 3: NFLS, SFLS (*CONTACT_TIEBREAK_NODES_TO_SURFACE), or with the failure
# model first (*CONTACT_AUTOMATIC_(ONE_WAY_)SURFACE_TO_SURFACE_TIEBREAK: OPTION 1 is the stress criterion)
TIEBREAK_NODES = layout("NFLS SFLS", nfls=0.0, sfls=0.0)
TIEBREAK_OPTION = layout("int:OPTION NFLS SFLS PARAM ERATEN ERATES CT2CN CN", option=0, nfls=0.0, sfls=0.0,
                         param=0.0, eraten=0.0, erates=0.0, ct2cn=1.0, cn=0.0)
PART_CONTACT = layout("FS FD DC VC OPTT SFT SSF CPARM8", fs=0.0, fd=0.0, dc=0.0, vc=0.0, optt=0.0, sft=1.0,
                      ssf=1.0, cparm8=0.0)


@dataclass(frozen=True)
class Variant:
    """How a *CONTACT_... keyword maps: ``form`` is "pair", "single", "tied" or "tiebreak"; ``note`` a warning
    when the mapping is not LS-DYNA's own behaviour."""

    form: str
    note: str = ""


_ONE_WAY = ("is one-way in LS-DYNA (slave nodes on master segments); ParaDyn's node_to_segment pair is two-way "
            "(each side's nodes on the other's segments), symmetric = true")
VARIANTS = {
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE": Variant("pair"),
    "CONTACT_SURFACE_TO_SURFACE": Variant("pair", "is read as the automatic kind: ParaDyn's contact surfaces are "
                                                  "two-sided, whatever the segments' orientation"),
    "CONTACT_AUTOMATIC_SINGLE_SURFACE": Variant("single"),
    "CONTACT_SINGLE_SURFACE": Variant("single"),
    "CONTACT_NODES_TO_SURFACE": Variant("pair", _ONE_WAY),
    "CONTACT_AUTOMATIC_NODES_TO_SURFACE": Variant("pair", _ONE_WAY),
    "CONTACT_TIED_NODES_TO_SURFACE": Variant("tied"),
    "CONTACT_TIED_SHELL_EDGE_TO_SURFACE": Variant("tied"),
    "CONTACT_TIED_SURFACE_TO_SURFACE": Variant("tied"),
    "CONTACT_TIEBREAK_NODES_TO_SURFACE": Variant("tiebreak"),
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK": Variant("tiebreak", "is read as ties of the first side's nodes "
                                                                         "on the second side's segments (one-way)"),
    "CONTACT_AUTOMATIC_ONE_WAY_SURFACE_TO_SURFACE_TIEBREAK": Variant("tiebreak"),
}
TIEBREAK_CARDS = {"CONTACT_TIEBREAK_NODES_TO_SURFACE": TIEBREAK_NODES}   # the others: TIEBREAK_OPTION
_MORTAR = "(mortar) is read as {}, ParaDyn's nearest kind: node-to-segment penalty contact, not mortar"


def _read_contact(base: str, options: frozenset[str]) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        lines = r.lines(skip_blank=False)
        identified = bool(options & {"ID", "TITLE"})
        if not lines or (identified and len(lines) < 2):
            raise KeywordError(f"{r.block.where}: *{r.keyword} has no data card; complete it")
        head = r.card(lines[0], CONTACT_ID) if identified else Record({"CID": 0, "HEADING": ""}, r.block.where)
        body = lines[1:] if identified else lines
        tiebreak: list[Record] = []
        if VARIANTS[base].form == "tiebreak":   # its card follows card 3
            if len(body) < 4:
                raise KeywordError(f"{r.block.where}: *{r.keyword} has no tiebreak card (the fourth: NFLS, SFLS); "
                                   f"complete it")
            tiebreak = [r.card(body[3], TIEBREAK_CARDS.get(base, TIEBREAK_OPTION))]
            body = body[:3] + body[4:]
        records = [head] + [r.card(line, card, skip) for line, card, skip in zip(body, CONTACT, IGNORED, strict=False)]
        records += [Record({f.name: f.default for f in card}, body[-1].where) for card in CONTACT[len(records) - 1:]]
        if any(line.text.strip() for line in body[len(CONTACT):]):
            r.data.warn(f"{body[len(CONTACT)].where}: *{r.keyword}: the optional cards D and after are not read "
                        f"(docs/keyword.md)")
        name = base + "".join(f"_{o}" for o in ("MORTAR", "OFFSET") if o in options)
        r.data.contacts.append((name, records + tiebreak))
    return read


def _control_contact(r: _Reading) -> None:
    lines = r.head_and_rest(False)
    records = [r.card(line, card, skip) for line, card, skip in zip(lines, CONTROL_CONTACT, CONTROL_CONTACT_IGNORED,
                                                                   strict=False)]
    records += [Record({f.name: f.default for f in card}, lines[-1].where) for card in CONTROL_CONTACT[len(records):]]
    if any(line.text.strip() for line in lines[len(CONTROL_CONTACT):]):
        r.data.warn(f"{lines[len(CONTROL_CONTACT)].where}: *CONTROL_CONTACT: cards 7 and after are not read")
    merged = {k: v for record in records for k, v in record.values.items()}
    r.data.control["CONTROL_CONTACT"] = Record(merged, records[0].where)


def _part_contact(r: _Reading) -> None:
    """*PART_CONTACT: a *PART (heading, card 1) with a card of the part's contact data."""
    for heading, card, contact in r.groups(3):
        record = r.card(card, cards.PART[1], {"EOSID": 0, "GRAV": 0, "ADPOPT": 0, "TMID": 0})
        record.values["HEADING"] = heading.text.strip()
        r.data.parts.append(record)
        r.data.part_contacts[int(record["PID"])] = r.card(contact, PART_CONTACT, {"VC": 0.0, "OPTT": 0.0, "SFT": 1.0,
                                                                                  "SSF": 1.0, "CPARM8": 0.0})


READERS: dict[str, Callable[[_Reading], None]] = {"CONTROL_CONTACT": _control_contact, "PART_CONTACT": _part_contact}
for _base, _variant in VARIANTS.items():
    _extras = [(), ("OFFSET",)] if _variant.form == "tied" else [(), ("MORTAR",)]
    if "AUTOMATIC" not in _base or _variant.form == "tiebreak":
        _extras = [()] if _variant.form != "tied" else _extras
    for _extra in _extras:
        for _id in ((), ("ID",), ("TITLE",)):
            _name = "_".join((_base, *_extra, *_id))
            READERS[_name] = _read_contact(_base, frozenset((*_extra, *_id)))


# ----------------------------------------------------------------------------------------------
# the mapping


def contact_specs(data: KeywordData, names_of: dict[int, list[str]], unit: Units, end_time: float) -> list[ContactSpec]:
    """The contacts of the deck as scene specs; ``names_of`` gives each PID with shells its engine
    parts (one, or one per thickness) and ``end_time`` (the deck's units) dates the death times."""
    specs: list[ContactSpec] = []
    for name, records in data.contacts:
        specs += _contact(data, name, records, names_of, unit, end_time)
    return specs


def _label(name: str, head: Record, first: Record) -> str:
    cid, heading = int(head["CID"] or 0), str(head["HEADING"] or "").strip()
    named = f" {cid}" if cid else ""
    named += f" '{heading}'" if heading else ""
    return f"{first.where}: *{name}{named}"


def _contact(data: KeywordData, name: str, records: list[Record], names_of: dict[int, list[str]], unit: Units,
             end_time: float) -> list[ContactSpec]:
    head, first, second = records[:3]
    base = name.removesuffix("_MORTAR").removesuffix("_OFFSET")
    variant = VARIANTS[base]
    label = _label(name, head, first)
    if name.endswith("_MORTAR"):
        data.warn(f"{label} {_MORTAR.format('*' + base)}")
    elif variant.note:
        data.warn(f"{label} {variant.note}")
    elif variant.form == "tied" and not name.endswith("_OFFSET"):
        data.warn(f"{label} (a constraint tie in LS-DYNA) is read as ParaDyn's penalty tie, LS-DYNA's _OFFSET form")
    times = _times(data, label, second, unit)
    slave = _side(data, label, "SSTYP", int(first["SSTYP"]), int(first["SSID"]), names_of)
    common = {**_law(data, label, records, slave, unit), **times}
    soft = int(records[4]["SOFT"] or 0)
    edges = _edges(data, label, soft, variant.form)
    if variant.form not in ("tied", "tiebreak"):
        common["edges"] = edges
    if soft == 1 and variant.form not in ("tied", "tiebreak"):
        common["soft_constraint"] = float(records[4]["SOFSCL"])
    common["thickness_scale"] = _thickness_scales(records[3], variant.form == "single")
    if variant.form == "single":
        every = int(first["SSTYP"]) == 5 or int(first["SSID"]) == 0
        members = tuple(n for pid in slave for n in names_of[pid])
        return [ContactSpec(parts=() if every else members, kind="single_surface", **common)]
    master = _side(data, label, "MSTYP", int(first["MSTYP"]), int(first["MSID"]), names_of)
    if variant.form == "tiebreak":
        common.update(_tiebreak(label, records[7], unit))
        pairs = [(a, b) for s in slave for m in master if s != m for a in names_of[s] for b in names_of[m]]
        return [ContactSpec(parts=pair, kind="tiebreak", **common) for pair in pairs]
    if variant.form == "tied":
        pairs = [(a, b) for s in slave for m in master if s != m for a in names_of[s] for b in names_of[m]]
        if base == "CONTACT_TIED_SHELL_EDGE_TO_SURFACE":   # the edges' rotations too (deck/rotation_ties.py)
            data.shell_edges += pairs
        return [ContactSpec(parts=pair, kind="tied", **common) for pair in pairs]
    pairs: dict[frozenset[str], tuple[str, str]] = {}   # symmetric: (a, b) and (b, a) are one contact
    for s, m in ((s, m) for s in slave for m in master if s != m):
        for a in names_of[s]:
            for b in names_of[m]:
                pairs.setdefault(frozenset((a, b)), (a, b))
    return [ContactSpec(parts=pair, symmetric=True, **common) for pair in pairs.values()]


def _thickness_scales(third: Record, single: bool) -> tuple[float, float]:
    """SFST, SFMT (card 3): the scales on the slave and master sides' contact thickness, read as
    ``thickness_scale`` (first part: the slave side; 0 or blank: 1, LS-DYNA's default); a
    single-surface contact has one surface and takes SFST."""
    sfst = float(third["SFST"] or 0.0) or 1.0
    sfmt = float(third["SFMT"] or 0.0) or 1.0
    return (sfst, sfst) if single else (sfst, sfmt)


def _tiebreak(label: str, card: Record, unit: Units) -> dict[str, float]:
    """The failure stresses NFLS, SFLS (the deck's stress, to Pa) of a tiebreak: a tie fails when
    (sigma_n / NFLS)^2 + (sigma_s / SFLS)^2 >= 1. Of the failure models (OPTION), only 1, that
    criterion followed by contact, is read; the others (damage, energy release, cohesive laws) are
    refused."""
    option = int(card.values.get("OPTION", 1) or 1)
    if option != 1:
        raise KeywordError(f"{label}: tiebreak OPTION = {option} is not supported: ParaDyn reads OPTION 1 (failure "
                           f"when (sigma_n/NFLS)^2 + (sigma_s/SFLS)^2 >= 1, then contact); change OPTION to 1 or "
                           f"use *CONTACT_TIEBREAK_NODES_TO_SURFACE")
    normal, shear = float(card["NFLS"] or 0.0), float(card["SFLS"] or 0.0)
    if normal < 0.0 or shear < 0.0:
        raise KeywordError(f"{label}: a negative failure stress (NFLS = {normal:g}, SFLS = {shear:g}, LS-DYNA's load "
                           f"curve ids) is not read; give the stresses")
    if normal == 0.0 and shear == 0.0:
        raise KeywordError(f"{label}: NFLS and SFLS are both 0, so no tie would ever fail; give a failure stress or "
                           f"use *CONTACT_TIED_NODES_TO_SURFACE")
    return {"normal_failure_stress": normal * unit.stress, "shear_failure_stress": shear * unit.stress}


def _edges(data: KeywordData, label: str, soft: int, form: str) -> bool:
    """SOFT = 2 (LS-DYNA's segment-based contact, which finds walls crossing edge against edge) is read
    as ParaDyn's contact with edge checks (edges = true: kinds edge_to_edge, single_surface_edges);
    SOFT = 1 (the soft-constraint stiffness, ``soft_constraint`` = SOFSCL) is read by the caller."""
    if soft == 2 and form in ("tied", "tiebreak"):
        data.warn(f"{label}: SOFT = 2 on a tied contact is ignored (a tie has no edge checks)")
        return False
    if soft == 1 and form in ("tied", "tiebreak"):
        data.warn(f"{label}: SOFT = 1 on a tied contact is ignored (a tie's spring is the stable cap)")
    if soft not in (0, 1, 2):
        data.warn(f"{label}: SOFT = {soft} is not supported and ignored (SOFT = 2 is read as edges = true: "
                  f"docs/keyword.md)")
    return soft == 2


def _times(data: KeywordData, label: str, second: Record, unit: Units) -> dict[str, float]:
    """Birth and death times BT, DT (the deck's time, to s): the contact acts while BT <= t <= DT.
    DT = 0 means never (1e20), as in LS-DYNA; a negative BT or DT (LS-DYNA: times that also hold
    during dynamic relaxation, which ParaDyn does not run) is read as its absolute value, with a
    warning. The scene's keys are left at their defaults for a contact of the whole run."""
    birth, death = float(second["BT"] or 0.0), float(second["DT"] or 0.0)
    if birth < 0.0 or death < 0.0:
        data.warn(f"{label}: BT = {birth:g}, DT = {death:g}: a negative time (dynamic relaxation) is read as its "
                  f"absolute value; ParaDyn runs no dynamic relaxation")
        birth, death = abs(birth), abs(death)
    if death == 0.0:
        death = 1e20
    if death <= birth:
        raise KeywordError(f"{label}: DT = {death:g} is not after BT = {birth:g}: the contact would never act; "
                           f"remove it or correct its times")
    times: dict[str, float] = {}
    if birth > 0.0:
        times["birth_time"] = birth * unit.time
    if death < 1e20:
        times["death_time"] = death * unit.time
    return times


def _side(data: KeywordData, label: str, what: str, kind: int, ident: int,
          names_of: dict[int, list[str]]) -> list[int]:
    """PIDs (with shells) of a contact side: ``kind`` is LS-DYNA's SSTYP/MSTYP (2 part set, 3 part,
    4 node set: the parts of its nodes, 5 every part, 6 every part but a part set); an id of 0
    takes every part with shells."""
    shells = list(names_of)
    if kind == 5 or ident == 0:
        return shells
    if kind == 3:
        if ident not in names_of:
            raise KeywordError(f"{label} names part {ident} ({what} 3), which has no shell elements; name a part "
                               f"with shells, or leave the contact out")
        return [ident]
    if kind in (2, 6):
        if ident not in data.part_sets:
            raise KeywordError(f"{label} names part set {ident} ({what} {kind}), which no *SET_PART defines")
        listed = data.part_sets[ident]
        if kind == 6:
            return [pid for pid in shells if pid not in listed]
        skipped = [pid for pid in listed if pid not in names_of]
        if skipped:
            data.warn(f"{label}: part set {ident} holds parts without shells ({', '.join(map(str, skipped))}); "
                      f"they are left out of the contact")
        return [pid for pid in listed if pid in names_of]
    if kind == 4:
        return _node_set_parts(data, label, ident, names_of)
    raise KeywordError(f"{label}: {what} = {kind} is not read; give parts (3), a part set (2), a node set (4), every "
                       f"part (5) or every part but a part set (6)")


def _node_set_parts(data: KeywordData, label: str, ident: int, names_of: dict[int, list[str]]) -> list[int]:
    if ident not in data.node_sets:
        raise KeywordError(f"{label} names node set {ident}, which no *SET_NODE defines")
    nodes = set(data.node_sets[ident])
    pids = list(dict.fromkeys(int(e["PID"]) for e in data.elements
                              if nodes & {int(e[f"N{k}"] or 0) for k in range(1, 5)}))
    pids = [pid for pid in pids if pid in names_of]
    data.warn(f"{label}: node set {ident} as a contact side is read as the parts that hold its nodes "
              f"({', '.join(map(str, pids))}): ParaDyn's contacts are by part, so every node of those parts takes part")
    return pids


def _law(data: KeywordData, label: str, records: list[Record], slave: list[int], unit: Units) -> dict[str, float]:
    """Penalty scale SLSFAC x SFS and friction FS, FD, DC (FS = -1: the parts' *PART_CONTACT values)."""
    second, third = records[2], records[3]
    sfs, sfm = float(third["SFS"]), float(third["SFM"])
    if sfm != sfs:
        data.warn(f"{label}: SFM = {sfm:g} differs from SFS = {sfs:g}; ParaDyn has one penalty scale per contact, "
                  f"SLSFAC x SFS is used")
    control = data.control.get("CONTROL_CONTACT")
    slsfac = float(control["SLSFAC"]) if control is not None else 0.1
    fs, fd, dc = float(second["FS"]), float(second["FD"]), float(second["DC"])
    if fs == -1.0:
        fs, fd, dc = _part_friction(data, label, slave)
    return {"penalty_scale": slsfac * sfs, "static_friction": fs, "dynamic_friction": fd,
            "friction_decay": dc * unit.time / unit.length}


def _part_friction(data: KeywordData, label: str, slave: list[int]) -> tuple[float, float, float]:
    """FS = -1: each part's FS, FD, DC of *PART_CONTACT (or *CONTROL_CONTACT's SFRIC, DFRIC, EDC)."""
    control = data.control.get("CONTROL_CONTACT")
    fallback = tuple(float(control[k]) if control else 0.0 for k in ("SFRIC", "DFRIC", "EDC"))
    values = [tuple(float(data.part_contacts[pid][k]) for k in ("FS", "FD", "DC")) if pid in data.part_contacts
              else fallback for pid in slave]
    if len(set(values)) > 1:
        data.warn(f"{label}: FS = -1 takes each part's friction from *PART_CONTACT, and the parts differ; ParaDyn "
                  f"has one friction per contact, part {slave[0]}'s is used")
    return values[0] if values else fallback
