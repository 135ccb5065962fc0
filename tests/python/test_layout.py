"""The source layout's include rules (scripts/check-layout.py): a part includes only its own private
header and the others' interface headers, and the parts' include graph has no cycle."""
import shutil
import subprocess
import sys
from pathlib import Path

TOP = Path(__file__).resolve().parents[2]
CHECK = TOP / "scripts" / "check-layout.py"


def run_check(root):
    return subprocess.run([sys.executable, str(CHECK), "--root", str(root)], capture_output=True, text=True)


def test_the_layout_keeps_its_rules():
    r = run_check(TOP)
    assert r.returncode == 0, r.stderr


def copy_tree(tmp_path):
    root = tmp_path / "checkout"
    shutil.copytree(TOP / "src", root / "src")
    shutil.copytree(TOP / "include", root / "include")
    return root


def test_a_private_header_of_another_part_is_refused(tmp_path):
    root = copy_tree(tmp_path)
    f = root / "src" / "terms" / "impls" / "gravity.c"
    f.write_text('#include "solver/solverimpl.h"\n' + f.read_text())
    r = run_check(root)
    assert r.returncode == 1
    assert "src/terms/impls/gravity.c:1: includes src/solver/solverimpl.h, the private header of src/solver/" in r.stderr


def test_a_cycle_between_parts_is_refused(tmp_path):
    root = copy_tree(tmp_path)
    f = root / "src" / "particles" / "kernel.c"  # particles -> terms -> sys; sys -> particles closes a loop
    f.write_text('#include "terms/fsterms.h"\n' + f.read_text())
    g = root / "src" / "sys" / "registry.c"
    g.write_text('#include "particles/fsparticles.h"\n' + g.read_text())
    r = run_check(root)
    assert r.returncode == 1
    assert "cycle in the parts' includes" in r.stderr and "particles" in r.stderr and "sys" in r.stderr
