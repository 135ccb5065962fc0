/*
   flexslosh: liquid sloshing in tanks carried by flexible structures (delta-LES-SPH + PETSc TS).

   Public interface of libflexslosh. The objects follow PETSc's pattern
   (Create / SetFromOptions / SetUp / Solve / View / Destroy, options prefixes, registries):

     FSSolver  the whole run: particles, decomposition, physics terms, time stepping, output
     FSTerm    one physics term of the right-hand side (continuity, pressure, viscosity, ...)
     FSCase    the set-up of a run (domain, particles, initial fields, default parameters)

   Implementations of terms and cases are registered in tables (FSTermRegister, FSCaseRegister)
   and chosen by name at run time (-fs_terms, -fs_case). Plug-ins loaded with -dll_append register
   their own from their entry point PetscDLLibraryRegister_<libname>().
*/
#pragma once
#include <petscts.h>
#include <petscdmswarm.h>
#include <petscsf.h>

#define FLEXSLOSH_VERSION "0.1.0"

typedef struct _p_FSSolver *FSSolver;
typedef struct _p_FSTerm   *FSTerm;

PETSC_EXTERN PetscClassId FSSOLVER_CLASSID;

/* ---------- library ---------- */
PETSC_EXTERN PetscErrorCode FSInitializePackage(void);
PETSC_EXTERN PetscErrorCode FSFinalizePackage(void);
PETSC_EXTERN PetscErrorCode FSCheckPlugins(MPI_Comm);

