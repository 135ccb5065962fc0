/*
   The run's memory by data structure, for summary.json's "memory": the bytes each structure has
   allocated (its capacity, not what it uses), summed over the ranks, beside the peak resident memory.
   Cheap: read from the capacities the structures keep, no allocation is traced.
*/
#include "solver/solverimpl.h"
#include <petsc/private/tsimpl.h> /* whether the TS is set up (its vectors allocated) */

/* the items of "memory", in this order (FSSolverWriteMemory) */
typedef enum {
  FS_MEM_PARTICLE_FIELDS, /* the swarm's fields: position, velocity, density, mass, id, build position, DMSwarm's own */
  FS_MEM_PARTICLE_WORK,   /* records of owned and ghost particles, first-pass quantities, volumes, pressures, gamma, the
                             pair cache */
  FS_MEM_TS_VECTORS,      /* the state U, Uprev, Fout and the integrator's own vectors */
  FS_MEM_CANDIDATES,      /* the candidate (Verlet) list and its row starts */
  FS_MEM_CELLS,           /* the cell list */
  FS_MEM_HALO,            /* the halo's shifts and send lists, the PetscSF's graph and buffers (estimated) */
  FS_MEM_WALLS_LISTS,     /* the particles' candidate wall elements and wall lists */
  FS_MEM_WALLS_ELEMENTS,  /* the wall elements, their search grid and per-element arrays */
  FS_MEM_N
} FSMemoryItem;

static const char *const FSMemoryItemNames[FS_MEM_N] = {
    "particle_fields", "particle_work", "ts_vectors", "candidates", "cells", "halo", "walls_lists", "walls_elements"};

/* the bytes per particle of the swarm's fields, and the swarm's capacity */
static PetscErrorCode FSSolverSwarmBytes(FSSolver s, PetscInt64 *bytes)
{
  const char *names[] = {FS_FIELD_POSITION, FS_FIELD_VELOCITY, FS_FIELD_DENSITY, FS_FIELD_MASS,
                         FS_FIELD_ID,       FS_FIELD_BUILD,    DMSwarmField_pid, DMSwarmField_rank};
  PetscInt    n, per = 0;

  PetscFunctionBegin;
  *bytes = 0;
  if (!s->swarm) PetscFunctionReturn(0);
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  for (size_t f = 0; f < sizeof(names) / sizeof(names[0]); f++) {
    PetscInt      bs;
    PetscDataType type;
    size_t        size;
    void         *data;
    PetscCall(DMSwarmGetField(s->swarm, names[f], &bs, &type, &data));
    PetscCall(DMSwarmRestoreField(s->swarm, names[f], &bs, &type, &data));
    PetscCall(PetscDataTypeGetSize(type, &size));
    per += bs * (PetscInt)size;
  }
  *bytes = (PetscInt64)(n + 1024) * per; /* the swarm keeps a buffer of 1024 points (DMSwarmSetLocalSizes) */
  PetscFunctionReturn(0);
}

/* the vectors of the state: U, Uprev, Fout, and those the integrator allocates (rk4lean: two or three; TSRK: a
   stage and its rate per stage; other types are not counted) */
static PetscErrorCode FSSolverTSBytes(FSSolver s, PetscInt64 *bytes)
{
  PetscInt  n, nvec = 0;
  PetscBool isrk;

  PetscFunctionBegin;
  *bytes = 0;
  if (!s->state.U) PetscFunctionReturn(0);
  PetscCall(VecGetLocalSize(s->state.U, &n));
  nvec = 1 + (s->state.Uprev ? 1 : 0) + (s->state.Fout ? 1 : 0);
  if (s->ts) {
    PetscInt nlean;
    PetscCall(FSTSRK4LeanGetNumVectors(s->ts, &nlean));
    nvec += nlean; /* rk4lean's stage, rate (unless in place) and sum */
    PetscCall(PetscObjectTypeCompare((PetscObject)s->ts, TSRK, &isrk));
    if (isrk && s->ts->setupcalled) {
      PetscInt stages;
      PetscCall(TSRKGetTableau(s->ts, &stages, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
      nvec += 2 * stages; /* TSRK's Y and YdotRHS */
    }
  }
  *bytes = (PetscInt64)nvec * n * sizeof(PetscScalar);
  PetscFunctionReturn(0);
}

/* the resident pages of this process that another process maps too and none has written (Shared_Clean of
   /proc/self/smaps_rollup, Linux): mostly the shared libraries' code and read-only data, one physical copy
   for all the ranks on a node; 0 where the file cannot be read */
static PetscErrorCode FSProcessSharedClean(PetscInt64 *bytes)
{
  FILE *f;
  char  line[256];

  PetscFunctionBegin;
  *bytes = 0;
  f      = fopen("/proc/self/smaps_rollup", "r");
  if (!f) PetscFunctionReturn(0);
  while (fgets(line, sizeof(line), f)) {
    long long kb;
    if (sscanf(line, "Shared_Clean: %lld kB", &kb) == 1) {
      *bytes = (PetscInt64)kb * 1024;
      break;
    }
  }
  (void)fclose(f);
  PetscFunctionReturn(0);
}

/* the peak resident memory of all ranks counting once the clean pages the ranks of a node share: on each
   node the sum over its ranks less the largest rank's shared pages (the ranks map the same libraries, so
   the largest rank's set holds the others'), from the shared pages at the end of the run (the libraries'
   are resident from the start) */
static PetscErrorCode FSSolverSharedOnce(FSSolver s, PetscReal peak, PetscInt64 *shared, PetscReal *once)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s), node;
  PetscInt64  mine, v[2];
  PetscMPIInt noderank;

  PetscFunctionBegin;
  PetscCall(FSProcessSharedClean(&mine));
  PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_rank(node, &noderank));
  PetscCallMPI(MPI_Allreduce(&mine, &v[0], 1, MPIU_INT64, MPI_SUM, node));
  PetscCallMPI(MPI_Allreduce(&mine, &v[1], 1, MPIU_INT64, MPI_MAX, node));
  PetscCallMPI(MPI_Comm_free(&node));
  v[0] = noderank ? 0 : v[0] - v[1]; /* the node's shared pages counted more than once, on its first rank */
  v[1] = mine;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, v, 2, MPIU_INT64, MPI_SUM, comm));
  *shared = v[1];
  *once   = peak - (PetscReal)v[0];
  PetscFunctionReturn(0);
}

