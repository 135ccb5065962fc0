/*
   The energy budget of the run (seed Eqs. 31-40), written every step to energy.csv.

   The liquid (2-D: energies per unit width, J/m) in the tank's frame:
     E_kin  = 1/2 sum_i m_i |u_i|^2,  E_pot = -sum_i m_i g . x_i,
     E_comp = sum_i m_i e(rho_i),  de/drho = p/rho^2 for p = c0^2 (rho - rho0) + p_b, that is
              e(rho) = c0^2 (ln(rho/rho0) + rho0/rho - 1) + p_b (1/rho0 - 1/rho),
   so that dE_comp/dt = sum_i V_i p_i/rho_i D rho_i/Dt (seed Eq. 37) exactly, and
     d(E_kin + E_pot + E_comp)/dt = P_delta + P_alpha + P_wall + P_ext + P_relax
   holds exactly for the semi-discrete equations (with dx/dt = u: particle shifting moves particles
   without a power, which the residual then shows where there is gravity):
     P_delta  term delta,
     P_alpha  terms viscosity and les_viscosity (and any other term with a power, e.g. plug-ins),
     P_wall   terms continuity and pressure (their powers cancel exactly without walls; near walls the
              gradient is renormalized by gamma_i and the divergence is not), and the wall_* terms,
     P_ext    the inertial accelerations of the tank's frame (src/coupling/coupling.c), rotated gravity included,
     P_relax  the start-up relaxation (-fs_relax_time).
   Gravity's power is -dE_pot/dt. The powers' time integrals are global DOFs of the TS state
   (work_*), integrated by the same integrator as the particles, so
     residual_liquid = E_liquid(t) - E_liquid(0) - (work_delta + work_alpha + work_wall + work_ext + work_relax)
                       - work_bounce
   is the integrator's quadrature error only: it vanishes at the integrator's order as dt -> 0.
   work_bounce sums the energy changes of the wall bounces (-fs_walls_bounce_distance), which move
   particles and reverse their normal velocities between steps, outside the equations.

   The whole system (docs/decisions.md, "Energy budget"): with the liquid's energy in the absolute
   frame E_liquid_abs (velocities V = V_ref + R(theta) (u + omega e_z x r), positions X = x_ref +
   d + R(theta) r, r = x - x_ref) times the tank's width w, the structure's kinetic and potential
   energies (its ops.energy), and the potential of the liquid's static loads L_s that the structure does
   not see (its deflections are measured from the equilibrium under them), L_s . (d, theta):
     E_total = w E_liquid_abs + E_struct_kin + E_struct_elastic + L_s . (d, theta),
     residual_total = E_total - E_total(0) - w (work_delta + work_alpha + work_wall + work_relax)
                      - work_struct_damping - work_coupling - work_bounce_total - work_motion,
   where work_coupling integrates the power of the coupling's own error,
     P_coupling = w [(F_walls + F_L) . R(-theta) V_ref + omega (M_walls + M_L)],
   F_L, M_L the loads the structure receives (the wall-pressure integral and the wall shear, in the tank's
   frame, about x_ref, per unit width) and F_walls, M_walls = sum_i m_i (f_i - g) (x r) the force and
   moment that all terms but gravity put on the particles (the walls' force on the liquid: internal
   forces cancel, except where gamma_i renormalizes them). With the default loads, the exact reaction
   (-fs_coupling_loads reaction), P_coupling vanishes; with the wall-pressure integral (walls) it is the
   energy the coupling creates or destroys (a few per cent of the structure's energy in a free decay),
   while residual_total is the quadrature error only. work_bounce_total is the bounces' share (in the absolute frame a
   bounce is an impulse from the tank that the structure does not receive). Without coupling, w = 1, E_liquid_abs =
   E_liquid and L_s = 0: the sum of the two separate budgets.
   A prescribed motion (FSStructure.prescribed, docs/motion.md) has no energy of its own and L_s = 0: it does the
   work work_motion, the integral of w [R . R(-theta) V_ref + omega R_M] with R, R_M the force and moment of all terms
   but gravity and the frame's inertia (the relaxation's included) on the liquid, which residual_total subtracts.
*/
#include <math.h>
#include "solver/solverimpl.h"

