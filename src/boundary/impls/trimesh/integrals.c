/*
   The Shepard factor gamma_i of the boundary-integral method in 3-D, computed geometrically from the
   wall triangles (derivation in docs/boundary-integrals.md):

     gamma(x) = 1 + sum_T [ int_T Phi(r)/(4 pi r^2) (e_r . n_T) dS - Omega_T(x)/(4 pi) ],

   Phi(r) the 3-D kernel's mass inside radius r, r = |y - x|, e_r = (y - x)/r, n_T out of the liquid,
   Omega_T the signed solid angle of T seen from x (exact, FSTriangleSolidAngle). On a flat triangle
   (y - x) . n_T = d_T, the distance from x to its plane, so the first integrand is d_T Phi(r)/(4 pi r^3),
   bounded (Phi ~ r^3 at 0) and smooth: a 7-point Gauss rule of degree 5 (Dunavant 1985) on elements of
   edge h, those near x split once into four, gives gamma to 5e-7 (docs/boundary-integrals.md). Beyond the
   support Phi = 1 and the bracket vanishes, so only triangles within 2h count. The same points give
   int_T W dS, the wall terms' weight.
*/
#include "mesh.h"

/* Wendland C2 in 3-D, q = r/h <= 2: W = 21/(16 pi h^3) (1 - q/2)^4 (2q + 1), and its mass inside r,
   Phi = 4 pi int_0^r W s^2 ds = 21/4 (q^3/3 - q^5/2 + 5/12 q^6 - 15/112 q^7 + q^8/64), so that
   Phi/r^3 = 21/(4 h^3) (1/3 - q^2/2 + 5/12 q^3 - 15/112 q^4 + q^5/64) (FSTriangleIntegrals). */

/* an element whose centroid is nearer to x than this many of its radii is integrated as its four halves-scaled
   copies (elements of edge h then give gamma within 4.6e-7 of elements of edge h/8, 1.9e-6 without the split:
   docs/boundary-integrals.md) */
#define FS_TRI_SPLIT 1.5

/* Dunavant's 7-point rule, degree 5: barycentric coordinates of the points and weights (sum 1) */
#define FS_SQRT15 3.872983346207416885
static const PetscReal DunavantA[3] = {1.0 / 3.0, (9 - 2 * FS_SQRT15) / 21, (9 + 2 * FS_SQRT15) / 21};
static const PetscReal DunavantB[3] = {1.0 / 3.0, (6 + FS_SQRT15) / 21, (6 - FS_SQRT15) / 21};
static const PetscReal DunavantW[3] = {0.225, (155 + FS_SQRT15) / 1200, (155 - FS_SQRT15) / 1200};

/* the 7 points of the rule on the triangle with vertices a, b, c, into y (3 reals each). Computed where used
   rather than stored with the element: 21 reals an element against a few multiplications per element within a
   particle's support. */
static inline void FSTriangleQuadraturePoints(const PetscReal a[], const PetscReal b[], const PetscReal c[],
                                              PetscReal y[])
{
  for (PetscInt g = 0; g < 7; g++) {
    const PetscInt  set = g == 0 ? 0 : (g < 4 ? 1 : 2), rot = (g - 1) % 3;
    const PetscReal la = set && rot == 0 ? DunavantA[set] : DunavantB[set];
    const PetscReal lb = set && rot == 1 ? DunavantA[set] : DunavantB[set];
    const PetscReal lc = 1 - la - lb;
    for (PetscInt d = 0; d < 3; d++) y[3 * g + d] = la * a[d] + lb * b[d] + lc * c[d];
  }
}

/* the rule on the triangle a, b, c with its weights scaled by scale: adds its sums of Phi(r)/r^3 to *phi and of
   W(r) to *w (the mean values over the triangle, to be multiplied by its area) */
static inline void FSTriangleRule(PetscReal h, const PetscReal x[], const PetscReal a[], const PetscReal b[],
                                  const PetscReal c[], PetscReal scale, PetscReal *phi, PetscReal *w)
{
  const PetscReal R = 2 * h, ih = 1 / h, wnorm = 21.0 / (16.0 * PETSC_PI * h * h * h), pnorm = 5.25 * ih * ih * ih;
  PetscReal       y[21], sp = 0, sw = 0;

  FSTriangleQuadraturePoints(a, b, c, y);
  for (PetscInt g = 0; g < 7; g++) {
    const PetscReal *p  = y + 3 * g;
    const PetscReal  r2 = (p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) + (p[2] - x[2]) * (p[2] - x[2]);
    const PetscReal  wg = DunavantW[g == 0 ? 0 : (g < 4 ? 1 : 2)];
    if (r2 >= R * R) sp += wg / (r2 * PetscSqrtReal(r2)); /* Phi = 1, W = 0 beyond the support */
    else {
      const PetscReal q = PetscSqrtReal(r2) * ih, s = 1 - 0.5 * q, s2 = s * s;
      sp += wg * pnorm * (1.0 / 3.0 + q * q * (-0.5 + q * (5.0 / 12.0 + q * (-15.0 / 112.0 + q / 64.0))));
      sw += wg * wnorm * s2 * s2 * (2 * q + 1);
    }
  }
  *phi += scale * sp;
  *w += scale * sw;
}

