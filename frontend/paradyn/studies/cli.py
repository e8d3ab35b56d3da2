"""``paradyn-study SCENE``: what accuracy costs in time (issue 16, docs/accuracy-cost.md)."""

from __future__ import annotations

import argparse
import shlex
import sys
import tomllib
from pathlib import Path
from typing import Any

from paradyn._schema import STATUS_BAD_INPUT, STATUS_FAILURE, STATUS_OK
from paradyn.running.engine_process import EngineError
from paradyn.scene.specs import SceneError

from .design import DESIGNS, KNOBS, UNAVAILABLE, StudyError
from .spec import COSTS, REFERENCES
from .sweep import study

DESCRIPTION = f"""\
Sweep knobs of a scene and show what accuracy costs in time.

SCENE is a scene file (docs/scene.md); its [study] table, when it has one, gives the defaults of
every option below (docs/accuracy-cost.md). Every distinct deck runs once: a later study in the
same output folder reuses the runs it already has.

knobs: {', '.join(KNOBS)}
{''.join(f'not available: {k} ({v.split(";")[0]})' + chr(10) for k, v in UNAVAILABLE.items())}
quantities: POINT.COMPONENT@TIME[,TIME...], mean(P1,P2).COMPONENT@TIME (the mean of points),
diff(P1,P2).COMPONENT@TIME (P1 less P2), POINT.COMPONENT:STAT or ENERGY:STAT, with COMPONENT one
of dx dy dz vx vy vz, STAT one of peak max min final.

Writes OUT/study.csv, study.json, study.md, pareto.png and OUT/runs/<key>/ (one run per deck).
Exit status: 0 when every run finished, 2 for a bad scene or option, 1 when a run failed.
"""


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="paradyn-study", description=DESCRIPTION,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="scene file (.toml)")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help="study folder (default: runs/<scene folder>_study under the current folder)")
    parser.add_argument("--design", choices=DESIGNS, default=None, help="how knob values combine")
    parser.add_argument("--knob", action="append", default=[], metavar="NAME=V1,V2,...",
                        help="values of a knob, e.g. mesh=1,2,4 (repeat for several knobs)")
    parser.add_argument("--run", action="append", default=[], metavar="NAME=V,NAME=V",
                        help="one configuration of a 'list' design, e.g. mesh=2,integration_points=3")
    parser.add_argument("--quantity", action="append", default=[], metavar="[NAME=]EXPR",
                        help="a quantity of interest, e.g. top=upper_top.dz@1e-3 (repeat for several)")
    parser.add_argument("--reference", action="append", default=[], metavar="MODE|NAME=VALUE",
                        help=f"{' or '.join(REFERENCES)} (default richardson), or a quantity's given value")
    parser.add_argument("--target", default=None, help="relative error to meet, e.g. 1%% or 0.01")
    parser.add_argument("--target-quantity", action="append", default=[], metavar="NAME",
                        help="the quantities the target and the plot judge (default: all)")
    parser.add_argument("--cost", choices=list(COSTS), default=None, help="cost measure (default core_s)")
    parser.add_argument("--end-time", type=float, default=None, help="run length in s (default: the scene's)")
    parser.add_argument("-t", "--threads", type=int, default=None, help="OpenMP threads per run (default 1)")
    parser.add_argument("-j", "--jobs", type=int, default=None, help="runs at once (default: cores / threads)")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return parser


def parse_value(text: str) -> bool | int | float | str:
    """A knob value as TOML reads it: true/false, an integer, a float, else text."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def _assignments(items: list[str], what: str) -> list[tuple[str, str]]:
    pairs = []
    for item in items:
        name, equals, value = item.partition("=")
        if not equals or not name.strip() or not value.strip():
            raise StudyError(f"{what} '{item}' must be written NAME=VALUE")
        pairs.append((name.strip(), value.strip()))
    return pairs


def options_from(args: argparse.Namespace) -> dict[str, Any]:
    """The study options the command line gives (None where it gives none)."""
    knobs = {name: [parse_value(v) for v in values.split(",")] for name, values in _assignments(args.knob, "--knob")}
    runs = [{n: parse_value(v) for n, v in _assignments(run.split(","), "--run")} for run in args.run]
    quantities = {}
    for item in args.quantity:
        name, equals, expr = item.partition("=")
        quantities[name.strip() if equals else item] = expr if equals else item
    modes = [r for r in args.reference if "=" not in r]
    given = {}
    for name, value in _assignments([r for r in args.reference if "=" in r], "--reference"):
        try:
            given[name] = float(value)
        except ValueError:
            raise StudyError(f"--reference {name}={value}: the value must be a number") from None
    if len(modes) > 1:
        raise StudyError(f"give one reference mode, not {', '.join(modes)}")
    return {"design": args.design, "knobs": knobs or None, "runs": runs or None, "quantities": quantities or None,
            "reference": modes[0] if modes else None, "reference_values": given or None, "target": args.target,
            "target_quantities": args.target_quantity or None, "cost": args.cost, "end_time": args.end_time,
            "threads": args.threads, "jobs": args.jobs}


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    out = args.output or Path.cwd() / "runs" / f"{args.scene.resolve().parent.name}_study"
    command = shlex.join(["paradyn-study", *(sys.argv[1:] if argv is None else argv)])
    try:
        result = study(args.scene, out, progress=not args.quiet, command=command, **options_from(args))
    except (StudyError, SceneError) as error:
        print(f"paradyn-study: error: {error}", file=sys.stderr)
        return STATUS_BAD_INPUT
    except EngineError as error:
        print(f"paradyn-study: error: {error}", file=sys.stderr)
        return STATUS_FAILURE
    print(result.outputs["markdown"].read_text())
    for run in result.failed:
        print(f"paradyn-study: run '{run.label}' failed: {run.record['error']}", file=sys.stderr)
    return STATUS_FAILURE if result.failed else STATUS_OK


if __name__ == "__main__":
    sys.exit(main())
