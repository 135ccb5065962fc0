/*
   Fault injection, for the tests only: FLEXSLOSH_FAULT=alloc:RANK:STEP in the environment makes rank
   RANK fail an allocation (PETSC_ERR_MEM, as PetscMalloc() raises it) in the first right-hand side of
   step STEP, so that a test can check that an error raised on one rank only ends every rank. Unset, it
   costs one comparison per right-hand side.
*/
#include "sys/fssys.h"
#include <stdio.h>
#include <stdlib.h>

static int      FSFaultParsed = 0;  /* 0: not read yet, 1: none, 2: armed, 3: fired */
static int      FSFaultRank   = -1; /* the rank that fails */
static PetscInt FSFaultStep   = -1; /* the step at which it fails */

/*
   FSDebugFault - raises the fault FLEXSLOSH_FAULT asks for, if this rank and step are its own.

   Not collective (that is the point: the error is raised on one rank only)

   Input Parameters:
+  comm - the run's communicator (for the rank)
-  step - the step being computed
*/
PetscErrorCode FSDebugFault(MPI_Comm comm, PetscInt step)
{
  PetscMPIInt rank;

  PetscFunctionBegin;
  if (FSFaultParsed == 0) {
    const char *env = getenv("FLEXSLOSH_FAULT");
    long        r, st;
    int         used = 0;

    FSFaultParsed = 1;
    if (env && env[0]) {
      PetscCheck(sscanf(env, "alloc:%ld:%ld%n", &r, &st, &used) == 2 && env[used] == '\0' && r >= 0 && st >= 0,
                 PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
                 "FLEXSLOSH_FAULT=%s: expected alloc:RANK:STEP (a test-only fault injection)", env);
      FSFaultRank   = (int)r;
      FSFaultStep   = (PetscInt)st;
      FSFaultParsed = 2;
    }
  }
  if (FSFaultParsed != 2 || step != FSFaultStep) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != FSFaultRank) PetscFunctionReturn(0);
  FSFaultParsed = 3;
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_MEM,
          "Allocation failed on rank %d at step %" PetscInt_FMT " (injected for a test by FLEXSLOSH_FAULT)", (int)rank,
          step);
  PetscFunctionReturn(0);
}
