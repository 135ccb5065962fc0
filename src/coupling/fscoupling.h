/*
   The coupling of the liquid with the structure (src/coupling): FSCoupling, the tank's frame and the
   loads. The liquid is solved in the tank's frame; the structure's motion of the tank enters it as
   the frame's inertial accelerations (FSCouplingInertia), and the liquid's loads drive the structure
   (FSCouplingComputeLoads, from the reaction of the terms' forces or the walls' loads). The solver
   drives it at every right-hand side; without a structure or walls the coupling is off and the
   frame's body acceleration is gravity.
*/
#pragma once
#include <flexslosh.h>
#include "boundary/fsboundary.h"

typedef struct _p_FSCoupling *FSCoupling;

PETSC_INTERN PetscErrorCode FSCouplingCreate(MPI_Comm, FSCoupling *);
PETSC_INTERN PetscErrorCode FSCouplingSetUp(FSCoupling, PetscBool possible, PetscInt dim, const PetscReal gravity[],
                                            FSBoundary, PetscInt n, const PetscReal x[], const PetscReal m[]);
PETSC_INTERN PetscErrorCode FSCouplingHelp(MPI_Comm);
PETSC_INTERN PetscErrorCode FSCouplingGetActive(FSCoupling, PetscBool *);
PETSC_INTERN PetscErrorCode FSCouplingGetLiquidMass(FSCoupling, PetscReal *);
PETSC_INTERN PetscErrorCode FSCouplingGetWidth(FSCoupling, PetscReal *);
PETSC_INTERN PetscErrorCode FSCouplingGetBody(FSCoupling, const FSFrameField **);
PETSC_INTERN PetscErrorCode FSCouplingSetPredictedMotion(FSCoupling, const FSTankMotion *);
PETSC_INTERN PetscErrorCode FSCouplingReaction(FSCoupling, PetscInt n, PetscInt stride, const PetscReal rec[],
                                               PetscInt ustride, const PetscReal f[], PetscReal local[3],
                                               PetscInt nextra, PetscReal extra[]);
PETSC_INTERN PetscErrorCode FSCouplingGetReaction(FSCoupling, PetscReal reaction[3]);
PETSC_INTERN PetscErrorCode FSCouplingComputeLoads(FSCoupling, FSBoundary, FSLoads *);
PETSC_INTERN PetscErrorCode FSCouplingSetMotion(FSCoupling, const FSTankMotion *);
PETSC_INTERN PetscErrorCode FSCouplingInertia(FSCoupling, PetscInt n, PetscInt stride, const PetscReal rec[],
                                              PetscInt ustride, PetscReal f[], PetscReal *power);
/* the most extra sums FSCouplingReaction() carries on its MPI_Allreduce */
#define FS_COUPLING_MAX_EXTRA 64
/* the particle sums the inertial accelerations' power is made of (FSCouplingInertiaSums): m u and m u_d r_k */
#define FS_COUPLING_NINERTIA_SUMS 12
PETSC_INTERN void           FSCouplingInertiaSums(FSCoupling, PetscInt n, PetscInt stride, const PetscReal rec[],
                                                  PetscReal sums[FS_COUPLING_NINERTIA_SUMS]);
PETSC_INTERN PetscErrorCode FSCouplingInertiaPower(FSCoupling, const PetscReal sums[FS_COUPLING_NINERTIA_SUMS],
                                                   PetscReal *power);
PETSC_INTERN PetscErrorCode FSCouplingPower(FSCoupling, const PetscReal reaction[3], PetscReal *power);
PETSC_INTERN PetscErrorCode FSCouplingMotionPower(FSCoupling, const PetscReal reaction[3], PetscReal *power);
PETSC_INTERN PetscErrorCode FSCouplingStaticLoadsWork(FSCoupling, const FSTankMotion *, PetscReal *);
PETSC_INTERN PetscErrorCode FSCouplingDestroy(FSCoupling *);

/* a particle's kinetic and potential energy in the absolute frame */
PETSC_INTERN void FSCouplingAbsoluteEnergy(FSCoupling, const FSTankMotion *, PetscReal c, PetscReal sn,
                                           const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal *kin,
                                           PetscReal *pot);
