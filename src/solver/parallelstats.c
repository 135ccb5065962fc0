/*
   The run's parallel statistics (summary.json's "parallel"): per rank the owned particles and ghosts, the
   pairs with ghosts, the ranks it sends to, the messages and bytes it sends and the collectives it takes
   part in per step; the load imbalance over the steps. What bench/bench_scaling.py reads and the scaling
   model of docs/performance.md is built on.

   Counting costs a few additions per step and per message posted: PETSc's own counters (petsc_isend_ct,
   petsc_allreduce_ct, ... of petsclog.h, which count the MPI calls of every file that includes PETSc's
   headers, flexslosh's and PETSc's own, the PetscSF halo refreshes and DMSwarm's migration included) are
   read at the start and the end of each step (the step, its checks, rebuilds and monitors); what they do
   not count (MPI_Reduce, the MPI_Ibarrier of PETSc's two-sided handshake) is added where it happens.
*/
#include "solver/solverimpl.h"

/* the per-rank values, in the order of the keys */
static const char *FSParallelKeys[] = {"owned",
                                       "ghosts",
                                       "owned_first",
                                       "ghosts_first",
                                       "owned_mean",
                                       "ghosts_mean",
                                       "pairs",
                                       "pairs_with_ghosts",
                                       "work",
                                       "pair_visits",
                                       "send_ranks",
                                       "messages_per_step",
                                       "bytes_per_step",
                                       "halo_messages_per_step",
                                       "halo_bytes_per_step",
                                       "halo_build_messages_per_step",
                                       "halo_build_bytes_per_step",
                                       "migration_messages_per_step",
                                       "migration_bytes_per_step",
                                       "collectives_per_step"};
#define FS_PAR_NKEYS ((PetscInt)(sizeof(FSParallelKeys) / sizeof(FSParallelKeys[0])))

/* the largest rank's value of key over the ranks' mean, from the gathered per-rank values (rank 0) */
static PetscReal FSParallelMaxOverMean(const PetscReal all[], PetscMPIInt size, const char key[])
{
  PetscInt  c   = 0;
  PetscReal max = 0, sum = 0;

  while (c < FS_PAR_NKEYS - 1 && strcmp(FSParallelKeys[c], key)) c++;
  for (PetscMPIInt r = 0; r < size; r++) {
    max = PetscMax(max, all[r * FS_PAR_NKEYS + c]);
    sum += all[r * FS_PAR_NKEYS + c];
  }
  return sum > 0 ? max * size / sum : 1;
}

static inline void FSParallelCounters(PetscLogDouble c[3])
{
  c[0] = petsc_isend_ct + petsc_send_ct;
  c[1] = petsc_isend_len + petsc_send_len;
  c[2] = petsc_allreduce_ct + petsc_gather_ct + petsc_scatter_ct;
}

/* FSParallelStatsBegin - when the monitors begin (after the set-up): the statistics start from zero. Not collective */
PetscErrorCode FSParallelStatsBegin(FSSolver s)
{
  FSParallelStats *ps = &s->mon.par;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(ps, sizeof(*ps)));
  ps->owned_first  = s->pw.nowned;
  ps->ghosts_first = s->pw.halo.nghost;
  PetscFunctionReturn(0);
}

/* FSParallelStatsStepBegin - at the start of a step. Not collective */
void FSParallelStatsStepBegin(FSSolver s)
{
  FSParallelStats *ps = &s->mon.par;

  if (!s->mon.steps_taken) { /* the halo's counts from here, as PETSc's */
    ps->halo_msgs0   = s->pw.halo.refresh_msgs;
    ps->halo_bytes0  = s->pw.halo.refresh_bytes;
    ps->build_msgs0  = s->pw.halo.build_msgs;
    ps->build_bytes0 = s->pw.halo.build_bytes;
    ps->nbuilds0     = s->pw.halo.nbuilds;
  }
  FSParallelCounters(ps->mark);
}

/* FSParallelStatsStepEnd - at the end of a step, after its monitors. Not collective */
void FSParallelStatsStepEnd(FSSolver s)
{
  FSParallelStats *ps = &s->mon.par;
  PetscLogDouble   c[3];

  FSParallelCounters(c);
  ps->msgs += c[0] - ps->mark[0];
  ps->bytes += c[1] - ps->mark[1];
  ps->colls += c[2] - ps->mark[2];
  ps->owned_sum += s->pw.nowned;
  ps->ghost_sum += s->pw.halo.nghost;
  ps->pairs_sum += s->pw.nbrs.npairs;
  ps->max_owned_sum += ps->step_max[0];
  ps->max_pairs_sum += ps->step_max[1];
}

