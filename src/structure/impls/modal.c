/*
   Structure "modal": the cantilever as a sum of modes (seed Eqs. 18-27)

     w(x, t) = sum_i phi_i(x) q_i(t),   m_i q_i'' + 2 xi_i omega_i m_i q_i' + omega_i^2 m_i q_i = g_i(t),
     g_i = phi_i(a) F_y + theta_i(a) M_z + phi_i(x_p) F_p.

   The modes phi_i come from a finite-element beam (Hermite cubic Euler-Bernoulli elements, src/beamfe.c)
   with the tank's masses and rotary inertia at x = a, computed by SLEPc; each is scaled to a unit
   deflection at the tank, phi_i(a) = 1 (or to a unit largest deflection where the tank sits on a
   node line of the mode), so q_i is mode i's share of the tank's deflection and m_i = phi_i^T M phi_i
   its effective mass there. Forces and moments enter through the mode shapes and their slopes
   (seed Eq. 27): the liquid's force along y and moment about z at the tank, and -fs_beam_force at x_p.
   The initial state is the static deflection shape under a force at the tank, scaled to
   -fs_beam_preload there, projected onto the modes (q_i = phi_i^T M w_s / m_i), at rest.

   State y = (q_1..q_n, q_1'..q_n'). Options: -fs_modal_modes, -fs_modal_elements, -fs_modal_damping
   (one value per mode, default -fs_beam_damping for all), -fs_modal_view; SLEPc's options with the
   prefix -fs_modal_ (e.g. -fs_modal_eps_view).
*/
#include <flexslosh.h>
#include "beamfe.h"
#include "sys/fssys.h"

#define FS_MODAL_MAX_MODES 24

typedef struct {
  FSBeamParams beam;
  PetscInt     nmodes, ne, ndamp;
  PetscReal    damp[FS_MODAL_MAX_MODES];
  PetscBool    view;
  FSBeamFE     fe;
  PetscReal   *omega, *phi, *mass, *xi; /* per mode; phi: nmodes x N */
  PetscReal   *wa, *ta, *wp;            /* phi_i(a), theta_i(a), phi_i(x_p) */
  PetscReal   *y0;                      /* initial modal coordinates */
  PetscReal    static_modes, static_fe; /* deflection at a under -fs_beam_force: from the modes, from the FE solve */
} Modal;

