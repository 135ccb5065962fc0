/*
   A component of a prescribed motion from a time-series file. The file has one point a line, the time
   (s) and the value, separated by blanks, tabs or a comma; '#' starts a comment, blank lines are
   skipped. Times strictly increase; at least two points. The points are joined by a natural cubic
   spline (second derivative zero at both ends) and continued by straight lines before the first and
   after the last point: the value, the velocity and the acceleration are continuous everywhere (C2),
   so the inertial forces the liquid feels have no jumps. A file of several components (a 6-DOF motion:
   the time and six values a line) gives one such spline per column (FSMotionSeriesLoadColumns).
*/
#include <math.h>
#include <stdio.h>
#include "motionseries.h"
#include "sys/fssys.h"

/* the next number of a line (blanks, tabs and commas separate); PETSC_FALSE at the end of the line */
static PetscBool NextNumber(char **p, PetscReal *v, PetscBool *bad)
{
  char  *end;
  double d;

  while (**p == ' ' || **p == '\t' || **p == ',' || **p == '\r' || **p == '\n') (*p)++;
  if (!**p) return PETSC_FALSE;
  d = strtod(*p, &end);
  if (end == *p || !(*end == 0 || *end == ' ' || *end == '\t' || *end == ',' || *end == '\r' || *end == '\n') ||
      !isfinite(d)) {
    *bad = PETSC_TRUE;
    return PETSC_FALSE;
  }
  *p = end;
  *v = (PetscReal)d;
  return PETSC_TRUE;
}

/* the natural spline's second derivatives M (tridiagonal system, Thomas algorithm; w: n work values) */
static void SplineSecondDerivatives(PetscInt n, const PetscReal t[], const PetscReal y[], PetscReal M[], PetscReal w[])
{
  M[0] = M[n - 1] = 0;
  w[0]            = 0;
  for (PetscInt i = 1; i < n - 1; i++) { /* forward elimination of h_{i-1} M_{i-1} + 2(h_{i-1}+h_i) M_i + h_i M_{i+1} */
    const PetscReal h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
    const PetscReal r   = 6 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
    const PetscReal piv = 2 * (h0 + h1) - h0 * w[i - 1];
    w[i]                = h1 / piv;
    M[i]                = (r - h0 * M[i - 1]) / piv;
  }
  for (PetscInt i = n - 2; i > 0; i--) M[i] -= w[i] * M[i + 1];
}

/*
   FSMotionSeriesLoad - reads a time-series file and builds its spline; the values are multiplied by
   scale (e.g. degrees to radians). Errors name the option, the file and the line.

   Collective (every rank reads the file)
*/
PetscErrorCode FSMotionSeriesLoad(MPI_Comm comm, const char file[], const char option[], PetscReal scale,
                                  FSMotionSeries *s)
{
  PetscFunctionBegin;
  PetscCall(FSMotionSeriesLoadColumns(comm, file, option, 1, &scale, "two finite numbers, the time and the value", s));
  PetscFunctionReturn(0);
}

