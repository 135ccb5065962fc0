#!/usr/bin/env bash
# make demo: the seed's question in a few minutes on 2 cores. The beam released from a 0.04 m tip
# deflection carries (a) a solid mass, (b) the rectangular tank with water at 50 % fill (same total
# mass), fully coupled, at dx = 2.5 mm; then the seed's figures from both runs and the movie
# of the tank (python3 -m flexslosh.plot movie) with one frame of it (docs/images/sloshing_tank.png).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${BUILD:-build}"
PYTHON="${PYTHON:-$BUILD/venv/bin/python3}"  # the checkout's own (make build: scripts/install-python.sh)
NP="${NP:-2}"
out=output/demo
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
echo "flexslosh demo: 1/4 the solid mass on the beam (msd, 3 s)"
"$BUILD/flexslosh" -options_file cases/beam_free_decay_msd.opts -ts_max_time 3 -fs_output_dir "$out/solid" -fs_progress 0
# dx = 2.5 mm (12 particles across the liquid's depth): fine enough for the sheet, the jets and the splash to show;
# the density diffusion split off (RKL2) at 0.8 of the acoustic limit keeps it to a few minutes
# (docs/performance.md, "The density diffusion split off")
echo "flexslosh demo: 2/4 the rectangular tank at 50 % fill on the beam (msd, 3 s, dx = 2.5 mm, $NP ranks; a few minutes)"
mpirun -n "$NP" "$BUILD/flexslosh" -options_file cases/coupled_rectangular.opts -fs_dx 0.0025 -fs_delta_split \
  -fs_cfl 0.8 -fs_output_dir "$out/rectangular"
echo "flexslosh demo: 3/4 the figures"
"$PYTHON" -m flexslosh.plot "$out/rectangular" "$out/solid" --labels "liquid 50 %,solid mass" --out "$out/figures"
"$PYTHON" - "$out" <<'PY'
import sys
from flexslosh.damping import damping_per_cycle
from flexslosh.output import read_run
out = sys.argv[1]
print("\ndamping ratio per cycle (from the tip displacement), cycle amplitude in mm:")
for name in ("solid", "rectangular"):
    ts = read_run(f"{out}/{name}").timeseries
    c = damping_per_cycle(ts["time"], ts["tip_displacement"])
    row = "  ".join(f"{1e3 * a:.1f}:{100 * z:.2f}%" for a, z in zip(c.amplitude, c.zeta))
    print(f"  {name:12s} {row}")
PY
echo "flexslosh demo: 4/4 the movie of the 50 % tank (MP4 with ffmpeg, else GIF) and its frame at t = 0.35 s"
"$PYTHON" -m flexslosh.plot movie "$out/rectangular" --field velocity
"$PYTHON" -m flexslosh.plot movie "$out/rectangular" --field velocity --frame 7 --output "$out/figures/frame.png"
cat <<MSG

flexslosh demo finished. Results in $out/:
  solid/, rectangular/   each run: timeseries.csv (tip motion, loads), energy.csv (the energy budget),
                         particles.xdmf + snapshot_*.h5 and walls.xdmf (open in ParaView), summary.json;
                         rectangular/movie.mp4 (or .gif): the liquid coloured by its speed, with the tip's motion
  figures/               the seed's figures: tip_acceleration_*.png (Figs. 5, 8), normalized_motion.png (Fig. 9),
                         acceleration_envelope.png (Fig. 10), energy_terms_*.png (Fig. 11),
                         snapshots_*.png (Figs. 6, 7), damping_vs_amplitude.png, damping_*.csv,
                         frame.png (one frame of the movie: the README's picture)
MSG
