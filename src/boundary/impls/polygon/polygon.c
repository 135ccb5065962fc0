/*
   The polygon boundary ("polygon"): 2-D boundary integrals on closed polygons of named walls. Per time
   step, the candidate wall segments of every owned particle, the leak check, and the cut of fluid pairs
   that see each other through a wall (thin baffles); per right-hand side, the Shepard factor gamma_i
   and the facing segments within the support with their kernel values, which the wall terms use, and
   the wall pressure. The geometry (walls.h: polygons, segments, gamma of a point) is in geometry.c and
   shepard.c, the picture and ParaView files in geometryview.c.
*/
#include "polygonimpl.h"

static PetscErrorCode FSBoundaryPolygonSetWalls_Polygon(FSBoundary b, FSWalls *w)
{
  FSBoundary_Polygon *pg = (FSBoundary_Polygon *)b->data;

  PetscFunctionBegin;
  PetscCall(FSWallsDestroy(&pg->walls));
  pg->walls = *w;
  PetscCall(PetscMemzero(w, sizeof(*w)));
  PetscFunctionReturn(0);
}

/*
   FSBoundaryPolygonSetWalls - gives a polygon boundary its walls (the case builds them); the boundary
   owns them after, and w is zeroed.

   Collective
*/
PetscErrorCode FSBoundaryPolygonSetWalls(FSBoundary b, FSWalls *w)
{
  PetscFunctionBegin;
  PetscUseMethod(b, "FSBoundaryPolygonSetWalls_C", (FSBoundary, FSWalls *), (b, w));
  PetscFunctionReturn(0);
}

/* SetUp - discretizes the walls into segments of about dx and bins them in a static grid */
static PetscErrorCode SetUp(FSBoundary b)
{
  FSBoundary_Polygon *wd   = (FSBoundary_Polygon *)b->data;
  FSWalls            *w    = &wd->walls;
  MPI_Comm            comm = PetscObjectComm((PetscObject)b);
  PetscReal           R;

  PetscFunctionBegin;
  PetscCheck(b->dim == 2, comm, PETSC_ERR_SUP, "Walls are two-dimensional (polygons): use -fs_dim 2 with a tank case");
  PetscCall(FSWallsCheck(w, comm));
  PetscCall(FSWallsDiscretize(w, b->dx));
  PetscCall(PetscMalloc1(w->nwalls, &wd->names));
  for (PetscInt q = 0; q < w->nwalls; q++) wd->names[q] = w->name[q];
  b->nwalls           = w->nwalls;
  b->wallname         = wd->names;
  b->view.nelements   = w->nseg;
  b->view.stride      = FS_SEG_STRIDE;
  b->view.vertex      = FS_SEG_P0;
  b->view.centroid    = FS_SEG_MID;
  b->view.normal      = FS_SEG_NORMAL;
  b->view.measure     = FS_SEG_LENGTH;
  b->view.element     = w->seg;
  b->view.elementwall = w->segwall;
  /* a segment can hide another from a particle only if the liquid's region is not convex: obstacles, or
     a container with a reflex vertex (a notch, a baffle on the floor) */
  wd->occlusion = (PetscBool)(w->npoly > 1);
  for (PetscInt e = w->pstart[0]; e < w->pstart[1] && !wd->occlusion; e++) {
    const PetscInt n0 = w->pstart[1] - w->pstart[0], a = w->pstart[0] + (e - w->pstart[0] + n0 - 1) % n0,
                   c    = w->pstart[0] + (e - w->pstart[0] + 1) % n0;
    const PetscReal *pa = &w->vert[2 * a], *pb = &w->vert[2 * e], *pc = &w->vert[2 * c];
    if ((pb[0] - pa[0]) * (pc[1] - pb[1]) - (pb[1] - pa[1]) * (pc[0] - pb[0]) < 0)
      wd->occlusion = PETSC_TRUE; /* a right turn of the counter-clockwise outline */
  }
  /* the Shepard factor of the container at each segment (just inside its midpoint): the wall
     pressure's interpolation weights add up to it where the liquid covers the segment */
  PetscCall(PetscMalloc1(w->nseg, &wd->wetfull));
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal *sg   = &w->seg[k * FS_SEG_STRIDE];
    const PetscReal  x[2] = {sg[FS_SEG_MID] - 1e-3 * b->h * sg[FS_SEG_NORMAL],
                             sg[FS_SEG_MID + 1] - 1e-3 * b->h * sg[FS_SEG_NORMAL + 1]};
    PetscReal        grad[2];
    PetscCall(FSWallsShepard(w, b->h, x, PETSC_FALSE, &wd->wetfull[k], grad));
  }
  /* static grid of segments by midpoint, cells as wide as the candidate radius */
  R         = b->radius;
  wd->gcell = R;
  for (PetscInt d = 0; d < 2; d++) {
    wd->glo[d] = w->lo[d] - R;
    wd->gnc[d] = (PetscInt)((w->hi[d] + R - wd->glo[d]) / R) + 1;
  }
  PetscCall(PetscCalloc1(wd->gnc[0] * wd->gnc[1] + 1, &wd->gstart));
  PetscCall(PetscMalloc1(w->nseg, &wd->gseg));
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal *m = &w->seg[k * FS_SEG_STRIDE + FS_SEG_MID];
    wd->gstart[(PetscInt)((m[0] - wd->glo[0]) / R) + wd->gnc[0] * (PetscInt)((m[1] - wd->glo[1]) / R) + 1]++;
  }
  for (PetscInt c = 0; c < wd->gnc[0] * wd->gnc[1]; c++) wd->gstart[c + 1] += wd->gstart[c];
  {
    PetscInt *fill;
    PetscCall(PetscMalloc1(wd->gnc[0] * wd->gnc[1], &fill));
    PetscCall(PetscArraycpy(fill, wd->gstart, wd->gnc[0] * wd->gnc[1]));
    for (PetscInt k = 0; k < w->nseg; k++) {
      const PetscReal *m = &w->seg[k * FS_SEG_STRIDE + FS_SEG_MID];
      wd->gseg[fill[(PetscInt)((m[0] - wd->glo[0]) / R) + wd->gnc[0] * (PetscInt)((m[1] - wd->glo[1]) / R)]++] = k;
    }
    PetscCall(PetscFree(fill));
  }
  PetscFunctionReturn(0);
}