/*
   FSMotionSeriesLoadColumns - reads a file of lines 'time v_1 ... v_nc' and builds one spline per column
   s[0..nc) (column k multiplied by scale[k]); what names the numbers a line must hold, for the errors.

   Collective (every rank reads the file)
*/
PetscErrorCode FSMotionSeriesLoadColumns(MPI_Comm comm, const char file[], const char option[], PetscInt nc,
                                         const PetscReal scale[], const char what[], FSMotionSeries s[])
{
  FILE      *fp;
  char      *line    = NULL;
  size_t     linecap = 0;
  ssize_t    len;
  PetscInt   cap = 256, lineno = 0, np = 0;
  PetscReal *w, *T, *Y; /* the times, the values (nc a point) */

  PetscFunctionBegin;
  PetscCheck(nc >= 1 && nc <= FS_MOTION_MAX_COLUMNS, comm, PETSC_ERR_PLIB, "%" PetscInt_FMT " columns", nc);
  for (PetscInt k = 0; k < nc; k++) {
    PetscCall(PetscMemzero(&s[k], sizeof(s[k])));
    PetscCall(PetscStrncpy(s[k].file, file, sizeof(s[k].file)));
  }
  {
    PetscBool   elsewhere;
    const char *why;
    PetscCall(FSFileOpenOnEveryRank(comm, file, "r", &fp, &elsewhere, &why));
    PetscCheck(fp, comm, PETSC_ERR_FILE_OPEN, "%s: cannot open the time-series file %s%s%s", option, file,
               elsewhere ? " on some of the other ranks" : ": ", elsewhere ? "" : why);
  }
  PetscCall(PetscMalloc2(cap, &T, cap * nc, &Y));
  while ((len = getline(&line, &linecap, fp)) > 0) {
    char     *p = line, *hash;
    PetscReal v[FS_MOTION_MAX_COLUMNS + 2];
    PetscInt  nv  = 0;
    PetscBool bad = PETSC_FALSE;
    char      err[256];

    lineno++;
    err[0] = 0;
    if (strlen(line) < (size_t)len) PetscCall(PetscStrncpy(err, "a NUL byte: the file is text", sizeof(err)));
    if (lineno == 1 && FSTextByteOrderMark(line, (size_t)len))
      PetscCall(PetscSNPrintf(err, sizeof(err), "the file starts with %s: save it as plain text without the mark",
                              FSTextByteOrderMark(line, (size_t)len)));
    if ((hash = strchr(line, '#'))) *hash = 0;
    if (!err[0]) {
      while (nv < nc + 2 && NextNumber(&p, &v[nv], &bad)) nv++;
      if (!nv && !bad) continue; /* blank or comment */
      if (bad || nv != nc + 1) PetscCall(PetscSNPrintf(err, sizeof(err), "expected %s", what));
      else if (np && v[0] <= T[np - 1])
        PetscCall(PetscSNPrintf(err, sizeof(err),
                                "the time %g does not follow the previous time %g (times must strictly increase)",
                                (double)v[0], (double)T[np - 1]));
    }
    if (err[0]) {
      fclose(fp);
      free(line);
      PetscCall(PetscFree2(T, Y));
      SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "%s: file %s, line %" PetscInt_FMT ": %s", option, file, lineno, err);
    }
    if (np == cap) { /* grow */
      PetscReal *t, *y;
      PetscCall(PetscMalloc2(2 * cap, &t, 2 * cap * nc, &y));
      PetscCall(PetscArraycpy(t, T, cap));
      PetscCall(PetscArraycpy(y, Y, cap * nc));
      PetscCall(PetscFree2(T, Y));
      T = t;
      Y = y;
      cap *= 2;
    }
    T[np] = v[0];
    for (PetscInt k = 0; k < nc; k++) Y[np * nc + k] = scale[k] * v[1 + k];
    np++;
  }
  free(line);
  fclose(fp);
  if (np < 2) PetscCall(PetscFree2(T, Y));
  PetscCheck(np >= 2, comm, PETSC_ERR_FILE_UNEXPECTED,
             "%s: file %s has %" PetscInt_FMT " points (%s): at least two are needed", option, file, np,
             nc == 1 ? "time, value" : "lines");
  PetscCall(PetscMalloc1(np, &w));
  for (PetscInt k = 0; k < nc; k++) {
    FSMotionSeries *sk = &s[k];
    sk->n              = np;
    PetscCall(PetscMalloc2(np, &sk->t, np, &sk->y));
    PetscCall(PetscMalloc1(np, &sk->M));
    for (PetscInt i = 0; i < np; i++) {
      sk->t[i] = T[i];
      sk->y[i] = Y[i * nc + k];
    }
    SplineSecondDerivatives(np, sk->t, sk->y, sk->M, w);
    /* values too large, or times too close, for the spline's slopes and second derivatives (the velocity and
       acceleration the liquid feels) to be numbers */
    for (PetscInt i = 0; i + 1 < np; i++) {
      const PetscReal slope = (sk->y[i + 1] - sk->y[i]) / (sk->t[i + 1] - sk->t[i]);
      if (!PetscIsInfOrNanReal(slope) && !PetscIsInfOrNanReal(sk->M[i]) && !PetscIsInfOrNanReal(sk->M[i + 1])) continue;
      char msg[256];
      PetscCall(PetscSNPrintf(msg, sizeof(msg), "the points (%g, %g) and (%g, %g)%s", (double)T[i],
                              (double)(Y[i * nc + k] / scale[k]), (double)T[i + 1],
                              (double)(Y[(i + 1) * nc + k] / scale[k]), nc > 1 ? " of a column" : ""));
      for (PetscInt j = 0; j <= k; j++) PetscCall(FSMotionSeriesDestroy(&s[j]));
      PetscCall(PetscFree(w));
      PetscCall(PetscFree2(T, Y));
      SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
              "%s: file %s: %s give a velocity or acceleration that is not a finite number: values too large or "
              "times too close",
              option, file, msg);
    }
  }
  PetscCall(PetscFree(w));
  PetscCall(PetscFree2(T, Y));
  PetscFunctionReturn(0);
}

/* FSMotionSeriesEval - the value, velocity and acceleration v[0..2] at time t. */
void FSMotionSeriesEval(const FSMotionSeries *s, PetscReal t, PetscReal v[3])
{
  const PetscInt n  = s->n;
  PetscInt       lo = 0, hi = n - 1;

  if (t <= s->t[0] || t >= s->t[n - 1]) { /* the straight line leaving the end point (M = 0 there) */
    const PetscInt  e = t <= s->t[0] ? 0 : n - 1, i = e ? n - 2 : 0;
    const PetscReal h = s->t[i + 1] - s->t[i], slope = (s->y[i + 1] - s->y[i]) / h;
    const PetscReal d = e ? slope + h * s->M[i] / 6 : slope - h * s->M[1] / 6; /* the spline's end slopes */
    v[0]              = s->y[e] + d * (t - s->t[e]);
    v[1]              = d;
    v[2]              = 0;
    return;
  }
  while (hi - lo > 1) { /* bisection: t[lo] <= t < t[hi] */
    const PetscInt mid = (lo + hi) / 2;
    if (s->t[mid] <= t) lo = mid;
    else hi = mid;
  }
  {
    const PetscReal h = s->t[hi] - s->t[lo], a = (s->t[hi] - t) / h, b = 1 - a;
    v[0] = a * s->y[lo] + b * s->y[hi] + ((a * a * a - a) * s->M[lo] + (b * b * b - b) * s->M[hi]) * h * h / 6;
    v[1] = (s->y[hi] - s->y[lo]) / h + ((1 - 3 * a * a) * s->M[lo] + (3 * b * b - 1) * s->M[hi]) * h / 6;
    v[2] = a * s->M[lo] + b * s->M[hi];
  }
}

PetscErrorCode FSMotionSeriesDestroy(FSMotionSeries *s)
{
  PetscFunctionBegin;
  PetscCall(PetscFree2(s->t, s->y));
  PetscCall(PetscFree(s->M));
  PetscFunctionReturn(0);
}