/*
   FSParallelStatsSummary - the "parallel" object of summary.json: the process grid, the imbalance, and per
   rank (arrays indexed by rank) the values of FSParallelKeys. Per step: over the steps since the monitors
   began. The imbalance: the largest over the mean, of the owned particles at the end and of the owned
   particles and the pair lists summed over the steps (the sum of each step's largest over the sum of its
   means: what a step waits for).

   Collective
*/
PetscErrorCode FSParallelStatsSummary(FSSolver s, FSJSON js)
{
  MPI_Comm               comm = PetscObjectComm((PetscObject)s);
  const FSParallelStats *ps   = &s->mon.par;
  const FSHalo          *hl   = &s->pw.halo;
  const FSNeighbours    *nb   = &s->pw.nbrs;
  PetscReal              mine[FS_PAR_NKEYS], *all = NULL, *col = NULL, steps, grid[3], sums[3];
  PetscInt64             across = 0, work = 0;
  PetscMPIInt            size, rank;
  PetscLogDouble         uncounted = ps->uncounted;
  PetscBuildTwoSidedType bt;
  PetscInt               k = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  steps = (PetscReal)PetscMax(s->mon.steps_taken, 1);
  PetscCall(PetscCommBuildTwoSidedGetType(comm, &bt));
  if (bt == PETSC_BUILDTWOSIDED_IBARRIER && size > 1) uncounted += hl->nbuilds - ps->nbuilds0; /* its MPI_Ibarrier */
  /* the pairs within the support whose neighbour is a ghost, at the last right-hand side */
  if (nb->cstart && s->pw.rec)
    for (PetscInt i = 0; i < s->pw.nowned; i++) {
      const PetscReal *xi = &s->pw.rec[i * s->pw.stride];
      FSCandidateIter  it;
      PetscInt         j;
      FSNeighboursCandidateBegin(nb, i, &it);
      while (FSNeighboursCandidateNext(nb, &it, &j)) {
        const PetscReal *xj = &s->pw.rec[j * s->pw.stride];
        PetscReal        r2 = 0;
        if (j < s->pw.nowned) continue;
        for (PetscInt d = 0; d < s->opt.dim; d++) r2 += (xj[d] - xi[d]) * (xj[d] - xi[d]);
        across += r2 < s->pw.kernel.support2;
      }
    }
  if (nb->cstart && s->pw.rec) PetscCall(FSSolverGetWorkSum(s, &work));
  mine[k++] = s->pw.nowned;
  mine[k++] = hl->nghost;
  mine[k++] = ps->owned_first;
  mine[k++] = ps->ghosts_first;
  mine[k++] = ps->owned_sum / steps;
  mine[k++] = ps->ghost_sum / steps;
  mine[k++] = (PetscReal)nb->npairs;
  mine[k++] = (PetscReal)across;
  mine[k++] = (PetscReal)work;
  mine[k++] = (PetscReal)s->mon.pair_visits;
  mine[k++] = hl->nsendranks;
  mine[k++] = ps->msgs / steps;
  mine[k++] = ps->bytes / steps;
  mine[k++] = (hl->refresh_msgs - ps->halo_msgs0) / steps;
  mine[k++] = (hl->refresh_bytes - ps->halo_bytes0) / steps;
  mine[k++] = (hl->build_msgs - ps->build_msgs0) / steps;
  mine[k++] = (hl->build_bytes - ps->build_bytes0) / steps;
  mine[k++] = ps->mig_msgs / steps;
  mine[k++] = ps->mig_bytes / steps;
  mine[k++] = (ps->colls + uncounted) / steps;
  PetscCheck(k == FS_PAR_NKEYS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "parallel statistics: %" PetscInt_FMT " values", k);
  /* the time-integrated means, for the imbalance */
  sums[0] = (PetscReal)ps->owned_sum;
  sums[1] = (PetscReal)ps->pairs_sum;
  sums[2] = 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPIU_REAL, MPI_SUM, comm));
  if (!rank) PetscCall(PetscMalloc2(size * FS_PAR_NKEYS, &all, size, &col));
  PetscCallMPI(MPI_Gather(mine, FS_PAR_NKEYS, MPIU_REAL, all, FS_PAR_NKEYS, MPIU_REAL, 0, comm));
  PetscCall(FSJSONBeginObject(js, "parallel"));
  for (PetscInt d = 0; d < 3; d++) grid[d] = s->pw.decomp.np[d];
  PetscCall(FSJSONWriteRealArray(js, "grid", s->opt.dim, grid));
  PetscCall(FSJSONWriteInt(js, "steps", s->mon.steps_taken));
  PetscCall(FSJSONWriteInt(js, "halo_builds", hl->nbuilds - ps->nbuilds0));
  PetscCall(FSJSONWriteString(js, "two_sided", PetscBuildTwoSidedTypes[bt]));
  if (!rank) {
    PetscCall(FSJSONWriteReal(js, "imbalance_owned_end", FSParallelMaxOverMean(all, size, "owned")));
    PetscCall(FSJSONWriteReal(js, "imbalance_work_end", FSParallelMaxOverMean(all, size, "work")));
    PetscCall(FSJSONWriteReal(js, "imbalance_owned", sums[0] > 0 ? ps->max_owned_sum * size / sums[0] : 1));
    PetscCall(FSJSONWriteReal(js, "imbalance_pairs", sums[1] > 0 ? ps->max_pairs_sum * size / sums[1] : 1));
    for (PetscInt key = 0; key < FS_PAR_NKEYS; key++) {
      for (PetscMPIInt r = 0; r < size; r++) col[r] = all[r * FS_PAR_NKEYS + key];
      PetscCall(FSJSONWriteRealArray(js, FSParallelKeys[key], size, col));
    }
    PetscCall(PetscFree2(all, col));
  }
  PetscCall(FSJSONEndObject(js));
  PetscFunctionReturn(0);
}
