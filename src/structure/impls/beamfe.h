/*
   The cantilever beam shared by the structure models: its parameters (-fs_beam_* options) and a
   finite-element Euler-Bernoulli model with Hermite cubic elements, point masses and rotary
   inertias, whose modes SLEPc computes (seed Eqs. 15, 18-27).

   The beam lies along x, clamped at x = 0, free at x = L; w(x) is its deflection along y and
   theta = dw/dx its rotation about z. The tank (with its supports, ballast or solid mass) is
   attached at x = a (-fs_beam_tank_position, default the tip x = L).
*/
#pragma once
#include <flexslosh.h>
#include "io/fsoutput.h"

typedef struct {
  PetscReal E, Iz, L, mlin; /* Young's modulus, second moment of area, length, mass per unit length */
  PetscReal a;              /* the tank's reference point (attachment) */
  PetscReal tank_mass, ballast_mass, tank_inertia; /* rigid payload at x = a: masses, rotary inertia about z at a */
  PetscReal payload_mass;                          /* liquid + ballast (0: the ballast as given) */
  PetscReal xi;                                    /* damping ratio (every mode unless a model says otherwise) */
  PetscReal preload;                               /* initial deflection at x = a, static shape, released from rest */
  PetscReal force,
      force_position; /* constant external point force along y (e.g. the weight of added masses), and where */
} FSBeamParams;

PETSC_INTERN PetscErrorCode FSBeamParamsSetFromOptions(FSBeamParams *, MPI_Comm, PetscOptionItems *);
PETSC_INTERN PetscErrorCode FSBeamParamsDefault(FSBeamParams *);
PETSC_INTERN PetscErrorCode FSBeamParamsView(const FSBeamParams *, PetscViewer);
PETSC_INTERN PetscErrorCode FSBeamParamsSummary(const FSBeamParams *, FSJSON);

/* Static deflection of the bare massless cantilever at x under a unit force at xf (Maxwell reciprocity holds). */
PETSC_INTERN PetscReal FSBeamInfluence(const FSBeamParams *, PetscReal x, PetscReal xf);

/* Finite-element model: ne Hermite elements, nodes 0..ne (node 0 clamped), a node at x = a.
   DOFs (w, theta) of node i >= 1 are 2(i-1), 2(i-1)+1; N = 2 ne. */
typedef struct {
  PetscInt   ne, N, tank_node;
  PetscReal *x; /* ne+1 node positions */
  Mat        K, M;
} FSBeamFE;

PETSC_INTERN PetscErrorCode FSBeamFECreate(const FSBeamParams *, PetscInt ne, FSBeamFE *);
PETSC_INTERN PetscErrorCode FSBeamFEDestroy(FSBeamFE *);
/* Shape functions at x: the element's 4 DOF indices (-1: clamped), deflection and rotation weights. */
PETSC_INTERN PetscErrorCode FSBeamFEShape(const FSBeamFE *, PetscReal x, PetscInt dof[4], PetscReal Nw[4],
                                          PetscReal Nt[4]);
/* w(x) and theta(x) of a DOF vector (length N). */
PETSC_INTERN PetscErrorCode FSBeamFEEvaluate(const FSBeamFE *, const PetscReal u[], PetscReal x, PetscReal *w,
                                             PetscReal *theta);
/* u = K^{-1} f for a point force F (along y) and moment Mz at x. */
PETSC_INTERN PetscErrorCode FSBeamFEStatic(const FSBeamFE *, PetscReal x, PetscReal F, PetscReal Mz, PetscReal u[]);
/* The first n modes (K phi = omega^2 M phi, SLEPc GHEP, shift-and-invert about 0): omega[n], phi[n*N] (M-orthonormal).
 */
PETSC_INTERN PetscErrorCode FSBeamFEModes(const FSBeamFE *, PetscInt n, const char prefix[], PetscReal omega[],
                                          PetscReal phi[]);
/* y^T M z for DOF vectors. */
PETSC_INTERN PetscErrorCode FSBeamFEMassProduct(const FSBeamFE *, const PetscReal y[], const PetscReal z[],
                                                PetscReal *);
PETSC_INTERN PetscErrorCode FSBeamParamsResolvePayload(FSBeamParams *, MPI_Comm, PetscReal liquid_mass);
