/*
   Structure "msd": the cantilever as a mass-spring-damper at the tank position x = a (seed Eqs. 16-17)

     m w'' + c w' + K w = F(t),   K = 3 EI / a^3,   omega = sqrt(K/m),   c = 2 xi omega m.

   State y = (w, w'), w the deflection at the tank. The mass comes from named parts, or is given:
     m = f_b m_beam + m_tank + m_ballast,  f_b = 33/140 (-fs_msd_beam_mass_fraction),
   33/140 being the share of a uniform cantilever's mass that moves with its tip when it deflects in
   its static tip-load shape (Rayleigh). -fs_msd_mass and -fs_msd_stiffness replace m and K.
   A point force F_p at x_p (-fs_beam_force) enters through the static shape, as F_p w_s(x_p)/w_s(a)
   (reciprocity); the liquid's force along y acts at the tank. The model has no rotation (the seed:
   "no rolling motion"): the tank translates only.
*/
#include <flexslosh.h>
#include "beamfe.h"

typedef struct {
  FSBeamParams beam;
  PetscReal    mass_given, stiffness_given, beam_fraction;
  PetscReal    m, K, c, omega, force_eq; /* derived */
} MSD;

static PetscErrorCode SetFromOptions(FSStructure st, PetscOptionItems *PetscOptionsObject)
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsSetFromOptions(&p->beam, st->comm, PetscOptionsObject));
  PetscOptionsHeadBegin(PetscOptionsObject, "Structure msd: mass-spring-damper at the tank (seed Eqs. 16-17)");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_msd_beam_mass_fraction",
                          "Share of the beam's mass moving with the tank (33/140: static tip-load shape)", "",
                          &p->beam_fraction, NULL, 0, 1, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_msd_mass",
                          "Total moving mass m (kg), replacing the named parts (0: from the parts)", "", &p->mass_given,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_msd_stiffness",
                          "Stiffness K (N/m), replacing 3 EI/a^3 (0: from the beam)", "", &p->stiffness_given, NULL, 0,
                          PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSStructure st)
{
  MSD                *p = (MSD *)st->data;
  const FSBeamParams *b = &p->beam;
  FSSolver            solver;
  PetscReal           liquid_mass;

  PetscFunctionBegin;
  PetscCall(FSStructureGetSolver(st, &solver));
  PetscCall(FSSolverGetLiquidMass(solver, &liquid_mass));
  PetscCall(FSBeamParamsResolvePayload(&p->beam, st->comm, liquid_mass));
  p->m = p->mass_given > 0 ? p->mass_given : p->beam_fraction * b->mlin * b->L + b->tank_mass + b->ballast_mass;
  PetscCheck(p->m > 0, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Structure msd: the moving mass %g must be positive: set -fs_msd_mass or the parts "
             "(-fs_beam_mass_per_length, -fs_beam_tank_mass, -fs_beam_ballast_mass)",
             (double)p->m);
  p->K           = p->stiffness_given > 0 ? p->stiffness_given : 3 * b->E * b->Iz / (b->a * b->a * b->a);
  p->omega       = PetscSqrtReal(p->K / p->m);
  p->c           = 2 * b->xi * p->omega * p->m;
  p->force_eq    = b->force * FSBeamInfluence(b, b->force_position, b->a) / FSBeamInfluence(b, b->a, b->a);
  st->ndof       = 2;
  st->min_period = 2 * PETSC_PI / p->omega;
  PetscFunctionReturn(0);
}

static PetscErrorCode Initial(FSStructure st, PetscReal y[])
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  y[0] = p->beam.preload;
  y[1] = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  ydot[0] = y[1];
  ydot[1] = (loads->force[1] + p->force_eq - p->c * y[1] - p->K * y[0]) / p->m;
  PetscFunctionReturn(0);
}

static PetscErrorCode Motion(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  m->disp[1] = y[0];
  m->vel[1]  = y[1];
  m->acc[1]  = ydot[1];
  PetscFunctionReturn(0);
}

/* Energies: 1/2 m w'^2, 1/2 K w^2 - F_p w (the point force's potential), damping power c w'^2. */
static PetscErrorCode Energy(FSStructure st, const PetscReal y[], PetscReal E[3])
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  E[0] = 0.5 * p->m * y[1] * y[1];
  E[1] = 0.5 * p->K * y[0] * y[0] - p->force_eq * y[0];
  E[2] = p->c * y[1] * y[1];
  PetscFunctionReturn(0);
}

static PetscErrorCode View(FSStructure st, PetscViewer viewer)
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsView(&p->beam, viewer));
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "mass-spring-damper: m = %g kg, K = %g N/m, c = %g N s/m, f = %g Hz (T = %g s)\n", (double)p->m,
      (double)p->K, (double)p->c, (double)(p->omega / (2 * PETSC_PI)), (double)(2 * PETSC_PI / p->omega)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Summary(FSStructure st, FSJSON js)
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsSummary(&p->beam, js));
  PetscCall(FSJSONWriteReal(js, "mass", p->m));
  PetscCall(FSJSONWriteReal(js, "stiffness", p->K));
  PetscCall(FSJSONWriteReal(js, "damping_coefficient", p->c));
  PetscCall(FSJSONWriteReal(js, "omega", p->omega));
  PetscCall(FSJSONWriteRealArray(js, "frequencies_hz", 1, (PetscReal[]){p->omega / (2 * PETSC_PI)}));
  PetscCall(FSJSONWriteReal(js, "static_tip_deflection", p->force_eq / p->K));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(st->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSStructureCreate_MSD(FSStructure st)
{
  MSD *p;

  PetscFunctionBegin;
  PetscCall(PetscNew(&p));
  PetscCall(FSBeamParamsDefault(&p->beam));
  p->beam_fraction       = 33.0 / 140.0;
  st->data               = p;
  st->ops.setfromoptions = SetFromOptions;
  st->ops.setup          = SetUp;
  st->ops.initial        = Initial;
  st->ops.rhs            = RHS;
  st->ops.motion         = Motion;
  st->ops.energy         = Energy;
  st->ops.view           = View;
  st->ops.summary        = Summary;
  st->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
