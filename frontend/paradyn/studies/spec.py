"""What a study is asked to do: the scene's ``[study]`` table and the caller's options (issue 16).

:class:`StudySpec` holds the design, the quantities, the reference, the target, the cost measure
and the run settings. :func:`spec_from_table` reads a ``[study]`` table (docs/accuracy-cost.md);
:meth:`StudySpec.merged` lays options given on the command line or to :func:`paradyn.study` over
it. Every problem is a :class:`StudyError` naming the key and the fix.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

from paradyn.arguments import did_you_mean
from paradyn.scene.specs import Scene

from .design import DESIGNS, Design, StudyError
from .error import Quantity, parse_quantities, parse_target

REFERENCES = ("richardson", "finest")
COSTS = {"core_s": "core-seconds (engine wall time x ranks x threads)", "engine_s": "engine wall time (s)",
         "whole_s": "whole wall time: meshing, deck, engine, reading (s)", "cycles": "cycles",
         "peak_memory_mb": "peak memory (MiB)"}
_TABLE_KEYS = ("design", "knobs", "runs", "quantities", "reference", "reference_values", "target",
               "target_quantities", "cost", "end_time", "threads", "jobs")


@dataclass
class StudySpec:
    """A study's settings; ``None`` in an option means the default (see docs/accuracy-cost.md)."""

    design: Design = field(default_factory=Design)
    quantities: dict[str, str] = field(default_factory=dict)   # name -> quantity text (paradyn.studies.error)
    reference: str = "richardson"                              # or "finest"
    reference_values: dict[str, float] = field(default_factory=dict)   # quantity name -> given value
    target: float | None = None                                # relative error, 0.01 = 1 %
    target_quantities: list[str] = field(default_factory=list)  # empty: every quantity
    cost: str = "core_s"
    end_time: float | None = None                              # None: the scene's [run] end_time
    threads: int = 1
    jobs: int | None = None                                    # None: cores // threads

    def merged(self, **options: Any) -> StudySpec:
        """This spec with the options that are not None laid over it (``knobs``, ``runs`` and
        ``design`` replace the design's parts)."""
        design = replace(self.design, knobs=dict(self.design.knobs), runs=list(self.design.runs))
        for key in ("design", "knobs", "runs"):
            value = options.pop(key, None)
            if value is not None:
                setattr(design, "kind" if key == "design" else key, value)
        known = {f.name for f in fields(self)}
        unknown = set(options) - known
        if unknown:
            first, allowed = sorted(unknown)[0], sorted(known | {"knobs", "runs"})
            raise StudyError(f"unknown study option {first!r}; {did_you_mean(first, allowed)}the options are: "
                             f"{', '.join(allowed)}")
        return replace(self, design=design, **{k: v for k, v in options.items() if v is not None})

    def parsed_quantities(self, scene: Scene) -> list[Quantity]:
        """The quantities; by default the z displacement of every tracked point at the end."""
        wanted = self.quantities or {t.name: f"{t.name}.dz:final" for t in scene.tracks}
        if not wanted:
            raise StudyError(f"{scene.path} tracks no point, so there is no default quantity; give quantities "
                             "(--quantity NAME=EXPR or [study.quantities]), e.g. internal_energy:peak")
        quantities = [q for name, text in wanted.items() for q in parse_quantities(name, text)]
        names = [q.name for q in quantities]
        for name in [*self.reference_values, *self.target_quantities]:
            if name not in names:
                raise StudyError(f"'{name}' is not a quantity of the study; {did_you_mean(name, names)}the "
                                 f"quantities are: {', '.join(names)}")
        return quantities

    def check(self) -> None:
        """A StudyError for an option out of range."""
        if self.design.kind not in DESIGNS:
            raise StudyError(f"unknown design '{self.design.kind}'; {did_you_mean(self.design.kind, DESIGNS)}"
                             f"choose one of {', '.join(DESIGNS)}")
        if self.reference not in REFERENCES:
            raise StudyError(f"unknown reference '{self.reference}'; {did_you_mean(self.reference, REFERENCES)}"
                             f"choose one of {', '.join(REFERENCES)}, or give values (--reference NAME=VALUE)")
        if self.cost not in COSTS:
            raise StudyError(f"unknown cost '{self.cost}'; {did_you_mean(self.cost, COSTS)}choose one of "
                             f"{', '.join(COSTS)}")
        if self.threads < 1 or (self.jobs is not None and self.jobs < 1):
            raise StudyError("threads and jobs must be at least 1")
        if self.end_time is not None and not self.end_time > 0:
            raise StudyError(f"end_time must be above 0 s, got {self.end_time}")


def spec_from_table(table: Mapping[str, Any], where: str) -> StudySpec:
    """The spec of a ``[study]`` table (``where`` names it in messages: the scene file)."""
    for key in table:
        if key not in _TABLE_KEYS:
            raise StudyError(f"{where}: unknown key '{key}' in [study]; {did_you_mean(key, _TABLE_KEYS)}allowed "
                             f"keys are: {', '.join(_TABLE_KEYS)}")
    knobs = _typed(table, "knobs", dict, where, {})
    for name, values in knobs.items():
        if not isinstance(values, list) or not values:
            raise StudyError(f"{where}: [study.knobs] {name} must be a list of values, e.g. {name} = [1, 2, 4]")
    runs = _typed(table, "runs", list, where, [])
    if not all(isinstance(r, dict) for r in runs):
        raise StudyError(f"{where}: [study] runs must be an array of tables, [[study.runs]]")
    design = Design(kind=_typed(table, "design", str, where, "one_at_a_time"), knobs=knobs, runs=runs)
    values = _typed(table, "reference_values", dict, where, {})
    if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in values.values()):
        raise StudyError(f"{where}: [study.reference_values] must map quantity names to numbers")
    target = table.get("target")
    spec = StudySpec(
        design=design,
        quantities={str(k): str(v) for k, v in _typed(table, "quantities", dict, where, {}).items()},
        reference=_typed(table, "reference", str, where, "richardson"),
        reference_values={str(k): float(v) for k, v in values.items()},
        target=parse_target(target) if target is not None else None,
        target_quantities=[str(q) for q in _typed(table, "target_quantities", list, where, [])],
        cost=_typed(table, "cost", str, where, "core_s"),
        end_time=_typed(table, "end_time", float, where, None),
        threads=_typed(table, "threads", int, where, 1),
        jobs=_typed(table, "jobs", int, where, None),
    )
    spec.check()
    return spec


def _typed(table: Mapping[str, Any], key: str, kind: type, where: str, default: Any) -> Any:
    value = table.get(key, default)
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if value is not default and (not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool)):
        raise StudyError(f"{where}: [study] {key} must be a {kind.__name__}, got {value!r}")
    return value
