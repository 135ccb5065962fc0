"""bench/benchutil.py's rounds: the rank counts run interleaved, the fastest run of each is kept, and the
side-by-side control's two 1-rank runs run at once (a fake run stands in for flexslosh)."""
import sys
import threading
import time

from conftest import REPO_ROOT

sys.path.insert(0, str(REPO_ROOT / "bench"))
import benchutil  # noqa: E402


def fake_runs(times):
    """A run_one that returns the next step time of its rank count from `times`, and records the calls."""
    calls, lock = [], threading.Lock()
    left = {nr: list(ts) for nr, ts in times.items()}

    def run_one(nr):
        with lock:
            calls.append(nr)
            t = left[nr].pop(0)
        return ({"wall_time": t + 1.0}, {"FSStep": t}, nr)

    return run_one, calls


def test_rounds_interleave_and_keep_the_fastest(capsys):
    run_one, calls = fake_runs({1: [270.51, 253.46, 254.38], 2: [159.31, 126.86, 131.39]})
    best = benchutil.run_rounds(run_one, [1, 2], 3)
    assert calls == [1, 2, 1, 2, 1, 2]
    assert benchutil.step_time(best[1]) == 253.46 and benchutil.step_time(best[2]) == 126.86
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "round 1: 1 rank(s) 270.510 s, 2 rank(s) 159.310 s, efficiency 1 -> 2 ranks 84.9 %"
    assert "efficiency 1 -> 2 ranks 99.9 %" in out[1] and len(out) == 3


def test_one_round_prints_nothing_and_falls_back_to_the_wall_time(capsys):
    best = benchutil.run_rounds(lambda nr: ({"wall_time": 12.0}, {}), [1], 1)
    assert benchutil.step_time(best[1]) == 12.0  # no FSStep event: the whole run's time
    assert capsys.readouterr().out == ""


def test_side_by_side_runs_two_at_once(capsys):
    running, peak, lock = [0], [0], threading.Lock()
    times = iter([233.93, 127.01, 252.84, 254.38])

    def run_one(nr):
        with lock:
            running[0] += 1
            peak[0] = max(peak[0], running[0])
            t = next(times)
        time.sleep(0.2)
        with lock:
            running[0] -= 1
        return ({"wall_time": t}, {"FSStep": t})

    benchutil.run_rounds(run_one, [1, 2], 1, side_by_side=True)
    assert peak[0] == 2  # the control's two runs overlapped
    out = capsys.readouterr().out
    assert "the machine's own 1 -> 2 core efficiency 92.0 %" in out and "the 2-rank run's 100.1 % of it" in out
