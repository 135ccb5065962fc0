#!/usr/bin/env bash
# Shows that a code change leaves the results unchanged: runs the reference cases with two builds
# (on 1 and 2 ranks) and compares their time series and energy budgets column by column (the base's columns; new
# columns are listed).
#
#   scripts/compare-runs.sh BASE_REF [NEW_BUILD]
#
# BASE_REF is a git revision (e.g. a commit before the change), checked out into a temporary
# worktree and built there, or the build folder of such a revision made before. NEW_BUILD is the build folder of the change (default: build). Prints the
# largest relative difference per case and exits non-zero if any exceeds TOL (default 1e-12).
# The cases: dam break (a/dx 40, T = 1), Taylor-Green, the coupled rectangular tank (0.3 s) and the
# baffled tank (0.2 s).
set -euo pipefail
top="$(cd "$(dirname "$0")/.." && pwd)"
base="${1:?usage: scripts/compare-runs.sh BASE_REF [NEW_BUILD]}"
newbuild="$(cd "${2:-$top/build}" && pwd)"
tol="${TOL:-1e-12}"
py="${PYTHON:-/usr/bin/python3}"
work="$(mktemp -d /tmp/flexslosh-compare.XXXXXX)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1

mkdir -p "$work/out"
if [ -d "$base" ]; then # a build folder of the base made before (its cases are taken from this checkout)
  basebuild="$(cd "$base" && pwd)"; basesrc="$top"
else
  git -C "$top" worktree add --detach "$work/src" "$base" > /dev/null
  trap 'git -C "$top" worktree remove --force "$work/src" > /dev/null 2>&1 || true' EXIT
  cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release > /dev/null
  cmake --build "$work/build" -j 2 --target flexslosh-bin > /dev/null
  basebuild="$work/build"; basesrc="$work/src"
fi

cases=(
  "dam_break|-options_file cases/dam_break.opts -fs_dx 0.025 -ts_max_time 1"
  "taylor_green|-options_file cases/taylor_green.opts"
  "coupled_rectangular|-options_file cases/coupled_rectangular.opts -ts_max_time 0.3"
  "tank_baffled|-options_file cases/tank_baffled.opts -ts_max_time 0.2"
)
status=0
for c in "${cases[@]}"; do
  name="${c%%|*}"
  opts="${c#*|}"
  for np in 1 2; do
    for side in base new; do
      bin="$basebuild/flexslosh"; srcdir="$basesrc"
      if [ "$side" = new ]; then bin="$newbuild/flexslosh"; srcdir="$top"; fi
      out="$work/out/$name-$np-$side"
      (cd "$srcdir" && mpirun -n "$np" "$bin" $opts -fs_output_dir "$out" -fs_output_interval 0 -fs_progress 0 > "$out.log" 2>&1) ||
        { echo "$name on $np rank(s), $side build: the run failed, see $out.log"; status=1; continue 2; }
    done
    "$py" - "$work/out/$name-$np-base" "$work/out/$name-$np-new" "$name on $np rank(s)" "$tol" <<'PY' || status=1
import csv, math, sys
base, new, label, tol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
worst, where = 0.0, ""
for f in ("timeseries.csv", "energy.csv"):
    try:
        a = list(csv.reader(open(f"{base}/{f}")))
    except FileNotFoundError:
        continue
    b = list(csv.reader(open(f"{new}/{f}")))
    missing = [n for n in a[0] if n not in b[0]]
    if missing or len(a) != len(b):
        print(f"{label}: {f} differs in its columns or rows ({len(a)} against {len(b)} rows; missing {missing})")
        sys.exit(1)
    added = [n for n in b[0] if n not in a[0]]
    if added:
        print(f"{label}: {f} has new columns {added} (not compared)")
    for col, name in enumerate(a[0]):
        if name == "wall_time":
            continue
        cb = b[0].index(name)
        scale = max(abs(float(r[col])) for r in a[1:]) or 1.0
        for ra, rb in zip(a[1:], b[1:]):
            x, y = float(ra[col]), float(rb[cb])
            d = abs(x - y) / scale if not (math.isnan(x) and math.isnan(y)) else 0.0
            if d > worst:
                worst, where = d, f"{f}:{name} row {ra[0]}"
print(f"{label}: {len(a) - 1} rows, largest relative difference {worst:.3g} ({where or 'none'})")
sys.exit(0 if worst <= tol else 1)
PY
  done
done
exit $status
