"""Python style (issue 12): ``ruff check`` over the Python sources finds nothing.

The rule set, the line length and the files left out are the ``[tool.ruff]`` tables of
pyproject.toml.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("frontend", "tests", "cases", "tools", "schema")


def test_python_sources_are_ruff_clean() -> None:
    """Reference: ``python -m ruff check frontend tests cases tools schema`` (``schema`` where it
    exists) with the configuration of pyproject.toml; every finding is printed."""
    folders = [name for name in FOLDERS if (ROOT / name).is_dir()]
    command = [sys.executable, "-m", "ruff", "check", "--no-cache", "--output-format", "concise", *folders]
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"python {' '.join(command[1:])} found:\n{result.stdout}{result.stderr}"
