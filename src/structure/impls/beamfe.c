/*
   The cantilever beam shared by the structure models (see beamfe.h): the -fs_beam_* parameters,
   and the Hermite cubic Euler-Bernoulli finite elements with point masses and rotary inertias,
   the static solve and the modes (SLEPc).

   Element of length l, DOFs (w1, theta1, w2, theta2), s = (x - x1)/l in [0, 1]:
     N1 = 1 - 3s^2 + 2s^3, N2 = l (s - 2s^2 + s^3), N3 = 3s^2 - 2s^3, N4 = l (s^3 - s^2);
     K_e = EI/l^3 [12 6l -12 6l; 6l 4l^2 -6l 2l^2; -12 -6l 12 -6l; 6l 2l^2 -6l 4l^2],
     M_e = m l/420 [156 22l 54 -13l; 22l 4l^2 13l -3l^2; 54 13l 156 -22l; -13l -3l^2 -22l 4l^2].
   The tank's masses add to M at the w DOF of the node at x = a, its rotary inertia at the theta DOF.
*/
#include <flexslosh.h>
#include "beamfe.h"
#include <slepceps.h>

/* FSBeamParamsDefault - the seed's beam (E = 210 GPa, I = 5.57e-7 m^4, L = 2.48 m, 13.04 kg/m), no payload, xi = 1.5 %.
 */
PetscErrorCode FSBeamParamsDefault(FSBeamParams *p)
{
  PetscFunctionBegin;
  PetscCall(PetscMemzero(p, sizeof(*p)));
  p->E    = 210e9;
  p->Iz   = 5.57e-7;
  p->L    = 2.48;
  p->mlin = 13.04;
  p->xi   = 0.015;
  PetscFunctionReturn(0);
}

/*
   FSBeamParamsSetFromOptions - reads the beam's options (inside an options block) and checks them.

   Options Database Keys:
+  -fs_beam_E <210e9>                - Young's modulus (Pa)
.  -fs_beam_I <5.57e-7>              - second moment of area (m^4)
.  -fs_beam_length <2.48>            - effective length L (m)
.  -fs_beam_mass_per_length <13.04>  - mass per unit length (kg/m)
.  -fs_beam_tank_position <L>        - where the tank is attached, x in (0, L]
.  -fs_beam_tank_mass <0>            - tank mass (with its supports), at the tank position
.  -fs_beam_ballast_mass <0>         - ballast or solid mass in the tank
.  -fs_beam_payload_mass <0>         - liquid + ballast: the ballast makes up the difference (fill-level sweeps at equal
mass) .  -fs_beam_tank_inertia <0>         - rotary inertia of tank + ballast about z at the tank position (kg m^2) .
-fs_beam_damping <0.015>          - damping ratio xi, in [0, 1) .  -fs_beam_preload <0>              - initial
deflection at the tank position (static shape, released from rest) .  -fs_beam_force <0>                - constant point
force along y from t = 0 (e.g. -M g of masses hung at the tip)
-  -fs_beam_force_position <a>       - where that force acts, in (0, L]
*/
PetscErrorCode FSBeamParamsSetFromOptions(FSBeamParams *p, MPI_Comm comm, PetscOptionItems *PetscOptionsObject)
{
  PetscBool set;

  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "Cantilever beam carrying the tank (structure models msd and modal)");
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_E", "Young's modulus E (Pa)", "FSBeamParamsSetFromOptions",
                          &p->E, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_I", "Second moment of area I (m^4)",
                          "FSBeamParamsSetFromOptions", &p->Iz, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_length", "Effective length L (m)", "FSBeamParamsSetFromOptions",
                          &p->L, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_mass_per_length", "Mass per unit length (kg/m)",
                          "FSBeamParamsSetFromOptions", &p->mlin, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  if (p->a <= 0) p->a = p->L;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_tank_position",
                          "Where the tank is attached, x in (0, L] (default L, the tip)", "FSBeamParamsSetFromOptions",
                          &p->a, &set, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCheck(p->a > 0 && p->a <= p->L, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_beam_tank_position %g is outside the beam: expected a value in (0, %g] (-fs_beam_length)",
             (double)p->a, (double)p->L);
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_tank_mass",
                          "Tank mass with its supports (kg), at the tank position", "FSBeamParamsSetFromOptions",
                          &p->tank_mass, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_ballast_mass", "Ballast or solid mass in the tank (kg)",
                          "FSBeamParamsSetFromOptions", &p->ballast_mass, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_payload_mass",
                          "Mass of the liquid and the ballast together (kg): the ballast makes up the difference to "
                          "the liquid (0: -fs_beam_ballast_mass as given)",
                          "FSBeamParamsSetFromOptions", &p->payload_mass, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_tank_inertia",
                          "Rotary inertia of tank and ballast about z at the tank position (kg m^2)",
                          "FSBeamParamsSetFromOptions", &p->tank_inertia, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_damping", "Damping ratio xi (fraction of critical)",
                          "FSBeamParamsSetFromOptions", &p->xi, NULL, 0, 1, FS_RANGE_OPEN_UPPER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_preload",
                          "Initial deflection at the tank position (static shape), released from rest (m)",
                          "FSBeamParamsSetFromOptions", &p->preload, NULL, PETSC_NINFINITY, PETSC_INFINITY,
                          FS_RANGE_CLOSED));
  PetscCall(
      FSOptionsReal(PetscOptionsObject, "-fs_beam_force",
                    "Constant point force along y applied from t = 0 (N), e.g. the weight of masses hung at the tip",
                    "FSBeamParamsSetFromOptions", &p->force, NULL, PETSC_NINFINITY, PETSC_INFINITY, FS_RANGE_CLOSED));
  if (p->force_position <= 0) p->force_position = p->a;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_beam_force_position",
                          "Where -fs_beam_force acts, x in (0, L] (default: the tank position)",
                          "FSBeamParamsSetFromOptions", &p->force_position, NULL, PETSC_NINFINITY, PETSC_INFINITY,
                          FS_RANGE_CLOSED));
  PetscCheck(p->force_position > 0 && p->force_position <= p->L, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_beam_force_position %g is outside the beam: expected a value in (0, %g] (-fs_beam_length)",
             (double)p->force_position, (double)p->L);
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

