/* Private header of the coupling (src/coupling): the data of FSCoupling. */
#pragma once
#include "coupling/fscoupling.h"

struct _p_FSCoupling {
  MPI_Comm  comm;
  PetscBool coupled;          /* liquid and structure coupled */
  PetscBool loads_from_walls; /* -fs_coupling_loads walls */
  PetscReal gravity[3];
  PetscInt  dim;          /* of the liquid */
  PetscReal tank_width;   /* across the 2-D plane: loads per unit width times this (1 in 3-D) */
  PetscReal tank_ref[3];  /* the tank's point on the beam, in the tank frame (z: the middle of its width in 3-D) */
  PetscReal liquid_mass;  /* of the whole tank (2-D mass times width) */
  FSLoads   static_loads; /* of the liquid at rest in the undeflected tank, subtracted */
  PetscReal angle;        /* the tank's angle at this stage (from the structure's state) */
  FSFrameField
      body; /* the body acceleration field of the tank's frame predicted for this stage (g without a coupling) */
  FSTankMotion motion;    /* the tank's motion at the last right-hand side, every rank */
  FSTankMotion predicted; /* the motion predicted for this stage (FSCouplingSetPredictedMotion) */
  PetscReal reaction[3]; /* force (2) and moment of all terms but gravity on the liquid, tank frame, per unit width, all
                            ranks: the in-plane components the structure carries */
  PetscReal reaction_out[3]; /* 3-D: the components it does not carry, force_z, moment_x, moment_y */
  PetscReal tank_load[3]; /* the liquid's loads of the last right-hand side in the tank's frame, per unit width: force
                             (2), moment about tank_ref */
  PetscReal tank_load_out[3]; /* 3-D: force_z, moment_x, moment_y in the tank's frame */
};
