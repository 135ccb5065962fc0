/*
   The sensor model of a pressure probe (-fs_probes, probeset.c): what a physical pressure sensor adds
   to the pressure at a point.

   - Its face: the wall pressure averaged over the sensor's face, a disc of diameter D on the wall in 3-D, a
     segment of length D in 2-D. The boundary integrals' wall pressure is one value per wall element, so the
     exact face average is sum_e p_e |face ^ e| / sum_e |face ^ e|: the overlap of each element with the face,
     computed exactly (a segment's overlap with the face's segment, a triangle's intersection with the disc)
     in the face's plane, FSSensorSegmentOverlap() and FSSensorDiscTriangleArea().
   - Its time response: a low-pass filter of the sampled signal, first order (1/(1 + s/wc)) or second-order
     Butterworth (wc^2/(s^2 + sqrt(2) wc s + wc^2)), wc = 2 pi cutoff, and the sample-and-hold of an instrument
     sampling at a rate: the reading at t is the filter's output at the last sampling instant k/rate <= t.
     The probes are sampled at variable steps; between two samples the input is taken linear in time and the
     filter's ODE is integrated exactly over it (FSSensorFilterUpdate()), so that a constant or a linear
     signal passes exactly, whatever the steps, and a sampling instant between two samples reads the filter at
     that instant.
*/
#include "monitor/impls/probes/probesimpl.h"
#include <math.h>

/*
   FSSensorSegmentOverlap - the length of the overlap of [a, b] (in any order) with [-R, R]

   Not collective
*/
PetscReal FSSensorSegmentOverlap(PetscReal a, PetscReal b, PetscReal R)
{
  const PetscReal lo = PetscMax(PetscMin(a, b), -R), hi = PetscMin(PetscMax(a, b), R);
  return hi > lo ? hi - lo : 0;
}

/* the signed area of the disc of radius R (centred at the origin) intersected with the triangle (0, a, b):
   the edge from a to b is cut where it crosses the circle; a piece inside the circle adds its triangle with
   the origin, a piece outside adds the circular sector between its ends */
static PetscReal FSSensorDiscWedge(PetscReal R, const PetscReal a[2], const PetscReal b[2])
{
  const PetscReal d[2] = {b[0] - a[0], b[1] - a[1]}, A = d[0] * d[0] + d[1] * d[1], B = a[0] * d[0] + a[1] * d[1],
                  C = a[0] * a[0] + a[1] * a[1] - R * R;
  PetscReal t[4], area = 0;
  PetscInt  n = 0;

  if (A <= 0) return 0;
  t[n++] = 0;
  {
    const PetscReal disc = B * B - A * C;
    if (disc > 0) {
      const PetscReal sq = PetscSqrtReal(disc), t1 = (-B - sq) / A, t2 = (-B + sq) / A;
      if (t1 > 0 && t1 < 1) t[n++] = t1;
      if (t2 > 0 && t2 < 1) t[n++] = t2;
    }
  }
  t[n++] = 1;
  for (PetscInt k = 0; k + 1 < n; k++) {
    const PetscReal p[2] = {a[0] + t[k] * d[0], a[1] + t[k] * d[1]},
                    q[2] = {a[0] + t[k + 1] * d[0], a[1] + t[k + 1] * d[1]};
    const PetscReal tm = 0.5 * (t[k] + t[k + 1]), m[2] = {a[0] + tm * d[0], a[1] + tm * d[1]};
    const PetscReal cross = p[0] * q[1] - p[1] * q[0], dot = p[0] * q[0] + p[1] * q[1];
    if (m[0] * m[0] + m[1] * m[1] <= R * R) area += 0.5 * cross;
    else area += 0.5 * R * R * PetscAtan2Real(cross, dot);
  }
  return area;
}

/*
   FSSensorDiscTriangleArea - the area of the intersection of the disc of radius R centred at the origin with
   the triangle (p[0], p[1], p[2]) (points of the plane, either orientation), exact

   Not collective
*/
PetscReal FSSensorDiscTriangleArea(PetscReal R, const PetscReal p[3][2])
{
  PetscReal area = 0;
  for (PetscInt k = 0; k < 3; k++) area += FSSensorDiscWedge(R, p[k], p[(k + 1) % 3]);
  return PetscAbsReal(area);
}

/* advances the filter's state over tau from a point where the input is u0, rising at s (the input
   u0 + s t over the interval): the exact solution of the filter's ODE */
static void FSSensorFilterAdvance(FSSensorFilter *f, PetscReal tau, PetscReal u0, PetscReal s)
{
  const PetscReal w = f->omega;
  if (w <= 0) { /* no low-pass: the input itself */
    f->y[0] = u0 + s * tau;
    f->y[1] = s;
  } else if (f->order == 1) { /* y' = w (u - y): y = u - s/w + (y0 - u0 + s/w) e^{-w tau} */
    const PetscReal e = PetscExpReal(-w * tau);
    f->y[0]           = u0 + s * tau + (f->y[0] - u0) * e + (s / w) * (PetscReal)expm1((double)(-w * tau));
  } else { /* y'' + 2 z w y' + w^2 y = w^2 u, z = 1/sqrt(2): the particular solution (u - 2 z s/w, s) plus the
              free response, exp(A tau) = e^{-z w tau} (cos(wd tau) I + sin(wd tau)/wd (A + z w I)) */
    const PetscReal z = 1 / PetscSqrtReal(2.0), wd = w * PetscSqrtReal(1 - z * z), ex = PetscExpReal(-z * w * tau);
    const PetscReal c = PetscCosReal(wd * tau), sn = PetscSinReal(wd * tau) / wd;
    const PetscReal e0 = f->y[0] - (u0 - 2 * z * s / w), e1 = f->y[1] - s;
    f->y[0] = u0 + s * tau - 2 * z * s / w + ex * (c * e0 + sn * (z * w * e0 + e1));
    f->y[1] = s + ex * (c * e1 + sn * (-w * w * e0 - z * w * e1));
  }
}

/*
   FSSensorFilterUpdate - gives the filter the sample u of the signal at time t and returns the sensor's
   reading at t: the low-pass output, held at the last sampling instant when a rate is set

   Not collective

   Notes:
   The first sample starts the filter at rest at u (a steady reading). A sample at or before the last one's time
   changes nothing and returns the last reading. Between two samples the input is linear in time.
*/
PetscReal FSSensorFilterUpdate(FSSensorFilter *f, PetscReal t, PetscReal u)
{
  if (!f->started) {
    f->started = PETSC_TRUE;
    f->t       = t;
    f->u       = u;
    f->y[0]    = u;
    f->y[1]    = 0;
    f->held    = u;
    if (f->rate > 0) f->next = (PetscInt64)PetscFloorReal(t * f->rate) + 1; /* the first instant after t */
  } else if (t > f->t) {
    const PetscReal s  = (u - f->u) / (t - f->t);
    PetscReal       tc = f->t, uc = f->u;
    if (f->rate > 0)
      for (PetscReal tk = f->next / f->rate; tk <= t; tk = ++f->next / f->rate) {
        FSSensorFilterAdvance(f, tk - tc, uc, s);
        uc += s * (tk - tc);
        tc      = tk;
        f->held = f->y[0];
      }
    FSSensorFilterAdvance(f, t - tc, uc, s);
    f->t = t;
    f->u = u;
  }
  return f->rate > 0 ? f->held : f->y[0];
}
