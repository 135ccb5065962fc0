/*
   Unit tests of the sensor model of the pressure probes (src/monitor/impls/probes/sensor.c):
   - the face: the area of a disc intersected with a triangle against exact areas (a triangle inside the disc, the
     disc inside a triangle, a quarter and a half disc, the disc below a chord, a fan of triangles around an
     off-centre point that tiles a square holding the disc, either orientation), and a segment's overlap;
   - the time response at variable steps (steps drawn between 0.4 and 1.6 of a mean): a constant passes
     unchanged (first and second order, with a sample-and-hold); a ramp then hold (kink on a sample) through the
     first-order filter equals its exact response to 1e-12; a sine at the cut-off frequency comes out with the
     exact amplitude and phase (first order: 1/sqrt(2), -45 degrees; second-order Butterworth: 1/sqrt(2), -90
     degrees; also at half the cut-off) within the O(dt^2) of the linear input between samples; the
     sample-and-hold of a ramp reads the filtered ramp at the last instant k/rate.
*/
#include <math.h>
#include "monitor/impls/probes/probesimpl.h"

#define CHECK(cond, ...) PetscCheck(cond, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test_sensor: " __VA_ARGS__)

/* a pseudo-random step in [0.4, 1.6] h (a fixed sequence) */
static PetscReal Step(PetscReal h, unsigned *seed)
{
  *seed = *seed * 1103515245u + 12345u;
  return h * (0.4 + 1.2 * ((*seed >> 8) & 0xffff) / 65535.0);
}

/* the steady amplitude and phase of the filter's reading of sin(w t): its least-squares fit a sin + b cos over the
   last two periods of a run of ncycles periods at steps about T/nper */
static void SineResponse(PetscInt order, PetscReal fc, PetscReal f, PetscReal nper, PetscReal *amp, PetscReal *phase)
{
  FSSensorFilter  flt = {.order = order, .omega = 2 * PETSC_PI * fc};
  const PetscReal w = 2 * PETSC_PI * f, T = 1 / f, tend = 40 * T;
  PetscReal       ss = 0, sc = 0, cc = 0, ys = 0, yc = 0, t = 0;
  unsigned        seed = 7;
  while (t < tend) {
    const PetscReal y = FSSensorFilterUpdate(&flt, t, PetscSinReal(w * t));
    if (t > tend - 2 * T) { /* the fit's normal equations */
      const PetscReal sn = PetscSinReal(w * t), cs = PetscCosReal(w * t);
      ss += sn * sn;
      sc += sn * cs;
      cc += cs * cs;
      ys += y * sn;
      yc += y * cs;
    }
    t += Step(T / nper, &seed);
  }
  {
    const PetscReal det = ss * cc - sc * sc, a = (ys * cc - yc * sc) / det, b = (yc * ss - ys * sc) / det;
    *amp   = PetscSqrtReal(a * a + b * b);
    *phase = PetscAtan2Real(b, a);
  }
}