/* does the open segment a-b cross segment s (p0-p1)? */
static inline PetscBool Crosses(const PetscReal a[], const PetscReal b[], const PetscReal *s)
{
  const PetscReal *c = s + FS_SEG_P0, *d = s + FS_SEG_P1;
  const PetscReal  d1 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
  const PetscReal  d2 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
  const PetscReal  d3 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  const PetscReal  d4 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
  return (PetscBool)(((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)));
}

/* a candidate entry's segment: during Update a segment out of reach or hidden is listed as -1 - k until the
   particle's entries are compacted */
static inline PetscInt CandSegment(PetscInt c) { return c < 0 ? -1 - c : c; }

/*
   Update - once per step, after the candidate fluid neighbours are built: the candidate segments of
   every owned particle, the leak check (the first particle outside the liquid region, with the wall
   nearest to it), and the removal of fluid candidate pairs whose connecting segment crosses a wall.
   The leak check and the cuts see every segment within the candidate radius; a particle keeps those
   within reach (b->reach) that it can face before the lists are rebuilt.
*/
static PetscErrorCode Update(FSBoundary b, PetscInt n, const PetscReal rec[], PetscInt S, FSNeighbours *nb,
                             FSBoundaryLeak *lk)
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;
  FSWalls            *w  = &wd->walls;
  const PetscReal     R = b->radius, R2 = R * R, Rk2 = b->reach * b->reach, slack = b->reach - 2 * b->h;
  PetscInt            nc = 0, leak = -1, leakwall = -1, leakseg = -1;

  PetscFunctionBegin;
  if (n + 1 > wd->scap) {
    PetscCall(PetscFree2(wd->cstart, b->wstart));
    wd->scap = PetscMax(n + 1, (PetscInt)(1.25 * wd->scap));
    PetscCall(PetscMalloc2(wd->scap, &wd->cstart, wd->scap, &b->wstart));
  }
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal *x  = &rec[i * S];
    PetscInt         cx = (PetscInt)((x[0] - wd->glo[0]) / R), cy = (PetscInt)((x[1] - wd->glo[1]) / R), first = nc;
    wd->cstart[i] = nc;
    for (PetscInt cb = PetscMax(cy - 1, 0); cb <= PetscMin(cy + 1, wd->gnc[1] - 1); cb++)
      for (PetscInt ca = PetscMax(cx - 1, 0); ca <= PetscMin(cx + 1, wd->gnc[0] - 1); ca++) {
        const PetscInt c = ca + wd->gnc[0] * cb;
        for (PetscInt q = wd->gstart[c]; q < wd->gstart[c + 1]; q++) {
          const PetscInt   k  = wd->gseg[q];
          const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE], d2 = FSSegmentDistance2(sg, x);
          if (d2 < R2) {
            const PetscReal ds = (sg[FS_SEG_P0] - x[0]) * sg[FS_SEG_NORMAL] +
                                 (sg[FS_SEG_P0 + 1] - x[1]) * sg[FS_SEG_NORMAL + 1]; /* > 0: facing */
            /* kept: within reach and, unless visibility all, not so far behind its line that x cannot face it
               before the rebuild (FSSegmentIntegrals gives such a segment 0) */
            const PetscBool keep = (PetscBool)(d2 < Rk2 && (b->visall || ds > -slack));
            PetscCall(FSBoundaryListRoom_Private(sizeof(PetscInt), nc, &wd->ccap, &wd->cand));
            wd->cand[nc++] = keep ? k : -1 - k;
          }
        }
      }
    if (nc > first) {
      if (leak < 0 && !FSWallsInLiquid(w, x, 0)) {
        PetscReal best = PETSC_MAX_REAL;
        leak           = i;
        for (PetscInt q = first; q < nc; q++) {
          const PetscInt  k  = CandSegment(wd->cand[q]);
          const PetscReal d2 = FSSegmentDistance2(&w->seg[k * FS_SEG_STRIDE], x);
          if (d2 < best) {
            best     = d2;
            leakwall = w->segwall[k];
            leakseg  = k;
          }
        }
      }
      /* drop the fluid candidates seen through a wall (none with -fs_walls_visibility all) */
      if (!b->visall) {
        FSCandidateIter it;
        PetscInt        j;
        FSNeighboursCandidateBegin(nb, i, &it);
        while (FSNeighboursCandidateNext(nb, &it, &j)) {
          const PetscReal *xj  = &rec[j * S];
          PetscBool        cut = PETSC_FALSE;
          for (PetscInt r = first; r < nc && !cut; r++)
            cut = Crosses(x, xj, &w->seg[CandSegment(wd->cand[r]) * FS_SEG_STRIDE]);
          if (cut) FSNeighboursCandidateDrop(nb, &it);
        }
      }
      if (wd->occlusion && !b->visall) /* mark the segments hidden behind other walls: their shadows lie in those of
                                           the nearer ones */
        for (PetscInt q = first; q < nc; q++) {
          const PetscReal *sg     = &w->seg[CandSegment(wd->cand[q]) * FS_SEG_STRIDE];
          PetscBool        hidden = PETSC_FALSE;
          if (wd->cand[q] >= 0 &&
              (sg[FS_SEG_P0] - x[0]) * sg[FS_SEG_NORMAL] + (sg[FS_SEG_P0 + 1] - x[1]) * sg[FS_SEG_NORMAL + 1] >
                  0) /* facing: is its midpoint seen through another segment? */
            for (PetscInt r = first; r < nc && !hidden; r++)
              hidden = (PetscBool)(r != q &&
                                   Crosses(x, sg + FS_SEG_MID, &w->seg[CandSegment(wd->cand[r]) * FS_SEG_STRIDE]));
          if (hidden) wd->cand[q] = -1 - wd->cand[q];
        }
      { /* keep the segments within reach and not hidden */
        PetscInt keep = first;
        for (PetscInt q = first; q < nc; q++)
          if (wd->cand[q] >= 0) wd->cand[keep++] = wd->cand[q];
        nc = keep;
      }
    }
  }
  wd->cstart[n] = nc;
  PetscCall(FSBoundaryListFit_Private(sizeof(PetscInt), nc, &wd->ccap, &wd->cand));
  lk->particle = leak;
  lk->wall     = leakwall;
  lk->element  = leakseg;
  PetscFunctionReturn(0);
}

