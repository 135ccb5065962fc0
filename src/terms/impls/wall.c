/*
   Wall terms of the boundary-integral method (seed Eq. 14; Calderon-Sanchez et al. 2019; Cercos-Pita
   2015): the boundary parts of the renormalized operators, summed over the wall segments k that face
   particle i within the kernel support (normal n_k out of the liquid, length s_k, W_ik the mean kernel
   value over the segment), from the boundary's view (FSWallView) and the particle's wall
   neighbourhood. Like the fluid terms they join, they are divided by gamma_i by the core (wall_viscosity
   by gamma_v,i itself, as the laminar fluid sum).
   The walls are at rest in the tank's frame (u_k = 0).

   wall_continuity:  D rho_i/Dt += -rho_i sum_k (u_k - u_i) . n_k W_ik s_k
   wall_pressure:    D u_i/Dt   += -1/rho_i sum_k (f_ik p_i + p_k) n_k W_ik s_k, the wall pressure p_k
                     interpolated from the liquid near the segment (Shepard sum over all ranks with the
                     hydrostatic correction rho_j g . (x_k - x_j)). The liquid's pressure force on each
                     wall is the integral of that wall pressure, F_w = sum_{k in w} p_k s_k n_k (the
                     continuous form of seed Eq. 29, exact for a liquid at rest), computed by the core
                     with the wall pressures, and its moment about -fs_walls_load_point.
                     f_ik = 1 + kappa (d0 - d_ik)/d0 where particle i is closer than d0 to element k's plane
                     (d_ik), else 1 (kappa = -fs_walls_repulsion, 0 by default; d0 =
                     -fs_walls_repulsion_distance dx): a push back from the wall near contact. The particle's
                     own pressure holds it off the wall through the difference between the particles' kernel
                     gradient sum and the wall integral; in 3-D that restoring is weak for one particle of the
                     first row (docs/walls.md), and f_ik > 1 adds to it without changing a first row at rest
                     (which sits beyond the default d0). Faces turned away (d_ik <= 0) keep f_ik = 1.
                     With -fs_walls_tension false an element pushes but never pulls: its share
                     (f_ik p_i + p_k) W_ik s_k is taken as 0 where it is negative, so that a liquid in tension
                     leaves the wall (as air entering under it lets a real liquid do) instead of hanging on it.
   wall_viscosity:   on no-slip walls (-fs_walls_noslip), the part of the laminar viscous sum
                     (viscosity.c, K nu rho0/rho_i sum_j Pi_ij grad W_ij V_j) that the support behind the
                     wall would give, filled with the velocity that is linear along the wall's normal,
                     u_k at the wall and u_i at x_i's distance d_ik from the element's plane:
                     D u_i/Dt += K nu rho0/(rho_i gamma_v,i) sum_k M_ik (u_k - u_i), with the tensor
                     M_ik = int_k [(1 - d/d_e) P_{D-2}(r) + d/(r d_e) P_{D-1}(r)] d/r^D e_r e_r dS,
                     P_m(r) = int_r^2h (-W'(s)) s^m ds, r = |y - x_i|, d = d_ik, d_e = max(d, dx/2)
                     (each ray from x_i through the element, continued to the support's edge). With the
                     fluid sum's gamma_v (gamma plus this share) a linear shear along a flat no-slip wall
                     feels no viscous force; the term is dissipative (M_ik is positive semi-definite).
                     Free-slip walls carry no shear (the term adds nothing there).
   Their powers, the rates of change of the liquid's kinetic (m_i u_i . D u_i/Dt, with the core's
   1/gamma_i) and compressibility (V_i p_i/rho_i D rho_i/Dt) energies through the walls, make the
   wall power P_s of the energy budget (seed Eq. 39): the sum of the dissipated_wall_* columns.
   The wall pressure term does no net work on a liquid at rest; it exchanges energy with the fluid
   pressure term where gamma < 1.
*/
#include <flexslosh.h>