/*
   FSSolverWriteMemory - writes "memory" into summary.json: the bytes of each data structure summed over
   the ranks (what is allocated at the end of the run: the capacities only grow), their sum "accounted",
   the peak resident memory of all ranks, and "not_accounted", the rest (the process itself: the
   libraries, MPI, PETSc's objects; and whatever the items leave out). Also "shared_clean", the ranks'
   resident pages shared with other processes and not written (the libraries' code: each rank's peak
   counts them, the machine holds them once a node), and "peak_resident_shared_once", the peak with the
   pages the ranks of a node share counted once (an estimate: from the shared pages at the end).

   Collective
*/
PetscErrorCode FSSolverWriteMemory(FSSolver s, FSJSON js, PetscReal peak)
{
  MPI_Comm              comm = PetscObjectComm((PetscObject)s);
  const FSParticleWork *pw   = &s->pw;
  const FSNeighbours   *nb   = &pw->nbrs;
  const FSHalo         *hl   = &pw->halo;
  const PetscInt        dim  = s->opt.dim;
  PetscInt64            b[FS_MEM_N + 1];
  PetscInt64            sum = 0, shared = 0;
  PetscReal             once = peak;

  PetscFunctionBegin;
  PetscCall(PetscArrayzero(b, FS_MEM_N + 1));
  PetscCall(FSSolverSwarmBytes(s, &b[FS_MEM_PARTICLE_FIELDS]));
  b[FS_MEM_PARTICLE_WORK] = (PetscInt64)pw->reccap * (pw->stride + pw->auxstride + 2) * sizeof(PetscReal) +
                            (PetscInt64)pw->scratchcap * ((3 * dim + 3) * sizeof(PetscReal) + sizeof(PetscInt)) +
                            (PetscInt64)pw->gammacap * (pw->gammav ? 4 : 2) * sizeof(PetscReal) +
                            (PetscInt64)pw->passcap * sizeof(PetscInt) +
                            (PetscInt64)pw->pairstartcap * sizeof(PetscInt) +
                            pw->paircap * (sizeof(PetscInt) + sizeof(PetscReal)); /* the pair cache */
  PetscCall(FSSolverTSBytes(s, &b[FS_MEM_TS_VECTORS]));
  b[FS_MEM_CANDIDATES] = (PetscInt64)nb->mcap * sizeof(uint64_t) + (PetscInt64)nb->ccandcap * sizeof(PetscInt) +
                         (PetscInt64)nb->scap * 2 * sizeof(PetscInt);
  b[FS_MEM_CELLS] = (PetscInt64)nb->ccap * sizeof(PetscInt) + (PetscInt64)nb->ncap * 2 * sizeof(PetscInt);
  /* the shifts and send lists as allocated; the PetscSF's graph (a remote node and a local index per
     ghost, kept twice) and its pack buffers (a record per ghost and per copy sent) as estimated */
  b[FS_MEM_HALO] = (PetscInt64)hl->cap * dim * sizeof(PetscReal) +
                   (PetscInt64)hl->sendcap * (sizeof(PetscInt) + sizeof(PetscMPIInt) + dim * sizeof(PetscReal)) +
                   (PetscInt64)hl->nghost * 2 * (sizeof(PetscSFNode) + sizeof(PetscInt)) +
                   (PetscInt64)(hl->nghost + hl->nsend) * hl->recstride * sizeof(PetscReal);
  if (s->boundary) PetscCall(FSBoundaryGetMemory(s->boundary, &b[FS_MEM_WALLS_LISTS], &b[FS_MEM_WALLS_ELEMENTS]));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, b, FS_MEM_N, MPIU_INT64, MPI_SUM, comm));
  PetscCall(FSJSONBeginObject(js, "memory"));
  for (PetscInt k = 0; k < FS_MEM_N; k++) {
    PetscCall(FSJSONWriteInt(js, FSMemoryItemNames[k], b[k]));
    sum += b[k];
  }
  PetscCall(FSJSONWriteInt(js, "accounted", sum));
  PetscCall(FSJSONWriteInt(js, "peak_resident", (PetscInt64)peak));
  PetscCall(FSJSONWriteInt(js, "not_accounted", (PetscInt64)peak - sum));
  PetscCall(FSSolverSharedOnce(s, peak, &shared, &once));
  PetscCall(FSJSONWriteInt(js, "shared_clean", shared));
  PetscCall(FSJSONWriteInt(js, "peak_resident_shared_once", (PetscInt64)once));
  PetscCall(FSJSONEndObject(js));
  PetscFunctionReturn(0);
}
