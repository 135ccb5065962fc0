#pragma once
#include "boundary/impls/polygon/walls.h"
#include "boundary/impls/trimesh/mesh.h"

/* the default -fs_terms of the cases with walls: the seed's delta-LES-SPH with boundary integrals */
#define FS_WALL_CASE_TERMS \
  "continuity,delta,pressure,viscosity,les_viscosity,gravity,wall_continuity,wall_pressure,wall_viscosity"
/* the gravity of the hydrostatic start rho = rho0 (1 + G (ysurf - y) / c0^2) below the surface y = ysurf: G = |g|
   (the first dim components), negative where gravity points up (+y), where the liquid on the floor hangs in tension
   from it (a tank falling faster than g; the standing wave case's Rayleigh-Taylor layer) */
static inline PetscReal FSCaseHeadGravity(const PetscReal g[], PetscInt dim)
{
  PetscReal g2 = 0;
  for (PetscInt d = 0; d < dim; d++) g2 += g[d] * g[d];
  return g[1] > 0 ? -PetscSqrtReal(g2) : PetscSqrtReal(g2);
}
/* an initial velocity field for FSCaseFillLiquidWithVelocity: u at the point x (dim components) */
typedef PetscErrorCode (*FSCaseVelocityFn)(const PetscReal x[], PetscReal u[], void *ctx);
PETSC_INTERN PetscErrorCode FSCaseFillLiquid(FSSolver, FSWalls *, PetscReal x0, PetscReal x1, PetscReal y0,
                                             PetscReal ysurf, const char what[]);
PETSC_INTERN PetscErrorCode FSCaseFillLiquidWithVelocity(FSSolver, FSWalls *, PetscReal x0, PetscReal x1, PetscReal y0,
                                                         PetscReal ysurf, const char what[], FSCaseVelocityFn,
                                                         void *ctx);
PETSC_INTERN PetscErrorCode FSCaseFillLiquidMesh(FSSolver, FSMesh *, const PetscReal lo[3], const PetscReal hi[3],
                                                 const char what[]);
PETSC_INTERN PetscErrorCode FSCaseFillLiquidMeshWithVelocity(FSSolver, FSMesh *, const PetscReal lo[3],
                                                             const PetscReal hi[3], const char what[], FSCaseVelocityFn,
                                                             void *ctx);
/* the tank walls w (2-D outline) extruded across width along z and filled with liquid at rest in the box
   x0..x1, y0..ysurf over the whole width: the 3-D FSCaseFillLiquid of the built-in tanks */
PETSC_INTERN PetscErrorCode FSCaseFillLiquidExtruded(FSSolver, FSWalls *, PetscReal width, PetscReal x0, PetscReal x1,
                                                     PetscReal y0, PetscReal ysurf, const char what[], FSCaseVelocityFn,
                                                     void *ctx);
/* liquid boxes (-fs_liquid_box), 4 reals each in 2-D (x0, x1, y0, y1), 6 in 3-D (and z0, z1) */
PETSC_INTERN PetscErrorCode FSCaseFillLiquidBoxes(FSSolver, FSWalls *, PetscInt nbox, const PetscReal box[],
                                                  const char what[]);
PETSC_INTERN PetscErrorCode FSCaseFillLiquidMeshBoxes(FSSolver, FSMesh *, PetscInt nbox, const PetscReal box[],
                                                      const char what[]);
PETSC_INTERN PetscBool      FSSegmentClip(const PetscReal[], const PetscReal[], const PetscReal[], const PetscReal[],
                                          PetscInt, PetscReal, PetscReal *, PetscReal *);
PETSC_INTERN PetscBool      FSSegmentEntersBox(const PetscReal p[], const PetscReal q[], const PetscReal lo[],
                                               const PetscReal hi[], PetscInt dim, PetscReal eps);
/* the masses of this rank's particles of one body of liquid scaled so that they sum to mass over the ranks (unless
   they do to round-off already), and the body recorded with its exact volume */
PETSC_INTERN PetscErrorCode FSCaseFitLiquidMass(FSSolver, PetscReal volume, PetscReal mass, PetscInt n, PetscReal m[]);
/* with -fs_fill_packing: is a body of liquid relaxed rather than left on its lattice (masses m)? */
PETSC_INTERN PetscErrorCode FSCaseLatticeFits(FSSolver, FSFillPackingType, PetscBool aligned, PetscReal mass,
                                              PetscInt n, const PetscReal m[], PetscBool *relax);
/* the hydrostatic densities of relaxed particles and their masses, the volume shared evenly */
PETSC_INTERN PetscErrorCode FSCaseRelaxedDensities(FSSolver, PetscInt dim, PetscReal ysurf, PetscReal volume,
                                                   PetscInt n, const PetscReal x[], PetscReal rho[], PetscReal m[]);
/* the liquid's exact volume and hydrostatic mass below the level t (FSCaseFillLevel) */
typedef void (*FSCaseLevelFn)(const void *ctx, PetscReal t, PetscReal *volume, PetscReal *mass);
PETSC_INTERN PetscErrorCode FSCaseFillLevel(FSSolver, FSCaseLevelFn, const void *ctx, PetscReal y0, PetscReal y1,
                                            PetscBool bymass, PetscReal target, const char what[], PetscReal *level);
/* the level of -fs_fill_volume / -fs_fill_mass in the strip x0..x1 of w (2-D) or the box lo..hi of m (3-D) */
PETSC_INTERN PetscErrorCode FSCaseFillLevelPolygon(FSSolver, const FSWalls *, PetscReal x0, PetscReal x1, PetscReal y0,
                                                   PetscReal y1, PetscBool bymass, PetscReal target, const char what[],
                                                   PetscReal *level);
PETSC_INTERN PetscErrorCode FSCaseFillLevelMesh(FSSolver, const FSMesh *, const PetscReal lo[3], const PetscReal hi[3],
                                                PetscBool bymass, PetscReal target, const char what[],
                                                PetscReal *level);
/* the domain: the walls' box with a margin of 4h */
PETSC_INTERN PetscErrorCode FSCaseSetDomainAround(FSSolver, PetscInt dim, const PetscReal lo[], const PetscReal hi[]);
