/*
   Private header of the monitor object (src/monitor): its struct, the data every implementation shares. Only
   src/monitor includes it; an implementation in impls/ fills the ops in its FSMonitorCreate_<Name>() and keeps its
   own data in m->data (a plug-in's type: FSMonitorSetOps(), FSMonitorSetContext()).
*/
#pragma once
#include <petsc/private/petscimpl.h>
#include "solver/fssolver.h"

/* the ops table, struct _FSMonitorOps, is public (include/flexslosh.h): a plug-in's type fills it with
   FSMonitorSetOps() */
struct _p_FSMonitor {
  PETSCHEADER(struct _FSMonitorOps);
  PetscBool    setupcalled;
  PetscBool    begun;     /* FSMonitorBegin() called */
  PetscBool    first;     /* no step since FSMonitorBegin() */
  FSTimeSeries file;      /* its csv file whose rows' write status is deferred (FSMonitorGetWriteStatus()), or NULL */
  PetscBool    unchecked; /* rows of file written since its write status was last carried to the ranks */
  void        *data;      /* the implementation's */
};

/* the rows of timeseries.csv and energy.csv (impls/timeseries.c): -fs_series_interval, listed by -help with the time
   series monitor's options (listed true) and read unlisted, checked the same way, by the energy budget's, whose rows
   are its rows; whether a row is due at the solver's step with that interval */
PETSC_INTERN PetscErrorCode FSMonitorSeriesIntervalRead(FSMonitor, PetscOptionItems *, PetscBool, PetscInt *);
PETSC_INTERN PetscErrorCode FSMonitorSeriesDue(FSSolver, PetscInt, PetscBool *);
