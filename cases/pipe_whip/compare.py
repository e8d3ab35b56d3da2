"""Compare a pipe-whip run (case 1) with the published values: python compare.py RUN_FOLDER.

Prints a markdown table of the six tracked z displacements (mm, downward positive as the papers
quote them) at 0.5 to 2.5 ms, the upper ring's centre (mean of its top and bottom nodes), and the
references at 1 ms: Har's GT-PARADYN (the seed paper) and Malone & Johnson (1994).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

POINTS = ("lower_contact", "lower_bottom", "lower_quarter", "upper_contact", "upper_top", "upper_quarter")
TIMES_MS = (0.5, 1.0, 1.5, 2.0, 2.5)
# published displacements at 1 ms, mm (downward): (Har, Malone)
REFERENCES = {
    "lower_contact": ("0.86", "0.8"),
    "upper_contact": ("-", "1.0"),
    "upper_centre": ("2.54", "about 1.5"),
}


def read_history(path: Path) -> dict[str, np.ndarray]:
    """The columns of history.csv by name, the units of its header (``time [s]``) left out."""
    with path.open() as f:
        header = f.readline().strip().split(",")
    values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {column.split(" [")[0]: values[:, j] for j, column in enumerate(header)}


def table(history: dict[str, np.ndarray]) -> str:
    t_ms = history["time"] * 1e3
    rows = []
    columns = [*POINTS, "upper_centre"]
    down = {p: -history[f"{p}_dz"] * 1e3 for p in POINTS}
    down["upper_centre"] = 0.5 * (down["upper_contact"] + down["upper_top"])
    header = "| point (downward displacement, mm) | " + " | ".join(f"{t} ms" for t in TIMES_MS) + \
             " | Har (GT-PARADYN), 1 ms | Malone & Johnson 1994, 1 ms |"
    rows.append(header)
    rows.append("|" + "---|" * (len(TIMES_MS) + 3))
    for name in columns:
        values = [np.interp(t, t_ms, down[name]) for t in TIMES_MS]
        har, malone = REFERENCES.get(name, ("-", "-"))
        rows.append(f"| {name} | " + " | ".join(f"{v:.3f}" for v in values) + f" | {har} | {malone} |")
    return "\n".join(rows)


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("usage: python compare.py RUN_FOLDER (the folder paradyn-run wrote, with history.csv)",
              file=sys.stderr)
        return 2
    history_path = Path(argv[1]) / "history.csv"
    if not history_path.is_file():
        print(f"compare.py: {history_path} not found; run paradyn-run on cases/pipe_whip/scene.toml first",
              file=sys.stderr)
        return 2
    print(table(read_history(history_path)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