enum { FS_E_KIN, FS_E_POT, FS_E_COMP, FS_E_KIN_ABS, FS_E_POT_ABS };
#define FS_E_NLIQ FS_ENERGY_NSUMS /* the five above */

static const char *FSEnergyNames[] = {"time",
                                      "E_kin",
                                      "E_pot",
                                      "E_comp",
                                      "E_liquid",
                                      "work_delta",
                                      "work_alpha",
                                      "work_wall",
                                      "work_ext",
                                      "work_relax",
                                      "residual_liquid",
                                      "E_struct_kin",
                                      "E_struct_elastic",
                                      "work_struct_damping",
                                      "work_coupling",
                                      "work_motion",
                                      "work_bounce",
                                      "work_bounce_total",
                                      "E_liquid_abs",
                                      "E_total",
                                      "residual_total"};
#define FS_ENERGY_NCOLUMNS ((PetscInt)(sizeof(FSEnergyNames) / sizeof(FSEnergyNames[0])))

/* FSSolverEnergyColumns - the names of the columns of energy.csv. */
PetscErrorCode FSSolverEnergyColumns(FSSolver s, PetscInt *n, const char *names[])
{
  PetscFunctionBegin;
  (void)s;
  for (PetscInt c = 0; c < FS_ENERGY_NCOLUMNS; c++) names[c] = FSEnergyNames[c];
  *n = FS_ENERGY_NCOLUMNS;
  PetscFunctionReturn(0);
}

/* The compressibility energy per unit mass e(rho) of the linear equation of state (accurate near rho0). */
static inline PetscReal FSCompressibilityEnergy(PetscReal rho, PetscReal rho0, PetscReal c0, PetscReal pb)
{
  const PetscReal x = (rho - rho0) / rho0;
  return c0 * c0 * (log1p(x) - x / (1 + x)) + pb * x / rho;
}

/*
   The structure's energies at its state s->sy (rank 0; its ops.energy), checked: a value that is not finite
   is an error naming the step, the time, the energy, the state and the likely cause, raised before the
   row of energy.csv that would hold it is written.
*/
static PetscErrorCode FSSolverStructureEnergy(FSSolver s, PetscReal E[3])
{
  static const char *name[] = {"kinetic energy", "elastic energy", "damping power"};
  FSStructure        st     = s->structure;
  PetscReal          t, ymax = 0;
  PetscInt           step, c = 0;
  PetscBool          finite     = PETSC_TRUE, found;
  char               state[256] = "", cause[512];

  PetscFunctionBegin;
  PetscCall((*st->ops.energy)(st, s->sy, E));
  while (c < 3 && !PetscIsInfOrNanReal(E[c])) c++;
  if (c == 3) PetscFunctionReturn(0);
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  for (PetscInt k = 0; k < st->ndof; k++) {
    char v[32];
    if (PetscIsInfOrNanReal(s->sy[k])) finite = PETSC_FALSE;
    else ymax = PetscMax(ymax, PetscAbsReal(s->sy[k]));
    if (k == 6) PetscCall(PetscStrlcat(state, ", ...", sizeof(state)));
    if (k >= 6) continue;
    PetscCall(PetscSNPrintf(v, sizeof(v), "%s%g", k ? ", " : "", (double)s->sy[k]));
    PetscCall(PetscStrlcat(state, v, sizeof(state)));
  }
  PetscCall(FSSolverBlowUpCause(s, cause, sizeof(cause), &found));
  if (!found && finite && ymax > 1e150) /* a square of it overflows */
    PetscCall(PetscStrncpy(cause,
                           "a state so large that its energies overflow: check the structure's options and its initial "
                           "state (e.g. -fs_beam_preload)",
                           sizeof(cause)));
  else if (!found && finite)
    PetscCall(PetscStrncpy(
        cause, "the model's energy routine, which gives a value that is not finite for a finite state", sizeof(cause)));
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FP,
          "The run blew up: the structure's energy is not finite: structure %s's %s is %s at step %" PetscInt_FMT
          ", time %g (state: %s). Likely cause: %s",
          st->name, name[c], PetscIsNanReal(E[c]) ? "NaN" : (E[c] > 0 ? "+Inf" : "-Inf"), step, (double)t, state,
          cause);
}

