/*
   Unit test of the physics terms (src/terms) without the solver's loop: terms created through the
   registry (FSTermCreate on a solver that is created but never set up) act on three hand-placed
   particles in 2-D, with the neighbourhoods and the kernel gradients built here as the core builds
   them (FSKernelF of the Wendland C2 kernel), and their rates and powers are compared with the
   formulas written out below:
     continuity      drho_i = -rho_i sum_j (u_j - u_i).gradW_ij V_j,              power -V_i p_i sum_j ...
     pressure        du_i   = -1/rho_i sum_j (p_i + p_j) gradW_ij V_j,            power m_i/rho_i u_i.du_i (/gamma_i)
     gravity         du_i   = g
     viscosity       du_i   = K nu rho0/rho_i sum_j Pi_ij gradW_ij V_j (x (1/gamma_i + 1/gamma_j)/2 with walls),
                     Pi_ij = (u_j - u_i).(x_j - x_i)/|x_j - x_i|^2, K = 2 (dim + 2), power m_i u_i.du_i
     les_viscosity   the same with h c0 alpha_ij, alpha_ij = 2 a_i a_j/(a_i + a_j), a_i = K (C 2h)^2 ||D||_i/(c0 h)
     wall_continuity drho_i = rho_i sum_k (u_i.n_k) W_ik s_k,                     power V_i p_i sum_k ...
     wall_pressure   du_i   = -1/rho_i sum_k (p_i + p_k) n_k W_ik s_k,           power -V_i/gamma_i u_i.(...)
     wall_viscosity  du_i   = -K nu rho0/(rho_i gamma_v,i) M_ik u_i on no-slip walls, with its load, M_ik the
                     integral over the region behind the segment of (1 + delta/max(d_ik, dx/2)) (-W'(r)/r) e_r e_r
                     (delta the depth behind the wall), summed here on a fine grid (its own tolerance, TOLQ)
   where the gradient is the kernel's derivative written out, grad_i W = -5 a/h^2 (1 - q/2)^3 (x_i - x_j),
   a = 7/(4 pi h^2), and the wall view is a hand-built segment in a row layout of its own (the terms must
   read the view's layout). Also: the pressure forces of the pair sum conserve momentum, and an unknown
   term name is an error naming it. Every check is at round-off: 1e-12 relative to the size of the sum.
   Serial by nature (the particles are placed by hand on one rank).
*/
#include <string.h>
#include "terms/fsterms.h"
#include "particles/fsparticles.h"

#define TCHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_terms: " __VA_ARGS__)

#define NP  3 /* particles */
#define DIM 2
#define S   (2 * DIM + 2) /* record: x (2), u (2), rho, m */

static const PetscReal TOL = 1e-12, TOLQ = 2e-4;
static PetscReal       maxerr; /* the largest relative error met, printed at the end */

/* value against expected, relative to scale (the size of the sum it comes from) */
static PetscErrorCode CloseTo(const char what[], PetscInt i, PetscReal value, PetscReal expected, PetscReal scale,
                              PetscReal tol)
{
  const PetscReal err = PetscAbsReal(value - expected) / scale;

  PetscFunctionBegin;
  if (tol == TOL) maxerr = PetscMax(maxerr, err);
  TCHECK(err <= tol, "%s of particle %" PetscInt_FMT ": %.17g, expected %.17g (relative error %.3g > %g)", what, i,
         (double)value, (double)expected, (double)err, (double)tol);
  PetscFunctionReturn(0);
}

static PetscErrorCode Close(const char what[], PetscInt i, PetscReal value, PetscReal expected, PetscReal scale)
{
  PetscFunctionBegin;
  PetscCall(CloseTo(what, i, value, expected, scale, TOL));
  PetscFunctionReturn(0);
}