/* In the element rows of the boundary's view: p0 the element's point, c its centroid, n its normal
   (out of the liquid), a its length (2-D) or area (3-D). Each body is written for a compile-time
   dimension D and called with 2 or 3 (FS_ALWAYS_INLINE in flexslosh.h). */
FS_ALWAYS_INLINE void ContinuityD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                  const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   N = B->normal, A = B->measure;
  const PetscReal *ri  = &P->rec[nb->i * P->stride];
  PetscReal        sum = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscReal *e  = &B->element[nb->k[q] * B->stride];
    PetscReal        un = 0;
    for (PetscInt d = 0; d < D; d++) un += ri[D + d] * e[N + d];
    sum += un * nb->W[q] * e[A];
  }
  rate->drho += ri[2 * D] * sum;
  t->power += P->vol[nb->i] * P->pressure[nb->i] * sum;
}

static void Continuity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) ContinuityD(2, t, P, B, nb, rate);
  else ContinuityD(3, t, P, B, nb, rate);
}

/* The distance of x from element e's plane, positive on the liquid's side (negative: a face turned away, which
   -fs_walls_visibility all lists: the other side of a thin baffle) */
FS_ALWAYS_INLINE PetscReal PlaneDistance(PetscInt D, const FSWallView *B, const PetscReal *e, const PetscReal *x)
{
  PetscReal d = 0;
  for (PetscInt a = 0; a < D; a++) d += (e[B->vertex + a] - x[a]) * e[B->normal + a];
  return d;
}

/* wall_pressure's options: the repulsion near contact (f_ik above) */
typedef struct {
  PetscReal kappa, distance; /* distance in units of dx */
  PetscBool tension;         /* -fs_walls_tension: the elements pull on a liquid in tension (the seed's form) */
} WallPressure;

FS_ALWAYS_INLINE void PressureD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                const FSWallNeighbourhood *nb, FSRate *rate)
{
  const WallPressure *ctx = (const WallPressure *)t->data;
  const PetscInt      i = nb->i, N = B->normal, A = B->measure;
  const PetscReal    *ri = &P->rec[i * P->stride], rhoi = ri[2 * D], pi = P->pressure[i];
  const PetscReal     d0 = ctx->distance * P->dx, kd = ctx->kappa / d0;
  PetscReal           acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k  = nb->k[q];
    const PetscReal *e  = &B->element[k * B->stride];
    PetscReal        fi = 1;
    if (ctx->kappa > 0) {
      const PetscReal dist = PlaneDistance(D, B, e, ri);
      if (dist > 0 && dist < d0) fi += kd * (d0 - dist); /* not through a face turned away */
    }
    PetscReal f = (fi * pi + B->pressure[k]) * nb->W[q] * e[A];
    if (!ctx->tension && f < 0) f = 0; /* a wall that pushes only */
    for (PetscInt d = 0; d < D; d++) acc[d] += f * e[N + d];
  }
  for (PetscInt d = 0; d < D; d++) {
    rate->du[d] -= acc[d] / rhoi;
    pw += ri[D + d] * acc[d];
  }
  t->power -= P->vol[i] * P->invgamma[i] * pw;
}

static void Pressure(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) PressureD(2, t, P, B, nb, rate);
  else PressureD(3, t, P, B, nb, rate);
}