/*
   FSSolverEnergyLocal - this rank's sums of the liquid's energies of the current state (loc[FS_E_*],
   FS_ENERGY_NSUMS values: E_kin, E_pot, E_comp in the tank's frame, E_kin and E_pot in the absolute one) and the
   tank's motion mo, for FSSolverEnergySummed() once loc is summed over the ranks. Collective for a rank0 structure
   only (its motion is broadcast).
*/
PetscErrorCode FSSolverEnergyLocal(FSSolver s, PetscReal loc[], FSTankMotion *mo)
{
  const PetscInt     dim = s->opt.dim, US = s->state.ustride, S = s->pw.stride;
  const PetscReal   *g = s->opt.gravity;
  const PetscScalar *u;
  PetscReal          c, sn;
  PetscBool          coupled;

  PetscFunctionBegin;
  for (PetscInt k = 0; k < FS_E_NLIQ; k++) loc[k] = 0;
  PetscCall(FSCouplingGetActive(s->coupling, &coupled));
  PetscCall(FSSolverGetTankMotion(s, mo)); /* zero without a structure; sets s->sy */
  c  = PetscCosReal(mo->angle);
  sn = PetscSinReal(mo->angle);
  PetscCall(VecGetArrayRead(s->state.U, &u));
  for (PetscInt p = 0; p < s->pw.nowned; p++) {
    const PetscScalar *x = &u[p * US], *v = x + dim;
    const PetscReal    m = s->pw.rec[p * S + 2 * dim + 1], rho = x[2 * dim];
    PetscReal          v2 = 0, gx = 0;
    for (PetscInt d = 0; d < dim; d++) {
      v2 += v[d] * v[d];
      gx += g[d] * x[d];
    }
    loc[FS_E_KIN] += 0.5 * m * v2;
    loc[FS_E_POT] -= m * gx;
    loc[FS_E_COMP] += m * FSCompressibilityEnergy(rho, s->opt.rho0, s->opt.c0, s->opt.background_pressure);
    if (coupled) { /* the absolute frame */
      PetscReal kin, pot;
      FSCouplingAbsoluteEnergy(s->coupling, mo, c, sn, x, v, m, &kin, &pot);
      loc[FS_E_KIN_ABS] += kin;
      loc[FS_E_POT_ABS] += pot;
    }
  }
  PetscCall(VecRestoreArrayRead(s->state.U, &u));
  if (!coupled) {
    loc[FS_E_KIN_ABS] = loc[FS_E_KIN];
    loc[FS_E_POT_ABS] = loc[FS_E_POT];
  }
  PetscFunctionReturn(0);
}

/*
   The structure's energies at the tank's motion mo (rank 0; every rank for a structure that runs there):
   st[0..2] structure kinetic, potential, L_s . (d, theta). Collective for a rank0 structure.
*/
static PetscErrorCode FSSolverEnergyStructure(FSSolver s, const FSTankMotion *mo, PetscReal st[3])
{
  PetscFunctionBegin;
  st[0] = st[1] = st[2] = 0;
  if (s->structure && s->structure->ndof && s->structure->ops.energy) {
    PetscReal E[3] = {0, 0, 0};
    PetscCall(FSSolverStructureResultRank0(s, FSSolverStructureHere(s) ? FSSolverStructureEnergy(s, E) : 0, "energy", 0,
                                           NULL));
    st[0] = E[0];
    st[1] = E[1];
  }
  if (!s->structure || !s->structure->prescribed) PetscCall(FSCouplingStaticLoadsWork(s->coupling, mo, &st[2]));
  PetscFunctionReturn(0);
}

/* The liquid's energies of the current state summed over the ranks, liq[FS_E_*], and the tank's motion mo. Collective
 */
static PetscErrorCode FSSolverEnergyLiquid(FSSolver s, PetscReal liq[FS_E_NLIQ], FSTankMotion *mo)
{
  PetscReal loc[FS_E_NLIQ];

  PetscFunctionBegin;
  PetscCall(FSSolverEnergyLocal(s, loc, mo));
  PetscCallMPI(MPI_Allreduce(loc, liq, FS_E_NLIQ, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)s)));
  PetscFunctionReturn(0);
}

