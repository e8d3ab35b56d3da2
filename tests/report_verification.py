"""Run every verification problem of ``tests/test_verification.py`` once and print a markdown table.

Usage (from the repository root)::

    .venv/bin/python tests/report_verification.py [--workdir DIR]

Columns: problem, mesh, ParaDyn value, reference value and its source, ratio or error, the pass
criterion of the test, and the wall-clock seconds of the engine call (``models.run``: deck
already written, engine on one rank and ``models.THREADS`` OpenMP threads, results read back).
``docs/validation.md`` holds the table and discusses it.

Nothing here defines a problem. The materials, constants and helper functions come from
``tests/test_verification.py`` (``STEEL``, ``SAFETY``, ``ROOF_*``, ``PLATE_ALPHA``,
``_settled``, ``_patch``, ``_rotation``, ``_relaxed_plate``), the meshes, decks and engine runs
from ``tests/models.py``. Where a test builds its problem inline (cantilever static and
frequency, rigid body, wave speed, energy drift, default-step stability, the Scordelis-Lo fixture),
the functions below call the same ``models.py`` builders with the same parameters as the test; each
one names the test it mirrors. A change to one of those tests must be carried over here by hand.
Beyond the tests, the report adds the 4 x 4 roof and the 4 x 4 and 16 x 16 plates (same set-ups,
other meshes), which show convergence; the tests only check 8 x 8 and 16 x 16.

Exit status 0 when every criterion holds, 1 otherwise; the table is printed either way.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import models as M
import test_verification as V
from paradyn.deck import Control


@dataclass
class Row:
    problem: str
    mesh: str
    value: str
    reference: str
    ratio: str
    criterion: str
    ok: bool | None        # None: reported for information, no criterion
    wall_s: float | None
    wall_note: str = ""


def _close(value: float, reference: float, rel: float) -> bool:
    """pytest.approx(reference, rel=rel) without the absolute floor."""
    return abs(value - reference) <= rel * abs(reference)


def _g(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def _e(x: float) -> str:
    return f"{x:.1e}"


class Report:
    def __init__(self, workdir: Path) -> None:
        self.workdir = workdir
        self.rows: list[Row] = []
        self._count = 0

    def directory(self, name: str) -> Path:
        self._count += 1
        return self.workdir / f"{self._count:02d}_{name}"

    def add(self, *args: object, **kwargs: object) -> None:
        self.rows.append(Row(*args, **kwargs))  # type: ignore[arg-type]

    # ------------------------------------------------------------------------------------------
    # 1. cantilever strip

    def cantilever_static(self, material: M.Material, label: str, name: str) -> None:
        """Mirrors test_cantilever_tip_deflection."""
        beam = M.cantilever(material)
        P = 5.0
        f1 = beam.first_frequency
        period = 1.0 / f1
        control = Control(end_time=4.0 * period, output_interval=period,
                          history_interval=period / 50, mass_damping=2.0 * (2.0 * np.pi * f1),
                          time_step_safety=V.SAFETY)
        model = beam.model(control, loads=[M.Load(beam.tip, 3, P * beam.tip_weights,
                                                  ramp_time=period)])
        run = M.run(model, self.directory(f"cantilever_{name}"))
        h = run.results.history
        w_tip = h["tracked_displacement"][:, :, 2] @ beam.tip_weights
        reference = P * beam.length**3 / (3.0 * beam.bending_stiffness)
        stored = h["internal_energy"][-1] + h["hourglass_energy"][-1]
        ok = (V._settled(w_tip) < 1e-3 and _close(w_tip[-1], reference, 0.02)
              and _close(stored, 0.5 * P * w_tip[-1], 0.01))
        self.add(f"Cantilever tip deflection, {label} (dynamic relaxation)", "20 x 2",
                 f"{1e3 * w_tip[-1]:.4f} mm",
                 f"{1e3 * reference:.4f} mm: P L³/(3EI), beam theory (Timoshenko)",
                 f"{w_tip[-1] / reference:.4f}",
                 "±2 %; settled < 1e-3; IE+HG = P w/2 ± 1 %", ok, run.wall_s)

    def cantilever_frequency(self) -> None:
        """Runs test_cantilever_first_frequency's problem (test_verification.cantilever_frequency_run)."""
        f1, f, crossings, run = V.cantilever_frequency_run(self.directory("frequency"))
        self.add("Cantilever first bending frequency, ν = 0 (free vibration)", "20 x 2",
                 f"{f:.4f} Hz", f"{f1:.4f} Hz: Euler-Bernoulli (Timoshenko, Vibration Problems)",
                 f"{f / f1:.4f}", "±2 %", crossings >= 5 and _close(f, f1, 0.02), run.wall_s)

    def default_step_stability(self) -> None:
        """Mirrors test_default_time_step_is_stable, all five Poisson ratios, worst one reported."""
        worst, wall, finite = 0.0, 0.0, True
        for poisson in (-0.5, 0.0, 0.1, 0.3, 0.45):
            material = M.Material(young=V.STEEL_NU0.young, poisson=poisson,
                                  density=V.STEEL_NU0.density)
            beam = M.cantilever(material)
            dt = M.stable_time_step(beam.mesh, beam.material)
            control = Control(end_time=2000 * dt, output_interval=1000 * dt)
            model = beam.model(control, loads=[M.Load(beam.tip, 3, 5.0 * beam.tip_weights)])
            run = M.run(model, self.directory(f"stability_nu{poisson}"))
            h = run.results.history
            stored = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"]
            finite = finite and bool(np.all(np.isfinite(stored)))
            error = np.abs(stored - h["external_work"]).max() / np.abs(h["external_work"]).max()
            worst = max(worst, float(error)) if np.isfinite(error) else float("inf")
            wall += run.wall_s
        self.add("Default step (safety 0.9) stable, ν = -0.5, 0, 0.1, 0.3, 0.45; step tip load",
                 "20 x 2", f"worst energy error {_e(worst)} W", "energy balance KE+IE+HG = W",
                 f"{_e(worst)}", "finite; < 1e-3 W over 2000 cycles", finite and worst < 1e-3,
                 wall, " (5 runs)")

    # ------------------------------------------------------------------------------------------
    # 2. rigid-body motion

    def rigid_body(self, motion: str) -> None:
        """Runs test_rigid_body_motion's problem (test_verification.rigid_body_run)."""
        run, expected = V.rigid_body_run(motion, self.directory(f"rigid_{motion}"))
        h = run.results.history
        ke = h["kinetic_energy"]
        strain = (np.max(np.abs(h["internal_energy"])) + np.max(np.abs(h["hourglass_energy"])))
        strain /= ke[0]
        ke_change = (ke.max() - ke.min()) / ke[0]
        x0 = run.results.coordinates
        if motion == "translation":
            name = "Rigid translation, v = (3, -2, 1) m/s, 5000 steps"
        else:
            name = f"Rigid rotation about {motion[-1]}, 1 rad/s, quarter turn ({run.cycles} steps)"
        position = float(np.max(np.abs(x0 + run.results.displacement[-1] - expected)))
        self.add(name, "4 x 3 curved patch",
                 f"(IE+HG)/KE₀ = {_e(strain)}; ΔKE/KE₀ = {_e(ke_change)}",
                 "0: a rigid motion does no stress work",
                 f"position error {_e(position)} m",
                 "energies < 1e-6 KE₀; positions < 1e-6 m",
                 strain < 1e-6 and ke_change < 1e-6 and position < 1e-6, run.wall_s)

    # ------------------------------------------------------------------------------------------
    # 3. wave speeds

    def wave_speed(self, lateral: str) -> None:
        """Runs test_wave_speed's problem (test_verification.wave_speed_run)."""
        c, c_ref, plateau, v_plateau, run = V.wave_speed_run(lateral, self.directory(f"wave_{lateral}"))
        if lateral == "free":
            name, ref = "Bar wave speed (free sides)", "√(E/ρ)"
        else:
            name, ref = "Plate wave speed (u_y = 0)", "√(E/(ρ(1-ν²)))"
        self.add(name, "200 x 2", f"{c:.0f} m/s; plateau v = {plateau / v_plateau:.4f} F/(ρcA)",
                 f"{c_ref:.0f} m/s: {ref}, 1-D wave theory", f"{c / c_ref:.4f}",
                 "c and plateau ±2 % (bar and plate differ by 4.2 %)",
                 _close(c, c_ref, 0.02) and _close(plateau, v_plateau, 0.02), run.wall_s)

    # ------------------------------------------------------------------------------------------
    # 4. energy drift

    def energy_drift(self) -> None:
        """Mirrors test_free_vibration_energy_balance."""
        beam = M.cantilever(V.STEEL)
        dt = M.stable_time_step(beam.mesh, beam.material)
        velocity = np.zeros((beam.mesh.n_nodes, 3))
        velocity[beam.tip, 2] = 0.05
        end = 20000.5 * dt
        control = Control(end_time=end, output_interval=end / 4, history_interval=end / 400)
        run = M.run(beam.model(control, velocity=velocity), self.directory("energy"))
        h = run.results.history
        total = run.results.total_energy()
        drift = float(np.max(np.abs(total - total[0])) / total[0])
        ok = (run.cycles >= 20000 and drift < 1e-3 and h["internal_energy"].max() > 0.5 * total[0]
              and h["hourglass_energy"].max() > 0.0)
        self.add(f"Energy drift, undamped free vibration, {run.cycles} steps", "20 x 2",
                 f"max |E - E₀| = {_e(drift)} E₀ (E = KE+IE+HG-W)",
                 "0: central differences conserve E for a linear system "
                 "(Belytschko, Liu & Moran 6.2)",
                 _e(drift), "< 1e-3 E₀ at every record; IE > 0.5 E₀, HG > 0 at some time", ok,
                 run.wall_s)

    # ------------------------------------------------------------------------------------------
    # 5. Scordelis-Lo roof

    def scordelis_lo(self) -> None:
        """Mirrors the roof_runs fixture (8 x 8, 16 x 16) and adds 4 x 4 with the same set-up."""
        deflection = {}
        pending = []
        for n in (4, 8, 16):
            roof = M.scordelis_lo_quarter(n)
            control = Control(end_time=0.8, output_interval=0.4, history_interval=0.004,
                              mass_damping=V.ROOF_DAMPING, time_step_safety=V.SAFETY)
            model = roof.model(control, roof.WEIGHT * V.ROOF_LOAD_FACTOR, V.ROOF_DENSITY,
                               ramp_time=0.2)
            run = M.run(model, self.directory(f"roof{n}"))
            w = -run.results.history["tracked_displacement"][:, 0, 2] / V.ROOF_LOAD_FACTOR
            h = run.results.history
            u = run.results.displacement[-1]
            work = 0.5 * np.sum(-roof.WEIGHT * V.ROOF_LOAD_FACTOR * roof.weights * u[:, 2])
            stored = h["internal_energy"][-1] + h["hourglass_energy"][-1]
            static = V._settled(w) < 1e-3 and _close(stored, work, 5e-3)
            deflection[n] = float(w[-1])
            pending.append((n, static, run.wall_s))
        ref = V.ROOF_REFERENCE
        for n, static, wall in pending:
            w = deflection[n]
            if n == 16:
                criterion = "±5 %; settled < 1e-3; IE+HG = W/2 ± 0.5 %"
                ok = static and _close(w, ref, 0.05)
            elif n == 8:
                criterion = "within 4 % of 16 x 16; settled; IE+HG = W/2 ± 0.5 %"
                ok = static and _close(w, deflection[16], 0.04)
            else:
                criterion = "none (convergence); settled < 1e-3, IE+HG = W/2 ± 0.5 %"
                ok = None if static else False
            self.add("Scordelis-Lo roof, free-edge midside w_B (load × 1e-3, scaled back)",
                     f"{n} x {n} quarter", f"{w:.4f}",
                     f"{ref}: MacNeal & Harder (1985)", f"{w / ref:.4f}", criterion, ok, wall)

    # ------------------------------------------------------------------------------------------
    # 6. point-loaded square plate

    def plates(self) -> None:
        """Calls test_verification._relaxed_plate (the set-up of the hourglass and plate tests)."""
        deflection_rows = []
        for support in ("simple", "clamped"):
            label = "simply supported" if support == "simple" else "clamped"
            for n in (4, 8, 16):
                run, w, reference, P = V._relaxed_plate(self.directory(f"plate_{support}{n}"),
                                                        n, support)
                settled = V._settled(w) < 1e-3
                if n == 4:   # test_hourglass_energy_coarse_plate: the stiffness form, coefficient 0.1
                    run, w_hg, _, _ = V._relaxed_plate(self.directory(f"plate_hg_{support}"), n, support,
                                                       hourglass_form="stiffness")
                    h = run.results.history
                    ie, hg = h["internal_energy"][-1], h["hourglass_energy"][-1]
                    ok = (V._settled(w_hg) < 1e-3 and 0.0 < hg < 0.05 * ie
                          and _close(ie + hg, 0.5 * P * w_hg[-1], 0.01))
                    self.add(f"Hourglass energy, point-loaded plate, {label}, stiffness form 0.1", "4 x 4",
                             f"HG/IE = {hg / ie:.4f}",
                             "< 10 % IE: usual explicit-dynamics acceptance rule", f"{hg / ie:.4f}",
                             "0 < HG < 5 % IE; settled; IE+HG = P w/2 ± 1 %", ok, run.wall_s)
                if n == 8:
                    criterion = "±3 %; settled < 1e-3"
                    ok = settled and _close(w[-1], reference, 0.03)
                else:
                    criterion, ok = "none (convergence)", (None if settled else False)
                alpha = V.PLATE_ALPHA[support]
                deflection_rows.append(Row(
                    f"Plate centre deflection, point load, {label}", f"{n} x {n}",
                    f"{1e3 * w[-1]:.5f} mm",
                    f"{1e3 * reference:.5f} mm: α P a²/D, α = {alpha} (Timoshenko & "
                    "Woinowsky-Krieger)",
                    f"{w[-1] / reference:.4f}", criterion, ok, run.wall_s,
                    ""))
        self.rows.extend(deflection_rows)

    # ------------------------------------------------------------------------------------------

    def table(self) -> str:
        head = ("| problem | mesh | ParaDyn | reference (source) | ratio / error | pass criterion "
                "| result | wall (s) |")
        lines = [head, "|---|---|---|---|---|---|---|---|"]
        for r in self.rows:
            result = {True: "pass", False: "**FAIL**", None: "info"}[r.ok]
            wall = "" if r.wall_s is None else f"{r.wall_s:.2f}{r.wall_note}"
            cells = [r.problem, r.mesh, r.value, r.reference, r.ratio, r.criterion, result, wall]
            lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
        return "\n".join(lines)


def _commit() -> str:
    root = Path(__file__).resolve().parent.parent
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, text=True,
                              capture_output=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                               text=True, capture_output=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + (" + uncommitted changes" if dirty else "")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workdir", type=Path,
                        help="keep the decks and results here (default: a temporary directory)")
    args = parser.parse_args(argv)

    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="paradyn_verification_") as tmp:
        workdir = args.workdir or Path(tmp)
        report = Report(workdir)
        report.cantilever_static(V.STEEL_NU0, "ν = 0", "nu0")
        report.cantilever_static(V.STEEL, "ν = 0.3", "nu0.3")
        report.cantilever_frequency()
        report.default_step_stability()
        for motion in ("translation", "rotation_x", "rotation_y", "rotation_z"):
            report.rigid_body(motion)
        report.wave_speed("free")
        report.wave_speed("plane_strain")
        report.energy_drift()
        report.scordelis_lo()
        report.plates()
    total = time.perf_counter() - start

    print(report.table())
    print()
    print(f"Commit {_commit()}; one rank, {M.THREADS} OpenMP threads per run; "
          f"total {total:.0f} s.")
    return 0 if all(r.ok is not False for r in report.rows) else 1


if __name__ == "__main__":
    sys.exit(main())
