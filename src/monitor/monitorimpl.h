/*
   Private header of the monitor object (src/monitor): its ops table and the data every implementation shares. Only
   src/monitor includes it; an implementation in impls/ fills the ops in its FSMonitorCreate_<Name>() and keeps its
   own data in m->data.
*/
#pragma once
#include <petsc/private/petscimpl.h>
#include "solver/fssolver.h"

typedef struct _FSMonitorOps *FSMonitorOps;
struct _FSMonitorOps {
  PetscErrorCode (*setfromoptions)(FSMonitor, PetscOptionItems *);
  PetscErrorCode (*setup)(FSMonitor, FSSolver);
  /* the start of the run's output (FSMonitorBegin): opens the monitor's files; collective */
  PetscErrorCode (*begin)(FSMonitor, FSSolver);
  /* a monitor with a row whose sums are reduced with the other monitors' (FSMonitorRows): whether a row is due at
     this step and the sums and maxima it takes, this rank's values, then the row from the reduced values (where a
     check may stop the run before any row of the step is written), then its write */
  PetscErrorCode (*rowsize)(FSMonitor, FSSolver, PetscBool *due, PetscInt *nsum, PetscInt *nmax);
  PetscErrorCode (*rowlocal)(FSMonitor, FSSolver, PetscReal sum[], PetscReal max[]);
  PetscErrorCode (*rowvalues)(FSMonitor, FSSolver, const PetscReal sum[], const PetscReal max[]);
  PetscErrorCode (*rowwrite)(FSMonitor, FSSolver);
  /* after each step, and once before the first (first: FSMonitorBegin was the last call); collective */
  PetscErrorCode (*step)(FSMonitor, FSSolver, PetscInt step, PetscReal t, PetscBool first);
  /* the end of the run (FSMonitorEnd); collective */
  PetscErrorCode (*end)(FSMonitor, FSSolver);
  PetscErrorCode (*view)(FSMonitor, PetscViewer);
  PetscErrorCode (*destroy)(FSMonitor);
};

struct _p_FSMonitor {
  PETSCHEADER(struct _FSMonitorOps);
  PetscBool    setupcalled;
  PetscBool    begun;     /* FSMonitorBegin() called */
  PetscBool    first;     /* no step since FSMonitorBegin() */
  FSTimeSeries file;      /* its csv file whose rows' write status is deferred (FSMonitorGetWriteStatus()), or NULL */
  PetscBool    unchecked; /* rows of file written since its write status was last carried to the ranks */
  void        *data;      /* the implementation's */
};
