/*
   Private header of the probes monitor (src/monitor/impls/probes/): the probe set of -fs_probes (probeset.c: the
   file parsed, checked against the walls, sampled), the sensor model of a probe (sensor.c) and the monitor that writes
   probes.csv (probes.c). Only these files and the sensor's unit test include it.
*/
#pragma once
#include "monitor/monitorimpl.h"
#include "sys/fssys.h"
#include "particles/fsparticles.h"
#include "boundary/fsboundary.h"

#define FS_PROBE_NAME_LEN 64

/* A probe's time response (sensor.c): a low-pass filter and a sample-and-hold, and their state */
typedef struct {
  PetscInt   order;   /* 1: first order, 2: second-order Butterworth */
  PetscReal  omega;   /* 2 pi times the cut-off frequency (0: no low-pass) */
  PetscReal  rate;    /* the sampling rate of the sample-and-hold (0: none) */
  PetscBool  started; /* the filter has had its first sample */
  PetscReal  t, u;    /* the time and the input of the last sample */
  PetscReal  y[2];    /* the filter's output and its rate of change at t */
  PetscReal  held;    /* the output at the last sampling instant */
  PetscInt64 next;    /* the index k of the next sampling instant k/rate */
} FSSensorFilter;

typedef struct {
  char           name[FS_PROBE_NAME_LEN];
  PetscBool      gauge;
  PetscReal      x0[3], x1[3]; /* a probe's point (x0), a gauge's line from x0 to x1 */
  PetscReal      diameter;     /* a probe on a wall: the diameter of the face it averages the wall pressure over */
  PetscReal      cutoff;       /* a probe: the low-pass filter's cut-off frequency in Hz (0: none) */
  PetscReal      rate;         /* a probe: the sampling rate of its instrument in Hz (0: none) */
  PetscInt       order;        /* a probe: the low-pass filter's order (1 or 2) */
  PetscBool      filtered;     /* a probe with a cut-off or a rate: its reading, a column of its own */
  FSSensorFilter filter;       /* its state */
  PetscInt       estart, eend; /* a probe on a wall: its wall elements in FSProbeSet.elem[estart..eend), else equal */
  PetscInt       sample, nsample; /* a gauge: its first sample (in the samples' arrays) and their number */
  PetscBool      vertical;        /* a gauge along y: its elevation is the y coordinate, else the distance from x0 */
  PetscInt       line;            /* its line in the file, for the messages */
} FSProbe;

/* the items of the file and their current values */
typedef struct {
  char       file[PETSC_MAX_PATH_LEN]; /* -fs_probes */
  PetscInt   interval;                 /* -fs_probe_interval (steps) */
  PetscInt   n, nvalues, nsamples, nelem;
  FSProbe   *item;
  PetscInt  *offset; /* n+1: item k's values are values[offset[k] .. offset[k+1]) */
  PetscReal *values; /* the values of the state sampled last: a probe's pressure and velocity, a gauge's elevation */
  PetscReal *sgamma; /* per gauge sample: the walls' Shepard factor there (1 without walls) */
  PetscReal *sums;   /* the sums of one sample: per probe 2+dim, then one per gauge sample */
  PetscInt  *elem;   /* the wall elements of the probes on walls */
  PetscReal *ewt;    /* their weights: the area (length in 2-D) of the element within the probe's face */
  char (*colname)[FS_PROBE_NAME_LEN + 32];
  const char **names; /* the items' names, for FSSolverGetProbes */
  PetscInt     step;  /* the step of values (-1: none yet) */
  PetscReal    time;
} FSProbeSet;

/* probeset.c */
PETSC_INTERN PetscErrorCode FSProbeSetSetUp(FSProbeSet *, FSSolver);
PETSC_INTERN PetscErrorCode FSProbeSetSample(FSProbeSet *, FSSolver);
PETSC_INTERN PetscErrorCode FSProbeSetRecord(FSProbeSet *, FSSolver);
PETSC_INTERN PetscErrorCode FSProbeSetDestroy(FSProbeSet *);

/* sensor.c */
PETSC_INTERN PetscReal FSSensorSegmentOverlap(PetscReal, PetscReal, PetscReal);
PETSC_INTERN PetscReal FSSensorDiscTriangleArea(PetscReal, const PetscReal[3][2]);
PETSC_INTERN PetscReal FSSensorFilterUpdate(FSSensorFilter *, PetscReal, PetscReal);
