/*
   Unit test of the tank frame's inertial accelerations (FSCouplingInertia, src/coupling): the
   acceleration a particle feels in the moving, turning tank frame must be the second derivative of its
   path in that frame when it is free in the absolute frame (gravity alone).

   The frame: its reference point c (tank_ref) displaced by D(t), the frame turned by theta(t) about z,
   so that a point r of the tank frame is at x = c + D(t) + R(theta(t)) (r - c). A particle falls
   freely, x(t) = x0 + v0 t + g t^2/2; in the tank frame r(t) = c + R(-theta) (x(t) - c - D(t)), whose
   velocity and acceleration are taken here by sixth-order central differences of that transformation,
   without the rotating frame's formulas. The rate the solver gives a particle at r with velocity r'
   (the gravity term's g plus FSCouplingInertia's part: translation, Euler, centrifugal, Coriolis) must
   equal r''. Each part is first order in one motion (a sign or factor of any of them is an error of the
   size of that part); checked in 2-D and 3-D (the frame turns about z, D has a z part), for several
   particles at several times, with the inertial power sum_i m_i u_i . a_i against the same sum of the
   expected accelerations.
   A 3-D frame turned about any axis (rotated): Q(t) = R_y(yaw) R_x(pitch) R_z(roll) R_n(psi), each angle a
   smooth function of time, built here from the elementary matrices; the motion the coupling receives is
   built by FSTankMotionRotate from the angles and their two exact derivatives, and the path is
   r(t) = c + Q^T (x(t) - c - D(t)): the same check, and Q against the matrices' product.
   Measured: relative error 7.4e-11 of the acceleration scale (the differences' truncation and round-off);
   tolerance 1e-9.
   Serial by nature (the coupling's inertial accelerations are per particle, no communication).
*/
#include "coupling/couplingimpl.h"

#define TCHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_frame: " __VA_ARGS__)
#define NP                6

static const PetscReal TOL = 1e-9;

/* the frame's motion: displacement D(t) of the reference point and angle theta(t), smooth and nonlinear */
static void FrameAt(PetscReal t, PetscReal D[3], PetscReal *theta)
{
  D[0]   = 0.03 * PetscSinReal(2.1 * t) + 0.02 * t * t;
  D[1]   = -0.05 * PetscCosReal(3.3 * t + 0.4) + 0.01 * t;
  D[2]   = 0.04 * PetscSinReal(1.7 * t + 1.0);
  *theta = 0.3 * PetscSinReal(2.7 * t + 0.2) + 0.8 * t + 0.1 * t * t;
}

/* a free particle's path in the tank frame: r(t) = c + R(-theta) (x(t) - c - D(t)) */
static void PathAt(PetscReal t, const PetscReal c[3], const PetscReal x0[3], const PetscReal v0[3],
                   const PetscReal g[3], PetscReal r[3])
{
  PetscReal D[3], th, x[3];
  FrameAt(t, D, &th);
  for (PetscInt d = 0; d < 3; d++) x[d] = x0[d] + v0[d] * t + 0.5 * g[d] * t * t - c[d] - D[d];
  r[0] = c[0] + PetscCosReal(th) * x[0] + PetscSinReal(th) * x[1];
  r[1] = c[1] - PetscSinReal(th) * x[0] + PetscCosReal(th) * x[1];
  r[2] = c[2] + x[2];
}

/* first and second derivatives of the path at t (sixth-order central differences, step e) */
static void PathDerivatives(PetscReal t, const PetscReal c[3], const PetscReal x0[3], const PetscReal v0[3],
                            const PetscReal g[3], PetscReal r[3], PetscReal v[3], PetscReal a[3])
{
  const PetscReal e = 2e-3, w1[3] = {3.0 / 4, -3.0 / 20, 1.0 / 60}, w2[4] = {-49.0 / 18, 3.0 / 2, -3.0 / 20, 1.0 / 90};
  PetscReal       rp[3], rm[3];

  PathAt(t, c, x0, v0, g, r);
  for (PetscInt d = 0; d < 3; d++) {
    v[d] = 0;
    a[d] = w2[0] * r[d];
  }
  for (PetscInt k = 1; k <= 3; k++) {
    PathAt(t + k * e, c, x0, v0, g, rp);
    PathAt(t - k * e, c, x0, v0, g, rm);
    for (PetscInt d = 0; d < 3; d++) {
      v[d] += w1[k - 1] * (rp[d] - rm[d]);
      a[d] += w2[k] * (rp[d] + rm[d]);
    }
  }
  for (PetscInt d = 0; d < 3; d++) {
    v[d] /= e;
    a[d] /= e * e;
  }
}