typedef struct {
  PetscReal   rec[NP * S], vol[NP], pressure[NP], gamma[NP], invgamma[NP], aux[NP * (DIM + 1)];
  FSParticles P;
  FSKernel    kernel;
  /* each particle's neighbourhood: the two others */
  PetscInt  j[NP][NP - 1];
  PetscReal dx[NP][(NP - 1) * DIM], r2[NP][NP - 1], rinv2[NP][NP - 1], gradW[NP][(NP - 1) * DIM];
  PetscReal du[NP][(NP - 1) * DIM], Vj[NP][NP - 1];
  PetscReal hgrad[NP][(NP - 1) * DIM]; /* the gradient written out, for the expected values */
} Particles;

static PetscErrorCode SetUpParticles(Particles *pa)
{
  /* positions (all within 2h of each other), velocities, densities */
  const PetscReal h = 0.1, x[NP][DIM] = {{0.0, 0.0}, {0.071, 0.023}, {-0.032, 0.114}},
                  u[NP][DIM] = {{0.3, -0.2}, {-0.15, 0.41}, {0.05, 0.12}};
  const PetscReal rho[NP] = {1003.1, 998.7, 1001.4}, rho0 = 1000, c0 = 20, dxp = 0.05;
  FSParticles    *P = &pa->P;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(pa, sizeof(*pa)));
  PetscCall(FSKernelSetUp(&pa->kernel, DIM, h));
  for (PetscInt i = 0; i < NP; i++) {
    PetscReal *r = &pa->rec[i * S];
    for (PetscInt d = 0; d < DIM; d++) {
      r[d]       = x[i][d];
      r[DIM + d] = u[i][d];
    }
    r[2 * DIM]                   = rho[i];
    r[2 * DIM + 1]               = rho0 * dxp * dxp * (1 + 0.01 * i); /* masses a little different from each other */
    pa->vol[i]                   = r[2 * DIM + 1] / rho[i];
    pa->pressure[i]              = c0 * c0 * (rho[i] - rho0);
    pa->gamma[i]                 = 1 - 0.1 * (i + 1); /* for the renormalized variants */
    pa->invgamma[i]              = 1 / pa->gamma[i];
    pa->aux[i * (DIM + 1) + DIM] = 2.5 + i; /* ||D||_i for les_viscosity */
  }
  P->dim                 = DIM;
  P->nowned              = NP;
  P->nghost              = 0;
  P->stride              = S;
  P->rec                 = pa->rec;
  P->aux                 = pa->aux;
  P->vol                 = pa->vol;
  P->pressure            = pa->pressure;
  P->rho0                = rho0;
  P->c0                  = c0;
  P->h                   = h;
  P->dx                  = dxp;
  P->nu                  = 1e-3;
  P->gravity[1]          = -9.81;
  P->gravity[0]          = 0.7;
  P->background_pressure = 0;
  /* the neighbourhoods, as the core fills them: x_j - x_i, r^2, 1/r^2, grad_i W = -F(r) (x_j - x_i), u_j - u_i, V_j */
  for (PetscInt i = 0; i < NP; i++)
    for (PetscInt j = 0, k = 0; j < NP; j++) {
      PetscReal r, q, a;
      if (j == i) continue;
      pa->j[i][k]  = j;
      pa->r2[i][k] = 0;
      pa->Vj[i][k] = pa->vol[j];
      for (PetscInt d = 0; d < DIM; d++) {
        pa->du[i][k * DIM + d] = u[j][d] - u[i][d];
        pa->dx[i][k * DIM + d] = x[j][d] - x[i][d];
        pa->r2[i][k] += pa->dx[i][k * DIM + d] * pa->dx[i][k * DIM + d];
      }
      pa->rinv2[i][k] = 1 / pa->r2[i][k];
      r               = PetscSqrtReal(pa->r2[i][k]);
      TCHECK(r < 2 * h, "particles %" PetscInt_FMT " and %" PetscInt_FMT " are %g apart, outside the support %g", i, j,
             (double)r, (double)(2 * h));
      q = r / h;
      a = 1 - 0.5 * q;
      for (PetscInt d = 0; d < DIM; d++) {
        pa->gradW[i][k * DIM + d] = -FSKernelF(&pa->kernel, r) * pa->dx[i][k * DIM + d];
        pa->hgrad[i][k * DIM + d] = -5 * (7 / (4 * PETSC_PI * h * h)) / (h * h) * a * a * a * (x[i][d] - x[j][d]);
      }
      k++;
    }
  PetscFunctionReturn(0);
}

