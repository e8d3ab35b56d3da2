"""A study's files (issue 16): ``study.csv`` and ``study.json`` (every run), ``study.md`` (the
tables a person reads) and ``pareto.png`` (log error against log cost, the front drawn). All are
written atomically; columns and keys are in docs/accuracy-cost.md.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any

from paradyn.atomic_write import write_text_atomic
from paradyn.scene.specs import Scene

from .analysis import StudyResult
from .design import KNOBS, UNAVAILABLE
from .error import Quantity
from .spec import COSTS

COST_COLUMNS = ("engine_s", "loop_s", "whole_s", "core_s", "cycles", "peak_memory_mb")
ACCURACY_COLUMNS = ("energy_balance_error", "peak_hourglass_over_internal", "peak_penetration_over_thickness",
                    "peak_contact_over_internal", "dt_over_stable_dt", "added_mass_fraction")


def write_outputs(result: StudyResult, quantities: list[Quantity], out: Path, scene: Scene,
                  command: str | None) -> dict[str, Path]:
    """Write the four files into ``out``; return label -> path."""
    rows = table_rows(result, quantities)
    paths = {"csv": out / "study.csv", "json": out / "study.json", "markdown": out / "study.md",
             "pareto": out / "pareto.png"}
    write_text_atomic(paths["csv"], _csv(rows))
    write_text_atomic(paths["json"], json.dumps(_json(result, rows, scene, command), indent=2) + "\n")
    from .plot import plot_pareto  # matplotlib is loaded only here

    plot_pareto(result, paths["pareto"])
    write_text_atomic(paths["markdown"], markdown(result, quantities, scene, command, paths["pareto"].name))
    return paths


def table_rows(result: StudyResult, quantities: list[Quantity]) -> list[dict[str, Any]]:
    """One flat row per run: label, knob values, key, cost, accuracy indicators, quantities, errors."""
    knobs = [name for name in KNOBS if any(name in dict(r.config) for r in result.runs)]
    rows = []
    for run in result.runs:
        config = dict(run.config)
        row: dict[str, Any] = {"run": run.label, **{k: config.get(k, "") for k in knobs}, "key": run.key,
                               "cached": run.cached, "status": run.record.get("error", "ok")}
        row |= {c: run.record.get(c) for c in (*COST_COLUMNS, "elements", "dt_s", "track_offset_m")}
        row |= {c: run.record.get("accuracy", {}).get(c) for c in ACCURACY_COLUMNS}
        row |= {q.name: run.values.get(q.name) for q in quantities}
        row |= {f"error_{q.name}": run.errors.get(q.name) for q in quantities}
        row |= {"error": run.error, "on_front": run.on_front}
        rows.append(row)
    return rows


def _csv(rows: list[dict[str, Any]]) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: ("" if v is None else v) for k, v in row.items()} for row in rows)
    return buffer.getvalue()


def _json(result: StudyResult, rows: list[dict[str, Any]], scene: Scene, command: str | None) -> dict[str, Any]:
    spec = asdict(result.spec)
    return {
        "scene": str(Path(scene.path).resolve()), "command": command, "spec": spec,
        "cost_measure": result.spec.cost, "unavailable_knobs": UNAVAILABLE,
        "references": {name: asdict(ref) for name, ref in result.analysis.references.items()},
        "runs": rows,
        "pareto_front": [result.runs[i].label for i in result.analysis.front],
        "sensitivity": [asdict(step) for step in result.analysis.steps],
        "target": result.spec.target, "target_answer": result.analysis.target_answer,
        "ran": result.ran, "written_at": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }


def markdown(result: StudyResult, quantities: list[Quantity], scene: Scene, command: str | None,
             picture: str) -> str:
    """The study as markdown: references, runs, knob steps, the target answer and the picture."""
    spec, analysis = result.spec, result.analysis
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    lines = [f"# Study of {scene.title}", "",
             f"Scene `{scene.path}`; command `{command or 'paradyn.study(...)'}`; {len(result.runs)} runs, "
             f"{result.ran} run now, {len(result.runs) - result.ran} from the cache; {spec.threads} thread(s) "
             f"per run; load average {load:.1f} at the end. Cost: {COSTS[spec.cost]}.", "",
             "| quantity | reference | from | observed order | note |", "|---|---|---|---|---|"]
    for q in quantities:
        ref = analysis.references[q.name]
        lines.append(f"| {q.name} | {_g(ref.value)} | {ref.source} | {_g(ref.order, '.2f')} | {ref.note} |")
    names = [q.name for q in quantities]
    lines += ["", "| # | run | elements | cycles | engine s | whole s | core-s | memory MiB | "
              + " | ".join(names) + " | error | energy balance | hourglass / internal | front |",
              "|" + "---|" * (len(names) + 12)]
    for number, run in enumerate(result.runs, start=1):
        r, acc = run.record, run.record.get("accuracy", {})
        if not run.ok:   # the number, the label and the message fill 3 of the columns
            lines.append(f"| {number} | {run.label} | failed: {r['error']} |" + " |" * (len(names) + 9))
            continue
        lines.append(f"| {number} | {run.label} | {r.get('elements')} | {r.get('cycles')} "
                     f"| {_g(r.get('engine_s'), '.3g')} | {_g(r.get('whole_s'), '.3g')} | {_g(r.get('core_s'), '.3g')} "
                     f"| {_g(r.get('peak_memory_mb'), '.0f')} | "
                     + " | ".join(_g(run.values.get(n), '.5g') for n in names)
                     + f" | {_pct(run.error)} | {_g(acc.get('energy_balance_error'), '.1e')} "
                     f"| {_g(acc.get('peak_hourglass_over_internal'), '.2g')} | {'yes' if run.on_front else ''} |")
    if analysis.steps:
        lines += ["", "| knob | step | error before | error after | cost ratio |", "|---|---|---|---|---|"]
        lines += [f"| {s.knob} | {_v(s.before)} → {_v(s.after)} | {_pct(s.error_before)} | {_pct(s.error_after)} "
                  f"| {s.cost_ratio:.2f} |" for s in analysis.steps]
    if analysis.target_answer:
        lines += ["", analysis.target_answer]
    lines += ["", f"![Pareto plot]({picture})", ""]
    return "\n".join(lines)


def _v(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _g(value: float | None, form: str = ".4g") -> str:
    return "-" if value is None else format(value, form)


def _pct(fraction: float | None) -> str:
    return "-" if fraction is None else f"{fraction * 100:.3g} %"
