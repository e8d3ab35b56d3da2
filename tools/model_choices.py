"""Which model choice moves the converged pipe-whip answer (issue 35, item 6; docs/validation.md,
"Converged answers and model choices").

Case 1 (cases/pipe_whip/scene.toml) at the automatic step, on the meshes 32 x 64, 64 x 128 and
128 x 256 per pipe (mesh factors 2, 4, 8). For the base and for each model choice switched alone,
``paradyn.study`` runs the three meshes and this tool extrapolates the top of the upper mid ring at
2.5 ms by Richardson (paradyn.studies.error.richardson, the study's own formula), then prints a
markdown table: the value on each mesh, the extrapolated value, the observed order and the shift
from the base.

    .venv/bin/python tools/model_choices.py -o runs/model_choices [--jobs 1] [--end-time 2.5e-3]

Runs are cached by deck content in ``OUT/<choice>/runs``: a second call reruns nothing.
"""

from __future__ import annotations

import argparse
import copy
import math
from pathlib import Path

import paradyn
from paradyn.scene import Scene, load_scene
from paradyn.studies.design import KNOBS
from paradyn.studies.error import richardson

CASE = Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml"
MESHES = [2, 4, 8]
QUANTITY_TIME = 2.5e-3   # s
# (label, knob, value): each switched alone from the base (the case at the automatic step); a value
# given as {mesh factor: value} is set mesh by mesh (the runs listed one by one)
CHOICES = [
    ("base", None, None),
    ("physical hourglass form", "hourglass_form", "physical"),
    ("viscous hourglass form", "hourglass_form", "viscous"),
    ("warping correction on", "warping_correction", True),
    ("3 points through the thickness", "integration_points", 3),
    ("9 points through the thickness", "integration_points", 9),
    ("penalty scale 1.0 (stiffer contact)", "penalty_scale", 1.0),
    ("penalty scale 0.01 (softer contact)", "penalty_scale", 0.01),
    ("one contact pass (lower pipe master)", "symmetric", False),
    ("step 0.5 of the stable step", "time_step_safety", 0.5),
    ("radial return without the plane-stress iteration", "plastic_return", "radial"),
    ("radioss rotary inertia (m (t^2 + A) / 12, OpenRadioss's rule)", "rotary_inertia", "radioss"),
    ("physical rotary inertia (m t^2 / 12, the step capped)", "rotary_inertia", "physical"),
    ("thickness update (the element's forces use its current thickness, LS-DYNA ISTUPD = 1)", "thickness_update",
     True),
    ("contact thickness scale 0.5 (surfaces t / 4 off each mid-surface)", "contact_thickness_scale", 0.5),
    ("contact thickness scale 0.9 (the walls 2.7 mm apart at contact)", "contact_thickness_scale", 0.9),
    # OpenRadioss /INTER/TYPE7's default constant gap (Igap = 0, Gapmin blank): min(t, shortest main side / 2),
    # 3 mm on 32 x 64 and 64 x 128, 1.963 mm on 128 x 256 (side 2 R sin(pi / 128) = 3.927 mm)
    ("OpenRadioss's default gap as contact thickness (scale 1, 1, 0.654 on the three meshes)",
     "contact_thickness_scale", {2: 1.0, 4: 1.0, 8: min(1.0, 0.08 * math.sin(math.pi / 128) / 0.003)}),
]


def base_scene() -> Scene:
    """Case 1 with the automatic step (the case itself fixes 1 us)."""
    scene = load_scene(CASE)
    KNOBS["time_step"].apply(scene, 0.0)
    return scene


def ladder(label: str, knob: str | None, value: object, out: Path, jobs: int, end_time: float | None) -> list[float]:
    """The quantity on each mesh of MESHES for one choice."""
    scene = copy.deepcopy(base_scene())
    per_mesh = isinstance(value, dict)   # a value for each mesh factor: the runs listed one by one
    if knob is not None and not per_mesh:
        KNOBS[knob].apply(scene, value)
    at = QUANTITY_TIME if end_time is None else min(QUANTITY_TIME, end_time)
    options: dict[str, object] = {"reference": "finest", "quantities": {"q": f"upper_top.dz@{at:g}"}, "jobs": jobs,
                                  "threads": 1}
    if per_mesh:
        options.update(design="list", knobs={}, runs=[{"mesh": m, knob: value[m]} for m in MESHES])
    else:
        options.update(design="grid", knobs={"mesh": MESHES})
    if end_time is not None:
        options["end_time"] = end_time
    folder = out / label.split(" (")[0].replace("'s ", " ").replace(" ", "_").replace(".", "p")
    result = paradyn.study(scene, folder, progress=False, **options)
    if result.failed:
        raise SystemExit(f"{label}: a run failed ({result.failed[0].record.get('error')}); see {folder}")
    values = {dict(r.config).get("mesh", 1): r.values["q"] for r in result.runs}
    return [values[m] for m in MESHES]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--out", type=Path, default=Path("runs/model_choices"))
    parser.add_argument("--jobs", type=int, default=1, help="runs at once (default 1)")
    parser.add_argument("--end-time", type=float, default=None, help="shorter runs, for a quick check")
    parser.add_argument("--only", default=None, help="comma-separated knob names: the base and these choices alone")
    args = parser.parse_args()
    wanted = None if args.only is None else set(args.only.split(","))
    rows, base_value = [], None
    for label, knob, value in CHOICES:
        if wanted is not None and knob is not None and knob not in wanted:
            continue
        q = ladder(label, knob, value, args.out, args.jobs, args.end_time)
        ex = richardson(MESHES, q)
        if label == "base":
            base_value = ex.value
        rows.append((label, q, ex))
        print(f"{label}: {[f'{v * 1e3:.4f}' for v in q]} mm -> {ex.value} order {ex.order} {ex.message}", flush=True)
    print("\n| choice | 32 x 64 (mm) | 64 x 128 | 128 x 256 | Richardson (mm) | order | shift from base |")
    print("|---|---|---|---|---|---|---|")
    for label, q, ex in rows:
        value = "-" if ex.value is None else f"{ex.value * 1e3:.3f}"
        order = "-" if ex.order is None else f"{ex.order:.2f}"
        shift = "-" if ex.value is None or base_value is None or not math.isfinite(base_value) else \
            f"{(ex.value - base_value) / abs(base_value) * 100:+.2f} %"
        cells = " | ".join(f"{v * 1e3:.4f}" for v in q)
        print(f"| {label} | {cells} | {value} | {order} | {shift} |")


if __name__ == "__main__":
    main()
