"""scripts/install-python.sh (run by make build) makes this checkout's package importable by a virtual environment
of the checkout's own, over /usr/bin/python3 and its Debian packages, and writes nothing outside it: the system's
site directories are left as they were, so that two checkouts do not take over each other's `import flexslosh`."""
import os
import subprocess
import sys
from pathlib import Path

from conftest import PYTHON, REPO_ROOT


def site_dirs_state():
    """The .pth files of the base Python's site directories, with their sizes and times."""
    out = subprocess.run([PYTHON, "-c", "import site; print('\\n'.join(site.getsitepackages()))"], capture_output=True,
                         text=True, check=True).stdout.split()
    return {str(p): (p.stat().st_size, p.stat().st_mtime_ns) for d in out if Path(d).is_dir()
            for p in Path(d).glob("*.pth")}


def test_the_environment_imports_this_checkout_and_nothing_else_changes(tmp_path):
    before = site_dirs_state()
    venv = tmp_path / "build" / "venv"
    env = dict(os.environ, VENV=str(venv), BASE_PYTHON=PYTHON)
    env.pop("PYTHONPATH", None)
    for _ in range(2):  # a second build keeps the environment
        proc = subprocess.run(["bash", str(REPO_ROOT / "scripts" / "install-python.sh")], env=env, capture_output=True,
                              text=True, timeout=120)
        assert proc.returncode == 0, proc.stdout + proc.stderr
    probe = "import flexslosh, petsc4py, mpi4py, h5py, numpy, sys; print(flexslosh.__file__); print(sys.prefix)"
    out = subprocess.run([str(venv / "bin" / "python3"), "-c", probe], env=env, capture_output=True, text=True,
                         cwd=tmp_path, timeout=120)
    assert out.returncode == 0, out.stderr
    module, prefix = out.stdout.split()
    assert Path(module).resolve() == (REPO_ROOT / "python" / "flexslosh" / "__init__.py").resolve()
    assert Path(prefix) == venv
    pth = list(venv.glob("lib/python3*/site-packages/flexslosh.pth"))
    assert len(pth) == 1 and pth[0].read_text().strip() == str(REPO_ROOT / "python")
    assert site_dirs_state() == before, "the system's site directories changed"
    assert sys.prefix != str(venv)
