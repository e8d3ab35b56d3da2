"""What the edge contact costs on the pipe whip (docs/performance.md, "Edge contact"):
python tools/edge_contact_cost.py REPO OUT.

Case 1 as it is (node-to-segment) and with ``edges = true`` on its contact: 3 rounds, alternating which
runs first, each run ``OMP_NUM_THREADS=1 taskset -c 1 paradyn-engine DECK OUT``; prints the medians of
``/run element_cycles_per_s``, ``wall_s`` and ``phase_contact_s`` with each run's element-cycles/s.
"""

import os
import statistics
import subprocess
import sys
from pathlib import Path

import h5py

import paradyn
from paradyn import deck, scene

root = Path(sys.argv[1])
out = Path(sys.argv[2])
out.mkdir(exist_ok=True)
text = (root / "cases/pipe_whip/scene.toml").read_text()
edged = text.replace("symmetric = true ", "symmetric = true\nedges = true ")
assert edged != text
decks = {}
for name, t in (("nts", text), ("edges", edged)):
    p = out / f"{name}.toml"
    p.write_text(t)
    decks[name] = deck.write_deck(scene.build_model(scene.load_scene(p)), out / f"{name}.h5")
engine = Path(paradyn.__file__).parent / "bin" / "paradyn-engine"
rows = {n: [] for n in decks}
for r in range(3):
    for name in (("nts", "edges") if r % 2 == 0 else ("edges", "nts")):
        res = out / f"{name}_{r}.h5"
        subprocess.run(["taskset", "-c", "1", str(engine), str(decks[name]), str(res)], check=True,
                       env={**os.environ, "OMP_NUM_THREADS": "1"}, stdout=subprocess.DEVNULL)
        with h5py.File(res) as f:
            a = f["/run"].attrs
            rows[name].append((a["element_cycles_per_s"], a["wall_s"], a["phase_contact_s"]))
for name, v in rows.items():
    med = [statistics.median(x[i] for x in v) for i in range(3)]
    runs = ", ".join(f"{x[0]:.4g}" for x in v)
    print(f"{name}: element-cycles/s {med[0]:.4g} (runs {runs}), wall {med[1]:.3f} s, contact phase {med[2]:.3f} s")