/* the frame's motion at t as the structure hands it to the coupling: the reference point's displacement,
   velocity and acceleration in the global axes, the angle, its rate and its angular acceleration */
static void MotionAt(PetscReal t, FSTankMotion *m)
{
  const PetscReal e = 1e-3;
  PetscReal       D[5][3], th[5];

  for (PetscInt k = 0; k < 5; k++) FrameAt(t + (k - 2) * e, D[k], &th[k]);
  for (PetscInt d = 0; d < 3; d++) {
    m->disp[d] = D[2][d];
    m->vel[d]  = (-D[4][d] + 8 * D[3][d] - 8 * D[1][d] + D[0][d]) / (12 * e);
    m->acc[d]  = (-D[4][d] + 16 * D[3][d] - 30 * D[2][d] + 16 * D[1][d] - D[0][d]) / (12 * e * e);
  }
  m->angle  = th[2];
  m->rate   = (-th[4] + 8 * th[3] - 8 * th[1] + th[0]) / (12 * e);
  m->angacc = (-th[4] + 16 * th[3] - 30 * th[2] + 16 * th[1] - th[0]) / (12 * e * e);
}

/* the rotated frame's angles yaw, pitch, roll, psi (about n) at t with their first two derivatives, a[k][0..2] */
static void AnglesAt(PetscReal t, PetscReal a[4][3])
{
  const PetscReal A[4] = {0.4, -0.3, 0.5, 0.7}, W[4] = {1.3, 2.2, 1.7, 0.9}, P[4] = {0.3, 1.1, -0.4, 0.8},
                  B[4] = {0.2, 0.1, -0.3, 0.25};
  for (PetscInt k = 0; k < 4; k++) { /* A sin(W t + P) + B t^2 */
    a[k][0] = A[k] * PetscSinReal(W[k] * t + P[k]) + B[k] * t * t;
    a[k][1] = A[k] * W[k] * PetscCosReal(W[k] * t + P[k]) + 2 * B[k] * t;
    a[k][2] = -A[k] * W[k] * W[k] * PetscSinReal(W[k] * t + P[k]) + 2 * B[k];
  }
}

static const PetscReal AxisN[3] = {0.3, -0.5, 0.8}; /* not normalized: FSTankMotionRotate normalizes */