/*
   Prepare - at every right-hand side: gamma_i of every owned particle near a wall (1 elsewhere) and
   its facing segments within the support with their mean kernel values (int_k W dS / s_k); with
   -fs_walls_visibility all every segment within the support, with the signed gamma_k; the share of the
   support behind no-slip segments (-sum of their gamma_k) into noslip[i] when given. Then this rank's
   sums of the wall pressure, sent on their way (FSBoundaryWallPressureBegin; FSBoundaryPrepareEnd makes the
   pressure and the loads).
*/
static PetscErrorCode Prepare(FSBoundary b, const FSBoundaryParticles *P, PetscReal gamma[], PetscReal noslip[])
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;
  FSWalls            *w  = &wd->walls;
  const PetscInt      S = P->stride, n = P->nowned;
  const PetscReal     h  = b->h;
  PetscInt            nw = 0;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < n; i++) {
    FSCommProgress(i); /* the ghosts' records travel meanwhile (FSSolverEvaluateRates) */
    const PetscReal *x = &P->rec[i * S];
    PetscReal        g = 1, gn = 0;
    b->wstart[i] = nw;
    for (PetscInt q = wd->cstart[i]; q < wd->cstart[i + 1]; q++) {
      const PetscInt   k  = wd->cand[q];
      const PetscReal *sg = &w->seg[k * FS_SEG_STRIDE];
      PetscReal        gk, wi;
      FSSegmentIntegrals(h, x, sg, b->visall, &gk, &wi); /* zero for a segment facing away, unless visall */
      g += gk;
      if (b->noslip[b->view.elementwall[k]] && gk < 0) gn -= gk; /* the shadows the no-slip term fills */
      if (wi > 0) {
        PetscCall(FSBoundaryWallListsRoom_Private(b, nw));
        b->wk[nw] = k;
        b->wW[nw] = wi / sg[FS_SEG_LENGTH]; /* the segment's mean kernel value: wW s_k = int_k W dS */
        nw++;
      }
    }
    gamma[i] = g;
    if (noslip) noslip[i] = gn;
  }
  b->wstart[n] = nw;
  PetscCall(FSBoundaryWallListsFit_Private(b, nw));
  /* wall pressure: p_k = sum_i (p_i + rho_i g.(x_k - x_i)) W_ik V_i / sum_i W_ik V_i over the liquid near
     segment k (all ranks), so that a particle pressed against a wall meets a wall pressure set by its
     neighbours as well as by itself; g is the body acceleration of the tank's frame (P->body: gravity,
     and with a coupling the motion predicted for this stage). Below the ambient pressure p_b
     (-fs_background_pressure, 0) p_k counts with the square of the segment's wetted share
     c_k = min(1, sum_i W_ik V_i / gamma_k) (gamma_k: the container's Shepard factor there): the
     hydrostatic correction extrapolates the liquid's pressure to the dry wall above a free surface,
     where it would suck (docs/decisions.md); a covered wall keeps its tension */
  if (!wd->wp) PetscCall(PetscMalloc1(3 * w->nseg + 1, &wd->wp));
  PetscCall(PetscArrayzero(wd->wp, 3 * w->nseg));
  {
    PetscReal *num = wd->wp + w->nseg, *den = num + w->nseg;
    for (PetscInt i = 0; i < n; i++) {
      FSCommProgress(i);
      const PetscReal *x = &P->rec[i * S], rho = x[2 * P->dim];
      for (PetscInt q = b->wstart[i]; q < b->wstart[i + 1]; q++) {
        const PetscInt   k      = b->wk[q];
        const PetscReal *sg     = &w->seg[k * FS_SEG_STRIDE];
        const PetscReal  wv     = b->wW[q] * P->vol[i];
        const PetscReal  mid[2] = {0.5 * (sg[FS_SEG_MID] + x[0]), 0.5 * (sg[FS_SEG_MID + 1] + x[1])};
        PetscReal        g[2];
        if (b->visall &&
            (sg[FS_SEG_P0] - x[0]) * sg[FS_SEG_NORMAL] + (sg[FS_SEG_P0 + 1] - x[1]) * sg[FS_SEG_NORMAL + 1] <= 0)
          continue; /* p_k from the side the segment faces (the lists hold only such segments otherwise) */
        FSFrameFieldEval(P->body, mid, g);
        num[k] += (P->pressure[i] + rho * (g[0] * (sg[FS_SEG_MID] - x[0]) + g[1] * (sg[FS_SEG_MID + 1] - x[1]))) * wv;
        den[k] += wv;
      }
    }
    PetscCall(FSBoundaryWallPressureBegin(b, w->nseg, wd->wetfull, P->background_pressure, wd->wp));
  }
  PetscFunctionReturn(0);
}