/* 4-point Gauss-Legendre on [-1, 1]: exact for the radial moments' polynomials (degree 6) */
static const PetscReal GL4X[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
static const PetscReal GL4W[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
/* 8-point Gauss-Legendre on [-1, 1], for the angle along a segment */
static const PetscReal GL8X[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                                  0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
static const PetscReal GL8W[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066531250488, 0.3626837833783620,
                                  0.3626837833783620, 0.3137066531250488, 0.2223810344533745, 0.1012285362903763};

/* The radial moments pm[0] = P_{D-2}(r), pm[1] = P_{D-1}(r) of the Wendland C2 kernel (src/particles/kernel.c,
   -W'(s) = 5 a (s/h) (1 - s/2h)^3 / h): P_m = 5 a h^m int_q^2 t^(m+1) (1 - t/2)^3 dt, q = r/h */
static inline void RadialMoments(PetscInt D, PetscReal h, PetscReal r, PetscReal pm[2])
{
  const PetscReal q = r / h, half = 0.5 * (2 - q);
  const PetscReal a  = D == 2 ? 7 / (4 * PETSC_PI * h * h) : 21 / (16 * PETSC_PI * h * h * h);
  PetscReal       s0 = 0, s1 = 0;

  pm[0] = pm[1] = 0;
  if (q >= 2) return;
  for (PetscInt g = 0; g < 4; g++) {
    const PetscReal t = 0.5 * (2 + q) + half * GL4X[g], c = 1 - 0.5 * t;
    const PetscReal f = GL4W[g] * c * c * c * (D == 2 ? t : t * t);
    s0 += f;
    s1 += f * t;
  }
  pm[0] = 5 * a * half * s0 * (D == 2 ? 1 : h);
  pm[1] = 5 * a * half * s1 * (D == 2 ? h : h * h);
}

/* M (D x D, row-major) += the tensor M_ik of a segment v[0..1] -> v[2..3] seen from x at distance d > 0 (2-D), in the
   angle theta from the normal, dS = r^2/d dtheta: int [(1 - d/d_e) P_0(r) + cos(theta) P_1(r)/d_e] e_r e_r dtheta */
static void SegmentTensor(PetscReal h, const PetscReal x[], const PetscReal v[], const PetscReal n[], PetscReal d,
                          PetscReal de, PetscReal M[])
{
  const PetscReal len  = PetscSqrtReal((v[2] - v[0]) * (v[2] - v[0]) + (v[3] - v[1]) * (v[3] - v[1]));
  const PetscReal t[2] = {(v[2] - v[0]) / len, (v[3] - v[1]) / len}, R = 2 * h;
  const PetscReal s0 = (x[0] - v[0]) * t[0] + (x[1] - v[1]) * t[1], half = PetscSqrtReal(R * R - d * d);
  const PetscReal a = PetscMax(-s0, -half), b = PetscMin(len - s0, half); /* the part within the support */
  PetscReal       th[3];

  if (b <= a) return;
  th[0] = PetscAtan2Real(a, d);
  th[2] = PetscAtan2Real(b, d);
  th[1] = th[0] < 0 && th[2] > 0 ? 0 : 0.5 * (th[0] + th[2]); /* split at the foot of the perpendicular */
  for (PetscInt p = 0; p < 2; p++)
    for (PetscInt g = 0; g < 8; g++) {
      const PetscReal w = 0.5 * (th[p + 1] - th[p]), q = 0.5 * (th[p] + th[p + 1]) + w * GL8X[g];
      const PetscReal c = PetscCosReal(q), sn = PetscSinReal(q), e[2] = {c * n[0] + sn * t[0], c * n[1] + sn * t[1]};
      PetscReal       pm[2], f;
      RadialMoments(2, h, d / c, pm);
      f = w * GL8W[g] * ((1 - d / de) * pm[0] + c * pm[1] / de);
      M[0] += f * e[0] * e[0];
      M[1] += f * e[0] * e[1];
      M[3] += f * e[1] * e[1];
    }
  M[2] = M[1];
}

/* M (3 x 3) += the tensor M_ik of the triangle v (3 corners) seen from x at distance d > 0 from its plane: the
   triangle split into m^2 similar ones, finer near x, each with the 3-point rule of degree 2 */
static void TriangleTensor(PetscReal h, const PetscReal x[], const PetscReal v[], const PetscReal c[], PetscReal area,
                           PetscReal d, PetscReal de, PetscReal M[])
{
  PetscReal longest = 0, dc = 0, e1[3], e2[3];
  PetscInt  m;

  for (PetscInt a = 0; a < 3; a++) {
    const PetscReal *p = v + 3 * a, *q = v + 3 * ((a + 1) % 3);
    longest = PetscMax(longest, PetscSqrtReal((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                                              (q[2] - p[2]) * (q[2] - p[2])));
    dc += (c[a] - x[a]) * (c[a] - x[a]);
    e1[a] = (v[3 + a] - v[a]);
    e2[a] = (v[6 + a] - v[a]);
  }
  dc = PetscMax(PetscSqrtReal(dc) - longest, de);
  m  = PetscMin(8, (PetscInt)PetscCeilReal(2 * longest / dc));
  m  = PetscMax(m, 1);
  for (PetscInt ii = 0; ii < m; ii++)
    for (PetscInt jj = 0; jj < m - ii; jj++)
      for (PetscInt up = 0; up < (jj < m - ii - 1 ? 2 : 1);
           up++) /* the triangles of the grid: upright and upside down */
        for (PetscInt g = 0; g < 3; g++) {
          /* barycentric (along e1, along e2) of the rule's point in the sub-triangle, in units of 1/m */
          const PetscReal l1 = g == 1 ? 2.0 / 3 : 1.0 / 6, l2 = g == 2 ? 2.0 / 3 : 1.0 / 6;
          PetscReal       s, t, y[3], r = 0, pm[2], f;
          if (!up) {
            s = (ii + l1) / m;
            t = (jj + l2) / m;
          } else {
            s = (ii + 1 - l1) / m;
            t = (jj + 1 - l2) / m;
          }
          for (PetscInt a = 0; a < 3; a++) {
            y[a] = v[a] + s * e1[a] + t * e2[a] - x[a];
            r += y[a] * y[a];
          }
          r = PetscSqrtReal(r);
          if (r >= 2 * h) continue;
          RadialMoments(3, h, r, pm);
          f = area / (m * m) / 3 * ((1 - d / de) * pm[0] + d / (r * de) * pm[1]) * d / (r * r * r * r * r);
          for (PetscInt a = 0; a < 3; a++)
            for (PetscInt b = 0; b < 3; b++) M[3 * a + b] += f * y[a] * y[b];
        }
}

FS_ALWAYS_INLINE void ViscosityD(PetscInt D, FSTerm t, const FSParticles *P, const FSWallView *B,
                                 const FSWallNeighbourhood *nb, FSRate *rate)
{
  const PetscInt   i = nb->i, N = B->normal, A = B->measure, C = B->centroid, X = B->vertex;
  const PetscReal *ri = &P->rec[i * P->stride], rhoi = ri[2 * D], mi = ri[2 * D + 1], *u = ri + D;
  const PetscReal  igv = P->invgammav ? P->invgammav[i] : P->invgamma[i];
  const PetscReal  c = 2 * (D + 2) * P->nu * P->rho0 / rhoi * igv, dmin = 0.5 * P->dx;
  PetscReal        acc[3] = {0, 0, 0}, pw = 0;
  for (PetscInt q = 0; q < nb->n; q++) {
    const PetscInt   k = nb->k[q];
    const PetscReal *e = &B->element[k * B->stride];
    PetscReal        d, M[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, f[3] = {0, 0, 0}, r[3] = {0, 0, 0}, *L;
    if (!B->noslip[B->elementwall[k]]) continue;
    d = PlaneDistance(D, B, e, ri);
    if (d <= 0) continue; /* a face turned away: the other side's wall */
    if (D == 2) SegmentTensor(P->h, ri, e + X, e + N, d, PetscMax(d, dmin), M);
    else TriangleTensor(P->h, ri, e + X, e + C, e[A], d, PetscMax(d, dmin), M);
    for (PetscInt a = 0; a < D; a++)
      for (PetscInt b = 0; b < D; b++) f[a] += c * M[D * a + b] * u[b]; /* u_k = 0: the wall at rest */
    L = &B->load[FS_WALL_LOAD_STRIDE * B->elementwall[k]];
    for (PetscInt a = 0; a < D; a++) {
      acc[a] -= f[a];
      L[a] += mi * f[a]; /* the reaction on the wall */
      r[a] = e[C + a] - B->loadpoint[a];
    }
    if (D == 3) {
      L[3] += mi * (r[1] * f[2] - r[2] * f[1]);
      L[4] += mi * (r[2] * f[0] - r[0] * f[2]);
    }
    L[5] += mi * (r[0] * f[1] - r[1] * f[0]);
  }
  for (PetscInt a = 0; a < D; a++) {
    rate->du[a] += acc[a];
    pw += u[a] * acc[a];
  }
  t->power += mi * pw;
}

static void Viscosity(FSTerm t, const FSParticles *P, const FSWallView *B, const FSWallNeighbourhood *nb, FSRate *rate)
{
  if (P->dim == 2) ViscosityD(2, t, P, B, nb, rate);
  else ViscosityD(3, t, P, B, nb, rate);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallContinuity(FSTerm t)
{
  PetscFunctionBegin;
  t->has_power = PETSC_TRUE;
  t->ops.wall  = Continuity;
  PetscFunctionReturn(0);
}

static PetscErrorCode PressureSetFromOptions(FSTerm t, PetscOptionItems *PetscOptionsObject)
{
  WallPressure *ctx = (WallPressure *)t->data;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Term wall_pressure: the pressure's boundary integral");
  PetscCall(
      FSOptionsReal(PetscOptionsObject, "-fs_walls_repulsion",
                    "Push back from a wall near contact: the particle's own pressure counts 1 + kappa (d0 - d)/d0 "
                    "times for an element closer than d0 (0: none)",
                    "", &ctx->kappa, NULL, 0, 10, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_walls_repulsion_distance",
                          "Distance d0 from an element's plane (in dx) within which -fs_walls_repulsion acts", "",
                          &ctx->distance, NULL, 0, 1, FS_RANGE_OPEN_LOWER));
  PetscCall(PetscOptionsBool("-fs_walls_tension",
                             "The walls pull on a liquid in tension (false: they push only, and a liquid whose "
                             "pressure falls below zero leaves them)",
                             "", ctx->tension, &ctx->tension, NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode PressureView(FSTerm t, PetscViewer v)
{
  WallPressure *ctx = (WallPressure *)t->data;

  PetscFunctionBegin;
  if (ctx->kappa > 0)
    PetscCall(PetscViewerASCIIPrintf(v, "wall_pressure: repulsion %g within %g dx of a wall\n", (double)ctx->kappa,
                                     (double)ctx->distance));
  if (!ctx->tension) PetscCall(PetscViewerASCIIPrintf(v, "wall_pressure: the walls push only (no tension)\n"));
  PetscFunctionReturn(0);
}

static PetscErrorCode PressureDestroy(FSTerm t)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(t->data));
  PetscFunctionReturn(0);
}

/*
   FSTermWallPressureGetRepulsion - the push back near contact of a wall_pressure term: kappa (-fs_walls_repulsion, 0
   none) and d0 in units of dx (-fs_walls_repulsion_distance); 0 and 0 for any other term. The relaxed packing
   balances the same wall weights (src/cases/impls/packing.c).

   Not collective
*/
PetscErrorCode FSTermWallPressureGetRepulsion(FSTerm t, PetscReal *kappa, PetscReal *distance)
{
  PetscFunctionBegin;
  *kappa = *distance = 0;
  if (t->ops.wall == Pressure) {
    const WallPressure *ctx = (const WallPressure *)t->data;
    *kappa                  = ctx->kappa;
    *distance               = ctx->distance;
  }
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallPressure(FSTerm t)
{
  WallPressure *ctx;

  PetscFunctionBegin;
  PetscCall(PetscNew(&ctx));
  ctx->kappa            = 0;
  ctx->distance         = 0.45;
  ctx->tension          = PETSC_TRUE;
  t->data               = ctx;
  t->renormalized       = PETSC_TRUE;
  t->has_power          = PETSC_TRUE;
  t->ops.wall           = Pressure;
  t->ops.setfromoptions = PressureSetFromOptions;
  t->ops.view           = PressureView;
  t->ops.destroy        = PressureDestroy;
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSTermCreate_WallViscosity(FSTerm t)
{
  PetscFunctionBegin;
  t->renormalized = PETSC_FALSE; /* divided by gamma_v itself */
  t->has_power    = PETSC_TRUE;
  t->ops.wall     = Viscosity;
  PetscFunctionReturn(0);
}
