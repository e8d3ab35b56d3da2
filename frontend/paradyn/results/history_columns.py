"""The history's columns by part, contact definition, wall and support (docs/outputs.md,
"History"): what :meth:`Results.history_table` writes beside the energies and tracked points."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from . import names as run_names

Results = Any   # a paradyn.results.reading.Results (not imported: reading imports this module)


def part_columns(results: Results) -> dict[str, tuple[str, np.ndarray]]:
    """The per-part, per-contact, per-wall and reaction columns: column -> (its /history dataset,
    values). A contact definition's force is written for both of its parts (contact_sides)."""
    h = results.history
    columns: dict[str, tuple[str, np.ndarray]] = {}
    parts = run_names.unique_safe_names(results.part_names, "part")
    for quantity in ("kinetic_energy", "internal_energy", "hourglass_energy", "plastic_work"):
        name = f"part_{quantity}"
        for i, part in enumerate(parts[:h[name].shape[1]]):
            columns[f"{part}_{quantity}"] = (name, h[name][:, i])
    sides = contact_sides(results)
    for k in range(h["contact_force"].shape[1]):
        for c, axis in enumerate("xyz"):
            if k >= len(sides):   # the parts are not known: the first part's force alone
                columns[f"contact{k}_f{axis}"] = ("contact_force", h["contact_force"][:, k, c])
                continue
            for side, sign in zip(sides[k], (1.0, -1.0), strict=False):
                columns[f"contact{k}_on_{side}_f{axis}"] = ("contact_force", sign * h["contact_force"][:, k, c])
    for k in range(h["rigid_wall_force"].shape[1]):
        for c, axis in enumerate("xyz"):
            columns[f"wall{k}_f{axis}"] = ("rigid_wall_force", h["rigid_wall_force"][:, k, c])
    for c, axis in enumerate("xyz"):
        columns[f"reaction_f{axis}"] = ("reaction_force", h["reaction_force"][:, c])
    for c, axis in enumerate("xyz"):
        columns[f"reaction_m{axis}"] = ("reaction_moment", h["reaction_moment"][:, c])
    return columns


def contact_sides(results: Results) -> list[tuple[str, ...]]:
    """Each contact definition's parts by column-safe name, as the history names its forces:
    (first, second) for a pair, whose second part gets the opposite of the first's force, and
    (part,) for a single surface (its forces act and react within it). From the effect table,
    else the deck; empty when neither is at hand."""
    parts = run_names.unique_safe_names(results.part_names, "part")
    rows = [row for row in results.effect_table if row.name == "contact" and row.pairs]
    if rows:
        named = dict(zip(results.part_names, parts, strict=True))
        pairs = [tuple(named.get(n, n) for n in pair["parts"]) for pair in rows[0].pairs]
    elif results.deck_path is not None and Path(results.deck_path).is_file():
        from paradyn import deck  # the deck reader, for the pairs only

        found = deck.read_deck_arrays(results.deck_path, ("contact_pairs",))["contact_pairs"]
        pairs = [tuple(parts[int(i)] for i in pair) for pair in np.asarray(found if found is not None else [])]
    else:
        return []
    return [pair[:1] if pair[0] == pair[-1] else pair for pair in pairs]