/*
   Bounce - a particle closer to a wall than -fs_walls_bounce_distance (in units of dx) and moving
   towards it is put back at that distance and its normal velocity reversed, scaled by
   -fs_walls_bounce_restitution (1: elastic). The boundary integrals push particles away from walls in
   proportion to the pressure, which vanishes at free surfaces and under lids: this keeps such
   particles from crossing (the "elastic bounce" of AQUAgpusph's boundary integrals).
*/
static PetscErrorCode Bounce(FSBoundary b, PetscInt n, PetscReal x[], PetscReal v[], const PetscReal m[],
                             FSParticleEnergyFn energy, void *ctx, PetscReal de[2])
{
  FSBoundary_Polygon *wd   = (FSBoundary_Polygon *)b->data;
  FSWalls            *w    = &wd->walls;
  const PetscReal     dmin = b->bounce_distance * b->dx;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < n; i++) {
    PetscReal     *xi = &x[2 * i], *vi = &v[2 * i];
    const PetscInt cx = (PetscInt)((xi[0] - wd->glo[0]) / wd->gcell), cy = (PetscInt)((xi[1] - wd->glo[1]) / wd->gcell);
    if (cx < 0 || cy < 0 || cx >= wd->gnc[0] || cy >= wd->gnc[1]) continue;
    for (PetscInt cb = PetscMax(cy - 1, 0); cb <= PetscMin(cy + 1, wd->gnc[1] - 1); cb++)
      for (PetscInt ca = PetscMax(cx - 1, 0); ca <= PetscMin(cx + 1, wd->gnc[0] - 1); ca++) {
        const PetscInt c = ca + wd->gnc[0] * cb;
        for (PetscInt q = wd->gstart[c]; q < wd->gstart[c + 1]; q++) {
          const PetscReal *sg = &w->seg[wd->gseg[q] * FS_SEG_STRIDE];
          const PetscReal  d  = (sg[FS_SEG_P0] - xi[0]) * sg[FS_SEG_NORMAL] +
                              (sg[FS_SEG_P0 + 1] - xi[1]) *
                                  sg[FS_SEG_NORMAL + 1]; /* distance to the segment's line, > 0 on the liquid side */
          const PetscReal t = ((xi[0] - sg[FS_SEG_P0]) * (sg[FS_SEG_P1] - sg[FS_SEG_P0]) +
                               (xi[1] - sg[FS_SEG_P0 + 1]) * (sg[FS_SEG_P1 + 1] - sg[FS_SEG_P0 + 1])) /
                              (sg[FS_SEG_LENGTH] * sg[FS_SEG_LENGTH]);
          const PetscReal un = vi[0] * sg[FS_SEG_NORMAL] + vi[1] * sg[FS_SEG_NORMAL + 1];
          if (d < dmin && d > -dmin && t >= 0 && t <= 1 && un > 0)
            FSBoundaryBounceParticle(b, sg + FS_SEG_NORMAL, d, un, xi, vi, m[i], energy, ctx, de);
        }
      }
  }
  PetscFunctionReturn(0);
}