/* The liquid's energy (tank frame) and the whole system's energy of the current state (valid on rank 0). */
static PetscErrorCode FSSolverEnergyTotals(FSSolver s, PetscReal e[2])
{
  PetscReal    liq[FS_E_NLIQ], st[3], w;
  FSTankMotion mo;

  PetscFunctionBegin;
  PetscCall(FSCouplingGetWidth(s->coupling, &w));
  PetscCall(FSSolverEnergyLiquid(s, liq, &mo));
  PetscCall(FSSolverEnergyStructure(s, &mo, st));
  e[0] = liq[FS_E_KIN] + liq[FS_E_POT] + liq[FS_E_COMP];
  e[1] = w * (liq[FS_E_KIN_ABS] + liq[FS_E_POT_ABS] + liq[FS_E_COMP]) + st[0] + st[1] + st[2];
  PetscFunctionReturn(0);
}

/*
   FSSolverEnergyJumpFrame - the tank's motion of the current state, for FSEnergyParticle: the changes
   made to particles between steps (the wall bounces, FSSolverWallsBounce) are booked particle by
   particle, without passes over all particles. Collective (a Bcast when coupled).
*/
PetscErrorCode FSSolverEnergyJumpFrame(FSSolver s, FSEnergyFrame *fr)
{
  PetscFunctionBegin;
  PetscCall(FSSolverGetTankMotion(s, &fr->mo));
  PetscCall(FSCouplingGetActive(s->coupling, &fr->coupled));
  fr->c  = PetscCosReal(fr->mo.angle);
  fr->sn = PetscSinReal(fr->mo.angle);
  PetscFunctionReturn(0);
}

/* FSEnergyParticle - one particle's mechanical energy in the tank's frame (e[0]) and in the absolute frame
   (e[1], the tank's frame without a coupling); compressibility does not change in a bounce. */
void FSEnergyParticle(FSSolver s, const FSEnergyFrame *fr, const PetscReal x[], const PetscReal v[], PetscReal m,
                      PetscReal e[2])
{
  PetscReal v2 = 0, gx = 0;
  for (PetscInt d = 0; d < s->opt.dim; d++) {
    v2 += v[d] * v[d];
    gx += s->opt.gravity[d] * x[d];
  }
  e[0] = 0.5 * m * v2 - m * gx;
  if (fr->coupled) {
    PetscReal kin, pot;
    FSCouplingAbsoluteEnergy(s->coupling, &fr->mo, fr->c, fr->sn, x, v, m, &kin, &pot);
    e[1] = kin + pot;
  } else e[1] = e[0];
}

/* FSSolverEnergyAddJump - adds this rank's energy changes de (liquid, whole system) of the changes
   between steps to the energy block (work_bounce, work_bounce_total), summed over the ranks (summed: de is the
   sum already). After the repacking of the state. Collective unless summed. */
PetscErrorCode FSSolverEnergyAddJump(FSSolver s, const PetscReal de[2], PetscBool summed)
{
  PetscReal   sum[2] = {de[0], de[1]};
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  if (!summed) PetscCallMPI(MPI_Reduce(de, sum, 2, MPIU_REAL, MPI_SUM, 0, PetscObjectComm((PetscObject)s)));
  if (!summed && s->pw.decomp.size > 1) s->mon.par.uncounted++; /* PETSc's counters miss MPI_Reduce */
  if (!rank) {
    PetscReal    w; /* the liquid's energies are per unit width */
    PetscScalar *u;
    PetscCall(FSCouplingGetWidth(s->coupling, &w));
    PetscCall(VecGetArray(s->state.U, &u));
    u[s->pw.nowned * s->state.ustride + s->state.genergy + FS_ENERGY_WORK_BOUNCE] += sum[0];
    u[s->pw.nowned * s->state.ustride + s->state.genergy + FS_ENERGY_WORK_BOUNCE_TOTAL] += w * sum[1];
    PetscCall(VecRestoreArray(s->state.U, &u));
  }
  PetscFunctionReturn(0);
}

/* FSSolverCompressibilityEnergy - e(rho) of the run's equation of state (per unit mass). Not collective. */
PetscReal FSSolverCompressibilityEnergy(FSSolver s, PetscReal rho)
{
  return FSCompressibilityEnergy(rho, s->opt.rho0, s->opt.c0, s->opt.background_pressure);
}

/* FSSolverEnergyAddTermWork - adds this rank's share dw of the work of term t done between steps (its split
   stages, FSSolverSplitStep) to the term's dissipated energy, summed over the ranks. Collective. */