/*
   FSBeamParamsResolvePayload - with -fs_beam_payload_mass, the ballast is the payload minus the
   liquid's mass (of the whole tank; 0 without a coupled liquid), so that runs at different fill
   levels, and the solid-mass run, carry the same mass.
*/
PetscErrorCode FSBeamParamsResolvePayload(FSBeamParams *p, MPI_Comm comm, PetscReal liquid_mass)
{
  PetscFunctionBegin;
  if (p->payload_mass <= 0) PetscFunctionReturn(0);
  PetscCheck(p->payload_mass >= liquid_mass, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_beam_payload_mass %g kg is less than the liquid's mass %g kg: raise it or lower the fill",
             (double)p->payload_mass, (double)liquid_mass);
  p->ballast_mass = p->payload_mass - liquid_mass;
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamParamsView(const FSBeamParams *p, PetscViewer viewer)
{
  PetscFunctionBegin;
  PetscCall(PetscViewerASCIIPrintf(viewer, "beam: E = %g Pa, I = %g m^4, L = %g m, %g kg/m (%g kg); EI = %g N m^2\n",
                                   (double)p->E, (double)p->Iz, (double)p->L, (double)p->mlin, (double)(p->mlin * p->L),
                                   (double)(p->E * p->Iz)));
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "tank at x = %g m: tank %g kg, ballast %g kg, rotary inertia %g kg m^2; damping %g\n", (double)p->a,
      (double)p->tank_mass, (double)p->ballast_mass, (double)p->tank_inertia, (double)p->xi));
  if (p->payload_mass > 0)
    PetscCall(PetscViewerASCIIPrintf(viewer, "payload (liquid + ballast) %g kg\n", (double)p->payload_mass));
  if (p->preload != 0 || p->force != 0)
    PetscCall(PetscViewerASCIIPrintf(viewer, "preload %g m at the tank; force %g N at x = %g m\n", (double)p->preload,
                                     (double)p->force, (double)p->force_position));
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamParamsSummary(const FSBeamParams *p, FSJSON js)
{
  PetscFunctionBegin;
  PetscCall(FSJSONWriteReal(js, "E", p->E));
  PetscCall(FSJSONWriteReal(js, "I", p->Iz));
  PetscCall(FSJSONWriteReal(js, "length", p->L));
  PetscCall(FSJSONWriteReal(js, "mass_per_length", p->mlin));
  PetscCall(FSJSONWriteReal(js, "tank_position", p->a));
  PetscCall(FSJSONWriteReal(js, "tank_mass", p->tank_mass));
  PetscCall(FSJSONWriteReal(js, "ballast_mass", p->ballast_mass));
  PetscCall(FSJSONWriteReal(js, "tank_inertia", p->tank_inertia));
  PetscCall(FSJSONWriteReal(js, "damping", p->xi));
  PetscCall(FSJSONWriteReal(js, "preload", p->preload));
  PetscCall(FSJSONWriteReal(js, "force", p->force));
  PetscCall(FSJSONWriteReal(js, "force_position", p->force_position));
  PetscFunctionReturn(0);
}

