/*
   bench_rhs: what one right-hand side costs per particle, for any case (the options as for flexslosh).

   Sets the case up, takes -steps time steps (so that the flow has started: at rest the delta-LES viscosity and
   diffusion vanish and skip their pairs), then evaluates the right-hand side -reps times at that state and prints
   the seconds per right-hand side per particle, of CPU time (the process's: on a shared machine it leaves out the
   time other work took the core) and of wall time, with the passes' shares (their log events, wall time).

     build/bench_rhs -fs_case dam_break -fs_dx 0.01 [-steps 20] [-reps 40]
     build/bench_rhs -fs_case dam_break -fs_dim 3 -fs_dx 0.047 -steps 2 -reps 6
*/
#include "solver/solverimpl.h"
#include <time.h>

static double CPUSeconds(void)
{
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
  FSSolver           s;
  Vec                F;
  PetscScalar       *f;
  const PetscScalar *u;
  PetscInt           reps = 40, steps = 20, n;
  PetscMPIInt        size;
  PetscLogDouble     w0, w1, before[4], after[4];
  PetscLogEvent      ev[4]; /* registered by FSSolverCreate */
  const char        *evname[4] = {"first pass", "pair pass (terms)", "walls (gamma, lists, p_wall)", "wall terms"};
  double             c0, c1;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, "bench_rhs: the cost of a right-hand side per particle\n"));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCheck(size == 1, PETSC_COMM_WORLD, PETSC_ERR_SUP, "Run bench_rhs on one rank");
  PetscCall(PetscLogDefaultBegin());
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-reps", &reps, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-steps", &steps, NULL));
  PetscCheck(reps > 0 && steps >= 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "-reps %" PetscInt_FMT " and -steps %" PetscInt_FMT ": expected reps > 0 and steps >= 0", reps, steps);
  PetscCall(PetscOptionsSetValue(NULL, "-fs_output", "0"));
  PetscCall(PetscOptionsSetValue(NULL, "-fs_progress", "0"));
  PetscCall(FSSolverCreate(PETSC_COMM_WORLD, &s));
  PetscCall(FSSolverSetFromOptions(s));
  PetscCall(FSSolverSetUp(s));
  for (PetscInt k = 0; k < steps; k++) PetscCall(FSSolverStep(s));
  ev[0] = FS_FirstPass;
  ev[1] = FS_PairPass;
  ev[2] = FS_Walls;
  ev[3] = FS_WallPass;
  n     = s->pw.nowned;
  PetscCall(VecDuplicate(s->state.U, &F));
  PetscCall(VecGetArrayRead(s->state.U, &u));
  PetscCall(VecGetArray(F, &f));
  PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_FALSE)); /* warm-up: the arrays at their sizes */
  for (PetscInt e = 0; e < 4; e++) {
    PetscEventPerfInfo info;
    PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, ev[e], &info));
    before[e] = info.time;
  }
  c0 = CPUSeconds();
  PetscCall(PetscTime(&w0));
  for (PetscInt r = 0; r < reps; r++) PetscCall(FSSolverEvaluateRates(s, u, f, PETSC_FALSE));
  PetscCall(PetscTime(&w1));
  c1 = CPUSeconds();
  for (PetscInt e = 0; e < 4; e++) {
    PetscEventPerfInfo info;
    PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, ev[e], &info));
    after[e] = info.time;
  }
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "bench_rhs: %" PetscInt_FMT "-D, %" PetscInt_FMT
                        " particles, %.1f pairs a particle, %" PetscInt_FMT " right-hand sides after %" PetscInt_FMT
                        " steps\n",
                        s->opt.dim, n, (double)s->pw.nbrs.npairs / (double)PetscMax(n, 1), reps, steps));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "  a right-hand side per particle: %.4g us of CPU time, %.4g us of wall time\n",
                        1e6 * (c1 - c0) / reps / PetscMax(n, 1), 1e6 * (w1 - w0) / reps / PetscMax(n, 1)));
  for (PetscInt e = 0; e < 4; e++)
    if (after[e] > before[e])
      PetscCall(
          PetscPrintf(PETSC_COMM_WORLD, "  %-30s %5.1f %%\n", evname[e], 100 * (after[e] - before[e]) / (w1 - w0)));
  PetscCall(VecDestroy(&F));
  PetscCall(FSSolverDestroy(&s));
  PetscCall(PetscFinalize());
  return 0;
}