static void Neighbourhood(const Particles *pa, PetscInt i, FSNeighbourhood *nb)
{
  nb->i     = i;
  nb->n     = NP - 1;
  nb->j     = pa->j[i];
  nb->dx    = pa->dx[i];
  nb->r2    = pa->r2[i];
  nb->rinv2 = pa->rinv2[i];
  nb->gradW = pa->gradW[i];
  nb->du    = pa->du[i];
  nb->Vj    = pa->Vj[i];
}

/* the term's rates (pair pass and sources) of every particle, and its power */
static PetscErrorCode Rates(FSTerm t, const FSParticles *P, const Particles *pa, FSRate rate[NP], PetscReal *power)
{
  PetscFunctionBegin;
  t->power = 0;
  if (t->ops.prepare) PetscCall((*t->ops.prepare)(t, P));
  for (PetscInt i = 0; i < NP; i++) {
    FSNeighbourhood nb;
    PetscCall(PetscMemzero(&rate[i], sizeof(rate[i])));
    Neighbourhood(pa, i, &nb);
    if (t->ops.interact) t->ops.interact(t, P, &nb, &rate[i]);
    if (t->ops.source) t->ops.source(t, P, i, &rate[i]);
  }
  *power = t->power;
  PetscFunctionReturn(0);
}

