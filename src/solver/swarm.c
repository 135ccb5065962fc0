/*
   Particles: the DMSwarm (DMSWARM_BASIC) that owns them, their migration between ranks (any
   distance, periodic wrapping, losses reported), their ordering by cell for memory locality,
   and the packing of (x, u, rho) into the TS state vector.
*/
#include "solver/solverimpl.h"

static const char *FSFieldNames[] = {FS_FIELD_POSITION, FS_FIELD_VELOCITY, FS_FIELD_DENSITY,
                                     FS_FIELD_MASS,     FS_FIELD_ID,       FS_FIELD_BUILD};

/* FSSolverCreateSwarm - the DMSwarm with fields position, velocity (dim), density, mass, id, and the
   positions at the last build of the lists (FS_FIELD_BUILD, dim). */
PetscErrorCode FSSolverCreateSwarm(FSSolver s)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(DMCreate(comm, &s->swarm));
  PetscCall(PetscObjectSetName((PetscObject)s->swarm, "particles"));
  PetscCall(DMSetType(s->swarm, DMSWARM));
  PetscCall(DMSetDimension(s->swarm, s->opt.dim));
  PetscCall(DMSwarmSetType(s->swarm, DMSWARM_BASIC));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_POSITION, s->opt.dim, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_VELOCITY, s->opt.dim, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_DENSITY, 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_MASS, 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_ID, 1, PETSC_INT));
  PetscCall(DMSwarmRegisterPetscDatatypeField(s->swarm, FS_FIELD_BUILD, s->opt.dim, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(s->swarm));
  PetscCall(DMSwarmSetLocalSizes(s->swarm, 0, 1024));
  PetscFunctionReturn(0);
}

/*
   FSSolverAddParticles - appends particles created by a case on this rank. Ids continue the
   global numbering in rank order, so a case that enumerates a lattice in chunks gives every
   particle the same id on any number of ranks. The particles move to their owners in SetUp.

   Collective

   Input Parameters:
+  n   - number of particles added by this rank
.  x   - positions (n*dim)
.  u   - velocities (n*dim)
.  rho - densities (n)
-  m   - masses (n)
*/
PetscErrorCode FSSolverAddParticles(FSSolver s, PetscInt n, const PetscReal x[], const PetscReal u[],
                                    const PetscReal rho[], const PetscReal m[])
{
  PetscInt   nold, dim = s->opt.dim;
  PetscInt64 first = 0, n64 = n, total;
  PetscReal *px, *pu, *prho, *pm;
  PetscInt  *pid;
  MPI_Comm   comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCheck(s->swarm, comm, PETSC_ERR_ORDER, "FSSolverAddParticles() must be called from a case's setup");
  PetscCallMPI(MPI_Exscan(&n64, &first, 1, MPIU_INT64, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&n64, &total, 1, MPIU_INT64, MPI_SUM, comm));
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    if (!rank) first = 0;
  }
  PetscCheck(s->pw.nglobal_particles + total < PETSC_MAX_INT, comm, PETSC_ERR_SUP,
             "Too many particles (%" PetscInt64_FMT ") for 32-bit PetscInt ids", s->pw.nglobal_particles + total);
  first += s->pw.nglobal_particles;
  PetscCall(DMSwarmGetLocalSize(s->swarm, &nold));
  PetscCall(DMSwarmAddNPoints(s->swarm, n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&px));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&pu));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&prho));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&pm));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&pid));
  for (PetscInt p = 0; p < n; p++) {
    for (PetscInt d = 0; d < dim; d++) {
      px[(nold + p) * dim + d] = x[p * dim + d];
      pu[(nold + p) * dim + d] = u[p * dim + d];
    }
    prho[nold + p] = rho[p];
    pm[nold + p]   = m[p];
    pid[nold + p]  = (PetscInt)(first + p);
    PetscCheck(rho[p] > 0 && m[p] > 0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
               "Particle %" PetscInt64_FMT " created with density %g and mass %g: both must be positive", first + p,
               (double)rho[p], (double)m[p]);
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&pid));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&pm));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&prho));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&pu));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&px));
  s->pw.nglobal_particles += total;
  PetscFunctionReturn(0);
}

