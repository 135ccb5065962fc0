/*
   The walls inside the solver: per time step, the candidate wall segments of every owned particle,
   the leak check, and the cut of fluid pairs that see each other through a wall (thin baffles);
   per right-hand side, the Shepard factor gamma_i and the facing segments within the support with
   their kernel values, which the wall terms use.
*/
#include "solver/solverimpl.h"
#include "polygonimpl.h"

/* FSSolverSetWalls - gives the solver its walls (the case builds them); the solver owns them after. */
PetscErrorCode FSSolverSetWalls(FSSolver s, FSWalls *w)
{
  PetscFunctionBegin;
  if (!s->wd) PetscCall(PetscNew(&s->wd));
  else PetscCall(FSWallsDestroy(&s->wd->walls));
  s->wd->walls = *w;
  PetscCall(PetscMemzero(w, sizeof(*w)));
  PetscFunctionReturn(0);
}

/*
   FSSolverWallsSetUp - discretizes the walls into segments of about dx, reads the wall options,
   and bins the segments in a static grid.

   Options Database Keys:
+  -fs_walls_noslip <names> - the walls with no-slip conditions (the others are free-slip)
.  -fs_walls_load_point <x,y> - the point about which the wall moments are taken (default: the origin)
-  -fs_walls_visibility <cut|all> - what a particle near the walls interacts with. cut (default): fluid
   pairs whose connecting line crosses a wall are cut, and gamma and the wall terms count only the
   segments that face the particle and are not hidden behind others. all: every fluid pair and every
   segment within the support, far faces and faces turned away included (the exact boundary-integral
   identity for any polygon: no ray through a convex corner bounds the region a particle sees); the
   wall pressure p_k still comes only from the liquid on the side segment k faces, so each face of a
   thin baffle carries its own side's pressure, and the leak check and bounce are the same.
*/
PetscErrorCode FSSolverWallsSetUp(FSSolver s)
{
  FSWallData *wd = s->wd;
  FSWalls    *w;
  MPI_Comm    comm = PetscObjectComm((PetscObject)s);
  char       *names[32];
  PetscInt    nnames = 32, np = 3, vis = 0;
  const char *const visnames[] = {"cut", "all"};
  PetscReal   R;

  PetscFunctionBegin;
  if (!wd) PetscFunctionReturn(0);
  w = &wd->walls;
  PetscCheck(s->dim == 2, comm, PETSC_ERR_SUP, "Walls are two-dimensional (polygons): use -fs_dim 2 with a tank case");
  PetscCall(FSWallsCheck(w, comm));
  PetscCall(FSWallsDiscretize(w, s->dx));
  PetscCall(PetscCalloc1(w->nwalls, &wd->noslip));
  wd->bounce_distance = 0.1;
  wd->restitution     = 1.0;
  PetscCall(PetscCalloc2(6 * w->nwalls, &wd->load, 6 * w->nwalls, &wd->loadsum));
  PetscOptionsBegin(comm, NULL, "Walls (boundary integrals)", "FS");
  PetscCall(PetscOptionsStringArray("-fs_walls_noslip", "Walls with no-slip conditions, by name (the others are free-slip)", "FSSolverWallsSetUp", names, &nnames, NULL));
  PetscCall(PetscOptionsReal("-fs_walls_bounce_distance", "Particles closer to a wall than this (in dx) and moving towards it bounce back (0: never)", "FSSolverWallsBounce", wd->bounce_distance, &wd->bounce_distance, NULL));
  PetscCall(PetscOptionsReal("-fs_walls_bounce_restitution", "Fraction of the normal velocity kept by a bounce (1: elastic)", "FSSolverWallsBounce", wd->restitution, &wd->restitution, NULL));
  PetscCall(PetscOptionsEList("-fs_walls_visibility", "Fluid pairs and wall segments near walls: cut (pairs through walls cut, only facing and unhidden segments) or all (every pair and segment within the support; wall pressure from the facing side)", "FSSolverWallsSetUp", visnames, 2, visnames[0], &vis, NULL));
  PetscCall(PetscOptionsRealArray("-fs_walls_load_point", "Point about which the moments of the wall loads are taken", "FSSolverWallsSetUp", wd->loadpoint, &np, NULL));
  PetscOptionsEnd();
  for (PetscInt k = 0; k < nnames; k++) {
    PetscBool found = PETSC_FALSE;
    for (PetscInt q = 0; q < w->nwalls; q++)
      if (!strcmp(names[k], w->name[q])) {
        wd->noslip[q] = PETSC_TRUE;
        found         = PETSC_TRUE;
      }
    PetscCheck(found, comm, PETSC_ERR_ARG_WRONG, "-fs_walls_noslip names wall \"%s\", which this case does not have", names[k]);
    PetscCall(PetscFree(names[k]));
  }
  /* a segment can hide another from a particle only if the liquid's region is not convex: obstacles, or
     a container with a reflex vertex (a notch, a baffle on the floor) */
  wd->visall    = (PetscBool)(vis == 1);
  wd->occlusion = (PetscBool)(w->npoly > 1);
  for (PetscInt e = w->pstart[0]; e < w->pstart[1] && !wd->occlusion; e++) {
    const PetscInt   n0 = w->pstart[1] - w->pstart[0], a = w->pstart[0] + (e - w->pstart[0] + n0 - 1) % n0, c = w->pstart[0] + (e - w->pstart[0] + 1) % n0;
    const PetscReal *pa = &w->vert[2 * a], *pb = &w->vert[2 * e], *pc = &w->vert[2 * c];
    if ((pb[0] - pa[0]) * (pc[1] - pb[1]) - (pb[1] - pa[1]) * (pc[0] - pb[0]) < 0) wd->occlusion = PETSC_TRUE; /* a right turn of the counter-clockwise outline */
  }
  /* the Shepard factor of the container at each segment (just inside its midpoint): the wall
     pressure's interpolation weights add up to it where the liquid covers the segment */
  PetscCall(PetscMalloc1(w->nseg, &wd->wetfull));
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE];
    const PetscReal  x[2] = {sg[4] - 1e-3 * s->h * sg[6], sg[5] - 1e-3 * s->h * sg[7]};
    PetscReal        grad[2];
    PetscCall(FSWallsShepard(w, s->h, x, PETSC_FALSE, &wd->wetfull[k], grad));
  }
  /* static grid of segments by midpoint, cells as wide as the candidate radius */
  R         = s->kernel.support + s->halo_skin * s->h;
  wd->gcell = R;
  for (PetscInt d = 0; d < 2; d++) {
    wd->glo[d] = w->lo[d] - R;
    wd->gnc[d] = (PetscInt)((w->hi[d] + R - wd->glo[d]) / R) + 1;
  }
  PetscCall(PetscCalloc1(wd->gnc[0] * wd->gnc[1] + 1, &wd->gstart));
  PetscCall(PetscMalloc1(w->nseg, &wd->gseg));
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal *m = &w->seg[k * FS_SEG_STRIDE + 4];
    wd->gstart[(PetscInt)((m[0] - wd->glo[0]) / R) + wd->gnc[0] * (PetscInt)((m[1] - wd->glo[1]) / R) + 1]++;
  }
  for (PetscInt c = 0; c < wd->gnc[0] * wd->gnc[1]; c++) wd->gstart[c + 1] += wd->gstart[c];
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(wd->gnc[0] * wd->gnc[1], &fill));
    PetscCall(PetscArraycpy(fill, wd->gstart, wd->gnc[0] * wd->gnc[1]));
    for (PetscInt k = 0; k < w->nseg; k++) {
      const PetscReal *m = &w->seg[k * FS_SEG_STRIDE + 4];
      wd->gseg[fill[(PetscInt)((m[0] - wd->glo[0]) / R) + wd->gnc[0] * (PetscInt)((m[1] - wd->glo[1]) / R)]++] = k;
    }
    PetscCall(PetscFree(fill));
  }
  PetscFunctionReturn(0);
}

