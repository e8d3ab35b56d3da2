"""Reports of a run: the history as CSV, the energy report and ``summary.json``.

Keys, columns and units are in docs/outputs.md ("History" and "Run summary"); both files are
written atomically (:mod:`paradyn.atomic_write`).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from paradyn.atomic_write import write_text_atomic

from .layout import to_python
from .names import EffectRow
from .reading import ENERGY_NAMES, Results

PHASE_NAMES = ("elements", "contact", "communication", "output", "other")
CONTACT_PHASE_NAMES = ("sort", "search", "force")  # the contact phase split


def write_history_csv(results: Results, path: str | Path) -> Path:
    """Write the history table (see :meth:`Results.history_table`) as CSV; return the path.

    One header line, comma separated, each column named ``name [unit]`` (``time [s]``; ``[-]``:
    no unit; :meth:`Results.history_units`), every value written with Python's ``repr``
    (shortest text that reads back to the same float64).
    """
    path = Path(path)
    table, units = results.history_table(), results.history_units()
    columns = np.column_stack([np.asarray(v, dtype=np.float64) for v in table.values()])
    lines = [",".join(f"{name} [{units[name]}]" for name in table)]
    lines += [",".join(map(repr, row)) for row in columns.tolist()]
    return write_text_atomic(path, "\n".join(lines) + "\n")


def energy_report(results: Results) -> dict[str, Any]:
    """Initial and final energies (J) and the energy balance error.

    ``balance_error = |E_total(end) - E_total(0)| / max(max_t KE, max_t IE, max_t |W_ext|, tiny)``
    with ``E_total = KE + IE + hourglass + contact - W_ext``: the LS-DYNA style energy ratio
    check (a conservative run keeps it at a few percent at most).  ``hourglass_ratio`` is the
    final hourglass energy over the largest internal energy (LS-DYNA's rule of thumb: < 0.1).
    With no history records every value is None.
    """
    keys = ("kinetic", "internal", "hourglass", "contact", "external_work")
    columns = dict(zip(keys, ENERGY_NAMES, strict=True))
    h = results.history
    if results.n_records == 0:
        empty = {k: None for k in (*keys, "total")}
        return {
            "initial": dict(empty),
            "final": dict(empty),
            "balance_error": None,
            "reference_energy": None,
            "hourglass_ratio": None,
        }
    total = results.total_energy()
    initial = {k: float(h[c][0]) for k, c in columns.items()} | {"total": float(total[0])}
    final = {k: float(h[c][-1]) for k, c in columns.items()} | {"total": float(total[-1])}
    reference = max(
        float(np.max(h["kinetic_energy"])),
        float(np.max(h["internal_energy"])),
        float(np.max(np.abs(h["external_work"]))),
    )
    scale = max(reference, np.finfo(np.float64).tiny)
    max_internal = float(np.max(h["internal_energy"]))
    return {
        "initial": initial,
        "final": final,
        "balance_error": _finite(abs(final["total"] - initial["total"]) / scale),
        "reference_energy": reference,
        "hourglass_ratio": _finite(final["hourglass"] / max_internal) if max_internal > 0 else None,
    }


def accuracy_indicators(results: Results) -> dict[str, Any]:
    """What a run's own records say about its accuracy (issue 16), each None where the run has no
    record of it:

    - ``energy_balance_error``: as ``energy.balance_error``;
    - ``peak_hourglass_over_internal``: the largest hourglass energy over the largest internal
      energy (LS-DYNA's rule of thumb: below 0.1, and 0.05 is asked of ParaDyn's element);
    - ``peak_penetration_over_thickness``: the deepest contact penetration over the thinnest shell
      in a contact pair (the deck's thicknesses; None without contact or without the deck);
    - ``dt_over_stable_dt``: the step used over the mesh's stable step (safety factor included);
    - ``added_mass_fraction``: mass added by mass scaling over the model's mass (/run
      ``added_mass_fraction``; 0 without mass scaling);
    - ``peak_contact_over_internal``: the largest contact energy over the largest internal energy;
    - ``dt_min_s``, ``dt_max_s``: the range of the step over the history records (the step follows
      the mesh, docs/theory.md).
    """
    h, run = results.history, results.run
    indicators: dict[str, Any] = {"energy_balance_error": energy_report(results)["balance_error"],
                                  "peak_hourglass_over_internal": None, "peak_penetration_over_thickness": None,
                                  "dt_over_stable_dt": None, "added_mass_fraction": 0.0,
                                  "peak_contact_over_internal": None, "dt_min_s": None, "dt_max_s": None}
    if run.get("dt_s") and run.get("dt_stable_s"):
        indicators["dt_over_stable_dt"] = _finite(float(run["dt_s"]) / float(run["dt_stable_s"]))
    if run.get("added_mass_fraction") is not None:
        indicators["added_mass_fraction"] = _finite(float(run["added_mass_fraction"]))
    if results.n_records:
        peak_internal = float(np.max(h["internal_energy"]))
        if peak_internal > 0:
            indicators["peak_hourglass_over_internal"] = _finite(float(np.max(h["hourglass_energy"])) / peak_internal)
            indicators["peak_contact_over_internal"] = _finite(float(np.max(h["contact_energy"])) / peak_internal)
        indicators["peak_penetration_over_thickness"] = _penetration_over_thickness(results)
        if "dt" in h:
            indicators["dt_min_s"] = _finite(float(np.min(h["dt"])))
            indicators["dt_max_s"] = _finite(float(np.max(h["dt"])))
    return indicators


# Thresholds of the accuracy line paradyn-run prints (issue 15, guards a person sees): a crossing
# gets its own warning line.
WARN_ABOVE = {"energy_balance_error": 0.01, "peak_hourglass_over_internal": 0.10,
              "peak_penetration_over_thickness": 0.20}
_LABELS = {"energy_balance_error": "energy balance error", "peak_hourglass_over_internal": "peak hourglass / internal",
           "peak_penetration_over_thickness": "deepest penetration / thickness", "dt_over_stable_dt": "dt / stable dt",
           "added_mass_fraction": "added mass", "peak_contact_over_internal": "peak contact / internal",
           "dt_min_s": "dt from (s)", "dt_max_s": "to (s)"}
# What to try when a threshold is crossed (docs/outputs.md, accuracy)
_ADVICE = {"energy_balance_error": "a smaller [run] time_step_safety, or [run] energy_error_limit to stop such a run",
           "peak_hourglass_over_internal": "a finer mesh where it deforms most, or hourglass_form = \"physical\"",
           "peak_penetration_over_thickness": "a smaller [run] contact_closing_limit (0.05 by default) or "
                                              "contact_travel_limit = 0.1 if a wall is crossed within a step, "
                                              "or a larger penalty_scale"}


def accuracy_text(results: Results) -> str:
    """One line of the accuracy indicators, then a warning line per threshold crossed (WARN_ABOVE)."""
    indicators = accuracy_indicators(results)
    shown = [f"{_LABELS[k]} {v:.3g}" for k, v in indicators.items() if v is not None]
    lines = ["  accuracy: " + ", ".join(shown)]
    for key, limit in WARN_ABOVE.items():
        value = indicators[key]
        if value is not None and value > limit:
            lines.append(f"  warning: {_LABELS[key]} is {value:.3g}, above {limit:g}; try {_ADVICE[key]} "
                         f"(docs/outputs.md, accuracy)")
    return "\n".join(lines)


def mass_scaling_report(results: Results) -> dict[str, Any]:
    """The mass that mass scaling added (/run attributes): in all (kg), as a fraction of the
    model's mass, and per part by name (kg); zeros without mass scaling."""
    run = results.run
    per_part = run.get("part_added_mass_kg", [])
    per_part = [per_part] if isinstance(per_part, float | int) else list(per_part)
    names = list(results.part_names) or [f"part_{k}" for k in range(len(per_part))]
    return {"added_kg": run.get("added_mass_kg", 0.0), "fraction": run.get("added_mass_fraction", 0.0),
            "model_mass_kg": run.get("model_mass_kg"),
            "per_part_kg": {str(name): float(kg) for name, kg in zip(names, per_part, strict=False)}}


def _penetration_over_thickness(results: Results) -> float | None:
    if results.deck_path is None or not Path(results.deck_path).is_file():
        return None
    from paradyn import deck  # the deck reader is needed for the thicknesses only

    arrays = deck.read_deck_arrays(results.deck_path, ("thickness", "contact_pairs"))
    pairs = arrays["contact_pairs"]
    if pairs is None or pairs.size == 0:
        return None
    thinnest = float(np.min(np.asarray(arrays["thickness"])[np.asarray(pairs).ravel()]))
    return _finite(float(np.max(results.history["contact_penetration"])) / thinnest)


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def write_summary(
    results: Results,
    path: str | Path,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Write ``summary.json`` atomically and return its content.

    Run figures come from the ``/run`` attributes (None if the run did not write them);
    ``elements`` and ``nodes`` fall back to the mesh.  ``extra`` entries are merged last and
    may replace computed ones.  ``warnings`` (the run's, which ``paradyn.run`` gives in ``extra``)
    are those of the summary already at ``path`` when ``extra`` has none (post-processing again
    keeps them), else None.  Keys and units: docs/outputs.md.
    """
    run = results.run
    summary: dict[str, Any] = {
        "title": results.title,
        "complete": results.complete,
        "end_time": (
            results.end_time if results.end_time is not None else _last(results.time_values)
        ),
        "time_reached": (
            _last(results.history["time"]) if results.n_records else _last(results.time_values)
        ),
        "wall_s": run.get("wall_s"),
        "cycles": run.get("cycles"),
        "dt_s": run.get("dt_s"),
        "dt_stable_s": run.get("dt_stable_s"),
        "dt_first_s": run.get("dt_first_s"),
        "dt_stable_min_s": run.get("dt_stable_min_s"),
        "dt_stable_max_s": run.get("dt_stable_max_s"),
        "mass_scaling": mass_scaling_report(results),
        "elements": run.get("elements", results.n_elements),
        "nodes": run.get("nodes", results.n_nodes),
        "ranks": run.get("ranks"),
        "threads": run.get("threads"),
        "precision": run.get("precision", "double"),   # engines before issue 19 computed in double only
        "element_cycles_per_s": run.get("element_cycles_per_s"),
        "peak_memory_per_rank_mb": run.get("peak_memory_per_rank_mb"),
        "load_imbalance": run.get("load_imbalance"),
        "phase_s": {p: run.get(f"phase_{p}_s") for p in PHASE_NAMES},
        "contact_phase_s": {p: run.get(f"phase_contact_{p}_s") for p in CONTACT_PHASE_NAMES},
        "frames": results.n_frames,
        "history_records": results.n_records,
        "parts": list(results.part_names),
        "energy": energy_report(results),
        "accuracy": accuracy_indicators(results),
        "effects": [_effect_row(row) for row in results.effect_table],
        "warnings": _earlier_warnings(Path(path)),
    }
    if extra:
        summary.update(extra)
    summary = _jsonable(summary)
    write_text_atomic(Path(path), json.dumps(summary, indent=2, allow_nan=False) + "\n")
    return summary


def _earlier_warnings(path: Path) -> list[str] | None:
    """The ``warnings`` of the summary at ``path`` (None without one, or without the key)."""
    try:
        earlier = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    warnings = earlier.get("warnings") if isinstance(earlier, dict) else None
    return [str(w) for w in warnings] if isinstance(warnings, list) else None


def _effect_row(row: EffectRow) -> dict[str, Any]:
    """One effect for summary.json; the contact row also lists its pairs."""
    entry = dataclasses.asdict(row)
    entry["pairs"] = [dict(p) for p in row.pairs]
    if not row.pairs:
        del entry["pairs"]
    return entry


def effect_table_text(results: Results) -> str:
    """The effect table as aligned text, one effect per line (what paradyn-run prints at the end)."""
    lines = [f"  {'effect':20s} {'state':5s} {'active':>10s} {'skipped':>10s} {'wall s':>9s}"]
    for row in results.effect_table:
        wall = f"(in {row.timed_with})" if row.timed_with else f"{row.wall_s:9.3f}"
        lines.append(f"  {row.name:20s} {row.state:5s} {row.active_cycles:10d} {row.skipped_cycles:10d} {wall:>9s}")
        for pair in row.pairs:
            label = "  " + " / ".join(pair["parts"])   # a long pair of names pushes the counts right
            lines.append(f"  {label:20s} {'':5s} {pair['active_cycles']:10d} {pair['skipped_cycles']:10d}")
    return "\n".join(lines)


def _last(a: np.ndarray) -> float | None:
    return float(a[-1]) if a.shape[0] else None


def _jsonable(value: Any) -> Any:
    """Plain JSON values: numpy to Python, Path to str, non-finite floats to None."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, Path):
        return str(value)
    value = to_python(value)
    if isinstance(value, list):
        return [_jsonable(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
