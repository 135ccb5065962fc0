/*
   The coupling of the liquid with the structure (src/coupling): the tank's frame, the loads, and the
   energy budget.
*/
#pragma once
#include <flexslosh.h>


/* The energy block of the global DOFs: the time integrals of P_ext, of the start-up relaxation's
   power, of the structure's damping power (negative: energy lost) and of the coupling's power (the work
   of the difference between the loads the structure receives and the reaction of the walls' forces on
   the particles: energy the coupling creates), the energy changes of the wall bounces (liquid, whole
   system; changed between steps, not by the integrator), and the liquid's and the whole
   system's energies at the start of the run (rate zero: kept through restarts by the checkpoints). */
enum { FS_ENERGY_WORK_EXT, FS_ENERGY_WORK_RELAX, FS_ENERGY_WORK_DAMPING, FS_ENERGY_WORK_COUPLING, FS_ENERGY_WORK_BOUNCE, FS_ENERGY_WORK_BOUNCE_TOTAL, FS_ENERGY_LIQUID0, FS_ENERGY_TOTAL0, FS_ENERGY_NDOF };
PETSC_INTERN PetscErrorCode FSSolverEnergyColumns(FSSolver, PetscInt *, const char *[]);
PETSC_INTERN PetscErrorCode FSSolverEnergyValues(FSSolver, PetscReal[]);
PETSC_INTERN PetscErrorCode FSSolverEnergyInitial(FSSolver);
typedef struct {
  FSTankMotion mo;
  PetscReal    c, sn;
} FSEnergyFrame;
PETSC_INTERN PetscErrorCode FSSolverEnergyJumpFrame(FSSolver, FSEnergyFrame *);
PETSC_INTERN void           FSEnergyParticle(FSSolver, const FSEnergyFrame *, const PetscReal x[], const PetscReal v[], PetscReal m, PetscReal e[2]);
PETSC_INTERN PetscErrorCode FSSolverEnergyAddJump(FSSolver, const PetscReal[2]);

PETSC_INTERN PetscErrorCode FSSolverCouplingSetUp(FSSolver);
PETSC_INTERN PetscErrorCode FSSolverCouplingPredict(FSSolver, const PetscReal *u);
PETSC_INTERN PetscErrorCode FSSolverCouplingRates(FSSolver, PetscReal *f);
PETSC_INTERN PetscErrorCode FSSolverCouplingInertia(FSSolver, PetscReal *f, PetscReal *power);
PETSC_INTERN PetscErrorCode FSSolverCouplingReaction(FSSolver, const PetscReal *f, PetscReal local[3]);