/* gamma at a point (FSBoundaryShepardAt) from the segments in the static grid's cells around it: a
   segment within the support 2h of x has its midpoint within the candidate radius (the cell size) */
static PetscErrorCode ShepardAt(FSBoundary b, const PetscReal x[], PetscReal *gamma)
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;
  const PetscInt      cx = (PetscInt)PetscFloorReal((x[0] - wd->glo[0]) / wd->gcell),
                 cy      = (PetscInt)PetscFloorReal((x[1] - wd->glo[1]) / wd->gcell);

  PetscFunctionBegin;
  *gamma = 1;
  if (cx < 0 || cy < 0 || cx >= wd->gnc[0] || cy >= wd->gnc[1]) PetscFunctionReturn(0); /* farther than 2h */
  for (PetscInt cb = PetscMax(cy - 1, 0); cb <= PetscMin(cy + 1, wd->gnc[1] - 1); cb++)
    for (PetscInt ca = PetscMax(cx - 1, 0); ca <= PetscMin(cx + 1, wd->gnc[0] - 1); ca++) {
      const PetscInt c = ca + wd->gnc[0] * cb;
      for (PetscInt q = wd->gstart[c]; q < wd->gstart[c + 1]; q++) {
        PetscReal gk, wi;
        FSSegmentIntegrals(b->h, x, &wd->walls.seg[wd->gseg[q] * FS_SEG_STRIDE], b->visall, &gk, &wi);
        *gamma += gk;
      }
    }
  PetscFunctionReturn(0);
}

