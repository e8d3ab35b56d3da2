"""The Pareto plot of a study (issue 16): log error against log cost, one marker per knob, every
point labelled, the front drawn as a staircase, the target as a dashed line."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from .analysis import StudyResult
from .spec import COSTS

MARKERS = "osD^v<>phX*P"


def plot_pareto(result: StudyResult, path: Path) -> Path:
    """Draw the runs that have an error and a cost; a run with error 0 (the reference itself) sits
    on the bottom edge, drawn open. The front's runs carry their labels; the others their number
    in the study's table (#), listed beside the plot. Returns ``path``."""
    measure = result.spec.cost
    numbered = [(k + 1, r) for k, r in enumerate(result.runs) if r.error is not None and r.cost(measure)]
    positive = [r.error for _, r in numbered if r.error > 0]
    floor = min(positive) / 3 if positive else 1e-6
    most = max((r.cost(measure) for _, r in numbered), default=1.0)
    fig, ax = plt.subplots(figsize=(10, 5.5), dpi=120)
    groups: dict[str, list] = {}
    for number, run in numbered:
        group = "base" if not run.config else run.config[0][0] if len(run.config) == 1 else "several knobs"
        groups.setdefault(group, []).append((number, run))
    for k, (group, members) in enumerate(groups.items()):
        xs = [r.cost(measure) for _, r in members]
        ys = [max(r.error, floor) for _, r in members]
        faces = ["none" if r.error == 0 else f"C{k % 10}" for _, r in members]
        ax.scatter(xs, ys, marker=MARKERS[k % len(MARKERS)], s=46, label=group, edgecolors=f"C{k % 10}",
                   facecolors=faces, zorder=3)
        for (number, r), x, y in zip(members, xs, ys, strict=True):
            text = f"#{number} {r.label}" if r.on_front else f"#{number}"
            right = x >= most / 2   # near the right edge: the label goes to the left of the point
            ax.annotate(text + (" (reference)" if r.error == 0 else ""), (x, y), textcoords="offset points",
                        xytext=(-4 if right else 4, 3), ha="right" if right else "left", fontsize=7)
    front = [result.runs[i] for i in result.analysis.front]
    if len(front) > 1:
        xs = [r.cost(measure) for r in front]
        ys = [max(r.error, floor) for r in front]
        ax.step(xs, ys, where="post", color="0.35", linewidth=1.2, zorder=2, label="Pareto front")
    if result.spec.target is not None:
        ax.axhline(result.spec.target, color="C3", linestyle="--", linewidth=1, label="target")
    if not numbered:
        ax.text(0.5, 0.5, "no run has both an error and a cost", transform=ax.transAxes, ha="center")
    else:
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel(COSTS[measure])
    names = ", ".join(result.spec.target_quantities) or "every quantity"
    ax.set_ylabel(f"relative error (largest over {names})")
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(1.01, 0.0))   # beside the plot, below the list
    listing = "\n".join(f"#{n} {r.label}"[:38] for n, r in numbered)
    fig.text(0.755, 0.95, listing, fontsize=6.5, va="top", family="monospace")
    fig.subplots_adjust(left=0.08, right=0.74, bottom=0.1, top=0.96)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.tmp.png")
    fig.savefig(temporary)
    plt.close(fig)
    temporary.replace(path)
    return path
