"""Floating-point operations executed by a scalar build: python tools/count_flops.py DUMP BINARY.

DUMP is a callgrind output written with ``--dump-instr=yes`` while running BINARY, a build without
vectorisation (``-fno-tree-vectorize -fno-tree-slp-vectorize``), where every double-precision
operation is one scalar instruction. Prints how often each arithmetic instruction
(``vaddsd``, ``vmulsd``, ``vdivsd``, ``vsqrtsd``, ...) ran inside BINARY itself (not its libraries)
and their total: the kernel's operations counted, not estimated (docs/performance.md).
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

ARITHMETIC = re.compile(r"v?(add|sub|mul|div|sqrt|min|max)sd$")
COST = re.compile(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+(?:0x[0-9a-f]+|[+-]?\d+|\*)\s+(\d+)")
NAMED = re.compile(r"^c?(ob|fn)=\((\d+)\)(?: (.*))?")


def mnemonics(binary: Path) -> dict[int, str]:
    """Instruction address to mnemonic, from ``objdump -d``."""
    listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", str(binary)],
                             capture_output=True, text=True, check=True).stdout
    found = (re.match(r"^\s+([0-9a-f]+):\s+(\S+)", line) for line in listing.splitlines())
    return {int(m.group(1), 16): m.group(2) for m in found if m}


def instruction_counts(dump: Path, binary: Path) -> Counter[int]:
    """Executions per instruction address of BINARY's own code (positions: address, line)."""
    names: dict[tuple[str, str], str] = {}
    counts: Counter[int] = Counter()
    address, inside, after_call = 0, False, False
    for line in dump.read_text().splitlines():
        named = NAMED.match(line)
        if named:
            kind, key, name = named.groups()
            if name:
                names[(kind, key)] = name
            if line.startswith("ob="):
                inside = names.get(("ob", key), "").endswith(binary.name)
            continue
        if line.startswith("calls="):
            after_call = True   # the next cost line is the call's inclusive cost
            continue
        cost = COST.match(line)
        if not cost:
            continue
        position = cost.group(1)
        if position.startswith("0x"):
            address = int(position, 16)
        elif position != "*":
            address += int(position)
        if after_call:
            after_call = False
        elif inside:
            counts[address] += int(cost.group(2))
    return counts


def main(argv: list[str]) -> int:
    dump, binary = Path(argv[0]), Path(argv[1])
    names = mnemonics(binary)
    ops: Counter[str] = Counter()
    for address, count in instruction_counts(dump, binary).items():
        name = names.get(address, "")
        if ARITHMETIC.match(name):
            ops[name] += count
    for name, count in ops.most_common():
        print(f"{name:10s} {count}")
    print(f"{'total':10s} {sum(ops.values())}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