/* Deflection at x of the massless cantilever under a unit force at xf: x^2 (3 xf - x)/(6 EI) for x <= xf. */
PetscReal FSBeamInfluence(const FSBeamParams *p, PetscReal x, PetscReal xf)
{
  const PetscReal lo = PetscMin(x, xf), hi = PetscMax(x, xf);
  return lo * lo * (3 * hi - lo) / (6 * p->E * p->Iz);
}

/* FSBeamFECreate - the mesh (uniform on [0, a] and on [a, L], with a node at a) and the matrices K and M. */
PetscErrorCode FSBeamFECreate(const FSBeamParams *p, PetscInt ne, FSBeamFE *fe)
{
  PetscInt        ne1, ne2;
  const PetscReal EI = p->E * p->Iz;

  PetscFunctionBegin;
  PetscCall(PetscMemzero(fe, sizeof(*fe)));
  if (p->a < p->L * (1 - 1e-12)) {
    PetscCheck(ne >= 2, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
               "-fs_modal_elements %" PetscInt_FMT
               ": a tank inside the beam (-fs_beam_tank_position %g < L) needs at least 2 elements",
               ne, (double)p->a);
    ne1 = PetscMin(ne - 1, PetscMax(1, (PetscInt)(ne * p->a / p->L + 0.5)));
    ne2 = ne - ne1;
  } else {
    ne1 = ne;
    ne2 = 0;
  }
  fe->ne        = ne;
  fe->N         = 2 * ne;
  fe->tank_node = ne1;
  PetscCall(PetscMalloc1(ne + 1, &fe->x));
  for (PetscInt i = 0; i <= ne1; i++) fe->x[i] = p->a * i / ne1;
  for (PetscInt i = 1; i <= ne2; i++) fe->x[ne1 + i] = p->a + (p->L - p->a) * i / ne2;
  fe->x[ne] = p->L;
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, fe->N, fe->N, 6, NULL, &fe->K));
  PetscCall(MatCreateSeqAIJ(PETSC_COMM_SELF, fe->N, fe->N, 6, NULL, &fe->M));
  for (PetscInt e = 0; e < ne; e++) {
    const PetscReal l = fe->x[e + 1] - fe->x[e], k = EI / (l * l * l), m = p->mlin * l / 420;
    const PetscReal Ke[16] = {12 * k,     6 * l * k,     -12 * k,    6 * l * k,    6 * l * k, 4 * l * l * k,
                              -6 * l * k, 2 * l * l * k, -12 * k,    -6 * l * k,   12 * k,    -6 * l * k,
                              6 * l * k,  2 * l * l * k, -6 * l * k, 4 * l * l * k};
    const PetscReal Me[16] = {156 * m,     22 * l * m,     54 * m,      -13 * l * m,  22 * l * m, 4 * l * l * m,
                              13 * l * m,  -3 * l * l * m, 54 * m,      13 * l * m,   156 * m,    -22 * l * m,
                              -13 * l * m, -3 * l * l * m, -22 * l * m, 4 * l * l * m};
    const PetscInt  idx[4] = {2 * e - 2, 2 * e - 1, 2 * e,
                              2 * e + 1}; /* node e's DOFs are negative for e = 0: dropped (clamp) */
    PetscCall(MatSetValues(fe->K, 4, idx, 4, idx, Ke, ADD_VALUES));
    PetscCall(MatSetValues(fe->M, 4, idx, 4, idx, Me, ADD_VALUES));
  }
  {
    const PetscInt  w = 2 * (fe->tank_node - 1), th = w + 1;
    const PetscReal mt = p->tank_mass + p->ballast_mass, J = p->tank_inertia;
    PetscCall(MatSetValue(fe->M, w, w, mt, ADD_VALUES));
    PetscCall(MatSetValue(fe->M, th, th, J, ADD_VALUES));
  }
  PetscCall(MatAssemblyBegin(fe->K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(fe->K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyBegin(fe->M, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(fe->M, MAT_FINAL_ASSEMBLY));
  PetscCall(MatSetOption(fe->K, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(fe->M, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(fe->K, MAT_SPD, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamFEDestroy(FSBeamFE *fe)
{
  PetscFunctionBegin;
  PetscCall(PetscFree(fe->x));
  PetscCall(MatDestroy(&fe->K));
  PetscCall(MatDestroy(&fe->M));
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamFEShape(const FSBeamFE *fe, PetscReal x, PetscInt dof[4], PetscReal Nw[4], PetscReal Nt[4])
{
  PetscInt  e = 0;
  PetscReal l, s;

  PetscFunctionBegin;
  while (e < fe->ne - 1 && x > fe->x[e + 1]) e++;
  l      = fe->x[e + 1] - fe->x[e];
  s      = (x - fe->x[e]) / l;
  dof[0] = 2 * e - 2;
  dof[1] = 2 * e - 1;
  dof[2] = 2 * e;
  dof[3] = 2 * e + 1;
  Nw[0]  = 1 - 3 * s * s + 2 * s * s * s;
  Nw[1]  = l * (s - 2 * s * s + s * s * s);
  Nw[2]  = 3 * s * s - 2 * s * s * s;
  Nw[3]  = l * (s * s * s - s * s);
  Nt[0]  = (-6 * s + 6 * s * s) / l;
  Nt[1]  = 1 - 4 * s + 3 * s * s;
  Nt[2]  = (6 * s - 6 * s * s) / l;
  Nt[3]  = 3 * s * s - 2 * s;
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamFEEvaluate(const FSBeamFE *fe, const PetscReal u[], PetscReal x, PetscReal *w, PetscReal *theta)
{
  PetscInt  dof[4];
  PetscReal Nw[4], Nt[4], ww = 0, tt = 0;

  PetscFunctionBegin;
  PetscCall(FSBeamFEShape(fe, x, dof, Nw, Nt));
  for (PetscInt k = 0; k < 4; k++)
    if (dof[k] >= 0) {
      ww += Nw[k] * u[dof[k]];
      tt += Nt[k] * u[dof[k]];
    }
  if (w) *w = ww;
  if (theta) *theta = tt;
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamFEStatic(const FSBeamFE *fe, PetscReal x, PetscReal F, PetscReal Mz, PetscReal u[])
{
  Vec                f, v;
  KSP                ksp;
  PC                 pc;
  PetscInt           dof[4];
  PetscReal          Nw[4], Nt[4];
  const PetscScalar *a;

  PetscFunctionBegin;
  PetscCall(MatCreateVecs(fe->K, &v, &f));
  PetscCall(FSBeamFEShape(fe, x, dof, Nw, Nt));
  for (PetscInt k = 0; k < 4; k++) /* consistent nodal loads of a point force and moment */
    if (dof[k] >= 0) PetscCall(VecSetValue(f, dof[k], F * Nw[k] + Mz * Nt[k], ADD_VALUES));
  PetscCall(VecAssemblyBegin(f));
  PetscCall(VecAssemblyEnd(f));
  PetscCall(KSPCreate(PETSC_COMM_SELF, &ksp));
  PetscCall(KSPSetOperators(ksp, fe->K, fe->K));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(KSPSolve(ksp, f, v));
  PetscCall(VecGetArrayRead(v, &a));
  for (PetscInt i = 0; i < fe->N; i++) u[i] = a[i];
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

PetscErrorCode FSBeamFEMassProduct(const FSBeamFE *fe, const PetscReal y[], const PetscReal z[], PetscReal *r)
{
  Vec vy, vz, mz;

  PetscFunctionBegin;
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, fe->N, y, &vy));
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, fe->N, z, &vz));
  PetscCall(VecDuplicate(vz, &mz));
  PetscCall(MatMult(fe->M, vz, mz));
  PetscCall(VecDot(vy, mz, r));
  PetscCall(VecDestroy(&mz));
  PetscCall(VecDestroy(&vz));
  PetscCall(VecDestroy(&vy));
  PetscFunctionReturn(0);
}

/*
   FSBeamFEModes - the first n modes of K phi = omega^2 M phi: SLEPc, generalized symmetric
   (EPS_GHEP), Krylov-Schur with shift-and-invert about 0 and a direct Cholesky solve
   (KSPPREONLY + PCCHOLESKY). Every rank solves the same small problem on PETSC_COMM_SELF, so the
   modes are the same everywhere. The options prefix lets -<prefix>eps_* and -<prefix>st_* tune it.
   Eigenvectors come M-orthonormal.
*/
PetscErrorCode FSBeamFEModes(const FSBeamFE *fe, PetscInt n, const char prefix[], PetscReal omega[], PetscReal phi[])
{
  EPS       eps;
  ST        st;
  KSP       ksp;
  PC        pc;
  Vec       xr;
  PetscInt  nconv, ncv;
  PetscReal lambda;

  PetscFunctionBegin;
  PetscCheck(n >= 1 && n <= fe->N, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "The beam mesh has %" PetscInt_FMT " DOFs: it cannot give %" PetscInt_FMT " modes", fe->N, n);
  { /* front ends start PETSc, not SLEPc: initialize SLEPc on first use (its finalization is a no-op then) */
    PetscBool init;
    PetscCall(SlepcInitialized(&init));
    if (!init) PetscCall(SlepcInitializeNoArguments());
  }
  PetscCall(EPSCreate(PETSC_COMM_SELF, &eps));
  PetscCall(EPSSetOperators(eps, fe->K, fe->M));
  PetscCall(EPSSetProblemType(eps, EPS_GHEP));
  PetscCall(EPSSetType(eps, EPSKRYLOVSCHUR));
  ncv = PetscMin(fe->N, PetscMax(2 * n, n + 15));
  PetscCall(EPSSetDimensions(eps, n, ncv, PETSC_DEFAULT));
  PetscCall(EPSSetTarget(eps, 0.0));
  PetscCall(EPSSetWhichEigenpairs(eps, EPS_TARGET_MAGNITUDE));
  PetscCall(EPSSetTolerances(eps, 1e-13, 200));
  PetscCall(EPSGetST(eps, &st));
  PetscCall(STSetType(st, STSINVERT));
  PetscCall(STGetKSP(st, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCCHOLESKY));
  if (prefix) PetscCall(EPSSetOptionsPrefix(eps, prefix));
  PetscCall(EPSSetFromOptions(eps));
  PetscCall(EPSSolve(eps));
  PetscCall(EPSGetConverged(eps, &nconv));
  PetscCheck(nconv >= n, PETSC_COMM_SELF, PETSC_ERR_CONV_FAILED,
             "SLEPc found %" PetscInt_FMT " of the %" PetscInt_FMT
             " beam modes asked for (-fs_modal_modes): use more elements (-fs_modal_elements) or fewer modes",
             nconv, n);
  PetscCall(MatCreateVecs(fe->K, &xr, NULL));
  for (PetscInt i = 0; i < n; i++) {
    const PetscScalar *a;
    PetscScalar        kr;
    PetscCall(EPSGetEigenpair(eps, i, &kr, NULL, xr, NULL));
    lambda = PetscRealPart(kr);
    PetscCheck(lambda > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "Beam mode %" PetscInt_FMT " has eigenvalue omega^2 = %g <= 0", i + 1, (double)lambda);
    omega[i] = PetscSqrtReal(lambda);
    PetscCall(VecGetArrayRead(xr, &a));
    for (PetscInt j = 0; j < fe->N; j++) phi[i * fe->N + j] = a[j];
    PetscCall(VecRestoreArrayRead(xr, &a));
  }
  PetscCall(VecDestroy(&xr));
  PetscCall(EPSDestroy(&eps));
  PetscFunctionReturn(0);
}
