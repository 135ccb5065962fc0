"""The C sources keep the project's format (.clang-format, PETSc's style with lines of at most 120
characters): clang-format would change nothing, and no line is longer than 120 characters."""
import shutil
import subprocess
from pathlib import Path

TOP = Path(__file__).resolve().parents[2]
FOLDERS = ("src", "include", "app", "plugins", "bench", "tests/c")


def c_files():
    return sorted(p for d in FOLDERS for p in (TOP / d).rglob("*.[ch]"))


def test_clang_format_changes_nothing():
    exe = shutil.which("clang-format")
    assert exe, "clang-format is not installed (scripts/install-deps.sh installs it)"
    r = subprocess.run([exe, "--dry-run", "--Werror", "-style=file", *map(str, c_files())], capture_output=True,
                       text=True, cwd=TOP)
    assert r.returncode == 0, "files to reformat with clang-format -i -style=file:\n" + r.stderr[:4000]


def test_lines_are_at_most_120_characters():
    long = [f"{p.relative_to(TOP)}:{k}" for p in c_files() for k, line in enumerate(p.read_text().splitlines(), 1)
            if len(line) > 120]
    assert not long, f"{len(long)} lines longer than 120 characters: {', '.join(long[:20])}"
