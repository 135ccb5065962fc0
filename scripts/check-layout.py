#!/usr/bin/env python3
"""Checks the include rules of the source layout (src/README.md).

Every folder directly under src/ is one part of the library (sys, particles, io, terms, boundary,
structure, coupling, cases, solver). A header whose name ends in ``impl.h`` is the private header of
its part: only files of that part may include it. The other headers of a part are its interface to
the rest of the library. The parts' include graph must have no cycle.

    scripts/check-layout.py [--graph] [--root DIR]

Exits 1 and names the file, the line and the header for every include that breaks a rule, or the
parts of a cycle. ``--graph`` prints the parts and what each includes; ``--root`` checks another
checkout (the tests check a copy with a broken rule).
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

TOP = Path(sys.argv[sys.argv.index("--root") + 1]).resolve() if "--root" in sys.argv else Path(__file__).resolve().parents[1]
SRC = TOP / "src"
INCLUDE_DIRS = [SRC, TOP / "include"]


INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def part_of(path: Path) -> str:
    return path.relative_to(SRC).parts[0]


def resolve(name: str, where: Path) -> Path | None:
    for d in [where.parent, *INCLUDE_DIRS]:
        p = (d / name).resolve()
        if p.is_file():
            return p
    return None


def main() -> int:
    errors: list[str] = []
    graph: dict[str, set[str]] = {}
    for f in sorted(SRC.rglob("*.[ch]")):
        if len(f.relative_to(SRC).parts) < 2:
            errors.append(f"{f.relative_to(TOP)}: a source file directly in src/ belongs to no part")
            continue
        part = part_of(f)
        graph.setdefault(part, set())
        for lineno, line in enumerate(f.read_text().splitlines(), 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = resolve(m.group(1), f)
            if target is None:
                errors.append(f"{f.relative_to(TOP)}:{lineno}: \"{m.group(1)}\" not found")
                continue
            if SRC not in target.parents:
                continue
            tpart = part_of(target)
            if tpart == part:
                continue
            key = (str(f.relative_to(TOP)), str(target.relative_to(TOP)))
            if target.name.endswith("impl.h"):
                errors.append(f"{key[0]}:{lineno}: includes {key[1]}, the private header of src/{tpart}/ "
                              f"(use src/{tpart}/'s interface header instead)")
            graph[part].add(tpart)

    # cycles in the parts' graph (depth-first search, the path on the stack is the cycle)
    state: dict[str, int] = {}

    def visit(p: str, stack: list[str]) -> None:
        state[p] = 1
        for q in sorted(graph.get(p, ())):
            if state.get(q) == 1:
                cyc = stack[stack.index(q):] + [q] if q in stack else [p, q]
                errors.append("cycle in the parts' includes: " + " -> ".join(cyc))
            elif q not in state:
                visit(q, stack + [q])
        state[p] = 2

    for p in sorted(graph):
        if p not in state:
            visit(p, [p])

    if "--graph" in sys.argv:
        for p in sorted(graph):
            print(f"{p}: {' '.join(sorted(graph[p])) or '-'}")
    for e in errors:
        print(e, file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
