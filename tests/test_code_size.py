"""The house rules of issue 12 (docs/architecture.md): no source file over 500 lines and no routine
over 120 lines, so that a file fits in a reader's head. The one exception is named here with its
reason; a new one needs the same."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ("fortran", "frontend", "tests", "schema", "tools", "cases")
MAX_FILE_LINES = 500
MAX_ROUTINE_LINES = 120
# routine -> why it may be longer
LONG_ROUTINES = {
    "blt_internal_forces": "the element kernel: one pass over a group's stages (frame, strain rates, each "
                           "through-thickness point, hourglass, forces) on per-stage arrays that the stages share; "
                           "split into procedures, the vectorised stages lose their inlining across the group loop",
}
_FORTRAN_START = re.compile(
    r"^\s*(?:(?:pure|elemental|recursive|impure|module)\s+)*"
    r"(?:(?:integer|real|logical|character|type|class)\s*(?:\([^)]*\))?\s+)?(subroutine|function)\s+(\w+)", re.I)
_FORTRAN_END = re.compile(r"^\s*end\s+(subroutine|function)\b", re.I)


def _sources(suffix: str) -> list[Path]:
    return sorted(p for folder in FOLDERS for p in (ROOT / folder).rglob(f"*{suffix}")
                  if "__pycache__" not in p.parts)


def _fortran_routines(path: Path) -> list[tuple[str, int]]:
    routines, stack = [], []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if _FORTRAN_END.match(line):
            name, start = stack.pop()
            routines.append((name, number - start + 1))
        elif (match := _FORTRAN_START.match(line)) and "procedure" not in line.lower():
            stack.append((match.group(2), number))
    return routines


def _python_routines(path: Path) -> list[tuple[str, int]]:
    tree = ast.parse(path.read_text())
    return [(node.name, node.end_lineno - node.lineno + 1) for node in ast.walk(tree)
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)]


def test_no_source_file_is_over_500_lines() -> None:
    long = {str(p.relative_to(ROOT)): n for p in _sources(".f90") + _sources(".py")
            if (n := len(p.read_text().splitlines())) > MAX_FILE_LINES}
    assert long == {}, f"split these by concern (docs/architecture.md): {long}"


def test_no_routine_is_over_120_lines_but_the_named_exceptions() -> None:
    routines = [(p, name, n) for p in _sources(".f90") for name, n in _fortran_routines(p)]
    routines += [(p, name, n) for p in _sources(".py") for name, n in _python_routines(p)]
    assert len(routines) > 500   # the scan found the project's routines
    long = {f"{p.relative_to(ROOT)}:{name}": n for p, name, n in routines
            if n > MAX_ROUTINE_LINES and name not in LONG_ROUTINES}
    assert long == {}, f"split these into named steps: {long}"
    assert all(any(name == exception and n > MAX_ROUTINE_LINES for _, name, n in routines)
               for exception in LONG_ROUTINES), "an exception that is no longer needed: remove it"