static PetscErrorCode SetFromOptions(FSStructure st, PetscOptionItems *PetscOptionsObject)
{
  Modal    *p  = (Modal *)st->data;
  PetscInt  nd = FS_MODAL_MAX_MODES;
  PetscBool set;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsSetFromOptions(&p->beam, st->comm, PetscOptionsObject));
  PetscOptionsHeadBegin(
      PetscOptionsObject,
      "Structure modal: modal Euler-Bernoulli beam, modes from finite elements and SLEPc (seed Eqs. 18-27)");
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_modal_elements", "Hermite cubic beam elements", "", &p->ne, NULL, 1,
                         PETSC_MAX_INT));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_modal_modes", "Number of modes kept", "", &p->nmodes, NULL, 1,
                         FS_MODAL_MAX_MODES));
  PetscCheck(p->nmodes <= 2 * p->ne, st->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_modal_modes %" PetscInt_FMT " is more than the mesh can give: %" PetscInt_FMT
             " elements (-fs_modal_elements) have %" PetscInt_FMT " DOFs, hence at most %" PetscInt_FMT " modes",
             p->nmodes, p->ne, 2 * p->ne, 2 * p->ne);
  for (PetscInt i = 0; i < FS_MODAL_MAX_MODES; i++) p->damp[i] = p->beam.xi;
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_modal_damping",
                               "Damping ratio of each mode, comma separated (default -fs_beam_damping for all)", "",
                               p->damp, &nd, &set, 0, 1, FS_RANGE_OPEN_UPPER));
  p->ndamp = set ? nd : 0;
  if (set) {
    PetscCheck(nd >= 1 && nd <= p->nmodes, st->comm, PETSC_ERR_ARG_SIZ,
               "-fs_modal_damping has %" PetscInt_FMT " values: expected 1 to %" PetscInt_FMT
               " (-fs_modal_modes); modes without a value take -fs_beam_damping",
               nd, p->nmodes);
    for (PetscInt i = nd; i < FS_MODAL_MAX_MODES; i++) p->damp[i] = p->beam.xi;
  }
  PetscCall(PetscOptionsBool("-fs_modal_view", "Print the modes: frequencies, k_n L, modal masses", "", p->view,
                             &p->view, NULL));
  PetscOptionsHeadEnd();
  /* SLEPc's eigensolver reads -fs_modal_eps_*, its spectral transformation -fs_modal_st_* (with its KSP and PC),
     ... at set-up (FSBeamFEModes) */
  for (PetscInt k = 0; k < 5; k++) {
    const char *prefixes[] = {"-fs_modal_eps_", "-fs_modal_st_", "-fs_modal_bv_", "-fs_modal_ds_", "-fs_modal_rg_"};
    PetscCall(FSOptionsSurveyPrefix(prefixes[k]));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SetUp(FSStructure st)
{
  Modal              *p = (Modal *)st->data;
  const FSBeamParams *b = &p->beam;
  const PetscInt      n = p->nmodes;
  PetscInt            N;
  PetscReal          *ws, wsa, big;
  char                name[32];
  FSSolver            solver;
  PetscReal           liquid_mass;

  PetscFunctionBegin;
  PetscCall(FSStructureGetSolver(st, &solver));
  PetscCall(FSSolverGetLiquidMass(solver, &liquid_mass));
  PetscCall(FSBeamParamsResolvePayload(&p->beam, st->comm, liquid_mass));
  PetscCall(FSBeamFECreate(b, p->ne, &p->fe));
  N = p->fe.N;
  PetscCall(PetscMalloc4(n, &p->omega, n * N, &p->phi, n, &p->mass, n, &p->xi));
  PetscCall(PetscMalloc4(n, &p->wa, n, &p->ta, n, &p->wp, 2 * n, &p->y0));
  PetscCall(FSBeamFEModes(&p->fe, n, "fs_modal_", p->omega, p->phi));
  for (PetscInt i = 0; i < n; i++) {
    PetscReal *ph = &p->phi[i * N], s;
    /* scale: unit deflection at the tank, or unit largest deflection if the tank is (nearly) on a node line */
    big = 0;
    for (PetscInt j = 0; j < N; j += 2) big = PetscMax(big, PetscAbsReal(ph[j]));
    PetscCall(FSBeamFEEvaluate(&p->fe, ph, b->a, &s, NULL));
    if (PetscAbsReal(s) < 1e-6 * big) {
      for (PetscInt j = 0; j < N; j += 2)
        if (PetscAbsReal(ph[j]) == big) {
          s = ph[j];
          break;
        }
    }
    for (PetscInt j = 0; j < N; j++) ph[j] /= s;
    PetscCall(FSBeamFEMassProduct(&p->fe, ph, ph, &p->mass[i]));
    PetscCall(FSBeamFEEvaluate(&p->fe, ph, b->a, &p->wa[i], &p->ta[i]));
    PetscCall(FSBeamFEEvaluate(&p->fe, ph, b->force_position, &p->wp[i], NULL));
    p->xi[i] = p->damp[i];
  }
  /* initial state: the static shape under a force at the tank, scaled to the preload there, projected on the modes */
  PetscCall(PetscMalloc1(N, &ws));
  PetscCall(FSBeamFEStatic(&p->fe, b->a, 1.0, 0.0, ws));
  PetscCall(FSBeamFEEvaluate(&p->fe, ws, b->a, &wsa, NULL));
  for (PetscInt j = 0; j < N; j++) ws[j] *= b->preload / wsa;
  for (PetscInt i = 0; i < n; i++) {
    PetscReal pr;
    PetscCall(FSBeamFEMassProduct(&p->fe, &p->phi[i * N], ws, &pr));
    p->y0[i]     = pr / p->mass[i];
    p->y0[n + i] = 0;
  }
  /* the static deflection at the tank under -fs_beam_force: from the kept modes, and from the full FE model */
  p->static_modes = 0;
  for (PetscInt i = 0; i < n; i++)
    p->static_modes += p->wa[i] * p->wp[i] * b->force / (p->omega[i] * p->omega[i] * p->mass[i]);
  PetscCall(FSBeamFEStatic(&p->fe, b->force_position, b->force, 0.0, ws));
  PetscCall(FSBeamFEEvaluate(&p->fe, ws, b->a, &p->static_fe, NULL));
  PetscCall(PetscFree(ws));

  st->ndof       = 2 * n;
  st->min_period = 2 * PETSC_PI / p->omega[n - 1];
  st->nmodes     = n;
  for (PetscInt i = 0; i < n; i++) st->period[i] = 2 * PETSC_PI / p->omega[i];
  for (PetscInt i = 0; i < n; i++) {
    PetscCall(PetscSNPrintf(name, sizeof(name), "q%" PetscInt_FMT, i + 1));
    PetscCall(FSStructureAddColumn(st, name));
  }
  if (p->view) PetscCall((*st->ops.view)(st, PETSC_VIEWER_STDOUT_(st->comm)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Initial(FSStructure st, PetscReal y[])
{
  Modal *p = (Modal *)st->data;

  PetscFunctionBegin;
  PetscCall(PetscArraycpy(y, p->y0, 2 * p->nmodes));
  PetscFunctionReturn(0);
}

static PetscErrorCode RHS(FSStructure st, PetscReal t, const PetscReal y[], const FSLoads *loads, PetscReal ydot[])
{
  Modal         *p = (Modal *)st->data;
  const PetscInt n = p->nmodes;

  PetscFunctionBegin;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal w = p->omega[i],
                    g = p->wa[i] * loads->force[1] + p->ta[i] * loads->moment[2] + p->wp[i] * p->beam.force;
    ydot[i]           = y[n + i];
    ydot[n + i]       = g / p->mass[i] - 2 * p->xi[i] * w * y[n + i] - w * w * y[i];
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Motion(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[], FSTankMotion *m)
{
  Modal         *p = (Modal *)st->data;
  const PetscInt n = p->nmodes;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  for (PetscInt i = 0; i < n; i++) {
    m->disp[1] += p->wa[i] * y[i];
    m->vel[1] += p->wa[i] * y[n + i];
    m->acc[1] += p->wa[i] * ydot[n + i];
    m->angle += p->ta[i] * y[i];
    m->rate += p->ta[i] * y[n + i];
    m->angacc += p->ta[i] * ydot[n + i];
  }
  PetscFunctionReturn(0);
}

/*
   Energies, sums over the modes (orthogonal in mass and stiffness): 1/2 m_i q_i'^2, 1/2 m_i omega_i^2 q_i^2 -
   phi_i(x_p) F_p q_i (the point force's potential), damping power 2 xi_i omega_i m_i q_i'^2.
*/
static PetscErrorCode Energy(FSStructure st, const PetscReal y[], PetscReal E[3])
{
  Modal         *p = (Modal *)st->data;
  const PetscInt n = p->nmodes;

  PetscFunctionBegin;
  E[0] = E[1] = E[2] = 0;
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal w = p->omega[i], m = p->mass[i], q = y[i], v = y[n + i];
    E[0] += 0.5 * m * v * v;
    E[1] += 0.5 * m * w * w * q * q - p->wp[i] * p->beam.force * q;
    E[2] += 2 * p->xi[i] * w * m * v * v;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Columns(FSStructure st, PetscReal t, const PetscReal y[], const PetscReal ydot[],
                              PetscReal vals[])
{
  Modal *p = (Modal *)st->data;

  PetscFunctionBegin;
  PetscCall(PetscArraycpy(vals, y, p->nmodes));
  PetscFunctionReturn(0);
}

/* The deflected shape at the nodes: <dir>/beam_shape_<step>.csv with x, w, rotation (rank 0). */
static PetscErrorCode Snapshot(FSStructure st, const char dir[], PetscReal t, PetscInt step, const PetscReal y[])
{
  Modal         *p = (Modal *)st->data;
  const PetscInt n = p->nmodes, N = p->fe.N;
  char           path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN + 8];
  FILE          *fp;
  FSFileId       id;
  int            err;

  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/beam_shape_%06" PetscInt_FMT ".csv", dir, step));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
  err = FSFileCreate_Private(tmp, &fp, &id); /* not through a link under the name */
  PetscCheck(!err, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Cannot write the beam shape to %s: %s", tmp, strerror(err));
  PetscCheck(fprintf(fp, "# time %.10e step %" PetscInt_FMT "\nx,w,rotation\n%.10e,%.10e,%.10e\n", (double)t, step, 0.0,
                     0.0, 0.0) > 0,
             PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write %s", tmp);
  for (PetscInt k = 1; k <= p->fe.ne; k++) {
    PetscReal w = 0, th = 0;
    for (PetscInt i = 0; i < n; i++) {
      w += p->phi[i * N + 2 * (k - 1)] * y[i];
      th += p->phi[i * N + 2 * (k - 1) + 1] * y[i];
    }
    PetscCheck(fprintf(fp, "%.10e,%.10e,%.10e\n", (double)p->fe.x[k], (double)w, (double)th) > 0, PETSC_COMM_SELF,
               PETSC_ERR_FILE_WRITE, "Cannot write %s", tmp);
  }
  PetscCheck(fclose(fp) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot close %s", tmp);
  err = FSFileReplace_Private(tmp, path, &id);
  PetscCheck(!err, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot rename %s to %s: %s", tmp, path, strerror(err));
  PetscFunctionReturn(0);
}

/* k_n L of mode i referred to the beam's own mass per length: (omega^2 m L^4/EI)^(1/4) */
static PetscReal KL(const Modal *p, PetscInt i)
{
  const FSBeamParams *b = &p->beam;
  return PetscPowReal(p->omega[i] * p->omega[i] * b->mlin * PetscPowReal(b->L, 4) / (b->E * b->Iz), 0.25);
}

static PetscErrorCode View(FSStructure st, PetscViewer viewer)
{
  Modal *p = (Modal *)st->data;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsView(&p->beam, viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "modal beam: %" PetscInt_FMT " modes from %" PetscInt_FMT
                                   " Hermite elements (SLEPc); modes scaled to a unit deflection at the tank\n",
                                   p->nmodes, p->ne));
  if (!p->omega) PetscFunctionReturn(0);
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "  mode   f (Hz)         omega (rad/s)  k_n L        modal mass (kg) damping  phi(a)   theta(a)\n"));
  for (PetscInt i = 0; i < p->nmodes; i++)
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "  %4" PetscInt_FMT "   %-13.7g  %-13.7g  %-11.8f  %-15.6g %-8.4g %-8.4g %-8.4g\n", i + 1,
        (double)(p->omega[i] / (2 * PETSC_PI)), (double)p->omega[i], (double)KL(p, i), (double)p->mass[i],
        (double)p->xi[i], (double)p->wa[i], (double)p->ta[i]));
  if (p->beam.force != 0)
    PetscCall(PetscViewerASCIIPrintf(
        viewer, "  static deflection at the tank under -fs_beam_force %g N: %.8g m (modes), %.8g m (finite elements)\n",
        (double)p->beam.force, (double)p->static_modes, (double)p->static_fe));
  PetscFunctionReturn(0);
}

static PetscErrorCode Summary(FSStructure st, FSJSON js)
{
  Modal         *p = (Modal *)st->data;
  const PetscInt n = p->nmodes;
  PetscReal     *f, *kl;

  PetscFunctionBegin;
  PetscCall(FSBeamParamsSummary(&p->beam, js));
  PetscCall(FSJSONWriteInt(js, "elements", p->ne));
  PetscCall(FSJSONWriteInt(js, "modes", n));
  PetscCall(PetscMalloc2(n, &f, n, &kl));
  for (PetscInt i = 0; i < n; i++) {
    f[i]  = p->omega[i] / (2 * PETSC_PI);
    kl[i] = KL(p, i);
  }
  PetscCall(FSJSONWriteRealArray(js, "frequencies_hz", n, f));
  PetscCall(FSJSONWriteRealArray(js, "omega", n, p->omega));
  PetscCall(FSJSONWriteRealArray(js, "kL", n, kl));
  PetscCall(FSJSONWriteRealArray(js, "modal_mass", n, p->mass));
  PetscCall(FSJSONWriteRealArray(js, "modal_damping", n, p->xi));
  PetscCall(FSJSONWriteRealArray(js, "phi_tank", n, p->wa));
  PetscCall(FSJSONWriteRealArray(js, "theta_tank", n, p->ta));
  PetscCall(FSJSONWriteRealArray(js, "initial_q", n, p->y0));
  PetscCall(FSJSONWriteReal(js, "static_tip_deflection", p->static_modes));
  PetscCall(FSJSONWriteReal(js, "static_tip_deflection_fe", p->static_fe));
  PetscCall(PetscFree2(f, kl));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FSStructure st)
{
  Modal *p = (Modal *)st->data;

  PetscFunctionBegin;
  if (p->omega) {
    PetscCall(PetscFree4(p->omega, p->phi, p->mass, p->xi));
    PetscCall(PetscFree4(p->wa, p->ta, p->wp, p->y0));
  }
  PetscCall(FSBeamFEDestroy(&p->fe));
  PetscCall(PetscFree(st->data));
  PetscFunctionReturn(0);
}

PETSC_EXTERN PetscErrorCode FSStructureCreate_Modal(FSStructure st)
{
  Modal *p;

  PetscFunctionBegin;
  PetscCall(PetscNew(&p));
  PetscCall(FSBeamParamsDefault(&p->beam));
  p->nmodes              = 5;
  p->ne                  = 40;
  st->data               = p;
  st->ops.setfromoptions = SetFromOptions;
  st->ops.setup          = SetUp;
  st->ops.initial        = Initial;
  st->ops.rhs            = RHS;
  st->ops.motion         = Motion;
  st->ops.energy         = Energy;
  st->ops.columns        = Columns;
  st->ops.snapshot       = Snapshot;
  st->ops.view           = View;
  st->ops.summary        = Summary;
  st->ops.destroy        = Destroy;
  PetscFunctionReturn(0);
}