/* does the open segment a-b cross segment s (p0-p1)? */
static inline PetscBool Crosses(const PetscReal a[], const PetscReal b[], const PetscReal *s)
{
  const PetscReal *c = s, *d = s + 2;
  const PetscReal  d1 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
  const PetscReal  d2 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
  const PetscReal  d3 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  const PetscReal  d4 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
  return (PetscBool)(((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)));
}

/*
   FSSolverWallsUpdate - once per step, after the candidate fluid neighbours are built: the candidate
   segments of every owned particle, the leak check (a particle outside the liquid region stops the
   run, naming the step, time, particle and nearest wall), and the removal of fluid candidate pairs
   whose connecting segment crosses a wall.

   Collective
*/
PetscErrorCode FSSolverWallsUpdate(FSSolver s)
{
  FSWallData     *wd = s->wd;
  FSWalls        *w;
  const PetscInt  S = s->stride, n = s->nowned;
  const PetscReal R = s->kernel.support + s->halo_skin * s->h, R2 = R * R;
  PetscInt        nc = 0, leak = -1, leakwall = -1, nleak;
  FSNeighbours   *nb = &s->nbrs;

  PetscFunctionBegin;
  if (!wd) PetscFunctionReturn(0);
  w = &wd->walls;
  if (n + 1 > wd->scap) {
    PetscCall(PetscFree2(wd->cstart, wd->wstart));
    wd->scap = PetscMax(n + 1, (PetscInt)(1.25 * wd->scap));
    PetscCall(PetscMalloc2(wd->scap, &wd->cstart, wd->scap, &wd->wstart));
  }
  for (PetscInt i = 0, wp = 0; i < n; i++) {
    const PetscReal *x = &s->rec[i * S];
    const PetscInt   os = nb->cstart[i], oe = nb->cstart[i + 1]; /* this particle's fluid candidates, before compaction */
    PetscInt         cx = (PetscInt)((x[0] - wd->glo[0]) / R), cy = (PetscInt)((x[1] - wd->glo[1]) / R), first = nc;
    wd->cstart[i] = nc;
    for (PetscInt b = PetscMax(cy - 1, 0); b <= PetscMin(cy + 1, wd->gnc[1] - 1); b++)
      for (PetscInt a = PetscMax(cx - 1, 0); a <= PetscMin(cx + 1, wd->gnc[0] - 1); a++) {
        const PetscInt c = a + wd->gnc[0] * b;
        for (PetscInt q = wd->gstart[c]; q < wd->gstart[c + 1]; q++) {
          const PetscInt k = wd->gseg[q];
          if (FSSegmentDistance2(&w->seg[k * FS_SEG_STRIDE], x) < R2) {
            if (nc == wd->ccap) {
              PetscInt *cand;
              wd->ccap = PetscMax(1024, 2 * wd->ccap);
              PetscCall(PetscMalloc1(wd->ccap, &cand));
              if (nc) PetscCall(PetscArraycpy(cand, wd->cand, nc));
              PetscCall(PetscFree(wd->cand));
              wd->cand = cand;
            }
            wd->cand[nc++] = k;
          }
        }
      }
    nb->cstart[i] = wp;
    if (nc > first) {
      if (leak < 0 && !FSWallsInLiquid(w, x, 0)) {
        PetscReal best = PETSC_MAX_REAL;
        leak = i;
        for (PetscInt q = first; q < nc; q++) {
          PetscReal d2 = FSSegmentDistance2(&w->seg[wd->cand[q] * FS_SEG_STRIDE], x);
          if (d2 < best) {
            best     = d2;
            leakwall = w->segwall[wd->cand[q]];
          }
        }
      }
      /* keep the fluid candidates not seen through a wall (all of them with -fs_walls_visibility all) */
      if (wd->visall)
        for (PetscInt q = os; q < oe; q++) nb->cand[wp++] = nb->cand[q];
      else for (PetscInt q = os; q < oe; q++) {
        const PetscReal *xj  = &s->rec[nb->cand[q] * S];
        PetscBool        cut = PETSC_FALSE;
        for (PetscInt r = first; r < nc && !cut; r++) cut = Crosses(x, xj, &w->seg[wd->cand[r] * FS_SEG_STRIDE]);
        if (!cut) nb->cand[wp++] = nb->cand[q];
      }
      if (wd->occlusion && !wd->visall) { /* drop the segments hidden behind other walls: their shadows lie in those of the nearer ones */
        PetscInt keep = first;
        for (PetscInt q = first; q < nc; q++) {
          const PetscReal *sg = &w->seg[wd->cand[q] * FS_SEG_STRIDE];
          PetscBool        hidden = PETSC_FALSE;
          if ((sg[0] - x[0]) * sg[6] + (sg[1] - x[1]) * sg[7] > 0) /* facing: is its midpoint seen through another segment? */
            for (PetscInt r = first; r < nc && !hidden; r++) hidden = (PetscBool)(r != q && Crosses(x, sg + 4, &w->seg[(wd->cand[r] < 0 ? -1 - wd->cand[r] : wd->cand[r]) * FS_SEG_STRIDE]));
          if (hidden) wd->cand[q] = -1 - wd->cand[q];
        }
        for (PetscInt q = first; q < nc; q++)
          if (wd->cand[q] >= 0) wd->cand[keep++] = wd->cand[q];
        nc = keep;
      }
    } else
      for (PetscInt q = os; q < oe; q++) nb->cand[wp++] = nb->cand[q];
    if (i == n - 1) {
      nb->cstart[n] = wp;
      nb->ncand     = wp;
    }
  }
  wd->cstart[n] = nc;
  nleak         = leak >= 0 ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &nleak, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)s)));
  if (leak >= 0) {
    PetscInt  step = 0, *id;
    PetscReal t    = 0;
    if (s->ts) {
      PetscCall(TSGetTime(s->ts, &t));
      PetscCall(TSGetStepNumber(s->ts, &step));
    }
    PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "[flexslosh] leak: particle %" PetscInt_FMT " crossed wall \"%s\" at step %" PetscInt_FMT ", time %g: it is at (%g, %g), outside the liquid region\n", id[leak], w->name[leakwall], step, (double)t, (double)s->rec[leak * S], (double)s->rec[leak * S + 1]));
    PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_ID, NULL, NULL, (void **)&id));
  }
  PetscCheck(!nleak, PetscObjectComm((PetscObject)s), PETSC_ERR_CONV_FAILED, "Particles crossed a wall on %" PetscInt_FMT " rank(s) (the particle, wall, step and time are named above): reduce -fs_cfl or refine -fs_dx", nleak);
  PetscFunctionReturn(0);
}

