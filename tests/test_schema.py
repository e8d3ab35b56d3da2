"""The schema (schema/*.toml) and the files generated from it agree (docs/formats.md, "Schema").

``python3 schema/generate.py --check`` must pass on the repository: a generated file edited by
hand, or a schema edited without rerunning the generator, fails here with the file's name.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from paradyn import _schema, deck

ROOT = Path(__file__).resolve().parents[1]
GENERATOR = ROOT / "schema" / "generate.py"
GENERATED = ("frontend/paradyn/_schema.py", "fortran/src/core/paradyn_schema.f90", "fortran/src/model/deck_fields.f90",
             "docs/formats.md")


def _check(root: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(GENERATOR), "--check", "--root", str(root)],
                          capture_output=True, text=True, timeout=60)


def test_generated_files_are_up_to_date() -> None:
    done = _check(ROOT)
    assert done.returncode == 0, done.stderr


def _copy_tree(destination: Path) -> Path:
    shutil.copytree(ROOT / "schema", destination / "schema", ignore=shutil.ignore_patterns("__pycache__"))
    for relative in GENERATED:
        (destination / relative).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(ROOT / relative, destination / relative)
    return destination


def test_check_names_every_stale_file(tmp_path: Path) -> None:
    """A change of the schema makes every generated file stale; --check names each and exits 1."""
    root = _copy_tree(tmp_path)
    toml = root / "schema" / "control.toml"
    text = toml.read_text()
    assert "default = 0.9\n" in text   # time_step_safety
    toml.write_text(text.replace("default = 0.9\n", "default = 0.8\n", 1))
    done = _check(root)
    assert done.returncode == 1
    for relative in GENERATED:
        assert f"{relative} is stale" in done.stderr, done.stderr


def test_check_finds_a_hand_edited_table(tmp_path: Path) -> None:
    root = _copy_tree(tmp_path)
    docs = root / "docs" / "formats.md"
    docs.write_text(docs.read_text().replace("| `/parts/thickness` |", "| `/parts/thicknes` |", 1))
    done = _check(root)
    assert done.returncode == 1 and "docs/formats.md is stale" in done.stderr
    assert "_schema.py" not in done.stderr


def test_generator_rewrites_the_stale_file(tmp_path: Path) -> None:
    root = _copy_tree(tmp_path)
    target = root / "frontend" / "paradyn" / "_schema.py"
    target.write_text("# edited by hand\n")
    subprocess.run([sys.executable, str(GENERATOR), "--root", str(root)], check=True, capture_output=True,
                   timeout=60)
    assert target.read_text() == (ROOT / "frontend" / "paradyn" / "_schema.py").read_text()
    assert _check(root).returncode == 0


def test_frontend_constants_come_from_the_schema() -> None:
    """paradyn.deck's public constants are the schema's codes (the engine's paradyn_schema has the same)."""
    assert (deck.ELASTIC, deck.J2_PLASTICITY) == (1, 2)
    assert (deck.HOURGLASS_VISCOUS, deck.HOURGLASS_STIFFNESS) == (1, 2)
    assert deck.PARTITIONS == {"blocks": 1, "rcb": 2} and deck.DEFAULT_PARTITION == "blocks"
    assert deck.DOF_NAMES == ("ux", "uy", "uz", "rx", "ry", "rz")
    assert _schema.EXIT_STATUSES == {0: "ok", 1: "failure", 2: "bad_input", 3: "numerical", 4: "stopped"}
    assert deck.Control(end_time=1.0, output_interval=0.1).time_step_safety == 0.9


def test_fortran_module_declares_the_schema_codes() -> None:
    """The generated Fortran module names every enum member and exit status with its code."""
    text = (ROOT / "fortran" / "src" / "core" / "paradyn_schema.f90").read_text()
    assert "implicit none" in text and "private" in text
    assert max(len(line) for line in text.splitlines()) < 132
    for name, code in [("material_elastic", 1), ("material_j2_plasticity", 2), ("hourglass_viscous", 1),
                       ("hourglass_stiffness", 2), ("partition_blocks", 1), ("partition_rcb", 2),
                       ("max_integration_points", 9), ("status_ok", 0), ("status_failure", 1),
                       ("status_bad_input", 2), ("status_numerical", 3), ("status_stopped", 4)]:
        assert f"integer, parameter :: {name} = {code}" in text, name