PetscErrorCode FSSolverEnergyAddTermWork(FSSolver s, FSTerm t, PetscReal dw)
{
  PetscReal   sum;
  PetscMPIInt rank;
  PetscInt    q = 0;

  PetscFunctionBegin;
  PetscCheck(t->has_power, PetscObjectComm((PetscObject)s), PETSC_ERR_PLIB, "term %s has no power to book", t->name);
  for (PetscInt k = 0; k < s->terms.nterms && s->terms.term[k] != t; k++)
    if (s->terms.term[k]->has_power) q++;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  PetscCallMPI(MPI_Reduce(&dw, &sum, 1, MPIU_REAL, MPI_SUM, 0, PetscObjectComm((PetscObject)s)));
  if (s->pw.decomp.size > 1) s->mon.par.uncounted++; /* PETSc's counters miss MPI_Reduce */
  if (!rank) {
    PetscScalar *u;
    PetscCall(VecGetArray(s->state.U, &u));
    u[s->pw.nowned * s->state.ustride + s->state.gdiss + q] += sum;
    PetscCall(VecRestoreArray(s->state.U, &u));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverEnergyInitial - records the liquid's and the whole system's energies of the current state as
   the budget's initial values (in the energy block of the state; at the start of a run, not on restart).

   Collective
*/
PetscErrorCode FSSolverEnergyInitial(FSSolver s)
{
  PetscReal   e[2] = {0, 0};
  PetscMPIInt rank;

  PetscFunctionBegin;
  PetscCall(FSSolverEnergyTotals(s, e));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  if (!rank) {
    PetscScalar *u;
    PetscCall(VecGetArray(s->state.U, &u));
    u[s->pw.nowned * s->state.ustride + s->state.genergy + FS_ENERGY_LIQUID0] = e[0];
    u[s->pw.nowned * s->state.ustride + s->state.genergy + FS_ENERGY_TOTAL0]  = e[1];
    PetscCall(VecRestoreArray(s->state.U, &u));
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverEnergySummed - the values of the columns of energy.csv at the current state (valid on rank 0) from the
   liquid's energies liq of FSSolverEnergyLocal() summed over the ranks and the tank's motion mo it gave.

   Collective for a rank0 structure
*/
PetscErrorCode FSSolverEnergySummed(FSSolver s, const PetscReal liq[], const FSTankMotion *mo, PetscReal vals[])
{
  PetscReal   st[3], work[3] = {0, 0, 0}, eb[FS_ENERGY_NDOF], t;
  PetscMPIInt rank;
  PetscInt    k = 0;

  PetscFunctionBegin;
  PetscCall(FSSolverEnergyStructure(s, mo, st));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)s), &rank));
  if (rank) PetscFunctionReturn(0);
  PetscCall(TSGetTime(s->ts, &t));
  {
    const PetscScalar *u;
    const PetscInt     off = s->pw.nowned * s->state.ustride;
    PetscInt           q   = 0;
    PetscCall(VecGetArrayRead(s->state.U, &u));
    for (PetscInt tt = 0; tt < s->terms.nterms; tt++) {
      FSTerm          term = s->terms.term[tt];
      const char     *name = term->name;
      const PetscReal wk   = term->has_power ? u[off + s->state.gdiss + q++] : 0;
      if (!term->has_power) continue;
      if (!strcmp(name, "delta")) work[0] += wk;
      else if (!strcmp(name, "continuity") || !strcmp(name, "pressure") || !strncmp(name, "wall_", 5)) work[2] += wk;
      else work[1] += wk;
    }
    for (PetscInt e = 0; e < FS_ENERGY_NDOF; e++) eb[e] = u[off + s->state.genergy + e];
    PetscCall(VecRestoreArrayRead(s->state.U, &u));
  }
  {
    PetscReal w;
    PetscCall(FSCouplingGetWidth(s->coupling, &w));
    const PetscReal Eliq = liq[FS_E_KIN] + liq[FS_E_POT] + liq[FS_E_COMP],
                    Eabs = liq[FS_E_KIN_ABS] + liq[FS_E_POT_ABS] + liq[FS_E_COMP];
    const PetscReal Etot = w * Eabs + st[0] + st[1] + st[2];
    const PetscReal Wint = work[0] + work[1] + work[2] + eb[FS_ENERGY_WORK_RELAX];
    vals[k++]            = t;
    vals[k++]            = liq[FS_E_KIN];
    vals[k++]            = liq[FS_E_POT];
    vals[k++]            = liq[FS_E_COMP];
    vals[k++]            = Eliq;
    vals[k++]            = work[0];
    vals[k++]            = work[1];
    vals[k++]            = work[2];
    vals[k++]            = eb[FS_ENERGY_WORK_EXT];
    vals[k++]            = eb[FS_ENERGY_WORK_RELAX];
    vals[k++]            = Eliq - eb[FS_ENERGY_LIQUID0] - Wint - eb[FS_ENERGY_WORK_EXT] - eb[FS_ENERGY_WORK_BOUNCE];
    vals[k++]            = st[0];
    vals[k++]            = st[1];
    vals[k++]            = eb[FS_ENERGY_WORK_DAMPING];
    vals[k++]            = eb[FS_ENERGY_WORK_COUPLING];
    vals[k++]            = eb[FS_ENERGY_WORK_MOTION];
    vals[k++]            = eb[FS_ENERGY_WORK_BOUNCE];
    vals[k++]            = eb[FS_ENERGY_WORK_BOUNCE_TOTAL];
    vals[k++]            = Eabs;
    vals[k++]            = Etot;
    vals[k++] = Etot - eb[FS_ENERGY_TOTAL0] - w * Wint - eb[FS_ENERGY_WORK_DAMPING] - eb[FS_ENERGY_WORK_COUPLING] -
                eb[FS_ENERGY_WORK_BOUNCE_TOTAL] - eb[FS_ENERGY_WORK_MOTION];
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverEnergyValues - the values of the columns of energy.csv at the current state (valid on rank 0).

   Collective
*/
static PetscErrorCode FSSolverEnergyValues(FSSolver s, PetscReal vals[])
{
  PetscReal    liq[FS_E_NLIQ];
  FSTankMotion mo;

  PetscFunctionBegin;
  PetscCall(FSSolverEnergyLiquid(s, liq, &mo));
  PetscCall(FSSolverEnergySummed(s, liq, &mo, vals));
  PetscFunctionReturn(0);
}

/*
   FSSolverGetEnergy - the energy budget of the current state: the columns of energy.csv (time, E_kin,
   E_pot, ..., residual_total), on every rank.

   Collective

   Input Parameter:
.  s - the solver, set up

   Output Parameters:
+  n      - the number of columns (at most FS_ENERGY_MAX_COLUMNS)
.  names  - their names (an array of FS_ENERGY_MAX_COLUMNS pointers, or NULL); static strings
-  values - their values (an array of FS_ENERGY_MAX_COLUMNS reals, or NULL)

   Notes:
   The budget's initial energies are those of the state the run starts from: asked before the first
   FSSolverStep() or FSSolverSolve(), they are recorded from the current state (the run records them
   again at its start, from the same state), so the residuals are zero there.

.seealso: FSSolverSolve(), docs/running.md, "Output" (energy.csv)
*/
PetscErrorCode FSSolverGetEnergy(FSSolver s, PetscInt *n, const char *names[], PetscReal values[])
{
  PetscFunctionBegin;
  PetscCheck(s->setupcalled, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_WRONGSTATE,
             "FSSolverGetEnergy(): call FSSolverSetUp() first");
  PetscCheck(FS_ENERGY_NCOLUMNS <= FS_ENERGY_MAX_COLUMNS, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "energy.csv has %" PetscInt_FMT " columns, more than FS_ENERGY_MAX_COLUMNS", FS_ENERGY_NCOLUMNS);
  *n = FS_ENERGY_NCOLUMNS;
  if (names)
    for (PetscInt c = 0; c < FS_ENERGY_NCOLUMNS; c++) names[c] = FSEnergyNames[c];
  if (values) {
    if (!s->mon.monitoring && !s->opt.restart[0])
      PetscCall(FSSolverEnergyInitial(s)); /* before the run: its initial state */
    PetscCall(FSSolverEnergyValues(s, values));
    PetscCallMPI(MPI_Bcast(values, (PetscMPIInt)FS_ENERGY_NCOLUMNS, MPIU_REAL, 0, PetscObjectComm((PetscObject)s)));
  }
  PetscFunctionReturn(0);
}