/*
   FSTriangleIntegrals - an element's contribution gamma_k to gamma(x) - 1, and int_k W(|y - x|) dS
   over it, from the same quadrature points. The latter is the wall terms' kernel weight: with it
   the wall part of grad gamma, -sum_k n_k int_k W dS, is the gradient of the geometric gamma.
   With all = PETSC_FALSE only an element that faces x (x on the liquid side of its plane) counts,
   else both are 0 (a thin baffle's far face is hidden behind its near face); with all = PETSC_TRUE
   (-fs_walls_visibility all) every element within the support counts with its signed distance.
   An element whose centroid lies within FS_TRI_SPLIT of its radii from x, where the integrands vary most
   across it, is integrated as its four halves-scaled copies (the rule on each).

   el is an element row (mesh.h: FS_TRI_*).
*/
void FSTriangleIntegrals(PetscReal h, const PetscReal x[], const PetscReal el[], PetscBool all, PetscReal *gammak,
                         PetscReal *wint)
{
  const PetscReal *a = el + FS_TRI_P0, *b = el + FS_TRI_P1, *c = el + FS_TRI_P2, *n = el + FS_TRI_NORMAL;
  const PetscReal  d = (a[0] - x[0]) * n[0] + (a[1] - x[1]) * n[1] + (a[2] - x[2]) * n[2]; /* > 0: facing */
  const PetscReal  R = 2 * h, *ct = el + FS_TRI_CENTROID, rad = el[FS_TRI_RADIUS];
  PetscReal        dc2, phi = 0, w = 0;

  *gammak = *wint = 0;
  if ((!all && d <= 0) || PetscAbsReal(d) >= R) return;
  dc2 = (ct[0] - x[0]) * (ct[0] - x[0]) + (ct[1] - x[1]) * (ct[1] - x[1]) + (ct[2] - x[2]) * (ct[2] - x[2]);
  /* beyond the support: its bounding sphere first, the exact distance where the sphere straddles it */
  if (dc2 >= (R + rad) * (R + rad)) return;
  if ((rad >= R || dc2 > (R - rad) * (R - rad)) && FSTriangleDistance2(a, b, c, x) >= R * R) return;
  if (dc2 < FS_TRI_SPLIT * FS_TRI_SPLIT * rad * rad) { /* near x: the rule on the four halves-scaled copies */
    PetscReal ab[3], bc[3], ca[3];
    for (PetscInt k = 0; k < 3; k++) {
      ab[k] = 0.5 * (a[k] + b[k]);
      bc[k] = 0.5 * (b[k] + c[k]);
      ca[k] = 0.5 * (c[k] + a[k]);
    }
    FSTriangleRule(h, x, a, ab, ca, 0.25, &phi, &w);
    FSTriangleRule(h, x, ab, b, bc, 0.25, &phi, &w);
    FSTriangleRule(h, x, ca, bc, c, 0.25, &phi, &w);
    FSTriangleRule(h, x, bc, ca, ab, 0.25, &phi, &w);
  } else FSTriangleRule(h, x, a, b, c, 1, &phi, &w);
  *wint = w * el[FS_TRI_AREA];
  if (d == 0) return; /* x in the element's plane: e_r . n = 0 and no solid angle */
  *gammak = (d * phi * el[FS_TRI_AREA] - FSTriangleSolidAngle(a, b, c, x)) / (4 * PETSC_PI);
}

/*
   FSMeshShepard - gamma(x) and grad gamma(x) = -sum_k n_k int_k W dS from all the elements, those that
   face x only or every one (all, as FSTriangleIntegrals): a reference for tests and set-up; the
   solver uses its per-particle lists of nearby elements.
*/
PetscErrorCode FSMeshShepard(const FSMesh *m, PetscReal h, const PetscReal x[], PetscBool all, PetscReal *gamma,
                             PetscReal grad[])
{
  PetscFunctionBegin;
  *gamma  = 1;
  grad[0] = grad[1] = grad[2] = 0;
  for (PetscInt k = 0; k < m->nel; k++) {
    const PetscReal *el = &m->el[k * FS_TRI_STRIDE];
    PetscReal        gk, wi;
    FSTriangleIntegrals(h, x, el, all, &gk, &wi);
    *gamma += gk;
    for (PetscInt d = 0; d < 3; d++) grad[d] -= wi * el[FS_TRI_NORMAL + d];
  }
  PetscFunctionReturn(0);
}
