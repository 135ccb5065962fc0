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

   The reduced model (-fs_msd_liquid_table, docs/equivalent.md "The reduced model"): the liquid replaced by its
   heave describing function, an effective mass and a damper that depend on the motion's amplitude,
     (m + m_eff(A)) w'' + (c + c_eq(A)) w' + K w = F_p,   A = sqrt(w^2 + (w' / omega_0)^2),
   omega_0 = sqrt(K / (m + M)) with the liquid (mass M) carried rigidly: A is the amplitude of the harmonic
   motion through the current state, the describing function's own assumption, and needs no memory. With
   -fs_msd_liquid_lag tau > 0 the table is looked up at A_tau instead, A seen through a first-order lag,
   A_tau' = (A - A_tau) / tau (a third state, starting at A): a liquid whose response builds up and dies out over
   about tau. m_eff and c_eq are interpolated linearly between the table's rows and held at its first and last
   rows outside.
*/
#include <flexslosh.h>
#include "beamfe.h"
#include "motionseries.h"

typedef struct {
  FSBeamParams   beam;
  PetscReal      mass_given, stiffness_given, beam_fraction;
  PetscReal      m, K, c, omega, force_eq; /* derived */
  char           table_file[PETSC_MAX_PATH_LEN];
  PetscReal      table_mass;  /* M: the liquid's mass the table stands for (kg) */
  FSMotionSeries table[2];    /* m_eff(A), c_eq(A): the rows' points (table[0].n = 0: no table) */
  PetscReal      table_omega; /* omega_0 */
  PetscReal      lag;         /* tau (s); 0: none */
} MSD;

/* m_eff and c_eq at the amplitude of the state (w, w'): linear between the rows, held outside */
static PetscReal HarmonicAmplitude(const MSD *p, const PetscReal y[])
{
  return PetscSqrtReal(y[0] * y[0] + PetscSqr(y[1] / p->table_omega));
}

