"""From a study's runs to an answer (issue 16): references, errors, the Pareto front, what each knob
step buys, and the cheapest run that meets a target.

Every run's error is the largest relative error over the target quantities (all quantities when
none is named) against their references (:mod:`paradyn.studies.error`).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .design import Config, Value, label
from .error import Quantity, Reference, pareto_front, reference, relative_error
from .spec import COSTS, StudySpec


@dataclass
class StudyRun:
    """One configuration of a study and what came of it."""

    config: Config
    key: str
    cached: bool
    record: dict[str, Any]                          # run.json (cost, accuracy) or {"error": ...}
    values: dict[str, float] = field(default_factory=dict)   # quantity name -> value
    errors: dict[str, float] = field(default_factory=dict)   # quantity name -> relative error
    error: float | None = None                      # largest error over the target quantities
    on_front: bool = False

    @property
    def label(self) -> str:
        return label(self.config)

    @property
    def ok(self) -> bool:
        return "error" not in self.record

    def cost(self, measure: str) -> float | None:
        value = self.record.get(measure)
        return float(value) if value is not None else None


@dataclass
class Step:
    """One step of one knob: from a value to the next, the change in error and the cost ratio."""

    knob: str
    before: Value
    after: Value
    error_before: float
    error_after: float
    cost_ratio: float


@dataclass
class Analysis:
    references: dict[str, Reference]
    front: list[int]                # indices into the runs, cheapest first
    steps: list[Step]
    target_answer: str              # the sentence about --target ("" without a target)
    target_run: int | None = None   # the index of the cheapest run that meets the target


def analyse(runs: list[StudyRun], quantities: list[Quantity], spec: StudySpec,
            base: dict[str, Value | None]) -> Analysis:
    """Fill every run's errors and ``on_front``; return the references, front, steps and target answer."""
    ladder_runs = sorted((dict(r.config).get("mesh", 1.0), r) for r in runs
                         if r.ok and all(name == "mesh" for name, _ in r.config))
    references = {}
    for q in quantities:
        ladder = [(float(f), r.values[q.name]) for f, r in ladder_runs]
        finest = ladder[-1][1] if ladder else None
        references[q.name] = reference(spec.reference_values.get(q.name), spec.reference, ladder, finest)
    chosen = spec.target_quantities or [q.name for q in quantities]
    for run in runs:
        if not run.ok:
            continue
        run.errors = {name: relative_error(run.values[name], ref.value)
                      for name, ref in references.items() if ref.value is not None}
        picked = [run.errors[name] for name in chosen if name in run.errors]
        run.error = max(picked) if picked else None
    scored = [i for i, r in enumerate(runs) if r.error is not None and r.cost(spec.cost) is not None]
    front = [scored[k] for k in pareto_front([runs[i].cost(spec.cost) for i in scored],
                                             [runs[i].error for i in scored])]
    for i in front:
        runs[i].on_front = True
    answer, best = _target_answer(runs, scored, spec, chosen)
    by_finest = [name for name in chosen if references[name].source == "finest run"]
    if best is not None and ladder_runs and runs[best] is ladder_runs[-1][1] and by_finest:
        answer += (f" It is the finest run, the reference of {', '.join(by_finest)}: its error there is 0 by "
                   "construction, and only a finer mesh would tell how far it is from converged.")
    return Analysis(references, front, knob_steps(runs, spec, base), answer, best)


def knob_steps(runs: list[StudyRun], spec: StudySpec, base: dict[str, Value | None]) -> list[Step]:
    """Per knob, its runs with every other knob at the base, ordered by value (numbers ascending;
    other values from the base), and each step's change in error and cost ratio."""
    by_config = {r.config: r for r in runs if r.error is not None and r.cost(spec.cost)}
    base_run = by_config.get(())
    steps: list[Step] = []
    names = list(dict.fromkeys([*spec.design.knobs, *(n for run in spec.design.runs for n in run)]))
    for name in names:
        points = [(value, r) for config, r in by_config.items() if len(config) == 1 and config[0][0] == name
                  for value in [config[0][1]]]
        if base_run is not None and base[name] is not None:
            points.append((base[name], base_run))
        if all(isinstance(v, int | float) and not isinstance(v, bool) for v, _ in points):
            points.sort(key=lambda p: p[0])
            pairs = list(itertools.pairwise(points))
        else:
            start = next((p for p in points if p[1] is base_run), None)
            pairs = [(start, p) for p in points if start is not None and p is not start]
        for (v0, r0), (v1, r1) in pairs:
            steps.append(Step(name, v0, v1, r0.error, r1.error, r1.cost(spec.cost) / r0.cost(spec.cost)))
    return steps


def _target_answer(runs: list[StudyRun], scored: list[int], spec: StudySpec,
                   chosen: list[str]) -> tuple[str, int | None]:
    if spec.target is None:
        return "", None
    unit = COSTS[spec.cost].split(" (")[0].split(":")[0]
    what = f"{spec.target:.3g} relative error ({spec.target * 100:g} %) on {', '.join(chosen)}"
    meeting = [i for i in scored if runs[i].error <= spec.target]
    if not meeting:
        best = min(scored, key=lambda i: runs[i].error, default=None)
        if best is None:
            return f"No run has an error to compare with the target {what}.", None
        return (f"No run meets {what}. The most accurate is '{runs[best].label}' with "
                f"{_percent(runs[best].error)}; refine further (a finer mesh, more knob values)."), None
    cheapest = min(meeting, key=lambda i: (runs[i].cost(spec.cost), runs[i].error))
    run = runs[cheapest]
    return (f"Cheapest configuration that meets {what}: '{run.label}', error {_percent(run.error)}, "
            f"{unit} {run.cost(spec.cost):.3g}."), cheapest


def _percent(fraction: float | None) -> str:
    if fraction is None or not math.isfinite(fraction):
        return "-"
    return f"{fraction * 100:.3g} %"


@dataclass
class StudyResult:
    """What :func:`study` did: the spec, every run (base first), the analysis and the files written."""

    spec: StudySpec
    runs: list[StudyRun]
    analysis: Analysis
    outputs: dict[str, Path] = field(default_factory=dict)
    ran: int = 0            # runs the engine made in this call (the others came from the cache)

    @property
    def failed(self) -> list[StudyRun]:
        return [r for r in self.runs if not r.ok]