static PetscErrorCode Create(FSSolver s, const char name[], FSTerm *t)
{
  PetscFunctionBegin;
  PetscCall(FSTermCreate(s, name, t));
  TCHECK(!strcmp((*t)->name, name) && (*t)->solver == s, "term \"%s\" created as \"%s\" or without its solver", name,
         (*t)->name);
  if ((*t)->ops.setfromoptions) { /* as the solver does, inside its options block */
    PetscOptionsBegin(PETSC_COMM_SELF, NULL, "test_terms", "");
    PetscCall((*(*t)->ops.setfromoptions)(*t, PetscOptionsObject));
    PetscOptionsEnd();
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TestContinuity(FSSolver s, Particles *pa)
{
  FSTerm    t;
  FSRate    rate[NP];
  PetscReal power, epower = 0, pscale = 0;

  PetscFunctionBegin;
  PetscCall(Create(s, "continuity", &t));
  PetscCall(Rates(t, &pa->P, pa, rate, &power));
  for (PetscInt i = 0; i < NP; i++) {
    const PetscReal *ri  = &pa->rec[i * S];
    PetscReal        sum = 0, scale = 0;
    for (PetscInt k = 0; k < NP - 1; k++) {
      const PetscInt   j  = pa->j[i][k];
      const PetscReal *rj = &pa->rec[j * S], *g = pa->hgrad[i] + k * DIM;
      const PetscReal  c = ((rj[2] - ri[2]) * g[0] + (rj[3] - ri[3]) * g[1]) * pa->vol[j];
      sum += c;
      scale += PetscAbsReal(c);
    }
    PetscCall(Close("continuity drho/dt", i, rate[i].drho, -ri[4] * sum, ri[4] * scale));
    for (PetscInt d = 0; d < DIM; d++)
      TCHECK(rate[i].du[d] == 0 && rate[i].dx[d] == 0, "continuity changed du or dx of particle %" PetscInt_FMT, i);
    epower += -pa->vol[i] * pa->pressure[i] * sum;
    pscale += PetscAbsReal(pa->vol[i] * pa->pressure[i]) * scale;
  }
  PetscCall(Close("continuity power", -1, power, epower, pscale));
  PetscCall(FSTermDestroy(&t));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestPressure(FSSolver s, Particles *pa)
{
  FSTerm    t;
  FSRate    rate[NP];
  PetscReal power;

  PetscFunctionBegin;
  PetscCall(Create(s, "pressure", &t));
  TCHECK(t->renormalized, "term pressure must be renormalized by gamma_i");
  /* without walls (invgamma NULL), then with gamma_i < 1: the rates are the same (the core divides
     them), the power carries 1/gamma_i */
  for (PetscInt walls = 0; walls < 2; walls++) {
    PetscReal epower = 0, pscale = 0, mom[DIM] = {0, 0}, momscale = 0;
    pa->P.invgamma = walls ? pa->invgamma : NULL;
    pa->P.gamma    = walls ? pa->gamma : NULL;
    PetscCall(Rates(t, &pa->P, pa, rate, &power));
    for (PetscInt i = 0; i < NP; i++) {
      const PetscReal *ri       = &pa->rec[i * S];
      PetscReal        acc[DIM] = {0, 0}, scale = 0, pw = 0;
      for (PetscInt k = 0; k < NP - 1; k++) {
        const PetscInt   j = pa->j[i][k];
        const PetscReal *g = pa->hgrad[i] + k * DIM, f = (pa->pressure[i] + pa->pressure[j]) * pa->vol[j];
        for (PetscInt d = 0; d < DIM; d++) acc[d] += f * g[d];
        scale += PetscAbsReal(f) * PetscSqrtReal(g[0] * g[0] + g[1] * g[1]);
      }
      for (PetscInt d = 0; d < DIM; d++) {
        PetscCall(Close(walls ? "pressure du/dt (walls)" : "pressure du/dt", i, rate[i].du[d], -acc[d] / ri[4],
                        scale / ri[4]));
        pw += ri[DIM + d] * (-acc[d] / ri[4]);
        mom[d] += ri[5] * rate[i].du[d];
      }
      TCHECK(rate[i].drho == 0, "pressure changed drho of particle %" PetscInt_FMT, i);
      epower += ri[5] * pw / (walls ? pa->gamma[i] : 1);
      pscale += ri[5] * PetscSqrtReal(ri[2] * ri[2] + ri[3] * ri[3]) * scale / ri[4] / (walls ? pa->gamma[i] : 1);
      momscale += ri[5] * scale / ri[4];
    }
    PetscCall(Close(walls ? "pressure power (walls)" : "pressure power", -1, power, epower, pscale));
    /* m_i du_i = -V_i V_j (p_i + p_j) grad_i W_ij is antisymmetric: the pair forces cancel */
    for (PetscInt d = 0; d < DIM; d++)
      PetscCall(Close("pressure: total force (momentum conservation)", -1, mom[d], 0, momscale));
  }
  pa->P.invgamma = NULL;
  pa->P.gamma    = NULL;
  PetscCall(FSTermDestroy(&t));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestGravity(FSSolver s, Particles *pa)
{
  FSTerm    t;
  FSRate    rate[NP];
  PetscReal power;

  PetscFunctionBegin;
  PetscCall(Create(s, "gravity", &t));
  PetscCall(Rates(t, &pa->P, pa, rate, &power));
  for (PetscInt i = 0; i < NP; i++) {
    for (PetscInt d = 0; d < DIM; d++)
      TCHECK(rate[i].du[d] == pa->P.gravity[d],
             "gravity du_%" PetscInt_FMT "/dt of particle %" PetscInt_FMT ": %.17g, expected %.17g", d, i,
             (double)rate[i].du[d], (double)pa->P.gravity[d]);
    TCHECK(rate[i].drho == 0, "gravity changed drho of particle %" PetscInt_FMT, i);
  }
  PetscCall(FSTermDestroy(&t));
  PetscFunctionReturn(0);
}

/* viscosity (les = 0) and les_viscosity (les = 1), without and with walls */
static PetscErrorCode TestViscosity(FSSolver s, Particles *pa, PetscBool les)
{
  const char     *name = les ? "les_viscosity" : "viscosity";
  const PetscReal K = 2.0 * (DIM + 2), C = 0.12, h = pa->P.h, c0 = pa->P.c0, rho0 = pa->P.rho0, nu = pa->P.nu;
  FSTerm          t;
  FSRate          rate[NP];
  PetscReal       power, a[NP];
  char            what[64];

  PetscFunctionBegin;
  PetscCall(Create(s, name, &t));
  TCHECK(!t->renormalized, "term %s must not be renormalized as a whole (its pairs carry the gamma factor)", name);
  for (PetscInt i = 0; i < NP; i++) a[i] = K * (C * 2 * h) * (C * 2 * h) * pa->aux[i * (DIM + 1) + DIM] / (c0 * h);
  for (PetscInt walls = 0; walls < 2; walls++) {
    PetscReal epower = 0, pscale = 0;
    pa->P.invgamma = walls ? pa->invgamma : NULL;
    pa->P.gamma    = walls ? pa->gamma : NULL;
    PetscCall(Rates(t, &pa->P, pa, rate, &power));
    for (PetscInt i = 0; i < NP; i++) {
      const PetscReal *ri       = &pa->rec[i * S];
      PetscReal        acc[DIM] = {0, 0}, scale = 0, du[DIM], pw = 0;
      for (PetscInt k = 0; k < NP - 1; k++) {
        const PetscInt   j  = pa->j[i][k];
        const PetscReal *rj = &pa->rec[j * S], *g = pa->hgrad[i] + k * DIM;
        const PetscReal  xx = rj[0] - ri[0], yy = rj[1] - ri[1];
        PetscReal        Pi = ((rj[2] - ri[2]) * xx + (rj[3] - ri[3]) * yy) / (xx * xx + yy * yy) * pa->vol[j];
        if (les) Pi *= 2 * a[i] * a[j] / (a[i] + a[j]);
        if (walls) Pi *= 0.5 * (1 / pa->gamma[i] + 1 / pa->gamma[j]);
        for (PetscInt d = 0; d < DIM; d++) acc[d] += Pi * g[d];
        scale += PetscAbsReal(Pi) * PetscSqrtReal(g[0] * g[0] + g[1] * g[1]);
      }
      for (PetscInt d = 0; d < DIM; d++) {
        const PetscReal f = (les ? h * c0 : K * nu) * rho0 / ri[4];
        du[d]             = f * acc[d];
        PetscCall(PetscSNPrintf(what, sizeof(what), "%s du_%d/dt%s", name, (int)d, walls ? " (walls)" : ""));
        PetscCall(Close(what, i, rate[i].du[d], du[d], f * scale));
        pw += ri[DIM + d] * du[d];
        if (!d) pscale += ri[5] * PetscSqrtReal(ri[2] * ri[2] + ri[3] * ri[3]) * f * scale;
      }
      epower += ri[5] * pw;
    }
    PetscCall(PetscSNPrintf(what, sizeof(what), "%s power%s", name, walls ? " (walls)" : ""));
    PetscCall(Close(what, -1, power, epower, pscale));
    TCHECK(power < 0, "%s: the power %g must be negative (dissipation)", name, (double)power);
    if (les) { /* the largest viscosity the term applies, for the time step */
      PetscReal numax = 0;
      for (PetscInt i = 0; i < NP; i++)
        numax = PetscMax(numax, (C * 2 * h) * (C * 2 * h) * pa->aux[i * (DIM + 1) + DIM]);
      PetscCall(Close("les_viscosity max_viscosity", -1, t->max_viscosity, numax, numax));
    } else
      TCHECK(t->max_viscosity == nu, "viscosity: max_viscosity %g, expected nu = %g", (double)t->max_viscosity,
             (double)nu);
  }
  pa->P.invgamma = NULL;
  pa->P.gamma    = NULL;
  PetscCall(FSTermDestroy(&t));
  PetscFunctionReturn(0);
}

/*
   The wall terms on one segment below the particles: a hand-built view whose rows are laid out as
   p0 (2), centroid (2), normal (2), length (1), so unlike the polygon boundary's (the terms must read
   the layout from the view), and two walls, the segment on wall 1. Particles 0 and 1 see it.
*/
#define ES 9 /* a segment's row: p0, p1, midpoint, normal, length */

/* M = int over the part of the support of x behind the segment p0 -> p1 (normal n, x at distance d in front)
   of (1 + delta/de) (-W'(r)/r) e_r e_r, delta the depth behind the segment's line: by the midpoint rule on a
   grid of the support's box, the points whose ray from x crosses the segment */
static void BehindSegment(const Particles *pa, const PetscReal x[], const PetscReal p0[], const PetscReal p1[],
                          const PetscReal n[], PetscReal d, PetscReal de, PetscReal M[3])
{
  const PetscInt  G = 2000;
  const PetscReal R = 2 * pa->P.h, cell = 2 * R / G;
  M[0] = M[1] = M[2] = 0;
  for (PetscInt a = 0; a < G; a++)
    for (PetscInt b = 0; b < G; b++) {
      const PetscReal y[2]  = {-R + (a + 0.5) * cell, -R + (b + 0.5) * cell},
                      r     = PetscSqrtReal(y[0] * y[0] + y[1] * y[1]);
      const PetscReal depth = y[0] * n[0] + y[1] * n[1] - d;
      PetscReal       s, c0, c1, f;
      if (r >= R || depth <= 0) continue;
      /* the ray x + s y crosses the line at s = d/(y.n); between p0 and p1 when the cross products change sign */
      s  = d / (y[0] * n[0] + y[1] * n[1]);
      c0 = (p0[0] - x[0]) * y[1] - (p0[1] - x[1]) * y[0];
      c1 = (p1[0] - x[0]) * y[1] - (p1[1] - x[1]) * y[0];
      if (s <= 0 || c0 * c1 > 0) continue;
      f = -(1 + depth / de) * FSKernelF(&pa->kernel, r) * cell * cell / (r * r); /* -W'(r)/r = -F(r), over r^2 */
      M[0] += f * y[0] * y[0];
      M[1] += f * y[0] * y[1];
      M[2] += f * y[1] * y[1];
    }
}
static PetscErrorCode TestWalls(FSSolver s, Particles *pa)
{
  const PetscReal p0[2] = {-0.2, -0.04}, p1[2] = {0.3, -0.09}, len = PetscSqrtReal(0.5 * 0.5 + 0.05 * 0.05);
  PetscReal       element[ES], pressure[1] = {173.2}, load[12];
  const PetscInt  elementwall[1] = {1}, k[1] = {0};
  PetscBool       noslip[2] = {PETSC_FALSE, PETSC_TRUE};
  const PetscReal Wmean[NP] = {3.25, 1.5, 0}; /* the mean kernel values over the segment: inputs of the terms */
  FSWallView      B;
  FSTerm          tc, tp, tv;
  PetscReal       n[2], igv[NP] = {1 / 0.95, 1 / 0.85, 1 / 0.75}; /* 1/gamma_v, gamma_v > gamma */

  PetscFunctionBegin;
  /* the liquid (the particles) lies above the segment p0 -> p1, so its normal out of the liquid is (dy, -dx)/len,
   * pointing down */
  n[0]       = (p1[1] - p0[1]) / len;
  n[1]       = -(p1[0] - p0[0]) / len;
  element[0] = p0[0];
  element[1] = p0[1];
  element[2] = p1[0];
  element[3] = p1[1];
  element[4] = 0.5 * (p0[0] + p1[0]);
  element[5] = 0.5 * (p0[1] + p1[1]);
  element[6] = n[0];
  element[7] = n[1];
  element[8] = len;
  PetscCall(PetscMemzero(&B, sizeof(B)));
  PetscCall(PetscArrayzero(load, 12));
  B.dim           = DIM;
  B.nwalls        = 2;
  B.nelements     = 1;
  B.stride        = ES;
  B.vertex        = 0;
  B.centroid      = 4;
  B.normal        = 6;
  B.measure       = 8;
  B.element       = element;
  B.elementwall   = elementwall;
  B.pressure      = pressure;
  B.noslip        = noslip;
  B.load          = load;
  B.loadpoint[0]  = 0.05;
  B.loadpoint[1]  = -0.3;
  pa->P.invgamma  = pa->invgamma; /* the wall terms run only with walls, where 1/gamma is there */
  pa->P.gamma     = pa->gamma;
  pa->P.invgammav = igv;
  PetscCall(Create(s, "wall_continuity", &tc));
  PetscCall(Create(s, "wall_pressure", &tp));
  PetscCall(Create(s, "wall_viscosity", &tv));
  TCHECK(!tc->renormalized && tp->renormalized && !tv->renormalized,
         "renormalization by the core: wall_pressure only (wall_viscosity divides by gamma_v itself)");
  TCHECK(tc->ops.wall && tp->ops.wall && tv->ops.wall && !tc->ops.interact && !tp->ops.interact,
         "the wall terms act through ops.wall only");
  tc->power = tp->power = tv->power = 0;
  {
    PetscReal epc = 0, epp = 0, epv = 0, eload[6] = {0, 0, 0, 0, 0, 0};
    for (PetscInt i = 0; i < 2; i++) {
      const PetscReal    *ri = &pa->rec[i * S], rho = ri[4], *u = ri + DIM, f = Wmean[i] * len;
      const PetscReal     d  = (p0[0] - ri[0]) * n[0] + (p0[1] - ri[1]) * n[1];
      FSWallNeighbourhood nb = {i, 1, k, &Wmean[i]};
      FSRate              rc = {0, {0, 0, 0}, {0, 0, 0}}, rp = rc, rv = rc;
      PetscReal           un = u[0] * n[0] + u[1] * n[1];
      TCHECK(d > 0, "particle %" PetscInt_FMT " is not on the liquid side of the segment (d = %g)", i, (double)d);
      tc->ops.wall(tc, &pa->P, &B, &nb, &rc);
      tp->ops.wall(tp, &pa->P, &B, &nb, &rp);
      /* continuity: rho_i (u_i.n) W s, the walls at rest */
      PetscCall(Close("wall_continuity drho/dt", i, rc.drho, rho * un * f,
                      rho * PetscSqrtReal(u[0] * u[0] + u[1] * u[1]) * f));
      epc += pa->vol[i] * pa->pressure[i] * un * f;
      /* pressure: -(p_i + p_k) n W s / rho_i */
      for (PetscInt dd = 0; dd < DIM; dd++)
        PetscCall(Close("wall_pressure du/dt", i, rp.du[dd], -(pa->pressure[i] + pressure[0]) * n[dd] * f / rho,
                        PetscAbsReal(pa->pressure[i] + pressure[0]) * f / rho));
      epp += -pa->vol[i] * pa->invgamma[i] * (pa->pressure[i] + pressure[0]) * un * f;
      /* viscosity: free-slip wall 0 adds nothing, no-slip wall 1 the shear -nu rho0/rho_i u_i W s/max(d, dx/2) */
      noslip[1] = PETSC_FALSE;
      {
        const PetscReal before[2] = {load[6], load[7]};
        tv->ops.wall(tv, &pa->P, &B, &nb, &rv);
        TCHECK(rv.du[0] == 0 && rv.du[1] == 0 && load[6] == before[0] && load[7] == before[1],
               "wall_viscosity acts on a free-slip wall (particle %" PetscInt_FMT ")", i);
      }
      noslip[1] = PETSC_TRUE;
      tv->ops.wall(tv, &pa->P, &B, &nb, &rv);
      {
        PetscReal M[3], ev[2], c = 8 * pa->P.nu * pa->P.rho0 / rho * igv[i];
        BehindSegment(pa, ri, p0, p1, n, d, PetscMax(d, 0.5 * pa->P.dx), M);
        ev[0] = -c * (M[0] * u[0] + M[1] * u[1]);
        ev[1] = -c * (M[1] * u[0] + M[2] * u[1]);
        for (PetscInt dd = 0; dd < DIM; dd++)
          PetscCall(CloseTo("wall_viscosity du/dt", i, rv.du[dd], ev[dd], PetscSqrtReal(ev[0] * ev[0] + ev[1] * ev[1]),
                            TOLQ));
        /* the power and the load from the term's own rates: m_i u_i.du_i and the reaction -m_i du_i */
        epv += ri[5] * (u[0] * rv.du[0] + u[1] * rv.du[1]);
        eload[0] -= ri[5] * rv.du[0];
        eload[1] -= ri[5] * rv.du[1];
        eload[5] -= ri[5] * ((element[4] - B.loadpoint[0]) * rv.du[1] - (element[5] - B.loadpoint[1]) * rv.du[0]);
        TCHECK(u[0] * rv.du[0] + u[1] * rv.du[1] < 0, "wall_viscosity must dissipate (particle %" PetscInt_FMT ")", i);
      }
      TCHECK(rc.du[0] == 0 && rc.du[1] == 0 && rp.drho == 0 && rv.drho == 0,
             "a wall term changed a rate it does not own (particle %" PetscInt_FMT ")", i);
    }
    PetscCall(Close("wall_continuity power", -1, tc->power, epc, PetscAbsReal(epc)));
    PetscCall(Close("wall_pressure power", -1, tp->power, epp, PetscAbsReal(epp)));
    PetscCall(Close("wall_viscosity power", -1, tv->power, epv, PetscAbsReal(epv)));
    for (PetscInt c = 0; c < 6; c++) {
      TCHECK(load[c] == 0, "wall_viscosity put a load %g on the free-slip wall 0", (double)load[c]);
      if (c == 2 || c == 3 || c == 4)
        TCHECK(load[6 + c] == 0, "wall_viscosity: load component %" PetscInt_FMT " %g must be 0 in 2-D", c,
               (double)load[6 + c]);
      else
        PetscCall(Close("wall_viscosity load on wall 1", c, load[6 + c], eload[c],
                        PetscAbsReal(eload[0]) + PetscAbsReal(eload[1]) + PetscAbsReal(eload[5])));
    }
  }
  pa->P.invgamma  = NULL;
  pa->P.gamma     = NULL;
  pa->P.invgammav = NULL;
  PetscCall(FSTermDestroy(&tc));
  PetscCall(FSTermDestroy(&tp));
  PetscCall(FSTermDestroy(&tv));
  PetscFunctionReturn(0);
}

static PetscErrorCode TestUnknown(FSSolver s)
{
  FSTerm         t = NULL;
  PetscErrorCode ierr;
  const char    *text;
  char          *msg;

  PetscFunctionBegin;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = FSTermCreate(s, "no_such_term", &t);
  PetscCall(PetscPopErrorHandler());
  TCHECK(ierr == PETSC_ERR_ARG_UNKNOWN_TYPE,
         "FSTermCreate of an unknown name returned %d, expected PETSC_ERR_ARG_UNKNOWN_TYPE (%d)", (int)ierr,
         (int)PETSC_ERR_ARG_UNKNOWN_TYPE);
  PetscCall(PetscErrorMessage(ierr, &text, &msg));
  TCHECK(msg && strstr(msg, "\"no_such_term\"") && strstr(msg, "continuity"),
         "the error message must name the unknown term and the registered ones: \"%s\"", msg ? msg : "(none)");
  TCHECK(!t, "FSTermCreate returned a term for an unknown name");
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  FSSolver    s;
  Particles  *pa;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  TCHECK(size == 1, "serial by nature: run it on one rank");
  /* FSTermCreate only stores the solver; viscosity's setfromoptions reads its dimension (2 by default) */
  PetscCall(FSSolverCreate(PETSC_COMM_SELF, &s));
  PetscCall(FSTermRegisterAll());
  PetscCall(PetscNew(&pa));
  PetscCall(SetUpParticles(pa));
  PetscCall(TestContinuity(s, pa));
  PetscCall(TestPressure(s, pa));
  PetscCall(TestGravity(s, pa));
  PetscCall(TestViscosity(s, pa, PETSC_FALSE));
  PetscCall(TestViscosity(s, pa, PETSC_TRUE));
  PetscCall(TestWalls(s, pa));
  PetscCall(TestUnknown(s));
  PetscCall(PetscFree(pa));
  PetscCall(FSSolverDestroy(&s));
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "test_terms: largest relative error %.3g (tolerance %g)\ntest_terms: OK\n",
                        (double)maxerr, (double)TOL));
  PetscCall(PetscFinalize());
  return 0;
}