/*
   FSSolverWallsPrepare - at every right-hand side: gamma_i of every owned particle near a wall (1
   elsewhere) and its facing segments within the support with their mean kernel values (int_k W dS / s_k);
   with -fs_walls_visibility all every segment within the support, with the signed gamma_k.
*/
PetscErrorCode FSSolverWallsPrepare(FSSolver s)
{
  FSWallData     *wd = s->wd;
  FSWalls        *w;
  const PetscInt  S = s->stride, n = s->nowned;
  const PetscReal h = s->h;
  PetscInt        nw = 0;

  PetscFunctionBegin;
  if (!wd) PetscFunctionReturn(0);
  w = &wd->walls;
  if (s->reccap > wd->gcap) { /* gamma of the owned and ghost particles */
    PetscCall(PetscFree2(wd->gamma, wd->invgamma));
    wd->gcap = s->reccap;
    PetscCall(PetscMalloc2(wd->gcap, &wd->gamma, wd->gcap, &wd->invgamma));
  }
  if (wd->cstart[n] > wd->wcap) {
    PetscCall(PetscFree2(wd->wnbr, wd->wW));
    wd->wcap = PetscMax(wd->cstart[n], 2 * wd->wcap);
    PetscCall(PetscMalloc2(wd->wcap, &wd->wnbr, wd->wcap, &wd->wW));
  }
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *x = &s->rec[i * S];
    PetscReal        g = 1;
    wd->wstart[i]      = nw;
    for (PetscInt q = wd->cstart[i]; q < wd->cstart[i + 1]; q++) {
      const PetscInt   k  = wd->cand[q];
      const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE];
      PetscReal        gk, wi;
      FSSegmentIntegrals(h, x, sg, wd->visall, &gk, &wi); /* zero for a segment facing away, unless visall */
      g += gk;
      if (wi > 0) {
        wd->wnbr[nw] = k;
        wd->wW[nw]   = wi / sg[8]; /* the segment's mean kernel value: wW s_k = int_k W dS */
        nw++;
      }
    }
    wd->gamma[i] = g;
  }
  wd->wstart[n] = nw;
  PetscCall(PetscArrayzero(wd->load, 6 * w->nwalls));
  /* wall pressure: p_k = sum_i (p_i + rho_i g.(x_k - x_i)) W_ik V_i / sum_i W_ik V_i over the liquid near
     segment k (all ranks), so that a particle pressed against a wall meets a wall pressure set by its
     neighbours as well as by itself; g is the body acceleration of the tank's frame (s->body: gravity,
     and with a coupling the motion predicted for this stage). Below the ambient pressure p_b
     (-fs_background_pressure, 0) p_k counts with the square of the segment's wetted share
     c_k = min(1, sum_i W_ik V_i / gamma_k) (gamma_k: the container's Shepard factor there): the
     hydrostatic correction extrapolates the liquid's pressure to the dry wall above a free surface,
     where it would suck (the side walls' load 16 % short at H/dx = 10, and a pull on the top particles
     towards them); a covered wall keeps its tension */
  if (!wd->wp) PetscCall(PetscMalloc1(3 * w->nseg + 1, &wd->wp));
  PetscCall(PetscArrayzero(wd->wp, 3 * w->nseg));
  {
    PetscReal *num = wd->wp + w->nseg, *den = num + w->nseg;
    for (PetscInt i = 0; i < n; i++) {
      const PetscReal *x = &s->rec[i * S], rho = x[2 * s->dim];
      for (PetscInt q = wd->wstart[i]; q < wd->wstart[i + 1]; q++) {
        const PetscInt   k  = wd->wnbr[q];
        const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE];
        const PetscReal  wv = wd->wW[q] * s->vol[i];
        const PetscReal  mid[2] = {0.5 * (sg[4] + x[0]), 0.5 * (sg[5] + x[1])};
        PetscReal        g[2];
        if (wd->visall && (sg[0] - x[0]) * sg[6] + (sg[1] - x[1]) * sg[7] <= 0) continue; /* p_k from the side the segment faces (the lists hold only such segments otherwise) */
        FSFrameFieldEval(&s->body, mid, g);
        num[k] += (s->pressure[i] + rho * (g[0] * (sg[4] - x[0]) + g[1] * (sg[5] - x[1]))) * wv;
        den[k] += wv;
      }
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, num, (PetscMPIInt)(2 * w->nseg), MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
    for (PetscInt k = 0; k < w->nseg; k++) {
      const PetscReal pamb = s->background_pressure;
      PetscReal       pk   = den[k] > 0 ? num[k] / den[k] : pamb;
      if (pk < pamb) {
        const PetscReal c = PetscMin(1.0, den[k] / wd->wetfull[k]);
        pk = pamb + (pk - pamb) * c * c;
      }
      wd->wp[k] = pk;
    }
  }
  /* the pressure loads on the walls, the integral of p_k n_k over the segments (rank 0's share: every
     rank knows every wall pressure) */
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
    if (!rank)
      for (PetscInt k = 0; k < w->nseg; k++) {
        const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE], f = wd->wp[k] * sg[8];
        PetscReal       *L  = &wd->load[6 * w->segwall[k]];
        L[0] += f * sg[6];
        L[1] += f * sg[7];
        L[5] += f * ((sg[4] - wd->loadpoint[0]) * sg[7] - (sg[5] - wd->loadpoint[1]) * sg[6]);
      }
  }
  /* the ghosts' gamma, for the symmetric (dissipative) viscous terms */
  for (PetscInt g = 0; g < s->halo.nghost; g++) wd->gamma[n + g] = 1;
  PetscCall(FSHaloRefreshScalar(&s->halo, wd->gamma));
  for (PetscInt k = 0; k < n + s->halo.nghost; k++) wd->invgamma[k] = 1.0 / wd->gamma[k];
  PetscFunctionReturn(0);
}

