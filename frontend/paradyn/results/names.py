"""The names of a run: title, part names, tracked point names, effects and the requested end time.

They come from ``results.h5`` where the engine wrote them (root attribute ``title``, ``/mesh``
attribute ``part_names``, ``/run`` attribute ``effects`` and the effect table ``/effects``; the
engine alone decides which effects a deck declares), else from the deck the run used
(``deck.h5`` beside the results, or one passed explicitly), else from fallbacks (``part_<i>``,
``node_<id>``, ``tracked_<i>``). docs/outputs.md, "Names", says the same for users.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .layout import ResultsError, strings

if TYPE_CHECKING:
    import h5py

DECK_FILE_NAME = "deck.h5"


@dataclass
class RunNames:
    """What names a run; empty fields were not found."""

    deck_path: Path | None = None
    title: str | None = None
    part_names: list[str] = field(default_factory=list)
    n_parts: int = 0
    tracked_names: list[str] = field(default_factory=list)
    tracked_nodes: np.ndarray | None = None
    end_time: float | None = None
    effects: list[str] | None = None
    effect_table: list[EffectRow] = field(default_factory=list)
    file_ids: dict[str, np.ndarray] = field(default_factory=dict)   # "node"/"element"/"part" -> the deck's ids


@dataclass(frozen=True)
class EffectRow:
    """One effect of a run's effect table (docs/formats.md, the effect table)."""

    name: str
    state: str              # "on", or "off" where the scene switched it off
    active_cycles: int      # cycles it did its work
    skipped_cycles: int     # cycles it was idle and not called
    wall_s: float           # rank 0's wall seconds (0 where timed with another effect)
    timed_with: str         # the effect whose seconds include this one's, "" where timed alone
    pairs: tuple[dict, ...] = ()   # contact: per pair {"parts": [a, b], "active_cycles", "skipped_cycles"}


def effect_table(h5: h5py.File) -> list[EffectRow]:
    """The effect table the engine wrote (``/effects``), in the order of the step; empty for a
    run that did not finish writing it."""
    if "effects" not in h5:
        return []
    names = strings(h5["mesh"].attrs.get("part_names")) if "mesh" in h5 else []
    rows = []
    for name, group in h5["effects"].items():
        a = group.attrs
        rows.append((int(a["order"]), EffectRow(
            name=name, state=(strings(a["state"], one=True) or ["on"])[0].strip(),
            active_cycles=int(a["active_cycles"]), skipped_cycles=int(a["skipped_cycles"]),
            wall_s=float(a["wall_s"]), timed_with=(strings(a["timed_with"], one=True) or [""])[0],
            pairs=_contact_pairs(a, names))))
    return [row for _, row in sorted(rows, key=lambda item: item[0])]


def _contact_pairs(attrs: h5py.AttributeManager, part_names: list[str]) -> tuple[dict, ...]:
    """The contact row's pairs: their parts by name and the cycles each ran its stages or was idle."""
    if "pair_parts" not in attrs:
        return ()
    parts = np.asarray(attrs["pair_parts"]).reshape(-1, 2)

    def name(i: int) -> str:
        return part_names[i] if i < len(part_names) else f"part_{i}"

    return tuple({"parts": [name(int(a)), name(int(b))], "active_cycles": int(active), "skipped_cycles": int(skipped)}
                 for (a, b), active, skipped in zip(parts, attrs["pair_active_cycles"], attrs["pair_skipped_cycles"],
                                                    strict=True))


def names_in_results(h5: h5py.File) -> RunNames:
    """The names the engine wrote into an open results file (none yet in older files)."""
    names = RunNames()
    if "title" in h5.attrs:
        names.title = (strings(h5.attrs["title"], one=True) or [""])[0]
    if "mesh" in h5 and "part_names" in h5["mesh"].attrs:
        names.part_names = strings(h5["mesh"].attrs["part_names"])
    if "history" in h5 and "tracked_names" in h5["history"].attrs:
        names.tracked_names = strings(h5["history"].attrs["tracked_names"])
    if "run" in h5 and "effects" in h5["run"].attrs:
        text = (strings(h5["run"].attrs["effects"], one=True) or [""])[0]
        names.effects = [e.strip() for e in text.split(",") if e.strip()]
    names.effect_table = effect_table(h5)
    return names