/* ---------- solver ---------- */
PETSC_EXTERN PetscErrorCode FSSolverCreate(MPI_Comm, FSSolver *);
PETSC_EXTERN PetscErrorCode FSSolverSetFromOptions(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverSetUp(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverStep(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverSolve(FSSolver);
PETSC_EXTERN PetscErrorCode FSSolverView(FSSolver, PetscViewer);
PETSC_EXTERN PetscErrorCode FSSolverDestroy(FSSolver *);
PETSC_EXTERN PetscErrorCode FSSolverGetTS(FSSolver, TS *);
PETSC_EXTERN PetscErrorCode FSSolverGetSwarm(FSSolver, DM *);
PETSC_EXTERN PetscErrorCode FSSolverGetTime(FSSolver, PetscReal *, PetscInt *);
PETSC_EXTERN PetscErrorCode FSSolverGetDimension(FSSolver, PetscInt *);
PETSC_EXTERN PetscErrorCode FSSolverGetLocalSize(FSSolver, PetscInt *);

/* ---------- terms ---------- */
/* What a term needs the core to compute in the first pass over neighbour pairs. */
typedef enum {
  FS_NEED_NONE            = 0,
  FS_NEED_DENSITY_GRADIENT = 1, /* renormalized density gradient <grad rho>^L_i, also on ghosts */
  FS_NEED_STRAIN_RATE     = 2   /* ||D||_i = sqrt(2 D:D) with the corrected velocity gradient, also on ghosts */
} FSNeed;

/* Read-only view of the particles a term works on: owned particles 0..nowned-1, then ghost
   copies nowned..nowned+nghost-1 (neighbours on other ranks or periodic images).
   Per-particle record: rec[k*stride + ...] with position at 0, velocity at dim, density at
   2*dim, mass at 2*dim+1. aux[k*(dim+1)] holds the density gradient (dim) and ||D|| when requested. */
typedef struct {
  PetscInt         dim, nowned, nghost, stride;
  const PetscReal *rec;
  const PetscReal *aux;
  const PetscReal *vol;      /* V_k = m_k / rho_k, owned and ghosts */
  const PetscReal *pressure; /* p_k = c0^2 (rho_k - rho0) + background pressure, owned and ghosts */
  /* physical constants */
  PetscReal rho0, c0, h, dx, nu, gravity[3], background_pressure;
  PetscReal umax; /* largest particle speed at the start of the step */
} FSParticles;

/* The neighbourhood of one owned particle i: n neighbours j[k] with x_j - x_i in dx[k*dim], the
   squared distance r2[k] and its inverse rinv2[k], and the kernel gradient grad_i W(x_i - x_j) in
   gradW[k*dim], computed once per pair by the core and shared by all terms. */
typedef struct {
  PetscInt         i, n;
  const PetscInt  *j;
  const PetscReal *dx, *r2, *rinv2, *gradW;
} FSNeighbourhood;

/* Rate of change of particle i accumulated by the terms: drho/dt, du/dt (dim), and a correction
   of the particle's transport velocity dx/dt = u + dx (particle shifting; zero for most terms). */
typedef struct {
  PetscReal drho, du[3], dx[3];
} FSRate;

typedef struct {
  /* per owned particle, with its neighbours (hot: keep it free of PETSc calls) */
  void (*interact)(FSTerm, const FSParticles *, const FSNeighbourhood *, FSRate *);
  /* per owned particle, no neighbours (body forces) */
  void (*source)(FSTerm, const FSParticles *, PetscInt i, FSRate *);
  /* once per right-hand side, after the first pass and its ghost refresh, before the pair pass */
  PetscErrorCode (*prepare)(FSTerm, const FSParticles *);
  /* a per-particle output field the term can provide for the owned particles (e.g. "turbulent_viscosity") */
  PetscErrorCode (*field)(FSTerm, const char[], const FSParticles *, PetscReal *, PetscBool *);
  PetscErrorCode (*setfromoptions)(FSTerm, PetscOptionItems *);
  PetscErrorCode (*setup)(FSTerm, const FSParticles *);
  PetscErrorCode (*view)(FSTerm, PetscViewer);
  PetscErrorCode (*destroy)(FSTerm);
} FSTermOps;

struct _p_FSTerm {
  char       name[64];
  char       description[256];
  FSSolver   solver;
  FSTermOps  ops;
  PetscInt   needs;      /* FSNeed flags */
  PetscBool  has_power;  /* the term dissipates: it accumulates power */
  PetscReal  power;      /* dissipation power of the last right-hand side, this rank's share (seed Eq. 38) */
  PetscReal  max_viscosity; /* largest kinematic viscosity the term applies (time-step limit), set in prepare */
  void      *data;       /* implementation data */
};

typedef PetscErrorCode (*FSTermCreateFn)(FSTerm);

PETSC_EXTERN PetscErrorCode FSTermRegister(const char[], const char[], FSTermCreateFn);
PETSC_EXTERN PetscErrorCode FSTermRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSTermListView(PetscViewer);
PETSC_EXTERN PetscErrorCode FSTermGetSolver(FSTerm, FSSolver *);

/* ---------- cases ---------- */
/* A case sets up the run: called from FSSolverSetUp after options are read. It sets the domain
   box and periodicity (FSSolverSetDomain) and creates the particles (FSSolverAddParticles). */
typedef struct {
  PetscErrorCode (*setfromoptions)(FSSolver, PetscOptionItems *);
  PetscErrorCode (*setup)(FSSolver);
  PetscErrorCode (*analytic)(FSSolver, PetscReal t, PetscReal *value); /* optional reference value in the time series */
  const char *analytic_name;
} FSCaseOps;

typedef PetscErrorCode (*FSCaseCreateFn)(FSSolver, FSCaseOps *);

PETSC_EXTERN PetscErrorCode FSCaseRegister(const char[], const char[], FSCaseCreateFn);
PETSC_EXTERN PetscErrorCode FSCaseRegisterAll(void);
PETSC_EXTERN PetscErrorCode FSCaseListView(PetscViewer);

PETSC_EXTERN PetscErrorCode FSSolverSetDomain(FSSolver, const PetscReal lo[], const PetscReal hi[], const PetscBool periodic[]);
PETSC_EXTERN PetscErrorCode FSSolverAddParticles(FSSolver, PetscInt n, const PetscReal x[], const PetscReal u[], const PetscReal rho[], const PetscReal m[]);
PETSC_EXTERN PetscErrorCode FSSolverGetParameters(FSSolver, PetscReal *dx, PetscReal *h, PetscReal *rho0, PetscReal *c0, PetscReal *nu);
PETSC_EXTERN PetscErrorCode FSSolverSetDefaultPhysics(FSSolver, PetscReal rho0, PetscReal c0, PetscReal nu, const PetscReal g[]);