/*
   FSSolverWallsBounce - after each step, a particle closer to a wall than -fs_walls_bounce_distance
   (in units of dx, 0.1 by default) and moving towards it is put back at that distance and its normal
   velocity reversed, scaled by -fs_walls_bounce_restitution (1: elastic). The boundary integrals push
   particles away from walls in proportion to the pressure, which vanishes at free surfaces and under
   lids: this keeps such particles from crossing (the "elastic bounce" of AQUAgpusph's boundary
   integrals). The count of bounces is kept for the summary; de returns this rank's change of the
   liquid's mechanical energy (tank frame, absolute frame) for the energy budget (FSSolverEnergyAddJump).

   Not collective
*/
PetscErrorCode FSSolverWallsBounce(FSSolver s, PetscReal de[2])
{
  FSWallData   *wd = s->wd;
  FSWalls      *w;
  PetscReal    *x, *v, *m, dmin;
  PetscInt      n;
  FSEnergyFrame fr;

  PetscFunctionBegin;
  de[0] = de[1] = 0;
  if (!wd || wd->bounce_distance <= 0) PetscFunctionReturn(0);
  w    = &wd->walls;
  dmin = wd->bounce_distance * s->dx;
  PetscCall(FSSolverEnergyJumpFrame(s, &fr));
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  for (PetscInt i = 0; i < n; i++) {
    PetscReal      *xi = &x[2 * i], *vi = &v[2 * i];
    const PetscInt  cx = (PetscInt)((xi[0] - wd->glo[0]) / wd->gcell), cy = (PetscInt)((xi[1] - wd->glo[1]) / wd->gcell);
    if (cx < 0 || cy < 0 || cx >= wd->gnc[0] || cy >= wd->gnc[1]) continue;
    for (PetscInt b = PetscMax(cy - 1, 0); b <= PetscMin(cy + 1, wd->gnc[1] - 1); b++)
      for (PetscInt a = PetscMax(cx - 1, 0); a <= PetscMin(cx + 1, wd->gnc[0] - 1); a++) {
        const PetscInt c = a + wd->gnc[0] * b;
        for (PetscInt q = wd->gstart[c]; q < wd->gstart[c + 1]; q++) {
          const PetscReal *sg = &w->seg[wd->gseg[q] * FS_SEG_STRIDE];
          const PetscReal  d  = (sg[0] - xi[0]) * sg[6] + (sg[1] - xi[1]) * sg[7]; /* distance to the segment's line, > 0 on the liquid side */
          const PetscReal  t  = ((xi[0] - sg[0]) * (sg[2] - sg[0]) + (xi[1] - sg[1]) * (sg[3] - sg[1])) / (sg[8] * sg[8]);
          const PetscReal  un = vi[0] * sg[6] + vi[1] * sg[7];
          if (d < dmin && d > -dmin && t >= 0 && t <= 1 && un > 0) {
            PetscReal e0[2], e1[2];
            FSEnergyParticle(s, &fr, xi, vi, m[i], e0);
            xi[0] -= (dmin - d) * sg[6];
            xi[1] -= (dmin - d) * sg[7];
            vi[0] -= (1 + wd->restitution) * un * sg[6];
            vi[1] -= (1 + wd->restitution) * un * sg[7];
            FSEnergyParticle(s, &fr, xi, vi, m[i], e1);
            de[0] += e1[0] - e0[0];
            de[1] += e1[1] - e0[1];
            wd->nbounce++;
          }
        }
      }
  }
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscFunctionReturn(0);
}

