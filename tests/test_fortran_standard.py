"""The engine is standard Fortran 2008: it builds with ``-std=f2008 -pedantic-errors``.

Every later standard's feature or GNU extension would be a compile error here (the build keeps the
project's own flags, lines at most 132 characters). The build goes to a temporary folder with
CMake, as a cluster user would build the engine alone (README), in both precisions (the mixed
engine compiles every source again with the element kernel's kind single: docs/theory.md).
Marked ``build`` (minutes on two cores): ``make test`` leaves it out, ``make test-extra`` and CI run it.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.build
@pytest.mark.skipif(shutil.which("cmake") is None, reason="cmake is not installed")
def test_engine_builds_as_standard_fortran_2008(tmp_path: Path) -> None:
    build = tmp_path / "f2008"
    configure = subprocess.run(
        ["cmake", "-S", str(ROOT / "fortran"), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
         "-DCMAKE_Fortran_FLAGS=-std=f2008 -pedantic-errors", "-DPARADYN_PRECISION=double;mixed"],
        capture_output=True, text=True)
    assert configure.returncode == 0, configure.stdout + configure.stderr
    compiled = subprocess.run(["cmake", "--build", str(build), "-j", "2"], capture_output=True, text=True)
    assert compiled.returncode == 0, compiled.stdout[-4000:] + compiled.stderr[-4000:]
    assert (build / "paradyn-engine").is_file() and (build / "paradyn-engine-mixed").is_file()