/* FSSolverWrapPeriodic - brings a position into the domain along its periodic directions. */
void FSSolverWrapPeriodic(FSSolver s, PetscReal x[])
{
  for (PetscInt d = 0; d < s->opt.dim; d++)
    if (s->pw.periodic[d]) {
      const PetscReal L = s->pw.hi[d] - s->pw.lo[d];
      if (x[d] < s->pw.lo[d] || x[d] >= s->pw.hi[d]) x[d] -= L * PetscFloorReal((x[d] - s->pw.lo[d]) / L);
      if (x[d] >= s->pw.hi[d]) x[d] = s->pw.lo[d]; /* round-off at the upper edge */
    }
}

/*
   FSSolverMigrate - wraps periodic coordinates, checks that no particle left the domain through a
   non-periodic side (an error naming the particle, step, time and place), and sends every particle
   that left its rank's box to its new owner.

   Output Parameter:
.  changed - PETSC_TRUE on every rank if any particle changed rank (local sizes may have changed)

   Collective
*/
PetscErrorCode FSSolverMigrate(FSSolver s, PetscBool *changed)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  PetscInt    n, dim = s->opt.dim, nleave = 0, nlost = 0, lost = -1;
  PetscInt64  glob[2], before, after;
  PetscReal  *x;
  PetscInt   *rankf, *id;
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(FS_Migrate, 0, 0, 0, 0));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rankf));
  for (PetscInt p = 0; p < n; p++) {
    PetscReal  *xp = &x[p * dim];
    PetscMPIInt dest;
    FSSolverWrapPeriodic(s, xp);
    for (PetscInt d = 0; d < dim; d++) {
      if (!s->pw.periodic[d] && !(xp[d] >= s->pw.lo[d] && xp[d] <= s->pw.hi[d])) {
        if (lost < 0) lost = p;
        nlost++;
      }
    }
    dest     = FSDecompRankOf(&s->pw.decomp, xp);
    rankf[p] = dest;
    if (dest != rank) nleave++;
  }
  glob[0] = nleave;
  glob[1] = nlost;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, glob, 2, MPIU_INT64, MPI_SUM, comm));
  if (nlost) {
    PetscReal t;
    PetscInt  step;
    PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCall(TSGetTime(s->ts, &t));
    PetscCall(TSGetStepNumber(s->ts, &step));
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "[%d] flexslosh: particle %" PetscInt_FMT " left the domain at step %" PetscInt_FMT
                          ", time %g, position (%g, %g, %g); domain [%g,%g] x [%g,%g] x [%g,%g]; %" PetscInt_FMT
                          " particle(s) lost on this rank\n",
                          rank, id[lost], step, (double)t, (double)x[lost * dim], (double)x[lost * dim + 1],
                          dim == 3 ? (double)x[lost * dim + 2] : 0.0, (double)s->pw.lo[0], (double)s->pw.hi[0],
                          (double)s->pw.lo[1], (double)s->pw.hi[1], (double)s->pw.lo[2], (double)s->pw.hi[2], nlost));
    PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  }
  PetscCall(DMSwarmRestoreField(s->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rankf));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCheck(glob[1] == 0, comm, PETSC_ERR_CONV_FAILED,
             "%" PetscInt64_FMT " particle(s) left the domain through a non-periodic side (see the message above for "
             "where): the flow is unstable or the domain too small",
             glob[1]);
  *changed = PETSC_FALSE;
  if (glob[0]) {
    if (nleave) { /* the parallel statistics: one message per destination, the leaving particles' fields */
      PetscInt   *dests, nd = 0, bs, bytes = 0;
      PetscMPIInt size;
      PetscCallMPI(MPI_Comm_size(comm, &size));
      PetscCall(PetscCalloc1(size, &dests));
      PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
      PetscCall(DMSwarmGetField(s->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rankf));
      for (PetscInt p = 0; p < n; p++)
        if (rankf[p] != rank && !dests[rankf[p]]++) nd++;
      PetscCall(DMSwarmRestoreField(s->swarm, DMSwarmField_rank, NULL, NULL, (void **)&rankf));
      for (size_t f = 0; f < sizeof(FSFieldNames) / sizeof(FSFieldNames[0]); f++) {
        PetscDataType type;
        void         *data;
        PetscCall(DMSwarmGetField(s->swarm, FSFieldNames[f], &bs, &type, &data));
        bytes += bs * (PetscInt)(type == PETSC_INT ? sizeof(PetscInt) : sizeof(PetscReal));
        PetscCall(DMSwarmRestoreField(s->swarm, FSFieldNames[f], &bs, &type, &data));
      }
      bytes += (PetscInt)(sizeof(PetscInt64) + sizeof(PetscInt)); /* DMSwarm's own pid and rank fields */
      s->mon.par.mig_msgs += nd;
      s->mon.par.mig_bytes += (PetscLogDouble)nleave * bytes;
      PetscCall(PetscFree(dests));
    }
    PetscCall(DMSwarmGetSize(s->swarm, &n));
    before = n;
    PetscCall(DMSwarmMigrate(s->swarm, PETSC_TRUE));
    PetscCall(DMSwarmGetSize(s->swarm, &n));
    after = n;
    PetscCheck(before == after, comm, PETSC_ERR_PLIB, "Migration lost %" PetscInt64_FMT " particles", before - after);
    *changed = PETSC_TRUE;
    s->mon.nmigrations++;
  }
  PetscCall(DMSwarmGetLocalSize(s->swarm, &s->pw.nowned));
  PetscCall(PetscLogEventEnd(FS_Migrate, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* FSSolverSortByCell - orders the owned particles by cell (counting sort) so that neighbours are near in memory. */
PetscErrorCode FSSolverSortByCell(FSSolver s)
{
  PetscInt   n, dim = s->opt.dim;
  PetscReal *x;
  char      *tmp;
  size_t     maxbytes = 0;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  if (n < 2) PetscFunctionReturn(0);
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(FSNeighboursBuildCells(&s->pw.nbrs, dim, n, x, dim, s->pw.kernel.support));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  maxbytes = (size_t)n * dim * sizeof(PetscReal);
  PetscCall(PetscMalloc(maxbytes, &tmp));
  for (size_t f = 0; f < sizeof(FSFieldNames) / sizeof(FSFieldNames[0]); f++) {
    PetscInt      bs;
    PetscDataType type;
    char         *data;
    size_t        sz;
    PetscCall(DMSwarmGetField(s->swarm, FSFieldNames[f], &bs, &type, (void **)&data));
    sz = (type == PETSC_INT ? sizeof(PetscInt) : sizeof(PetscReal)) * (size_t)bs;
    for (PetscInt p = 0; p < n; p++) memcpy(tmp + p * sz, data + (size_t)s->pw.nbrs.order[p] * sz, sz);
    memcpy(data, tmp, (size_t)n * sz);
    PetscCall(DMSwarmRestoreField(s->swarm, FSFieldNames[f], &bs, &type, (void **)&data));
  }
  PetscCall(PetscFree(tmp));
  PetscFunctionReturn(0);
}

/* FSSolverEnsureWork - capacity of the record and derived-quantity arrays for n owned + ghost particles. */
PetscErrorCode FSSolverEnsureWork(FSSolver s, PetscInt n)
{
  PetscFunctionBegin;
  if (n <= s->pw.reccap) PetscFunctionReturn(0);
  {
    const PetscInt64 most = PETSC_MAX_INT / s->pw.stride - 1; /* the records are indexed p * stride in PetscInt */
    PetscInt         cap;
    PetscReal       *rec, *aux, *vol, *p;
    PetscCheck(n <= most, PETSC_COMM_SELF, PETSC_ERR_SUP,
               "%" PetscInt_FMT " particles with their ghosts on one rank are more than an index can count in their "
               "records (%" PetscInt_FMT " reals each): use more ranks or a coarser -fs_dx",
               n, s->pw.stride);
    cap = (PetscInt)PetscMax(n, PetscMin(most, (PetscInt64)(1.25 * s->pw.reccap)));
    PetscCall(PetscCalloc4(cap * s->pw.stride, &rec, cap * s->pw.auxstride, &aux, cap, &vol, cap, &p));
    if (s->pw.rec) PetscCall(PetscArraycpy(rec, s->pw.rec, s->pw.reccap * s->pw.stride));
    PetscCall(PetscFree4(s->pw.rec, s->pw.aux, s->pw.vol, s->pw.pressure));
    s->pw.rec      = rec;
    s->pw.aux      = aux;
    s->pw.vol      = vol;
    s->pw.pressure = p;
    s->pw.reccap   = cap;
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverPackState - copies the swarm's fields of the owned particles into the TS state vector
   (per particle: position, velocity, density) and their masses into the work records.
*/
PetscErrorCode FSSolverPackState(FSSolver s)
{
  const PetscInt dim = s->opt.dim, US = s->state.ustride, S = s->pw.stride;
  PetscReal     *x, *v, *rho, *m;
  PetscScalar   *u;

  PetscFunctionBegin;
  PetscCall(FSSolverEnsureWork(s, s->pw.nowned));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(VecGetArray(s->state.U, &u));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    for (PetscInt d = 0; d < dim; d++) {
      u[p * US + d]        = x[p * dim + d];
      u[p * US + dim + d]  = v[p * dim + d];
      s->pw.rec[p * S + d] = x[p * dim + d];
    }
    u[p * US + 2 * dim]            = rho[p];
    s->pw.rec[p * S + 2 * dim]     = rho[p];
    s->pw.rec[p * S + 2 * dim + 1] = m[p];
  }
  PetscCall(VecRestoreArray(s->state.U, &u));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/* FSSolverUnpackState - copies the TS state of the owned particles back into the swarm's fields. */
PetscErrorCode FSSolverUnpackState(FSSolver s)
{
  const PetscInt     dim = s->opt.dim, US = s->state.ustride;
  PetscReal         *x, *v, *rho;
  const PetscScalar *u;

  PetscFunctionBegin;
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(VecGetArrayRead(s->state.U, &u));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    for (PetscInt d = 0; d < dim; d++) {
      x[p * dim + d] = u[p * US + d];
      v[p * dim + d] = u[p * US + dim + d];
    }
    rho[p] = u[p * US + 2 * dim];
  }
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_DENSITY, NULL, NULL, (void **)&rho));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/*
   FSSolverAddLiquidVolume - records a body of liquid a case has filled: its exact volume (from the walls), the
   mass it should have (the integral of its initial density over that volume) and the mass of its lattice before
   the masses were fitted to it. The bodies add up; -fs_view and summary.json report them.

   Logically Collective (the same values on every rank)

   Input Parameters:
+  s            - the solver
.  volume       - the volume (2-D: the area) of the liquid
.  mass         - the mass it should have
-  lattice_mass - the sum of its particles' masses as the lattice gave them

   Level: developer

.seealso: FSSolverGetLiquidVolume(), FSSolverAddParticles()
*/
PetscErrorCode FSSolverAddLiquidVolume(FSSolver s, PetscReal volume, PetscReal mass, PetscReal lattice_mass)
{
  PetscFunctionBegin;
  s->liquid[0] += volume;
  s->liquid[1] += mass;
  s->liquid[2] += lattice_mass;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetLiquidVolume - the liquid the case filled (FSSolverAddLiquidVolume), summed over its bodies: zero in
   the cases that do not record it (the periodic ones).

   Not Collective

   Output Parameters:
+  volume       - the exact volume (2-D: area) of the liquid, or NULL
.  mass         - the mass it should have, or NULL
-  lattice_mass - the lattice's mass before the fit, or NULL

   Level: intermediate

.seealso: FSSolverAddLiquidVolume()
*/
PetscErrorCode FSSolverGetLiquidVolume(FSSolver s, PetscReal *volume, PetscReal *mass, PetscReal *lattice_mass)
{
  PetscFunctionBegin;
  if (volume) *volume = s->liquid[0];
  if (mass) *mass = s->liquid[1];
  if (lattice_mass) *lattice_mass = s->liquid[2];
  PetscFunctionReturn(0);
}
