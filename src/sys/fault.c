/*
   Fault injection, for the tests only: FLEXSLOSH_FAULT=KIND:RANK:STEP in the environment injects one
   fault on rank RANK at step STEP (at the first check at or after it: the leak checks come with the
   neighbour lists' rebuilds, which -fs_neighbour_rebuild auto skips while nothing moved far), so that
   a test can check that an error raised on one rank only ends
   every rank:
     alloc - an allocation fails (PETSC_ERR_MEM, as PetscMalloc() raises it) in the step's first
             right-hand side
     leak  - one particle of the rank is moved under the walls' lowest point, out of the tank, before the
             step's leak check
   Unset, it costs one comparison per call.
*/
#include "sys/fssys.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int      FSFaultParsed = 0; /* 0: not read yet, 1: none, 2: armed, 3: fired */
static char     FSFaultKind[16];   /* alloc or leak */
static int      FSFaultRank = -1;  /* the rank that fails */
static PetscInt FSFaultStep = -1;  /* the step at which it fails */

/*
   FSDebugFault - whether the fault FLEXSLOSH_FAULT asks for is of this kind, this rank and this step; an
   alloc fault is raised here, a leak is left to the caller (*fire).

   Not collective (that is the point: the fault is on one rank only)

   Input Parameters:
+  comm - the run's communicator (for the rank)
.  kind - alloc or leak
-  step - the step being computed

   Output Parameter:
.  fire - whether the caller injects its fault now (may be NULL for alloc)
*/
PetscErrorCode FSDebugFault(MPI_Comm comm, const char kind[], PetscInt step, PetscBool *fire)
{
  PetscMPIInt rank;

  PetscFunctionBegin;
  if (fire) *fire = PETSC_FALSE;
  if (FSFaultParsed == 0) {
    const char *env = getenv("FLEXSLOSH_FAULT");
    long        r, st;
    int         used = 0;

    FSFaultParsed = 1;
    if (env && env[0]) {
      PetscCheck(sscanf(env, "%15[a-z]:%ld:%ld%n", FSFaultKind, &r, &st, &used) == 3 && env[used] == '\0' &&
                     (!strcmp(FSFaultKind, "alloc") || !strcmp(FSFaultKind, "leak")) && r >= 0 && st >= 0,
                 PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
                 "FLEXSLOSH_FAULT=%s: expected alloc:RANK:STEP or leak:RANK:STEP (a fault injection for the tests)",
                 env);
      FSFaultRank   = (int)r;
      FSFaultStep   = (PetscInt)st;
      FSFaultParsed = 2;
    }
  }
  if (FSFaultParsed != 2 || step < FSFaultStep || strcmp(kind, FSFaultKind)) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank != FSFaultRank) PetscFunctionReturn(0);
  FSFaultParsed = 3;
  if (fire) *fire = PETSC_TRUE;
  PetscCheck(strcmp(kind, "alloc"), PETSC_COMM_SELF, PETSC_ERR_MEM,
             "Allocation failed on rank %d at step %" PetscInt_FMT " (injected for a test by FLEXSLOSH_FAULT)",
             (int)rank, step);
  PetscFunctionReturn(0);
}