/* Q(t) from the elementary matrices: R_y(yaw) R_x(pitch) R_z(roll) R_n(psi) */
static void RotationAt(PetscReal t, PetscReal Q[9])
{
  PetscReal a[4][3], M[4][9], T[9], n[3], len = 0;
  AnglesAt(t, a);
  for (PetscInt d = 0; d < 3; d++) len += AxisN[d] * AxisN[d];
  for (PetscInt d = 0; d < 3; d++) n[d] = AxisN[d] / PetscSqrtReal(len);
  {
    const PetscReal c = PetscCosReal(a[0][0]), s = PetscSinReal(a[0][0]);
    const PetscReal Ry[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
    for (PetscInt d = 0; d < 9; d++) M[0][d] = Ry[d];
  }
  {
    const PetscReal c = PetscCosReal(a[1][0]), s = PetscSinReal(a[1][0]);
    const PetscReal Rx[9] = {1, 0, 0, 0, c, -s, 0, s, c};
    for (PetscInt d = 0; d < 9; d++) M[1][d] = Rx[d];
  }
  {
    const PetscReal c = PetscCosReal(a[2][0]), s = PetscSinReal(a[2][0]);
    const PetscReal Rz[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    for (PetscInt d = 0; d < 9; d++) M[2][d] = Rz[d];
  }
  { /* about n: the frame whose z is n, turned about its z */
    const PetscReal c = PetscCosReal(a[3][0]), s = PetscSinReal(a[3][0]);
    for (PetscInt i = 0; i < 3; i++)
      for (PetscInt j = 0; j < 3; j++) {
        const PetscReal cross = (i == j) ? 0 : ((j == (i + 1) % 3) ? -n[3 - i - j] : n[3 - i - j]);
        M[3][3 * i + j]       = c * (i == j) + (1 - c) * n[i] * n[j] + s * cross;
      }
  }
  for (PetscInt d = 0; d < 9; d++) Q[d] = M[0][d];
  for (PetscInt k = 1; k < 4; k++) {
    for (PetscInt i = 0; i < 3; i++)
      for (PetscInt j = 0; j < 3; j++)
        T[3 * i + j] = Q[3 * i] * M[k][j] + Q[3 * i + 1] * M[k][3 + j] + Q[3 * i + 2] * M[k][6 + j];
    for (PetscInt d = 0; d < 9; d++) Q[d] = T[d];
  }
}

/* the rotated frame's path: r(t) = c + Q^T (x(t) - c - D(t)) */
static void PathAtRotated(PetscReal t, const PetscReal c[3], const PetscReal x0[3], const PetscReal v0[3],
                          const PetscReal g[3], PetscReal r[3])
{
  PetscReal D[3], th, x[3], Q[9];
  FrameAt(t, D, &th);
  RotationAt(t, Q);
  for (PetscInt d = 0; d < 3; d++) x[d] = x0[d] + v0[d] * t + 0.5 * g[d] * t * t - c[d] - D[d];
  for (PetscInt d = 0; d < 3; d++) r[d] = c[d] + Q[d] * x[0] + Q[3 + d] * x[1] + Q[6 + d] * x[2];
}

static void PathDerivativesRotated(PetscReal t, const PetscReal c[3], const PetscReal x0[3], const PetscReal v0[3],
                                   const PetscReal g[3], PetscReal r[3], PetscReal v[3], PetscReal a[3])
{
  const PetscReal e = 2e-3, w1[3] = {3.0 / 4, -3.0 / 20, 1.0 / 60}, w2[4] = {-49.0 / 18, 3.0 / 2, -3.0 / 20, 1.0 / 90};
  PetscReal       rp[3], rm[3];

  PathAtRotated(t, c, x0, v0, g, r);
  for (PetscInt d = 0; d < 3; d++) {
    v[d] = 0;
    a[d] = w2[0] * r[d];
  }
  for (PetscInt k = 1; k <= 3; k++) {
    PathAtRotated(t + k * e, c, x0, v0, g, rp);
    PathAtRotated(t - k * e, c, x0, v0, g, rm);
    for (PetscInt d = 0; d < 3; d++) {
      v[d] += w1[k - 1] * (rp[d] - rm[d]);
      a[d] += w2[k] * (rp[d] + rm[d]);
    }
  }
  for (PetscInt d = 0; d < 3; d++) {
    v[d] /= e;
    a[d] /= e * e;
  }
}

/* the inertial power from the particle sums that ride on the reaction's reduction (FSCouplingInertiaSums(),
   FSCouplingInertiaPower()) must be FSCouplingInertia()'s particle by particle sum to round-off */
static PetscErrorCode CheckPowerFromSums(FSCoupling cp, PetscInt n, PetscInt S, const PetscReal rec[], PetscReal power,
                                         PetscReal scale, const char what[], PetscReal t)
{
  PetscReal sums[FS_COUPLING_NINERTIA_SUMS], p;

  PetscFunctionBegin;
  FSCouplingInertiaSums(cp, n, S, rec, sums);
  PetscCall(FSCouplingInertiaPower(cp, sums, &p));
  TCHECK(PetscAbsReal(p - power) <= 1e-12 * (PetscAbsReal(power) + scale),
         "%s, t = %g: inertial power from the particle sums %.15g, particle by particle %.15g", what, (double)t,
         (double)p, (double)power);
  PetscFunctionReturn(0);
}

/* the rotated frame turns the tank about every axis at once: accelerations, power and Q */
static PetscErrorCode CheckRotatedFrame(PetscReal *maxerr)
{
  const PetscInt  dim = 3, S = 8, US = 7;
  const PetscReal c[3] = {0.4, -0.2, 0.05}, g[3] = {0.3, -9.81, -0.7}, times[3] = {0.0, 0.37, 1.21};
  const PetscReal ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
  FSCoupling      cp;
  PetscReal       rec[NP * 8], f[NP * 7], expect[NP][3], scale = 0;

  PetscFunctionBegin;
  PetscCall(FSCouplingCreate(PETSC_COMM_SELF, &cp));
  cp->dim = dim;
  for (PetscInt d = 0; d < 3; d++) {
    cp->gravity[d]  = g[d];
    cp->tank_ref[d] = c[d];
  }
  for (PetscInt it = 0; it < 3; it++) {
    const PetscReal t = times[it];
    FSTankMotion    m;
    PetscReal       power, epower = 0, a[4][3], Q[9];

    PetscCall(PetscMemzero(&m, sizeof(m)));
    MotionAt(t, &m);
    AnglesAt(t, a);
    PetscCall(FSTankMotionRotate(&m, ey, a[0]));
    PetscCall(FSTankMotionRotate(&m, ex, a[1]));
    PetscCall(FSTankMotionRotate(&m, ez, a[2]));
    PetscCall(FSTankMotionRotate(&m, AxisN, a[3]));
    RotationAt(t, Q);
    for (PetscInt d = 0; d < 9; d++)
      TCHECK(PetscAbsReal(m.Q[d] - Q[d]) < 1e-14, "t = %g: Q[%" PetscInt_FMT "] = %.15g, the matrices give %.15g",
             (double)t, d, (double)m.Q[d], (double)Q[d]);
    PetscCall(FSCouplingSetMotion(cp, &m));
    for (PetscInt i = 0; i < NP; i++) {
      const PetscReal x0[3] = {0.1 + 0.13 * i, 0.05 + 0.07 * (i % 3), 0.02 * i - 0.05};
      const PetscReal v0[3] = {0.5 - 0.2 * i, 0.3 * (i % 2) - 0.4, 0.1 * i - 0.2};
      PetscReal       r[3], v[3], acc[3], *ri = &rec[i * S];
      PathDerivativesRotated(t, c, x0, v0, g, r, v, acc);
      for (PetscInt d = 0; d < dim; d++) {
        ri[d]               = r[d];
        ri[dim + d]         = v[d];
        f[i * US + dim + d] = g[d];
        expect[i][d]        = acc[d];
        scale               = PetscMax(scale, PetscAbsReal(acc[d] - g[d]));
      }
      ri[2 * dim]     = 1000;
      ri[2 * dim + 1] = 0.01 * (1 + i);
    }
    PetscCall(FSCouplingInertia(cp, NP, S, rec, US, f, &power));
    for (PetscInt i = 0; i < NP; i++) {
      for (PetscInt d = 0; d < dim; d++) {
        const PetscReal err = PetscAbsReal(f[i * US + dim + d] - expect[i][d]) / scale;
        *maxerr             = PetscMax(*maxerr, err);
        TCHECK(err <= TOL,
               "rotated, t = %g, particle %" PetscInt_FMT ", component %" PetscInt_FMT
               ": the frame gives %.12g, the free path's acceleration is %.12g (relative error %.3g > %g)",
               (double)t, i, d, (double)f[i * US + dim + d], (double)expect[i][d], (double)err, (double)TOL);
        epower += rec[i * S + 2 * dim + 1] * rec[i * S + dim + d] * (expect[i][d] - g[d]);
      }
    }
    TCHECK(PetscAbsReal(power - epower) <= 10 * TOL * PetscAbsReal(epower) + TOL * scale,
           "rotated, t = %g: inertial power %.12g, expected %.12g", (double)t, (double)power, (double)epower);
    PetscCall(CheckPowerFromSums(cp, NP, S, rec, power, scale, "rotated", t));
  }
  PetscCall(FSCouplingDestroy(&cp));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckFrame(PetscInt dim, PetscReal *maxerr)
{
  const PetscInt  S = 2 * dim + 2, US = 2 * dim + 1;
  const PetscReal c[3] = {0.4, -0.2, 0.05}, g[3] = {0.3, -9.81, dim == 3 ? -0.7 : 0};
  const PetscReal times[3] = {0.0, 0.37, 1.21};
  FSCoupling      cp;
  PetscReal       rec[NP * 8], f[NP * 7], expect[NP][3], scale = 0;

  PetscFunctionBegin;
  PetscCall(FSCouplingCreate(PETSC_COMM_SELF, &cp));
  cp->dim = dim;
  for (PetscInt d = 0; d < 3; d++) {
    cp->gravity[d]  = g[d];
    cp->tank_ref[d] = c[d];
  }
  for (PetscInt it = 0; it < 3; it++) {
    const PetscReal t = times[it];
    FSTankMotion    m;
    PetscReal       power, epower = 0;

    PetscCall(PetscMemzero(&m, sizeof(m)));
    MotionAt(t, &m);
    if (dim == 2) m.disp[2] = m.vel[2] = m.acc[2] = 0; /* a 2-D tank moves in its plane */
    PetscCall(FSCouplingSetMotion(cp, &m));
    for (PetscInt i = 0; i < NP; i++) { /* particles spread over the tank, with various absolute velocities */
      const PetscReal x0[3] = {0.1 + 0.13 * i, 0.05 + 0.07 * (i % 3), dim == 3 ? 0.02 * i - 0.05 : 0};
      const PetscReal v0[3] = {0.5 - 0.2 * i, 0.3 * (i % 2) - 0.4, dim == 3 ? 0.1 * i - 0.2 : 0};
      PetscReal       r[3], v[3], a[3], *ri = &rec[i * S];
      PathDerivatives(t, c, x0, v0, g, r, v, a);
      for (PetscInt d = 0; d < dim; d++) {
        ri[d]               = r[d];
        ri[dim + d]         = v[d];
        f[i * US + dim + d] = g[d]; /* the gravity term's rate */
        expect[i][d]        = a[d];
        scale               = PetscMax(scale, PetscAbsReal(a[d] - g[d]));
      }
      ri[2 * dim]     = 1000;
      ri[2 * dim + 1] = 0.01 * (1 + i);
    }
    PetscCall(FSCouplingInertia(cp, NP, S, rec, US, f, &power));
    for (PetscInt i = 0; i < NP; i++) {
      for (PetscInt d = 0; d < dim; d++) {
        const PetscReal err = PetscAbsReal(f[i * US + dim + d] - expect[i][d]) / scale;
        *maxerr             = PetscMax(*maxerr, err);
        TCHECK(err <= TOL,
               "%" PetscInt_FMT "-D, t = %g, particle %" PetscInt_FMT ", component %" PetscInt_FMT
               ": the frame gives %.12g, the free path's acceleration is %.12g (relative error %.3g > %g)",
               dim, (double)t, i, d, (double)f[i * US + dim + d], (double)expect[i][d], (double)err, (double)TOL);
        epower += rec[i * S + 2 * dim + 1] * rec[i * S + dim + d] * (expect[i][d] - g[d]);
      }
    }
    TCHECK(PetscAbsReal(power - epower) <= 10 * TOL * PetscAbsReal(epower) + TOL * scale,
           "%" PetscInt_FMT "-D, t = %g: inertial power %.12g, expected %.12g", dim, (double)t, (double)power,
           (double)epower);
    PetscCall(CheckPowerFromSums(cp, NP, S, rec, power, scale, dim == 2 ? "2-D" : "3-D", t));
  }
  PetscCall(FSCouplingDestroy(&cp));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscReal maxerr = 0;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(CheckFrame(2, &maxerr));
  PetscCall(CheckFrame(3, &maxerr));
  PetscCall(CheckRotatedFrame(&maxerr));
  PetscCall(
      PetscPrintf(PETSC_COMM_WORLD,
                  "test_frame: the tank frame's accelerations are the free paths' (largest relative error %.2g)\n",
                  (double)maxerr));
  PetscCall(PetscFinalize());
  return 0;
}
