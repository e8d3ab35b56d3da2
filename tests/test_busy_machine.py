"""Issue 34: runs on a machine other programs use too. Threads are pinned only when the layout fits
the cores other work leaves idle, and wait at barriers with a bounded spin (a pinned thread beside
a busy loop, spinning, ran 10 x slower than one thread: docs/performance.md, "Threads on a busy
machine"); ``--check``'s wall time comes from this machine's rate, measured once and cached."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from paradyn import cli
from paradyn.running import launch, machine_rate, preflight, runners

ENGINE = Path("/opt/paradyn-engine")
SMALL_PLATE = Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml"


@pytest.mark.parametrize("busy, ranks, threads, cores, pinned", [
    (0.0, 1, 2, 2, True), (0.4, 1, 2, 2, True), (1.0, 1, 2, 2, False), (1.0, 1, 1, 2, True),
    (3.0, 2, 2, 8, True), (6.0, 2, 2, 8, False),
])
def test_threads_are_pinned_only_to_cores_other_work_leaves_idle(busy: float, ranks: int, threads: int, cores: int,
                                                                 pinned: bool) -> None:
    machine = runners.Machine(engine=ENGINE, cores=cores, busy_cores=busy)
    assert machine.binds_to_cores(ranks, threads) is pinned
    env = runners.DirectRunner(machine).environment(1, threads) if ranks == 1 else None
    if env is not None and threads > 1:
        assert ("OMP_PROC_BIND" in env) is pinned or "OMP_PROC_BIND" in os.environ


def test_the_load_decides_unless_paradyn_bind_says(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(launch, "_busy_seen", [])
    monkeypatch.setattr(launch.os, "getloadavg", lambda: (7.0, 0.0, 0.0))
    monkeypatch.setattr(launch.os, "cpu_count", lambda: 8)
    monkeypatch.setattr(launch, "available_cores", lambda: 4)
    monkeypatch.delenv(launch.BIND_ENV, raising=False)
    assert launch.busy_cores() == pytest.approx(3.5)   # 7 of 8 cores busy, as a share of this process's 4
    assert not launch.binds_to_cores(1, 4)
    monkeypatch.setattr(launch.os, "getloadavg", lambda: (0.0, 0.0, 0.0))
    assert launch.busy_cores() == pytest.approx(3.5)   # read again only after BUSY_REFRESH_S
    monkeypatch.setattr(launch, "_busy_seen", [])
    assert launch.binds_to_cores(1, 4)
    monkeypatch.setattr(launch.os, "getloadavg", lambda: (7.0, 0.0, 0.0))
    monkeypatch.setattr(launch, "_busy_seen", [])
    monkeypatch.setenv(launch.BIND_ENV, "cores")
    assert launch.busy_cores() == 0.0 and launch.binds_to_cores(1, 4)
    monkeypatch.setenv(launch.BIND_ENV, "none")
    assert not launch.binds_to_cores(1, 1)


def test_threads_wait_with_a_bounded_spin_unless_the_user_says(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in runners.WAIT_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    env = runners.engine_environment(2, bind_threads=False)
    assert {k: env[k] for k in runners.WAIT_POLICY} == runners.WAIT_POLICY
    assert "OMP_WAIT_POLICY" not in runners.engine_environment(1, bind_threads=False)   # no barriers to wait at
    oversubscribed = runners.MpirunRunner(runners.Machine(engine=ENGINE, cores=2)).environment(2, 2)
    assert oversubscribed["OMP_WAIT_POLICY"] == "passive" and "GOMP_SPINCOUNT" not in oversubscribed
    for name, value in (("OMP_WAIT_POLICY", "active"), ("GOMP_SPINCOUNT", "1000")):
        monkeypatch.setenv(name, value)   # the user's own policy wins
        env = runners.engine_environment(2, bind_threads=True)
        assert env[name] == value and all(env.get(k) == os.environ.get(k) for k in runners.WAIT_VARIABLES)
        assert runners.MpirunRunner(runners.Machine(engine=ENGINE, cores=2)).environment(2, 2)[name] == value
        monkeypatch.delenv(name)
    script = runners.SbatchRunner(runners.Machine(engine=ENGINE, cores=2)).script(
        Path("/d/deck.h5"), Path("/d/results.h5"), 1, 4, "job")
    assert 'if [ -z "${OMP_WAIT_POLICY:-}${GOMP_SPINCOUNT:-}" ]; then export OMP_WAIT_POLICY=passive; fi' in script


def test_check_measures_this_machine_once_and_caches_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    """The first --check runs the benchmark (two crossing pipes) with this engine and keeps its
    rate under $PARADYN_CACHE_DIR, keyed by the engine build and the CPU; the next reads it back.
    Another engine build (a different file) is another key."""
    monkeypatch.setenv(machine_rate.CACHE_ENV, str(tmp_path / "cache"))
    monkeypatch.delenv(preflight.RATE_ENV, raising=False)
    engine = launch.engine_path()
    assert machine_rate.cached_rate(engine) is None
    assert cli.main([str(SMALL_PLATE), "--check", "-n", "1", "-t", "1"]) == 0
    first = capsys.readouterr().out
    assert "per core, measured now on this machine" in first
    entries = json.loads((tmp_path / "cache" / machine_rate.CACHE_NAME).read_text())
    (key, entry), = entries.items()
    rate = entry["element_cycles_per_s"]
    assert 1e4 < rate < 1e9 and entry["cpu"] == f"{machine_rate.cpu_name()}, {os.cpu_count()} cores"
    assert f"(at {rate:.3g} element-cycles/s" in first   # 1 x 1: the rate itself
    assert cli.main([str(SMALL_PLATE), "--check", "-n", "1", "-t", "1", "-q"]) == 0
    second = capsys.readouterr().out
    assert "per core, measured on this machine" in second and "measured now" not in second
    cached = machine_rate.cached_rate(engine)
    assert cached is not None and cached.key == key and cached.per_core == rate
    copy = tmp_path / "other-engine"
    copy.write_bytes(engine.read_bytes() + b"\0")
    assert machine_rate.machine_key(copy)[0] != key and machine_rate.cached_rate(copy) is None
    # every run's report uses the cached rate too; $PARADYN_ELEMENT_RATE still wins
    rate_2x, source = preflight.element_rate(1, 2, cached)
    assert rate_2x == pytest.approx(2 * preflight.PARALLEL_EFFICIENCY * rate) and "measured on this machine" in source
    monkeypatch.setenv(preflight.RATE_ENV, "5e6")
    assert preflight.element_rate(1, 2, cached) == (5e6, f"${preflight.RATE_ENV}")