def names_in_deck(results_path: Path, deck: str | Path | None, n_nodes: int) -> RunNames:
    """The names in the run's deck: ``deck`` if given (it must exist and match), else
    ``deck.h5`` beside the results if it matches (a mismatch is ignored with a warning)."""
    if deck is None:
        candidate = results_path.parent / DECK_FILE_NAME
        if not candidate.is_file():
            return RunNames()
        try:
            return _read_deck_names(candidate, n_nodes)
        except (ResultsError, OSError) as exc:
            warnings.warn(f"ignoring {candidate} for names: {exc}", stacklevel=3)
            return RunNames()
    deck = Path(deck)
    if not deck.is_file():
        raise FileNotFoundError(
            f"no deck at {deck}; pass the deck.h5 the run used, or leave deck=None"
        )
    return _read_deck_names(deck, n_nodes)


def _read_deck_names(deck: Path, n_nodes: int) -> RunNames:
    import h5py  # where a file is opened (layout.open_results)

    try:
        h5 = h5py.File(deck, "r")
    except OSError as exc:
        raise ResultsError(
            f"{deck} is not a ParaDyn deck: it cannot be opened as HDF5 ({exc})"
        ) from exc
    with h5:
        if "paradyn_deck_version" not in h5.attrs:
            raise ResultsError(
                f"{deck} is not a ParaDyn deck (no root attribute paradyn_deck_version)"
            )
        deck_nodes = h5["/nodes/coordinates"].shape[0] if "/nodes/coordinates" in h5 else None
        if deck_nodes is not None and deck_nodes != n_nodes:
            raise ResultsError(
                f"{deck} has {deck_nodes} nodes but the results have "
                f"{n_nodes}; it is not the deck of this run"
            )
        names = RunNames(deck_path=deck)
        names.title = (strings(h5.attrs.get("title"), one=True) or [""])[0]
        if "parts" in h5:
            names.part_names = strings(h5["parts"].attrs.get("names"))
            if "thickness" in h5["parts"]:
                names.n_parts = int(h5["parts/thickness"].shape[0])
        if "output" in h5:
            names.tracked_names = strings(h5["output"].attrs.get("tracked_names"))
            if "tracked_nodes" in h5["output"]:
                tracked = np.asarray(h5["output/tracked_nodes"][()])
                names.tracked_nodes = tracked.astype(np.int64).reshape(-1)
        for kind, group in (("node", "nodes"), ("element", "elements"), ("part", "parts")):
            if f"{group}/id" in h5:
                names.file_ids[kind] = np.asarray(h5[f"{group}/id"][()], dtype=np.int64).reshape(-1)
        if "control" in h5 and "end_time" in h5["control"].attrs:
            names.end_time = float(np.asarray(h5["control"].attrs["end_time"]).reshape(-1)[0])
    return names


def merged(from_results: RunNames, from_deck: RunNames) -> RunNames:
    """The results file's names where it has them, the deck's otherwise."""
    return RunNames(
        deck_path=from_deck.deck_path,
        title=from_results.title if from_results.title is not None else from_deck.title,
        part_names=from_results.part_names or from_deck.part_names,
        n_parts=from_deck.n_parts,
        tracked_names=from_results.tracked_names or from_deck.tracked_names,
        tracked_nodes=from_deck.tracked_nodes,
        end_time=from_deck.end_time,
        effects=from_results.effects,
        file_ids=from_deck.file_ids,
    )


def part_names(names: list[str], n_parts: int) -> list[str]:
    """``n_parts`` names: the given ones stripped, ``part_<i>`` for missing or blank ones."""
    out = [n.strip() for n in names[:n_parts]]
    out += [f"part_{i}" for i in range(len(out), n_parts)]
    return [n if n else f"part_{i}" for i, n in enumerate(out)]


def tracked_names(names: RunNames, n_tracked: int) -> list[str]:
    """``n_tracked`` names: the deck's, else ``node_<id>``, else ``tracked_<i>``."""
    out: list[str] = []
    for i in range(n_tracked):
        if i < len(names.tracked_names) and names.tracked_names[i].strip():
            out.append(names.tracked_names[i].strip())
        elif names.tracked_nodes is not None and i < names.tracked_nodes.shape[0]:
            out.append(f"node_{int(names.tracked_nodes[i])}")
        else:
            out.append(f"tracked_{i}")
    return out


def unique_safe_names(names: list[str], fallback: str) -> list[str]:
    """Names usable as file names and CSV column names: [A-Za-z0-9_.-], unique."""
    out: list[str] = []
    seen: set[str] = set()
    for i, name in enumerate(names):
        safe = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_.") or f"{fallback}_{i}"
        candidate, n = safe, 1
        while candidate in seen:
            n += 1
            candidate = f"{safe}_{n}"
        seen.add(candidate)
        out.append(candidate)
    return out