int main(int argc, char **argv)
{
  const PetscReal R = 0.7;

  PetscFunctionBeginUser;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  /* the face */
  {
    const PetscReal in[3][2] = {{-0.2, -0.1}, {0.3, 0.0}, {0.0, 0.4}}, big[3][2] = {{-5, -5}, {5, -5}, {0, 6}};
    const PetscReal quarter[3][2] = {{0, 0}, {2 * R, 0}, {0, 2 * R}}, half[3][2] = {{-10, 0}, {0, -10}, {10, 0}};
    const PetscReal rev[3][2] = {{0, 0}, {0, 2 * R}, {2 * R, 0}}, c = 0.3;
    const PetscReal below[3][2] = {{-20, c}, {20, c}, {0, -30}}; /* the disc below the chord y = c */
    const PetscReal exact_below = R * R * (PETSC_PI - PetscAcosReal(c / R)) + c * PetscSqrtReal(R * R - c * c);
    CHECK(PetscAbsReal(FSSensorDiscTriangleArea(R, in) - 0.115) < 1e-14,
          "a triangle inside the disc: %g, expected 0.115", (double)FSSensorDiscTriangleArea(R, in));
    CHECK(PetscAbsReal(FSSensorDiscTriangleArea(R, big) - PETSC_PI * R * R) < 1e-13, "the disc inside: %g, expected %g",
          (double)FSSensorDiscTriangleArea(R, big), (double)(PETSC_PI * R * R));
    CHECK(PetscAbsReal(FSSensorDiscTriangleArea(R, quarter) - 0.25 * PETSC_PI * R * R) < 1e-13 &&
              PetscAbsReal(FSSensorDiscTriangleArea(R, rev) - 0.25 * PETSC_PI * R * R) < 1e-13,
          "a quarter disc (both orientations): %g, %g, expected %g", (double)FSSensorDiscTriangleArea(R, quarter),
          (double)FSSensorDiscTriangleArea(R, rev), (double)(0.25 * PETSC_PI * R * R));
    CHECK(PetscAbsReal(FSSensorDiscTriangleArea(R, half) - 0.5 * PETSC_PI * R * R) < 1e-13, "a half disc: %g",
          (double)FSSensorDiscTriangleArea(R, half));
    CHECK(PetscAbsReal(FSSensorDiscTriangleArea(R, below) - exact_below) < 1e-13, "below a chord: %g, expected %g",
          (double)FSSensorDiscTriangleArea(R, below), (double)exact_below);
    { /* a fan around (0.31, -0.22) of 4 x 7 triangles to the boundary of the square [-1, 1]^2: they tile it, the
         disc of radius 0.7 lies inside, and their edges cut the circle in every way */
      const PetscReal o[2] = {0.31, -0.22};
      PetscReal       sum  = 0;
      for (PetscInt side = 0; side < 4; side++)
        for (PetscInt k = 0; k < 7; k++) {
          PetscReal tri[3][2], a = -1 + 2.0 * k / 7, b = -1 + 2.0 * (k + 1) / 7;
          tri[0][0] = o[0];
          tri[0][1] = o[1];
          switch (side) {
          case 0: tri[1][0] = a, tri[1][1] = -1, tri[2][0] = b, tri[2][1] = -1; break;
          case 1: tri[1][0] = 1, tri[1][1] = a, tri[2][0] = 1, tri[2][1] = b; break;
          case 2: tri[1][0] = -a, tri[1][1] = 1, tri[2][0] = -b, tri[2][1] = 1; break;
          default: tri[1][0] = -1, tri[1][1] = -a, tri[2][0] = -1, tri[2][1] = -b;
          }
          sum += FSSensorDiscTriangleArea(R, tri);
        }
      CHECK(PetscAbsReal(sum - PETSC_PI * R * R) < 1e-13, "a fan tiling the square: %g, expected %g", (double)sum,
            (double)(PETSC_PI * R * R));
    }
    CHECK(FSSensorSegmentOverlap(0.5, -2, 1) == 1.5 && FSSensorSegmentOverlap(-0.2, 0.3, 1) == 0.5 &&
              FSSensorSegmentOverlap(1.5, 2, 1) == 0,
          "segment overlaps");
  }
  /* a constant passes unchanged */
  for (PetscInt order = 1; order <= 2; order++) {
    FSSensorFilter f = {.order = order, .omega = 2 * PETSC_PI * 30, .rate = 700};
    PetscReal      t = 0.0123, y = 0;
    unsigned       seed = 3;
    for (PetscInt k = 0; k < 500; k++, t += Step(1e-3, &seed)) y = FSSensorFilterUpdate(&f, t, 2345.678);
    CHECK(PetscAbsReal(y - 2345.678) < 1e-12 * 2345.678, "order %" PetscInt_FMT ": a constant reads %.15g", order,
          (double)y);
  }
  { /* a ramp to t = tr, then constant, through the first-order filter at variable steps: exact */
    const PetscReal w = 2 * PETSC_PI * 20, tr = 0.05;
    FSSensorFilter  f = {.order = 1, .omega = w};
    PetscReal       t = 0, err = 0;
    unsigned        seed = 11;
    while (t < 0.2) {
      const PetscReal u = t < tr ? t / tr : 1, y = FSSensorFilterUpdate(&f, t, u);
      const PetscReal yr = PetscMin(t, tr) / tr - (1 - PetscExpReal(-w * PetscMin(t, tr))) / (w * tr);
      const PetscReal ex = t <= tr ? yr : 1 + (yr - 1) * PetscExpReal(-w * (t - tr));
      PetscReal       tn = t + Step(1e-3, &seed);
      err                = PetscMax(err, PetscAbsReal(y - ex));
      if (t < tr && tn > tr) tn = tr; /* a sample on the kink */
      t = tn;
    }
    CHECK(err < 1e-12, "ramp and hold through the first-order filter: error %g", (double)err);
  }
  { /* sines: amplitude and phase of the steady response */
    PetscReal a, p;
    SineResponse(1, 10, 10, 200, &a, &p);
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "test_sensor: first order at the cut-off: amplitude %+.2e, phase %+.2e rad\n",
                          (double)(a - 1 / PetscSqrtReal(2)), (double)(p + PETSC_PI / 4)));
    CHECK(PetscAbsReal(a - 1 / PetscSqrtReal(2)) < 2e-4 && PetscAbsReal(p + PETSC_PI / 4) < 2e-3,
          "first order at the cut-off: amplitude %g (1/sqrt(2)), phase %g (-pi/4)", (double)a, (double)p);
    SineResponse(1, 10, 5, 200, &a, &p);
    CHECK(PetscAbsReal(a - 1 / PetscSqrtReal(1.25)) < 2e-4 && PetscAbsReal(p + PetscAtanReal(0.5)) < 2e-3,
          "first order at half the cut-off: amplitude %g, phase %g", (double)a, (double)p);
    SineResponse(2, 10, 10, 200, &a, &p);
    PetscCall(PetscPrintf(PETSC_COMM_SELF,
                          "test_sensor: Butterworth at the cut-off: amplitude %+.2e, phase %+.2e rad\n",
                          (double)(a - 1 / PetscSqrtReal(2)), (double)(p + PETSC_PI / 2)));
    CHECK(PetscAbsReal(a - 1 / PetscSqrtReal(2)) < 2e-4 && PetscAbsReal(p + PETSC_PI / 2) < 2e-3,
          "Butterworth at the cut-off: amplitude %g (1/sqrt(2)), phase %g (-pi/2)", (double)a, (double)p);
    SineResponse(2, 10, 5, 200, &a, &p);
    CHECK(PetscAbsReal(a - 1 / PetscSqrtReal(1 + 0.0625)) < 2e-4 &&
              PetscAbsReal(p + PetscAtan2Real(PetscSqrtReal(2) * 0.5, 0.75)) < 2e-3,
          "Butterworth at half the cut-off: amplitude %g, phase %g", (double)a, (double)p);
  }
  { /* the sample-and-hold of a ramp (rate 1 kHz, samples every 0.4-1.6 ms) through a first-order filter */
    const PetscReal w = 2 * PETSC_PI * 50, rate = 1000;
    FSSensorFilter  f = {.order = 1, .omega = w, .rate = rate};
    PetscReal       t = 0, err = 0;
    unsigned        seed = 5;
    for (; t < 0.1; t += Step(1e-3, &seed)) {
      const PetscReal y = FSSensorFilterUpdate(&f, t, 3 * t), tk = PetscFloorReal(t * rate) / rate;
      const PetscReal ex = t * rate < 1 ? 0 : 3 * tk - 3 * (1 - PetscExpReal(-w * tk)) / w;
      err                = PetscMax(err, PetscAbsReal(y - ex));
    }
    CHECK(err < 1e-12, "sample-and-hold of a filtered ramp: error %g", (double)err);
  }
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "test_sensor: the face's areas exact, the filters exact for constants and "
                                         "ramps, amplitude and phase of sines, the sample-and-hold\n"));
  PetscCall(PetscFinalize());
  return 0;
}
