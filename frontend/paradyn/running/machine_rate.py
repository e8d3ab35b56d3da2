"""This machine's element rate, for ``paradyn-run --check``'s wall-time estimate: measured once on
a small benchmark and cached.

The benchmark is two crossing pipes of J2 steel flying into each other (the pipe whip of
``cases/pipe_whip_scaling`` at a quarter of its mesh: 2 x 20 x 40 = 1 600 elements, 300 cycles,
contact on), run by this machine's engine on one rank and one thread, three times; the highest
``element_cycles_per_s`` of the three (the run other programs disturbed least) is the rate per
core. A machine busy with other work while it is measured gives a low rate: delete the cache
and measure again (``paradyn-run --check``) on a quiet machine. The cache, ``$XDG_CACHE_HOME/paradyn/element_rate.json``
(``~/.cache/paradyn`` by default, ``$PARADYN_CACHE_DIR`` instead), holds one rate per key: the
engine's build (its path, size and modification time: a rebuilt engine is measured again) and the
CPU (its model name and the cores the system has). Delete the file to measure again.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import platform
import tempfile
from dataclasses import dataclass
from pathlib import Path

from paradyn.atomic_write import write_text_atomic

CACHE_ENV = "PARADYN_CACHE_DIR"
CACHE_NAME = "element_rate.json"
BENCHMARK_ELEMENTS = 1600
BENCHMARK_RUNS = 3   # the fastest of these: the one the machine's other work disturbed least

_PIPE = """
[[part]]
name = "{name}"
material = "steel"
thickness = 0.003
hourglass_coefficient = 0.1
hourglass_form = "stiffness"
initial_velocity = [0.0, 0.0, {speed}]
[part.geometry]
kind = "cylinder"
radius = 0.08
length = 2.0
axis = {axis}
center = [0.0, 0.0, {z}]
elements_around = 20
elements_along = 40
"""
BENCHMARK_SCENE = """title = "paradyn element-rate benchmark: two crossing pipes, 1 600 J2 elements, contact"

[run]
end_time = 3e-4
output_interval = 3e-4
history_interval = 1e-4
time_step = 1e-6

[[material]]
name = "steel"
model = "j2_plasticity"
density = 7860.0
youngs_modulus = 200e9
poisson_ratio = 0.28
yield_stress = 250e6
tangent_modulus = 0.0
hardening_mixing = 1.0
""" + _PIPE.format(name="lower", speed=20.0, axis="[1.0, 0.0, 0.0]", z=0.0) + _PIPE.format(
    name="upper", speed=-20.0, axis="[0.0, 1.0, 0.0]", z=0.1631) + """
[[contact]]
parts = ["lower", "upper"]
penalty_scale = 0.1
"""


@dataclass(frozen=True)
class MachineRate:
    """Element-cycles per second of one core of this machine, and what it was measured with."""

    per_core: float
    key: str          # the cache's key: engine build and CPU
    cpu: str
    measured_now: bool


def cache_path() -> Path:
    """Where the rates are kept: $PARADYN_CACHE_DIR, else $XDG_CACHE_HOME/paradyn, else ~/.cache/paradyn."""
    folder = os.environ.get(CACHE_ENV) or Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "paradyn"
    return Path(folder) / CACHE_NAME


def cpu_name() -> str:
    """The CPU's model name (from /proc/cpuinfo on Linux), else what the platform says."""
    try:
        for line in Path("/proc/cpuinfo").read_text(errors="replace").splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def machine_key(engine: Path) -> tuple[str, str]:
    """The cache key of ``engine`` on this CPU (a digest) and the CPU's description."""
    stat = engine.stat()
    cpu = f"{cpu_name()}, {os.cpu_count() or 1} cores"
    text = json.dumps([str(engine.resolve()), stat.st_size, stat.st_mtime_ns, cpu])
    return hashlib.sha256(text.encode()).hexdigest()[:16], cpu


def _read_cache(path: Path) -> dict[str, dict]:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def cached_rate(engine: Path) -> MachineRate | None:
    """The rate cached for ``engine`` on this CPU; None before it was measured."""
    key, cpu = machine_key(engine)
    entry = _read_cache(cache_path()).get(key)
    if not isinstance(entry, dict):
        return None
    rate = entry.get("element_cycles_per_s")
    if not isinstance(rate, (int, float)) or not rate > 0:
        return None
    return MachineRate(float(rate), key, cpu, measured_now=False)


def measure_rate(engine: Path) -> MachineRate:
    """Run the benchmark on one rank and one thread with ``engine``, cache its rate and return it.

    Raises
    ------
    paradyn.running.engine_process.EngineError
        The engine failed on the benchmark."""
    from paradyn import deck, scene

    from . import launch
    from .engine_process import follow_engine

    key, cpu = machine_key(engine)
    with tempfile.TemporaryDirectory(prefix="paradyn-rate-") as name:
        folder = Path(name)
        scene_path = folder / "scene.toml"
        scene_path.write_text(BENCHMARK_SCENE)
        model = scene.build_model(scene.load_scene(scene_path))
        deck_path = deck.write_deck(model, folder / "deck.h5")
        rate = max(float(follow_engine([str(engine), str(deck_path), str(folder / "results.h5")],
                                       launch.engine_environment(1), folder).done["element_cycles_per_s"])
                   for _ in range(BENCHMARK_RUNS))
    path = cache_path()
    entries = _read_cache(path)
    entries[key] = {"element_cycles_per_s": rate, "engine": str(engine), "cpu": cpu,
                    "benchmark": f"two crossing pipes, {BENCHMARK_ELEMENTS} J2 elements with contact, 1 x 1"}
    with contextlib.suppress(OSError):   # a read-only home: the rate serves this check, the next measures again
        write_text_atomic(path, json.dumps(entries, indent=2) + "\n")
    return MachineRate(rate, key, cpu, measured_now=True)