/* Locate - in the liquid region (the container polygon, outside the obstacles), the nearest segment's wall */
static PetscErrorCode Locate(FSBoundary b, const PetscReal x[], PetscBool *inliquid, PetscInt *wall,
                             PetscReal *distance)
{
  const FSWalls *w    = &((FSBoundary_Polygon *)b->data)->walls;
  PetscReal      best = PETSC_MAX_REAL;

  PetscFunctionBegin;
  *inliquid = FSWallsInLiquid(w, x, 0);
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal d2 = FSSegmentDistance2(&w->seg[k * FS_SEG_STRIDE], x);
    if (d2 < best) {
      best  = d2;
      *wall = w->segwall[k];
    }
  }
  *distance = PetscSqrtReal(best);
  PetscFunctionReturn(0);
}

static PetscErrorCode BoundingBox(FSBoundary b, PetscReal lo[], PetscReal hi[])
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;

  PetscFunctionBegin;
  for (PetscInt d = 0; d < 2; d++) {
    lo[d] = wd->walls.lo[d];
    hi[d] = wd->walls.hi[d];
  }
  PetscFunctionReturn(0);
}

/* Hash - the polygons as given: their vertices, their walls and each edge's wall */
static PetscErrorCode Hash(FSBoundary b, uint64_t *h)
{
  FSWalls *w = &((FSBoundary_Polygon *)b->data)->walls;

  PetscFunctionBegin;
  FSBoundaryHashAdd_Private(h, &w->npoly, sizeof(w->npoly));
  FSBoundaryHashAdd_Private(h, w->pstart, (size_t)(w->npoly + 1) * sizeof(PetscInt));
  FSBoundaryHashAdd_Private(h, w->pwall, (size_t)w->npoly * sizeof(PetscInt));
  FSBoundaryHashAdd_Private(h, w->vwall, (size_t)w->nvert * sizeof(PetscInt));
  FSBoundaryHashAdd_Private(h, w->vert, (size_t)(2 * w->nvert) * sizeof(PetscReal));
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSBoundary b, PetscViewer viewer)
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;

  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "%" PetscInt_FMT " polygon(s), %" PetscInt_FMT " segments of about dx, visibility %s\n", wd->walls.npoly,
      wd->walls.nseg, b->visall ? "all" : "cut"));
  PetscFunctionReturn(0);
}

