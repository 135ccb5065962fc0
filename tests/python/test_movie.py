"""The movie (python3 -m flexslosh.plot movie, flexslosh.movie) on a tiny coupled tank run.

One run for the module: the rectangular tank on the beam at dx = 1 cm (210 particles), 0.1 s with a
snapshot every 0.05 s (3 snapshots, under a second); then GIFs of 2 and 3 frames, a frame PNG, the
walls the run wrote, and the errors. One tiny 3-D run checks the slice.
"""

import numpy as np
import pytest

from conftest import REPO_ROOT, plot_cli, run_flexslosh

from flexslosh import movie
from flexslosh.output import read_run

Image = pytest.importorskip("PIL.Image")


@pytest.fixture(scope="module")
def tank_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("movie") / "tank"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/coupled_rectangular.opts", "-fs_dx", "0.01",
                   "-ts_max_time", "0.1", "-fs_output_interval", "0.05", "-fs_output_dir", out])
    return out



def test_run_writes_walls(tank_dir):
    """Every run with walls writes walls.h5 beside its snapshots: the tank's closed outline."""
    walls = movie.read_walls(tank_dir)
    assert walls is not None and walls["dim"] == 2 and walls["names"] == ["tank"]
    seg = walls["elements"]
    assert seg.shape[1:] == (2, 2) and len(seg) > 4
    lo, hi = seg.reshape(-1, 2).min(axis=0), seg.reshape(-1, 2).max(axis=0)
    assert np.allclose(lo, [0, 0], atol=1e-12) and np.allclose(hi, [0.7, 0.06], atol=1e-12)
    assert (tank_dir / "walls.xdmf").is_file()


def test_gif_frames(tank_dir, tmp_path):
    """The command line writes a GIF with one frame per snapshot used (3, then 2 with --every 2)."""
    assert len(read_run(tank_dir).snapshots) == 3
    out = tmp_path / "m.gif"
    proc = plot_cli("movie", tank_dir, "--output", out, "--field", "pressure", "--fps", 5)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(out)
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == 3
    two = movie.movie(tank_dir, tmp_path / "two.gif", field="velocity", every=2)
    with Image.open(two) as im:
        assert im.n_frames == 2
    assert not list(tmp_path.glob("*.tmp*")), "temporary files left behind"


def test_default_output(tank_dir):
    """Without --output: movie.mp4 in the run's directory with ffmpeg, movie.gif without."""
    from matplotlib import animation

    path = movie.movie(tank_dir, field="density")
    want = "movie.mp4" if animation.writers.is_available("ffmpeg") else "movie.gif"
    assert path == tank_dir / want and path.is_file()


def test_frame_png(tank_dir, tmp_path):
    """--frame K writes one PNG of snapshot K; an out-of-range K is an error naming the count."""
    out = tmp_path / "f.png"
    proc = plot_cli("movie", tank_dir, "--frame", "-1", "--output", out)
    assert proc.returncode == 0, proc.stderr
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size[0] > 400
    proc = plot_cli("movie", tank_dir, "--frame", "7")
    assert proc.returncode == 1 and "out of range" in proc.stderr and "3 snapshot" in proc.stderr


def test_bad_field(tank_dir, tmp_path):
    """An unknown field names itself and the choices, from Python and from the command line."""
    with pytest.raises(ValueError) as err:
        movie.movie(tank_dir, tmp_path / "x.gif", field="vorticity")
    msg = str(err.value)
    assert "'vorticity'" in msg and all(f in msg for f in movie.FIELDS)
    proc = plot_cli("movie", tank_dir, "--field", "vorticity")
    assert proc.returncode == 2
    assert "'vorticity'" in proc.stderr and "pressure" in proc.stderr and "turbulent_viscosity" in proc.stderr


def test_bad_suffix(tank_dir, tmp_path):
    with pytest.raises(ValueError, match=r"\.mp4 \(ffmpeg\) or \.gif"):
        movie.movie(tank_dir, tmp_path / "x.avi")


def test_3d_slice(tmp_path):
    """A 3-D box: the walls cut by the middle plane are its rectangle; the frame draws the slab's particles."""
    out = tmp_path / "box"
    run_flexslosh(["-options_file", REPO_ROOT / "cases/hydrostatic_3d.opts", "-fs_dx", "0.006", "-ts_max_time", "0.005",
                   "-fs_output_interval", "0.005", "-fs_output_dir", out])
    walls = movie.read_walls(out)
    assert walls["dim"] == 3 and walls["elements"].shape[1:] == (3, 3)
    segs = movie._slice_triangles(walls["elements"], 0.015)
    pts = segs.reshape(-1, 2)
    assert np.allclose(pts.min(axis=0), [0, 0], atol=1e-12) and np.allclose(pts.max(axis=0), [0.06, 0.06], atol=1e-12)
    length = np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum()
    assert length == pytest.approx(4 * 0.06, rel=1e-12)  # the cut of a closed box: its perimeter, once
    gif = movie.movie(out, tmp_path / "box.gif", field="pressure")
    with Image.open(gif) as im:
        assert im.n_frames == 2