/* FSSolverWallsGetLoads - the loads of the liquid on each wall (force 3, moment 3), summed over the ranks. Collective. */
PetscErrorCode FSSolverWallsGetLoads(FSSolver s, const PetscReal **loads)
{
  PetscFunctionBegin;
  *loads = NULL;
  if (!s->wd) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Allreduce(s->wd->load, s->wd->loadsum, (PetscMPIInt)(6 * s->wd->walls.nwalls), MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  *loads = s->wd->loadsum;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetWallLoads - the liquid's load on each wall from the last right-hand side evaluation (the
   values of the wall_<name>_* columns of timeseries.csv), summed over the ranks, on every rank.

   Collective (not collective when loads is NULL)

   Input Parameter:
.  s - the solver

   Output Parameters:
+  nwalls - the number of walls (0 in a case without walls)
.  names  - the walls' names (an array of nwalls pointers into the solver, or NULL)
-  loads  - per wall: the force (3) and the moment (3) about -fs_walls_load_point, 6 nwalls values
            that stay valid until the next right-hand side (NULL without walls), or NULL

   Notes:
   After a step the last right-hand side is the integrator's last stage; FSSolverGetField() for a
   derived field evaluates one at the current state.

.seealso: FSSolverGetField(), FSSolverSetUp()
*/
PetscErrorCode FSSolverGetWallLoads(FSSolver s, PetscInt *nwalls, const char *names[], const PetscReal *loads[])
{
  PetscFunctionBegin;
  *nwalls = s->wd ? s->wd->walls.nwalls : 0;
  if (names)
    for (PetscInt w = 0; w < *nwalls; w++) names[w] = s->wd->walls.name[w];
  if (loads) PetscCall(FSSolverWallsGetLoads(s, loads));
  PetscFunctionReturn(0);
}

PetscErrorCode FSSolverWallsDestroy(FSSolver s)
{
  FSWallData *wd = s->wd;

  PetscFunctionBegin;
  if (!wd) PetscFunctionReturn(0);
  PetscCall(FSWallsDestroy(&wd->walls));
  PetscCall(PetscFree(wd->noslip));
  PetscCall(PetscFree2(wd->load, wd->loadsum));
  PetscCall(PetscFree(wd->gstart));
  PetscCall(PetscFree(wd->gseg));
  PetscCall(PetscFree2(wd->cstart, wd->wstart));
  PetscCall(PetscFree(wd->cand));
  PetscCall(PetscFree2(wd->wnbr, wd->wW));
  PetscCall(PetscFree2(wd->gamma, wd->invgamma));
  PetscCall(PetscFree(wd->wp));
  PetscCall(PetscFree(wd->wetfull));
  PetscCall(PetscFree(s->wd));
  PetscFunctionReturn(0);
}