static PetscErrorCode Memory(FSBoundary b, PetscInt64 *lists, PetscInt64 *elements)
{
  FSBoundary_Polygon *wd   = (FSBoundary_Polygon *)b->data;
  const PetscInt64    nseg = wd->walls.nseg;

  PetscFunctionBegin;
  /* cstart and wstart (scap each), the candidate segments (ccap), the wall lists' k and W (b->wcap) */
  *lists = (PetscInt64)wd->scap * 2 * sizeof(PetscInt) + (PetscInt64)wd->ccap * sizeof(PetscInt) +
           (PetscInt64)b->wcap * (sizeof(PetscInt) + sizeof(PetscReal));
  /* the segments, their walls, wetfull and wp (3 nseg + 1), the grid */
  *elements = nseg * (FS_SEG_STRIDE * sizeof(PetscReal) + sizeof(PetscInt) + 4 * sizeof(PetscReal)) +
              (PetscInt64)(wd->gnc[0] * wd->gnc[1] + 1 + nseg) * sizeof(PetscInt);
  PetscFunctionReturn(0);
}

/* a candidate segment's cost in a right-hand side (its integrals for gamma, and for the facing ones within the
   support the wall list entry, the wall pressure's sums and the wall terms), in fluid candidate pairs: measured on
   the 2-D dam break (docs/performance.md, "Balancing the work") */
#define FS_POLYGON_SEGMENT_COST 8.2

static PetscErrorCode Work(FSBoundary b, PetscInt n, PetscInt64 work[])
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;

  PetscFunctionBegin;
  if (!wd->cstart) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n; i++)
    work[i] += (PetscInt64)(FS_POLYGON_SEGMENT_COST * (wd->cstart[i + 1] - wd->cstart[i]) + 0.5);
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSBoundary b)
{
  FSBoundary_Polygon *wd = (FSBoundary_Polygon *)b->data;

  PetscFunctionBegin;
  PetscCall(FSWallsDestroy(&wd->walls));
  PetscCall(PetscFree(wd->names));
  PetscCall(PetscFree(wd->gstart));
  PetscCall(PetscFree(wd->gseg));
  PetscCall(PetscFree2(wd->cstart, b->wstart));
  PetscCall(PetscFree(wd->cand));
  PetscCall(PetscFree(b->wk));
  PetscCall(PetscFree(b->wW));
  PetscCall(PetscFree(wd->wp));
  PetscCall(PetscFree(wd->wetfull));
  PetscCall(PetscFree(b->data));
  b->wallname = NULL;
  b->nwalls   = 0;
  PetscCall(PetscObjectComposeFunction((PetscObject)b, "FSBoundaryPolygonSetWalls_C", NULL));
  PetscFunctionReturn(0);
}

PETSC_INTERN PetscErrorCode FSBoundaryDraw_Polygon(FSBoundary, FSImage *, const FSImageMap *);
PETSC_INTERN PetscErrorCode FSBoundaryWriteGeometry_Polygon(FSBoundary, const char[]);

/*
   FSBoundaryCreate_Polygon - the polygon boundary: 2-D boundary integrals on closed polygons (walls.h
   for the orientation convention), given by the case with FSBoundaryPolygonSetWalls().
*/
PetscErrorCode FSBoundaryCreate_Polygon(FSBoundary b)
{
  FSBoundary_Polygon *wd;

  PetscFunctionBegin;
  PetscCall(PetscNew(&wd));
  PetscCall(FSWallsCreate(&wd->walls));
  b->data               = wd;
  b->ops->setup         = SetUp;
  b->ops->update        = Update;
  b->ops->prepare       = Prepare;
  b->ops->bounce        = Bounce;
  b->ops->boundingbox   = BoundingBox;
  b->ops->shepard       = ShepardAt;
  b->ops->locate        = Locate;
  b->ops->draw          = FSBoundaryDraw_Polygon;
  b->ops->writegeometry = FSBoundaryWriteGeometry_Polygon;
  b->ops->view          = View;
  b->ops->hash          = Hash;
  b->ops->destroy       = Destroy;
  b->ops->memory        = Memory;
  b->ops->work          = Work;
  PetscCall(
      PetscObjectComposeFunction((PetscObject)b, "FSBoundaryPolygonSetWalls_C", FSBoundaryPolygonSetWalls_Polygon));
  PetscFunctionReturn(0);
}
