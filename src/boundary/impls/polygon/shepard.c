/*
   The Shepard factor gamma_i of the boundary-integral method, computed geometrically from the wall
   segments (Calderon-Sanchez, Cercos-Pita & Duque 2019; derivation in docs/boundary-integrals.md):

     gamma(x) = 1 + sum_k (1/2pi) int_k (Phi(r) - 1) (e_r . n_k) / r dS,   r = |y - x|, e_r = (y - x)/r,

   Phi(r) being the kernel's mass inside radius r (1 beyond the support 2h), n_k pointing out of the
   liquid. On a straight segment (y - x) . n_k = d, the distance from x to the segment's line, so the
   integrand is d (Phi(r) - 1) / r^2: the -d/r^2 part integrates exactly (the angle the segment
   subtends), and d Phi(r)/r^2 is smooth and integrates by Gauss-Legendre on each side of the foot of
   the perpendicular. Only the part of the segment within the support counts, and by default only
   segments that face x (d > 0): a thin baffle's far face is hidden behind its near face. With
   -fs_walls_visibility all every segment counts, with its signed distance.
*/
#include "walls.h"

/* Wendland C2 in 2-D: Phi(q) = 7/2 (q^2/2 - 5/8 q^4 + 1/2 q^5 - 5/32 q^6 + q^7/56), q = r/h <= 2.
   Returns Phi(r)/r^2 (finite at r = 0). */
static inline PetscReal PhiOverR2(PetscReal h, PetscReal r)
{
  const PetscReal q = r / h;
  if (q >= 2) return 1.0 / (r * r);
  return 3.5 / (h * h) * (0.5 + q * q * (-0.625 + q * (0.5 + q * (-0.15625 + q / 56.0))));
}

static const PetscReal GaussX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                                    0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
static const PetscReal GaussW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066531250488, 0.3626837833783620,
                                    0.3626837833783620, 0.3137066531250488, 0.2223810344533745, 0.1012285362903763};

/* Wendland C2 in 2-D, W(r) = 7/(4 pi h^2) (1 - q/2)^4 (2q + 1), q = r/h <= 2 */
static inline PetscReal Wendland(PetscReal h, PetscReal r)
{
  const PetscReal q = r / h, a = 1 - 0.5 * q;
  return q >= 2 ? 0 : 7.0 / (4.0 * PETSC_PI * h * h) * a * a * a * a * (2 * q + 1);
}

/* int_{a}^{b} of Phi(r)/r^2 and of W(r), r = sqrt(d^2 + s^2), by 8-point Gauss-Legendre (a, b on one
   side of 0, within the support, where both are smooth), added to sums[0] and sums[1] */
static void IntegrateAlong(PetscReal h, PetscReal d, PetscReal a, PetscReal b, PetscReal sums[2])
{
  PetscReal phi = 0, w = 0, mid = 0.5 * (a + b), half = 0.5 * (b - a);
  if (half <= 0) return;
  for (PetscInt g = 0; g < 8; g++) {
    const PetscReal s = mid + half * GaussX[g], r = PetscSqrtReal(d * d + s * s);
    phi += GaussW[g] * PhiOverR2(h, r);
    w += GaussW[g] * Wendland(h, r);
  }
  sums[0] += phi * half;
  sums[1] += w * half;
}

/*
   FSSegmentIntegrals - a segment's contribution gamma_k to gamma(x) - 1, and int_k W(|y - x|) dS over
   its part within the support of x. The latter is the boundary terms' kernel weight: with it the
   wall part of grad gamma, -sum_k n_k int_k W dS, is the exact gradient of the geometric gamma, so
   the wall terms balance the particle sums the way gamma does (a midpoint rule W(x_k) s_k would not).
   Both from one set of quadrature points. With all = PETSC_FALSE only a segment that faces x counts
   (else both 0: a thin baffle's far face is hidden behind its near face); with all = PETSC_TRUE
   (-fs_walls_visibility all) a segment on either side counts, the integrand d (Phi(r) - 1)/r^2 with
   the signed distance d, negative for a segment that faces away, so that the sum over every segment
   within the support is the exact gamma of the liquid region in the support, whatever its shape.

   seg holds p0 (2), p1 (2), midpoint (2), normal (2), length.
*/
void FSSegmentIntegrals(PetscReal h, const PetscReal x[], const PetscReal seg[], PetscBool all, PetscReal *gammak,
                        PetscReal *wint)
{
  const PetscReal *p0 = seg + FS_SEG_P0, *p1 = seg + FS_SEG_P1, *n = seg + FS_SEG_NORMAL, len = seg[FS_SEG_LENGTH];
  const PetscReal  t[2] = {(p1[0] - p0[0]) / len, (p1[1] - p0[1]) / len};
  const PetscReal  ds   = (p0[0] - x[0]) * n[0] + (p0[1] - x[1]) * n[1]; /* > 0: x on the liquid side */
  const PetscReal  d    = PetscAbsReal(ds);
  const PetscReal  s0 = (x[0] - p0[0]) * t[0] + (x[1] - p0[1]) * t[1]; /* foot of the perpendicular along the segment */
  const PetscReal  R  = 2 * h;
  PetscReal        a, b, half, sums[2] = {0, 0}, ang;

  *gammak = *wint = 0;
  if ((!all && ds <= 0) || d >= R) return;
  half = PetscSqrtReal(R * R - d * d);
  a    = PetscMax(0.0, s0 - half) - s0; /* the part of the segment within the support, relative to the foot */
  b    = PetscMin(len, s0 + half) - s0;
  if (b <= a) return;
  if (a < 0 && b > 0) {
    IntegrateAlong(h, d, a, 0, sums);
    IntegrateAlong(h, d, 0, b, sums);
  } else IntegrateAlong(h, d, a, b, sums);
  *wint = sums[1];
  if (d == 0) return;                                    /* x on the segment's line: e_r . n = 0 */
  ang     = PetscAtan2Real(b, d) - PetscAtan2Real(a, d); /* int d/(d^2+s^2) ds */
  *gammak = (ds > 0 ? 1 : -1) * (d * sums[0] - ang) / (2 * PETSC_PI);
}

/*
   FSWallsShepard - gamma(x) and grad gamma(x) = -sum_k n_k int_k W dS from all segments, those that
   face x only or every one (all, as FSSegmentIntegrals): a reference implementation for tests and
   set-up; the solver uses its per-particle lists of nearby segments.
*/
PetscErrorCode FSWallsShepard(const FSWalls *w, PetscReal h, const PetscReal x[], PetscBool all, PetscReal *gamma,
                              PetscReal grad[])
{
  PetscFunctionBegin;
  *gamma  = 1;
  grad[0] = grad[1] = 0;
  for (PetscInt k = 0; k < w->nseg; k++) {
    const PetscReal *seg = &w->seg[k * FS_SEG_STRIDE];
    PetscReal        gk, wi;
    FSSegmentIntegrals(h, x, seg, all, &gk, &wi);
    *gamma += gk;
    grad[0] -= wi * seg[FS_SEG_NORMAL];
    grad[1] -= wi * seg[FS_SEG_NORMAL + 1];
  }
  PetscFunctionReturn(0);
}