static void LiquidTable(const MSD *p, const PetscReal y[], PetscReal *meff, PetscReal *ceq)
{
  const FSMotionSeries *s = p->table;
  const PetscInt        n = s[0].n;
  const PetscReal       A = p->lag > 0 ? y[2] : HarmonicAmplitude(p, y);
  PetscInt              k = 0;
  PetscReal             f;

  *meff = *ceq = 0;
  if (!n) return;
  if (A <= s[0].t[0]) {
    *meff = s[0].y[0];
    *ceq  = s[1].y[0];
    return;
  }
  if (A >= s[0].t[n - 1]) {
    *meff = s[0].y[n - 1];
    *ceq  = s[1].y[n - 1];
    return;
  }
  while (s[0].t[k + 1] < A) k++;
  f     = (A - s[0].t[k]) / (s[0].t[k + 1] - s[0].t[k]);
  *meff = (1 - f) * s[0].y[k] + f * s[0].y[k + 1];
  *ceq  = (1 - f) * s[1].y[k] + f * s[1].y[k + 1];
}

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
  PetscCall(PetscOptionsString("-fs_msd_liquid_table",
                               "The reduced model: a file of rows 'A m_eff c_eq' (m, kg, N s/m; A increasing), the "
                               "liquid's heave describing function, replacing the particles (case beam)",
                               "", p->table_file, p->table_file, sizeof(p->table_file), NULL));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_msd_liquid_mass",
                          "The liquid's mass M (kg) of -fs_msd_liquid_table: the payload's share and omega_0", "",
                          &p->table_mass, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_msd_liquid_lag",
                          "The reduced model's lag tau (s): the table looked up at the amplitude seen through a "
                          "first-order lag (0: the current amplitude)",
                          "", &p->lag, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
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
  PetscCall(FSMotionSeriesDestroy(&p->table[0]));
  PetscCall(FSMotionSeriesDestroy(&p->table[1]));
  PetscCall(PetscMemzero(p->table, sizeof(p->table)));
  if (p->table_file[0]) {
    PetscCheck(liquid_mass == 0, st->comm, PETSC_ERR_ARG_INCOMP,
               "-fs_msd_liquid_table %s replaces the liquid by its describing function: use it with -fs_case beam "
               "(no particles), not with a case of %g kg of liquid",
               p->table_file, (double)liquid_mass);
    PetscCheck(p->table_mass > 0, st->comm, PETSC_ERR_ARG_WRONG,
               "-fs_msd_liquid_table %s needs -fs_msd_liquid_mass, the mass (kg) of the liquid it describes",
               p->table_file);
    PetscCall(FSMotionSeriesLoadColumns(st->comm, p->table_file, "-fs_msd_liquid_table", 2, (PetscReal[]){1, 1},
                                        "three numbers a row: the amplitude (m, increasing), m_eff (kg), c_eq (N s/m)",
                                        p->table));
    for (PetscInt k = 0; k < p->table[0].n; k++)
      PetscCheck(p->table[0].t[k] > 0 && p->table[0].y[k] >= 0 && p->table[1].y[k] >= 0, st->comm,
                 PETSC_ERR_FILE_UNEXPECTED,
                 "-fs_msd_liquid_table %s, row %" PetscInt_FMT ": A %g m, m_eff %g kg, c_eq %g N s/m: expected A > 0 "
                 "and m_eff, c_eq >= 0",
                 p->table_file, k + 1, (double)p->table[0].t[k], (double)p->table[0].y[k], (double)p->table[1].y[k]);
    liquid_mass = p->table_mass;
  } else {
    PetscCheck(p->table_mass == 0, st->comm, PETSC_ERR_ARG_WRONG,
               "-fs_msd_liquid_mass %g is the mass of -fs_msd_liquid_table's liquid: give the table too",
               (double)p->table_mass);
    PetscCheck(p->lag == 0, st->comm, PETSC_ERR_ARG_WRONG,
               "-fs_msd_liquid_lag %g is the reduced model's: give -fs_msd_liquid_table too", (double)p->lag);
  }
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
  p->table_omega = PetscSqrtReal(p->K / (p->m + p->table_mass));
  st->ndof       = p->lag > 0 ? 3 : 2;
  st->min_period = 2 * PETSC_PI / p->omega;
  if (p->table[0].n) { /* the shortest period: the smallest effective mass */
    PetscReal mmin = PETSC_MAX_REAL;
    for (PetscInt k = 0; k < p->table[0].n; k++) mmin = PetscMin(mmin, p->table[0].y[k]);
    st->min_period = 2 * PETSC_PI * PetscSqrtReal((p->m + mmin) / p->K);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Initial(FSStructure st, PetscReal y[])
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  y[0] = p->beam.preload;
  y[1] = 0;
  if (p->lag > 0) y[2] = HarmonicAmplitude(p, y);
  PetscFunctionReturn(0);
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  MSD      *p = (MSD *)st->data;
  PetscReal meff, ceq;

  PetscFunctionBegin;
  LiquidTable(p, y, &meff, &ceq);
  if (p->lag > 0) ydot[2] = (HarmonicAmplitude(p, y) - y[2]) / p->lag;
  ydot[0] = y[1];
  ydot[1] = (loads->force[1] + p->force_eq - (p->c + ceq) * y[1] - p->K * y[0]) / (p->m + meff);
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

/* Energies: 1/2 m w'^2, 1/2 K w^2 - F_p w (the point force's potential), damping power c w'^2; with the reduced
   model m + m_eff(A) and c + c_eq(A) (m_eff changing with A, the budget closes only to that change's work). */
static PetscErrorCode Energy(FSStructure st, const PetscReal y[], PetscReal E[3])
{
  MSD      *p = (MSD *)st->data;
  PetscReal meff, ceq;

  PetscFunctionBegin;
  LiquidTable(p, y, &meff, &ceq);
  E[0] = 0.5 * (p->m + meff) * y[1] * y[1];
  E[1] = 0.5 * p->K * y[0] * y[0] - p->force_eq * y[0];
  E[2] = (p->c + ceq) * y[1] * y[1];
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
  if (p->table[0].n)
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "reduced model: the liquid (%g kg) from %s, %" PetscInt_FMT " rows, A %g .. %g m; omega_0 %g rad/s\n",
        (double)p->table_mass, p->table_file, p->table[0].n, (double)p->table[0].t[0],
        (double)p->table[0].t[p->table[0].n - 1], (double)p->table_omega));
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
  if (p->table[0].n) {
    PetscCall(FSJSONWriteString(js, "liquid_table", p->table_file));
    PetscCall(FSJSONWriteReal(js, "liquid_table_mass", p->table_mass));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  MSD *p = (MSD *)st->data;

  PetscFunctionBegin;
  PetscCall(FSMotionSeriesDestroy(&p->table[0]));
  PetscCall(FSMotionSeriesDestroy(&p->table[1]));
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
