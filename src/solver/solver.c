/*
   FSSolver: the object that holds a run. Create / SetFromOptions / SetUp / Solve / View / Destroy.
*/
#include <time.h>
#include "solver/solverimpl.h"

PetscClassId FSSOLVER_CLASSID;

static const char FSDefaultTerms[] = "continuity,delta,pressure,viscosity,les_viscosity,gravity";

/*
   FSSolverCreate - creates a solver with default parameters; the case and every parameter are
   then set from the options database by FSSolverSetFromOptions().

   Collective

   Input Parameter:
.  comm - the communicator of the run

   Output Parameter:
.  solver - the new solver
*/
PetscErrorCode FSSolverCreate(MPI_Comm comm, FSSolver *solver)
{
  FSSolver s;

  PetscFunctionBegin;
  PetscCall(FSInitializePackage());
  PetscCall(PetscHeaderCreate(s, FSSOLVER_CLASSID, "FSSolver", "flexslosh solver", "FS", comm, FSSolverDestroy,
                              FSSolverView));
  PetscCall(PetscStrncpy(s->opt.casename, "taylor_green", sizeof(s->opt.casename)));
  s->opt.dim                   = 2;
  s->opt.dx                    = 0;
  s->opt.h_over_dx             = 2.0;
  s->opt.rho0                  = 1000.0;
  s->opt.c0                    = 20.0;
  s->opt.nu                    = 1e-6;
  s->opt.background_pressure   = 0;
  s->opt.relax_time            = 0;   /* no start-up relaxation */
  s->opt.cfl                   = 0.4; /* cases may raise it (RK4 only, see below) */
  s->opt.cfl_visc              = 0.125;
  s->opt.cfl_force             = 0.25;
  s->opt.halo_skin             = 0.5;
  s->opt.max_density_variation = 0.3;
  s->opt.write_output          = PETSC_TRUE;
  s->opt.sort_interval         = 1;
  s->opt.rebalance_threshold   = 1.2;
  s->opt.rebalance_interval    = 100;
  s->pw.worksum                = -1;
  s->opt.balance               = FS_BALANCE_WORK;
  s->opt.rebuild               = FS_REBUILD_AUTO;
  s->opt.candidates            = 0; /* auto */
  s->opt.final_time            = 1.0;
  s->opt.structure_cfl         = 0.02;
  s->opt.options_check         = PETSC_TRUE;
  s->opt.packing.type          = FS_FILL_PACKING_AUTO;
  s->opt.packing.iterations    = 200;
  s->opt.packing.step          = 0.3;
  s->opt.packing.thin          = 0.05;
  PetscCall(PetscStrncpy(s->opt.structname, "none", sizeof(s->opt.structname)));
  PetscCall(FSCouplingCreate(comm, &s->coupling));
  s->pw.halo.rectype = MPI_DATATYPE_NULL;
  s->pw.halo.auxtype = MPI_DATATYPE_NULL;
  *solver            = s;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetDefaultPhysics - lets a case set the defaults of -fs_rho0, -fs_c0, -fs_nu and -fs_gravity
   before they are read (called from the case's setfromoptions).
*/
PetscErrorCode FSSolverSetDefaultPhysics(FSSolver s, PetscReal rho0, PetscReal c0, PetscReal nu, const PetscReal g[])
{
  PetscFunctionBegin;
  s->opt.rho0 = rho0;
  s->opt.c0   = c0;
  s->opt.nu   = nu;
  for (PetscInt d = 0; d < 3; d++) s->opt.gravity[d] = g ? g[d] : 0;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetDefaultSpacing - lets a case set the default of -fs_dx, the particle spacing, before the
   options are read (called from the case's setfromoptions).

   Not collective

   Input Parameters:
+  s  - the solver
-  dx - the spacing, positive

.seealso: FSSolverSetDefaultPhysics(), FSSolverGetParameters()
*/
PetscErrorCode FSSolverSetDefaultSpacing(FSSolver s, PetscReal dx)
{
  PetscFunctionBegin;
  PetscCheck(dx > 0, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "FSSolverSetDefaultSpacing(): the default particle spacing %g must be positive", (double)dx);
  s->opt.dx = dx;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetDefaultFinalTime - lets a case set the default final time of the run (-ts_max_time)
   before the options are read (called from the case's setfromoptions).

   Not collective

   Input Parameters:
+  s - the solver
-  t - the final time, positive

.seealso: FSSolverSetDefaultSpacing()
*/
PetscErrorCode FSSolverSetDefaultFinalTime(FSSolver s, PetscReal t)
{
  PetscFunctionBegin;
  PetscCheck(t > 0, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "FSSolverSetDefaultFinalTime(): the default final time %g must be positive", (double)t);
  s->opt.final_time = t;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetDefaultCFL - lets a case set the default of -fs_cfl, the acoustic CFL number, before the
   options are read (called from the case's setfromoptions). A default above 0.4 holds with the RK4
   integrator only (rk4lean, or rk with -ts_rk_type 4): with any other the run uses 0.4 unless -fs_cfl is given.

   Not collective

   Input Parameters:
+  s   - the solver
-  cfl - the CFL number, in (0, 2] as -fs_cfl

.seealso: FSSolverSetDefaultSpacing()
*/
PetscErrorCode FSSolverSetDefaultCFL(FSSolver s, PetscReal cfl)
{
  PetscFunctionBegin;
  PetscCheck(cfl > 0 && cfl <= 2, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
             "FSSolverSetDefaultCFL(): the default CFL number %g is out of range: expected (0, 2]", (double)cfl);
  s->opt.cfl = cfl;
  PetscFunctionReturn(0);
}

/*
   FSSolverSetDefaultTerms - lets a case set the default of -fs_terms, the physics terms, before the
   options are read (called from the case's setfromoptions).

   Not collective

   Input Parameters:
+  s     - the solver
-  terms - the terms' names, comma separated (-fs_terms_view lists them)

.seealso: FSSolverSetDefaultPhysics(), FSTermRegister()
*/
PetscErrorCode FSSolverSetDefaultTerms(FSSolver s, const char terms[])
{
  size_t len;

  PetscFunctionBegin;
  PetscCheck(terms, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_NULL,
             "FSSolverSetDefaultTerms(): no list of terms given");
  PetscCall(PetscStrlen(terms, &len));
  PetscCheck(len < sizeof(s->opt.default_terms), PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_SIZ,
             "FSSolverSetDefaultTerms(): the list of terms has %d characters, at most %d fit", (int)len,
             (int)sizeof(s->opt.default_terms) - 1);
  PetscCall(PetscStrncpy(s->opt.default_terms, terms, sizeof(s->opt.default_terms)));
  PetscFunctionReturn(0);
}

/*
   FSSolverSetCaseData - gives the solver the case's own data (a case calls it from its create
   routine). The solver frees the data it held before, and the last with PetscFree() when it is
   destroyed: allocate it with PetscMalloc() or PetscNew().

   Not collective

   Input Parameters:
+  s    - the solver
-  data - the case's data, or NULL

.seealso: FSSolverGetCaseData(), FSCaseRegister()
*/
PetscErrorCode FSSolverSetCaseData(FSSolver s, void *data)
{
  PetscFunctionBegin;
  if (data != s->casedata) PetscCall(PetscFree(s->casedata));
  s->casedata = data;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetCaseData - the case's own data, as given to FSSolverSetCaseData().

   Not collective

   Input Parameter:
.  s - the solver

   Output Parameter:
.  dataptr - the address of a pointer to the data (NULL if none)

.seealso: FSSolverSetCaseData()
*/
PetscErrorCode FSSolverGetCaseData(FSSolver s, void *dataptr)
{
  PetscFunctionBegin;
  PetscCheck(dataptr, PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_NULL,
             "FSSolverGetCaseData(): no place given for the data");
  *(void **)dataptr = s->casedata;
  PetscFunctionReturn(0);
}

/* FSSolverOptionsCase - -fs_case and -fs_dim, then the case's own options and defaults; terms gets
   the case's default -fs_terms. */
static PetscErrorCode FSSolverOptionsCase(FSSolver s, PetscOptionItems *PetscOptionsObject, char terms[], size_t len)
{
  PetscBool      flg = PETSC_FALSE; /* PetscOptionsBool() leaves flg untouched when -fs_case_view is absent */
  FSCaseCreateFn create;
  MPI_Comm       comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(PetscOptionsString("-fs_case", "Case to set up (list with -fs_case_view)", "FSSolverSetFromOptions",
                               s->opt.casename, s->opt.casename, sizeof(s->opt.casename), NULL));
  PetscCall(PetscOptionsBool("-fs_case_view", "List the registered cases", "FSCaseListView", PETSC_FALSE, &flg, NULL));
  if (flg) PetscCall(FSCaseListView(PETSC_VIEWER_STDOUT_(comm)));
  PetscCall(FSCaseFind(s->opt.casename, &create));
  PetscCheck(create, comm, PETSC_ERR_ARG_UNKNOWN_TYPE,
             "Unknown case \"%s\" given to -fs_case: list the registered cases with -fs_case_view", s->opt.casename);
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_dim", "Dimension: 2 or 3", "FSSolverSetFromOptions", &s->opt.dim,
                         NULL, 2, 3));
  PetscCall(PetscMemzero(&s->caseops, sizeof(s->caseops)));
  PetscCall((*create)(s, &s->caseops));
  PetscCheck(s->caseops.ncolumns >= 0 && s->caseops.ncolumns <= FS_CASE_MAX_COLUMNS &&
                 (!s->caseops.ncolumns || s->caseops.columns),
             comm, PETSC_ERR_PLIB,
             "Case \"%s\" declares %" PetscInt_FMT
             " time-series columns: at most FS_CASE_MAX_COLUMNS = %d, with a columns() routine",
             s->opt.casename, s->caseops.ncolumns, FS_CASE_MAX_COLUMNS);
  PetscCall(PetscStrncpy(s->opt.default_terms, FSDefaultTerms, sizeof(s->opt.default_terms)));
  PetscCall(FSOptionsSurveyOwner("case", s->opt.casename));
  if (s->caseops.setfromoptions) PetscCall((*s->caseops.setfromoptions)(s, PetscOptionsObject));
  PetscCall(FSOptionsSurveyOwner(NULL, NULL));
  PetscCall(PetscStrncpy(terms, s->opt.default_terms, len));

  PetscFunctionReturn(0);
}

/* FSSolverOptionsPacking - how the cases place the liquid's particles (FSSolverGetFillPacking). */
static PetscErrorCode FSSolverOptionsPacking(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  static const char *const packnames[] = {"auto", "lattice", "relaxed"};
  FSFillPacking           *p           = &s->opt.packing;
  PetscInt                 type        = (PetscInt)p->type;

  PetscFunctionBegin;
  PetscCall(PetscOptionsEList("-fs_fill_packing",
                              "How the liquid's particles are placed: lattice (rows cut by the walls), relaxed (that "
                              "lattice relaxed against the walls and the fill level) or auto (relaxed where the "
                              "lattice does not fit the walls, the lattice where it does)",
                              "FSSolverGetFillPacking", packnames, 3, packnames[type], &type, NULL));
  p->type = (FSFillPackingType)type;
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_fill_packing_iterations",
                         "Iterations of the relaxed packing (-fs_fill_packing relaxed)", "FSSolverGetFillPacking",
                         &p->iterations, NULL, 1, 1000000));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_fill_packing_step",
                          "Step of the relaxed packing: each iteration moves a particle by -step h^2 e_i (e_i: the "
                          "particles' kernel-gradient sum and the walls' integral, zero when evenly spread)",
                          "FSSolverGetFillPacking", &p->step, NULL, 0, 10, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_fill_packing_thin",
                          "Fullness above which the relaxed packing's lattice is thinned before the relaxation (its "
                          "points removed, the most over-full first, until none there is over-full: a thin gap "
                          "filled nearer its volume); fullness: the kernel sum less the liquid's share of the kernel "
                          "(0: none thinned)",
                          "FSSolverGetFillPacking", &p->thin, NULL, 0, 1, FS_RANGE_CLOSED));
  PetscCall(PetscOptionsString("-fs_fill_packing_cache",
                               "Folder where relaxed packings are kept and found again, each file named by a hash of "
                               "the geometry, the spacing and the settings (empty: none)",
                               "FSSolverGetFillPacking", p->cache, p->cache, sizeof(p->cache), NULL));
  PetscFunctionReturn(0);
}

/* FSSolverOptionsPhysics - the spacing, the smoothing length, the liquid and the body force. */
static PetscErrorCode FSSolverOptionsPhysics(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  PetscBool set = PETSC_FALSE;
  PetscInt  ng  = 3;
  PetscReal g[3];
  MPI_Comm  comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_dx", "Particle spacing", "FSSolverSetFromOptions", &s->opt.dx, NULL,
                          0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCheck(s->opt.dx > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_dx %g must be positive", (double)s->opt.dx);
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_h_over_dx",
                          "Smoothing length over particle spacing (kernel support is 2h)", "FSSolverSetFromOptions",
                          &s->opt.h_over_dx, NULL, 1, 4, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_rho0", "Reference density of the liquid", "FSSolverSetFromOptions",
                          &s->opt.rho0, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCheck(s->opt.rho0 > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_rho0 %g must be positive", (double)s->opt.rho0);
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_c0",
                          "Artificial speed of sound (about 10 times the largest flow speed)", "FSSolverSetFromOptions",
                          &s->opt.c0, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCheck(s->opt.c0 > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_c0 %g must be positive", (double)s->opt.c0);
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_nu", "Kinematic viscosity of the liquid", "FSSolverSetFromOptions",
                          &s->opt.nu, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCheck(s->opt.nu >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "-fs_nu %g must be non-negative", (double)s->opt.nu);
  for (PetscInt d = 0; d < 3; d++) g[d] = s->opt.gravity[d];
  PetscCall(FSOptionsRealArray(PetscOptionsObject, "-fs_gravity", "Body force per unit mass, one value per dimension",
                               "FSSolverSetFromOptions", g, &ng, &set, PETSC_NINFINITY, PETSC_INFINITY,
                               FS_RANGE_CLOSED));
  if (set) {
    PetscCheck(ng == s->opt.dim, comm, PETSC_ERR_ARG_SIZ,
               "-fs_gravity has %" PetscInt_FMT " values: expected %" PetscInt_FMT " (one per dimension)", ng,
               s->opt.dim);
    for (PetscInt d = 0; d < 3; d++) s->opt.gravity[d] = d < ng ? g[d] : 0;
  }
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_background_pressure",
                          "Constant added to the equation of state p = c0^2 (rho - rho0) + p_b",
                          "FSSolverSetFromOptions", &s->opt.background_pressure, NULL, PETSC_NINFINITY, PETSC_INFINITY,
                          FS_RANGE_CLOSED));
  PetscCall(FSSolverOptionsPacking(s, PetscOptionsObject));
  PetscFunctionReturn(0);
}

/* FSSolverOptionsNumerics - the time-step limits, the start-up relaxation, the halo, blow-up detection
   and the particles' ordering. */
static PetscErrorCode FSSolverOptionsNumerics(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  static const char *const rebuildnames[] = {"auto", "always"}, *const candnames[] = {"auto", "indices", "bits"},
                           *const cachenames[]   = {"auto", "yes", "no"};
  static const char *const        balancenames[] = {"particles", "work"};

  PetscFunctionBegin;
  PetscCall(
      FSOptionsReal(PetscOptionsObject, "-fs_cfl",
                    "Acoustic CFL number: dt <= CFL h/(c0 + |u|max) (with RK4 the tanks use 1.0, the dam break 2.0)",
                    "FSSolverComputeStableDt", &s->opt.cfl, &s->opt.cfl_set, 0, 2, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_relax_time",
                          "Start-up relaxation: damp the particle velocities until this time (0: none)",
                          "FSSolverEvaluateRates", &s->opt.relax_time, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_cfl_viscous", "Viscous limit: dt <= CFL_v h^2/nu",
                          "FSSolverComputeStableDt", &s->opt.cfl_visc, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_cfl_force", "Body-force limit: dt <= CFL_f sqrt(h/|g|)",
                          "FSSolverComputeStableDt", &s->opt.cfl_force, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_halo_skin",
                          "Extra halo width beyond the kernel support, in units of h", "FSHaloBuild", &s->opt.halo_skin,
                          NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_max_density_variation",
                          "Stop the run when |rho/rho0 - 1| exceeds this (blow-up detection)", "FSSolverCheckState",
                          &s->opt.max_density_variation, NULL, 0, PETSC_INFINITY, FS_RANGE_OPEN_LOWER));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_sort_interval", "Steps between reorderings of the particles by cell",
                         "FSSolverSortByCell", &s->opt.sort_interval, NULL, 1, PETSC_MAX_INT));
  PetscCall(FSOptionsReal(PetscOptionsObject, "-fs_rebalance_threshold",
                          "Move the ranks' cuts, at a rebuild of the lists, when a rank has more than this times the "
                          "mean work or number of particles (-fs_balance; 0: never, the cuts set at the start stay)",
                          "FSSolverRebalance", &s->opt.rebalance_threshold, NULL, 0, PETSC_INFINITY, FS_RANGE_CLOSED));
  PetscCall(FSOptionsInt(PetscOptionsObject, "-fs_rebalance_interval", "Steps at least between two moves of the cuts",
                         "FSSolverRebalance", &s->opt.rebalance_interval, NULL, 1, PETSC_MAX_INT));
  PetscCall(PetscOptionsEList("-fs_balance",
                              "What the ranks' cuts balance, at the set-up and when they move: the particles, or "
                              "their work in a right-hand side (candidate pairs and wall elements)",
                              "FSSolverRebalance", balancenames, 2, balancenames[s->opt.balance], &s->opt.balance,
                              NULL));
  PetscCheck(s->opt.rebalance_threshold == 0 || s->opt.rebalance_threshold >= 1, PetscObjectComm((PetscObject)s),
             PETSC_ERR_ARG_OUTOFRANGE,
             "-fs_rebalance_threshold %g: a rank owns at least the mean; give 0 (never move the cuts) or a value >= 1",
             (double)s->opt.rebalance_threshold);
  PetscCall(
      PetscOptionsEList("-fs_neighbour_rebuild",
                        "When the halo and the neighbour lists are rebuilt: auto (when a particle could have moved "
                        "half the skin since the last build) or always (after every step)",
                        "FSSolverRebuildNeeded", rebuildnames, 2, rebuildnames[s->opt.rebuild], &s->opt.rebuild, NULL));
  PetscCall(PetscOptionsEList("-fs_neighbour_candidates",
                              "How the candidate neighbours are kept: indices (4 bytes a candidate), bits (one bit per "
                              "position of the rows of cells around a particle: a fifth of the memory, a few per cent "
                              "more time a pass) or auto (bits in 3-D, indices in 2-D)",
                              "FSNeighboursBuildCandidates", candnames, 3, candnames[s->opt.candidates],
                              &s->opt.candidates, NULL));
  PetscCall(
      PetscOptionsEList("-fs_pair_cache",
                        "Keep the pairs the first pass picks, with their kernel factors, for the pair pass: yes "
                        "(12 bytes a pair: about 0.5 KB a particle in 2-D, 2.7 KB in 3-D; a right-hand side about "
                        "18 % cheaper in 2-D, 12 % in 3-D), no (the pair pass picks them again from the "
                        "candidates) or auto (yes in 2-D, no in 3-D)",
                        "FSSolverFirstPass", cachenames, 3, cachenames[s->opt.paircache], &s->opt.paircache, NULL));
  PetscFunctionReturn(0);
}

/*
   FSSolverOutputDirDefault - the output directory without -fs_output_dir: a new one for every run,
   output/<-fs_output_name>-<YYYYMMDD-HHMMSS> (the time stamp is rank 0's; FSSolverOutputDirChoose() adds -2, -3, ...
   when a run of the same second took it), so that a second run, of the same case or another, leaves the first's
   results alone; for a restart, the directory of its checkpoint, whose run it continues.

   Collective
*/
static PetscErrorCode FSSolverOutputDirDefault(FSSolver s)
{
  MPI_Comm comm      = PetscObjectComm((PetscObject)s);
  char     stamp[32] = "";

  PetscFunctionBegin;
  if (s->opt.restart[0]) {
    char *slash;
    PetscCall(PetscStrncpy(s->opt.outdir, s->opt.restart, sizeof(s->opt.outdir)));
    slash = strrchr(s->opt.outdir, '/');
    if (slash) *(slash == s->opt.outdir ? slash + 1 : slash) = 0;
    else PetscCall(PetscStrncpy(s->opt.outdir, ".", sizeof(s->opt.outdir)));
    s->opt.outdir_auto = PETSC_FALSE; /* an existing directory, continued as a given one is */
    PetscFunctionReturn(0);
  }
  PetscCheck(s->opt.outname[0] && !strchr(s->opt.outname, '/') && strcmp(s->opt.outname, ".") &&
                 strcmp(s->opt.outname, ".."),
             comm, PETSC_ERR_ARG_WRONG,
             "-fs_output_name \"%s\": expected a name without '/' (the directory is "
             "output/<name>-<time stamp>; -fs_output_dir gives a whole path)",
             s->opt.outname);
  {
    time_t    now = time(NULL);
    struct tm tm;
    if (localtime_r(&now, &tm)) (void)strftime(stamp, sizeof(stamp), "%Y%m%d-%H%M%S", &tm);
  }
  PetscCallMPI(MPI_Bcast(stamp, sizeof(stamp), MPI_CHAR, 0, comm)); /* rank 0's clock for every rank */
  PetscCall(PetscSNPrintf(s->opt.outdir, sizeof(s->opt.outdir), "output/%s-%s", s->opt.outname, stamp));
  PetscFunctionReturn(0);
}

/* FSSolverOptionsOutput - where and how often the run writes, restarts, the geometry view, progress. */
static PetscErrorCode FSSolverOptionsOutput(FSSolver s, PetscOptionItems *PetscOptionsObject)
{
  PetscFunctionBegin;
  PetscCall(PetscOptionsBool("-fs_output", "Write output files (snapshots, time series, summary)", "FSSolverSolve",
                             s->opt.write_output, &s->opt.write_output, NULL));
  if (!s->opt.outdir_taken) { /* the default directory is new for every run: output/<name>-<time stamp> */
    PetscBool set;
    char      dir[PETSC_MAX_PATH_LEN] = "";
    PetscCall(PetscStrncpy(s->opt.outname, s->opt.casename, sizeof(s->opt.outname)));
    PetscCall(PetscOptionsString("-fs_output_name",
                                 "Name of the default output directory, output/<name>-<time stamp> (default: the "
                                 "options file's name, else the case's)",
                                 "FSSolverSolve", s->opt.outname, s->opt.outname, sizeof(s->opt.outname), NULL));
    PetscCall(PetscOptionsString("-fs_output_dir",
                                 "Output directory (default: a new one per run, output/<name>-<time stamp>; a "
                                 "restart's default is its checkpoint's directory)",
                                 "FSSolverSolve", dir, dir, sizeof(dir), &set));
    s->opt.outdir_auto = (PetscBool)!set;
    if (set) PetscCall(PetscStrncpy(s->opt.outdir, dir, sizeof(s->opt.outdir)));
  }
  /* the built-in monitors' options, each where -help always listed it: -fs_output_interval, -fs_checkpoint_interval */
  PetscCall(FSSolverBuiltinMonitorsCreate(s));
  PetscCall(FSMonitorSetFromOptionItems(s->mon.snapshots, PetscOptionsObject));
  PetscCall(FSMonitorSetFromOptionItems(s->mon.checkpoints, PetscOptionsObject));
  PetscCall(PetscOptionsString("-fs_restart", "Continue the run from this checkpoint file", "FSSolverLoadCheckpoint",
                               s->opt.restart, s->opt.restart, sizeof(s->opt.restart), NULL));
  if (s->opt.outdir_auto && !s->opt.outdir_taken) PetscCall(FSSolverOutputDirDefault(s));
  PetscCall(PetscOptionsString("-fs_restart_allow_changes",
                               "Items of the set-up that may differ from the checkpoint's, comma separated (e.g. "
                               "fs_nu,fs_beam_damping; all: any). The output options, -ts_max_time and -ts_max_steps "
                               "may always change",
                               "FSSolverCheckSetUp", s->opt.allow_changes, s->opt.allow_changes,
                               sizeof(s->opt.allow_changes), NULL));
  /* -fs_probes, -fs_probe_interval; -fs_series_interval (the time series', which the energy budget's rows follow) */
  PetscCall(FSMonitorSetFromOptionItems(s->mon.probes, PetscOptionsObject));
  PetscCall(FSMonitorSetFromOptionItems(s->mon.series, PetscOptionsObject));
  PetscCall(FSMonitorSetFromOptionItems(s->mon.energy, PetscOptionsObject));
  PetscCall(PetscOptionsBool("-fs_geometry_view",
                             "Write the walls and particles to <output_dir>/geometry/ (geometry.png, walls.xdmf, the "
                             "step-0 snapshot; a run's results in <output_dir> are not touched), then stop without "
                             "time stepping",
                             "FSSolverGeometryView", s->opt.geometry_view, &s->opt.geometry_view, NULL));
  { /* read at the end of the run by FSOptionsLeft(); here for -help */
    PetscBool warn = PETSC_TRUE;
    PetscCall(PetscOptionsBool("-fs_options_left",
                               "At the end of the run, warn about the options given but never used (-options_left: "
                               "PETSc's report instead)",
                               "FSOptionsLeft", warn, &warn, NULL));
  }
  { /* read by the executable after PetscInitialize, and by the Python package around each call; here for -help */
    PetscBool trace = PETSC_FALSE;
    PetscCall(PetscOptionsBool("-fs_error_trace",
                               "On an error, print PETSc's full report (every frame, the options, the configuration) "
                               "instead of the message and where it was raised",
                               "FSErrorHandler", trace, &trace, NULL));
  }
  PetscCall(PetscOptionsBool("-fs_options_check",
                             "Before the first step, refuse the -fs_ options that nothing reads (misspelt, or of an "
                             "object the run does not use), naming the nearest options (false: only the warning at the "
                             "end)",
                             "FSSolverCheckOptions", s->opt.options_check, &s->opt.options_check, NULL));
  { /* read by the executable after the set-up (PetscObjectViewFromOptions); here for -help and the check */
    char view[PETSC_MAX_PATH_LEN] = "";
    PetscCall(PetscOptionsString("-fs_view",
                                 "Print the set-up after FSSolverSetUp() (the executable; a viewer may follow)",
                                 "FSSolverView", view, view, sizeof(view), NULL));
  }
  PetscCall(FSMonitorSetFromOptionItems(s->mon.progress, PetscOptionsObject)); /* -fs_progress, its interval */

  PetscFunctionReturn(0);
}

/* FSSolverCreateTerms - the terms of the comma-separated list, each reading its options. */
static PetscErrorCode FSSolverCreateTerms(FSSolver s, PetscOptionItems *PetscOptionsObject, char terms[])
{
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  for (PetscInt t = 0; t < s->terms.nterms; t++) PetscCall(FSTermDestroy(&s->terms.term[t]));
  s->terms.nterms = 0;
  s->terms.needs  = 0;
  {
    char *tok, *save = NULL;
    for (tok = strtok_r(terms, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
      FSTerm term;
      PetscCheck(s->terms.nterms < FS_MAX_TERMS, comm, PETSC_ERR_ARG_OUTOFRANGE,
                 "Too many terms in -fs_terms (at most %d)", FS_MAX_TERMS);
      for (PetscInt t = 0; t < s->terms.nterms; t++) {
        PetscBool same;
        PetscCall(PetscStrcmp(s->terms.term[t]->name, tok, &same));
        PetscCheck(!same, comm, PETSC_ERR_ARG_WRONG, "Term \"%s\" appears twice in -fs_terms", tok);
      }
      PetscCall(FSTermCreate(s, tok, &term));
      PetscCall(FSOptionsSurveyOwner("term", tok));
      if (term->ops.setfromoptions) PetscCall((*term->ops.setfromoptions)(term, PetscOptionsObject));
      PetscCall(FSOptionsSurveyOwner(NULL, NULL));
      s->terms.term[s->terms.nterms++] = term;
      s->terms.needs |= term->needs;
    }
  }
  PetscFunctionReturn(0);
}

/*
   FSSolverSetFromOptions - reads the run's options (prefix -fs_), the case's and the terms'.

   Collective

   Options Database Keys:
+  -fs_case <name>                 - the case to set up (-fs_case_view lists them)
.  -fs_dim <2|3>                   - dimension
.  -fs_dx <dx>                     - particle spacing (default from the case)
.  -fs_h_over_dx <2>               - smoothing length over particle spacing; the kernel support is 2h
.  -fs_rho0, -fs_c0, -fs_nu        - reference density, speed of sound, kinematic viscosity
.  -fs_gravity <gx,gy[,gz]>        - body force per unit mass
.  -fs_background_pressure <0>     - constant added to the equation of state
.  -fs_terms <list>                - physics terms, by name (-fs_terms_view lists them)
.  -fs_structure <none|msd|modal>  - the structure carrying the tank (-fs_structure_view lists the models)
.  -fs_structure_cfl <0.02>        - without particles: time step as a fraction of the shortest period the structure
resolves (or -ts_dt) .  -fs_cfl, -fs_cfl_viscous, -fs_cfl_force - time-step limits: CFL h/(c0+|u|max), CFL_v h^2/nu,
CFL_f sqrt(h/|g|) (CFL 0.4; with the default RK4 the tanks use 1.0, the dam break 2.0) .  -fs_relax_time <0> - start-up
relaxation: the velocities are damped until this time .  -fs_output_dir <dir>            - output directory (default
output/<case>) .  -fs_output_interval <t>         - simulated time between particle snapshots (0: first and last only)
.  -fs_checkpoint_interval <n>     - steps between checkpoints (0: none)
.  -fs_restart <file>              - continue from a checkpoint (of a run set up the same way)
.  -fs_restart_allow_changes <a,b> - items of the set-up the restart may change (docs/running.md)
.  -fs_probes <file>               - pressure probes and wave gauges, sampled into probes.csv (docs/running.md)
.  -fs_probe_interval <1>          - steps between the samples of the probes and gauges
.  -fs_series_interval <1>         - steps between the rows of timeseries.csv and energy.csv (and the last step's)
.  -fs_geometry_view               - write the walls and particles (geometry.png, walls.xdmf, the step-0 snapshot) to
<output_dir>/geometry/ and stop after set-up
.  -fs_options_left <true>         - at the end, warn about the options given but never used
.  -fs_error_trace                 - on an error, PETSc's full report instead of the short one (FSErrorHandler())
-  -fs_progress, -fs_progress_interval - progress line on the terminal, and its period in seconds

   Notes:
   -fs_output_interval, -fs_checkpoint_interval, -fs_probes, -fs_probe_interval, -fs_series_interval, -fs_rest_check_*,
   -fs_progress and -fs_progress_interval are the built-in monitors' options (src/monitor/impls/): the solver makes
those monitors here and each reads its own in this options block (FSMonitorSetFromOptionItems()).
*/
PetscErrorCode FSSolverSetFromOptions(FSSolver s)
{
  char     terms[1024];
  MPI_Comm comm = PetscObjectComm((PetscObject)s);

  PetscFunctionBegin;
  PetscCall(FSCaseRegisterAll());
  PetscCall(FSTermRegisterAll());
  PetscCall(FSStructureRegisterAll());
  PetscCall(FSSolverCheckRanksAgree(s)); /* before any option steers a collective */
  PetscObjectOptionsBegin((PetscObject)s);
  PetscCall(FSOptionsSurveyBlock(PetscOptionsObject));
  PetscCall(FSSolverOptionsCase(s, PetscOptionsObject, terms, sizeof(terms)));
  PetscCall(FSSolverOptionsPhysics(s, PetscOptionsObject));
  PetscCall(PetscOptionsString("-fs_terms", "Physics terms, comma separated (list with -fs_terms_view)",
                               "FSSolverSetFromOptions", terms, terms, sizeof(terms), NULL));
  PetscCall(PetscOptionsBool("-fs_terms_view", "List the registered physics terms", "FSTermListView", s->opt.terms_view,
                             &s->opt.terms_view, NULL));
  PetscCall(PetscOptionsString(
      "-fs_structure", "Structure carrying the tank: none, or a registered model (list with -fs_structure_view)",
      "FSSolverSetFromOptions", s->opt.structname, s->opt.structname, sizeof(s->opt.structname), NULL));
  PetscCall(PetscOptionsBool("-fs_structure_view", "List the registered structure models", "FSStructureListView",
                             s->opt.structure_view, &s->opt.structure_view, NULL));
  PetscCall(FSOptionsReal(
      PetscOptionsObject, "-fs_structure_cfl",
      "Without particles: time step as a fraction of the shortest period the structure resolves (-ts_dt overrides)",
      "FSSolverStructureDt", &s->opt.structure_cfl, NULL, 0, 1, FS_RANGE_OPEN_LOWER));
  PetscCall(FSSolverOptionsNumerics(s, PetscOptionsObject));
  PetscCall(FSSolverOptionsOutput(s, PetscOptionsObject));
  PetscCall(FSMonitorSetFromOptionItems(s->mon.restcheck, PetscOptionsObject)); /* -fs_rest_check_* */
  PetscCall(FSSolverCreateTerms(s, PetscOptionsObject, terms));
  /* the structure */
  PetscCall(FSStructureDestroy(&s->structure));
  if (strcmp(s->opt.structname, "none")) {
    PetscCall(FSStructureCreate(s, s->opt.structname, &s->structure));
    PetscCall(FSOptionsSurveyOwner("structure model", s->opt.structname));
    if (s->structure->ops.setfromoptions)
      PetscCall((*s->structure->ops.setfromoptions)(s->structure, PetscOptionsObject));
    PetscCall(FSOptionsSurveyOwner(NULL, NULL));
  }
  {
    PetscBool help;
    PetscCall(PetscOptionsHasHelp(NULL, &help));
    if (help) {
      PetscCall(FSCaseHelpAll(s, s->opt.casename, PetscOptionsObject));
      PetscCall(FSTermHelpAll(s, &s->terms, PetscOptionsObject));
      PetscCall(FSStructureHelpAll(s, s->structure, PetscOptionsObject));
      PetscCall(FSBoundaryHelpAll(comm));
      PetscCall(FSCouplingHelp(comm));
    }
  }
  PetscOptionsEnd();
  if (s->opt.terms_view) PetscCall(FSTermListView(PETSC_VIEWER_STDOUT_(comm)));
  if (s->opt.structure_view) PetscCall(FSStructureListView(PETSC_VIEWER_STDOUT_(comm)));
  s->opt.h = s->opt.h_over_dx * s->opt.dx;
  PetscCall(FSSolverSetUpTS(s));
  {
    TSType    type;
    TSRKType  rk = NULL;
    PetscBool isrk, islean, rk4;
    PetscCall(TSGetType(s->ts, &type));
    PetscCall(PetscStrcmp(type, TSRK, &isrk));
    PetscCall(PetscStrcmp(type, FSTSRK4LEAN, &islean));
    if (isrk) PetscCall(TSRKGetType(s->ts, &rk));
    rk4 = (PetscBool)(islean || (isrk && rk && !strcmp(rk, TSRK4)));
    /* a case's larger CFL and a term's own default coefficient hold for RK4 only (stable on the imaginary axis up
       to 2.8, on the real axis to 2.79); the terms are made anew by each call, their coefficients 0 unless given */
    if (!s->opt.cfl_set && s->opt.cfl > 0.4 && !rk4) s->opt.cfl = 0.4;
    for (PetscInt t = 0; rk4 && t < s->terms.nterms; t++) {
      FSTerm term = s->terms.term[t];
      if (term->dt_coefficient == 0) term->dt_coefficient = term->dt_coefficient_rk4;
    }
  }
  PetscCall(FSSolverCheckOptions(s, PETSC_FALSE)); /* misspelt options, and those of cases, terms, models not in use */
  PetscFunctionReturn(0);
}

/*
   FSSolverGetBoundary - the run's walls, created (without a method) on the first call: a case gives
   them their method and geometry (for polygons FSBoundaryPolygonSetWalls()) from its setup. Without
   this call the run has no walls.

   Collective on the first call
*/
PetscErrorCode FSSolverGetBoundary(FSSolver s, FSBoundary *b)
{
  PetscFunctionBegin;
  if (!s->boundary) PetscCall(FSBoundaryCreate(PetscObjectComm((PetscObject)s), &s->boundary));
  *b = s->boundary;
  PetscFunctionReturn(0);
}

/* FSSolverSetDomain - the domain box and its periodicity (called by the case). */
PetscErrorCode FSSolverSetDomain(FSSolver s, const PetscReal lo[], const PetscReal hi[], const PetscBool periodic[])
{
  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) {
    s->pw.lo[d]       = d < s->opt.dim ? lo[d] : 0;
    s->pw.hi[d]       = d < s->opt.dim ? hi[d] : 1;
    s->pw.periodic[d] = d < s->opt.dim ? periodic[d] : PETSC_FALSE;
    PetscCheck(s->pw.hi[d] > s->pw.lo[d], PetscObjectComm((PetscObject)s), PETSC_ERR_ARG_OUTOFRANGE,
               "Empty domain in direction %" PetscInt_FMT ": [%g, %g]", d, (double)s->pw.lo[d], (double)s->pw.hi[d]);
  }
  s->pw.domain_set = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetFillPacking - how the cases place the liquid's particles: -fs_fill_packing (auto, lattice or relaxed)
   and the relaxation's settings, with the wall_pressure term's push near contact (-fs_walls_repulsion) and the walls'
   visibility (-fs_walls_visibility), which the relaxation balances so that its particles start in the equilibrium of
   the run's own wall terms.

   Not collective

   Output Parameter:
.  p - the settings

   Options Database Keys:
+  -fs_fill_packing <auto>            - auto, lattice or relaxed (docs/walls.md)
.  -fs_fill_packing_iterations <200>  - iterations of the relaxation
.  -fs_fill_packing_step <0.3>          - each iteration moves a particle by -step h^2 e_i
.  -fs_fill_packing_thin <0.05>         - the fullness above which the lattice is thinned before the relaxation
-  -fs_fill_packing_cache <dir>       - a folder where relaxed packings are kept and reused

   Level: intermediate
*/
PetscErrorCode FSSolverGetFillPacking(FSSolver s, FSFillPacking *p)
{
  PetscFunctionBegin;
  *p = s->opt.packing;
  for (PetscInt t = 0; t < s->terms.nterms && !p->repulsion; t++)
    PetscCall(FSTermWallPressureGetRepulsion(s->terms.term[t], &p->repulsion, &p->repulsion_distance));
  PetscCall(FSBoundaryGetVisibilityOption((PetscObject)s, &p->visall));
  PetscFunctionReturn(0);
}

/* FSSolverGetParameters - the particle spacing, smoothing length and liquid parameters (for cases and terms). */
PetscErrorCode FSSolverGetParameters(FSSolver s, PetscReal *dx, PetscReal *h, PetscReal *rho0, PetscReal *c0,
                                     PetscReal *nu)
{
  PetscFunctionBegin;
  if (dx) *dx = s->opt.dx;
  if (h) *h = s->opt.h;
  if (rho0) *rho0 = s->opt.rho0;
  if (c0) *c0 = s->opt.c0;
  if (nu) *nu = s->opt.nu;
  PetscFunctionReturn(0);
}

/* FSSolverGetGlobalSize - the particles over every rank. Not collective */
PetscErrorCode FSSolverGetGlobalSize(FSSolver s, PetscInt64 *n)
{
  PetscFunctionBegin;
  *n = s->pw.nglobal_particles;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetGravity - the body force per unit mass (-fs_gravity, or the case's default).

   Not collective

   Input Parameter:
.  s - the solver

   Output Parameter:
.  g - its three components (those beyond the dimension are 0)

.seealso: FSSolverGetParameters(), FSSolverSetDefaultPhysics()
*/
PetscErrorCode FSSolverGetGravity(FSSolver s, PetscReal g[3])
{
  PetscFunctionBegin;
  for (PetscInt d = 0; d < 3; d++) g[d] = s->opt.gravity[d];
  PetscFunctionReturn(0);
}

PetscErrorCode FSSolverGetDimension(FSSolver s, PetscInt *dim)
{
  PetscFunctionBegin;
  *dim = s->opt.dim;
  PetscFunctionReturn(0);
}

PetscErrorCode FSSolverGetLocalSize(FSSolver s, PetscInt *n)
{
  PetscFunctionBegin;
  *n = s->pw.nowned;
  PetscFunctionReturn(0);
}

PetscErrorCode FSSolverGetTS(FSSolver s, TS *ts)
{
  PetscFunctionBegin;
  *ts = s->ts;
  PetscFunctionReturn(0);
}

/*
   FSSolverGetSwarm - the particles' DMSwarm (fields FS_FIELD_POSITION, ..., this rank's owned particles).

   Not collective

   Notes:
   The swarm mirrors the state between steps: the state lives in the TS's vector and is copied into the
   swarm after every step (and the particles migrate and are reordered), so read its fields; a value
   written into them would be overwritten by the next step, unseen by the neighbour lists, the ghosts
   and the energy budget. (The Python package hands its fields out read-only.)
*/
PetscErrorCode FSSolverGetSwarm(FSSolver s, DM *sw)
{
  PetscFunctionBegin;
  *sw = s->swarm;
  PetscFunctionReturn(0);
}

/* FSSolverGetTime - the current time and step number. */
PetscErrorCode FSSolverGetTime(FSSolver s, PetscReal *t, PetscInt *step)
{
  PetscFunctionBegin;
  if (t) PetscCall(TSGetTime(s->ts, t));
  if (step) PetscCall(TSGetStepNumber(s->ts, step));
  PetscFunctionReturn(0);
}

/*
   FSSolverSetUp - builds the case (domain, particles), the decomposition, the halo and the TS.

   Collective

   Options Database Key:
.  -fs_geometry_view - then write the set-up's picture and walls (FSSolverGeometryView()) and the
                       particles at step 0 to <output directory>/geometry (the run's results are not touched)
*/
PetscErrorCode FSSolverSetUp(FSSolver s)
{
  MPI_Comm   comm = PetscObjectComm((PetscObject)s);
  PetscReal  width;
  PetscBool  changed;
  PetscReal *x, *m;
  PetscInt   n;

  PetscFunctionBegin;
  if (s->setupcalled) PetscFunctionReturn(0);
  PetscCall(FSKernelSetUp(&s->pw.kernel, s->opt.dim, s->opt.h));
  s->pw.stride     = 2 * s->opt.dim + 2;
  s->state.ustride = 2 * s->opt.dim + 1;
  s->pw.auxstride  = s->opt.dim + 1;
  PetscCall(FSSolverCreateSwarm(s));
  PetscCheck(s->caseops.setup, comm, PETSC_ERR_ARG_WRONGSTATE, "Case %s has no setup routine", s->opt.casename);
  PetscCall((*s->caseops.setup)(s));
  PetscCheck(s->pw.domain_set, comm, PETSC_ERR_ARG_WRONGSTATE, "Case %s did not set the domain (FSSolverSetDomain)",
             s->opt.casename);
  if (s->boundary) { /* the walls the case gave */
    PetscCall(FSBoundarySetFromOptions(s->boundary));
    PetscCall(FSBoundarySetUp(s->boundary, s->opt.dim, s->opt.dx, s->opt.h,
                              s->pw.kernel.support + s->opt.halo_skin * s->opt.h));
  }
  PetscCheck(s->pw.nglobal_particles > 0 || s->structure, comm, PETSC_ERR_ARG_WRONGSTATE,
             "Case %s created no particles and there is no structure (-fs_structure none): nothing to compute",
             s->opt.casename);
  PetscCall(FSSolverCheckStart(s)); /* before the structure takes the liquid's mass for its payload */

  width = s->pw.kernel.support + s->opt.halo_skin * s->opt.h;
  for (PetscInt d = 0; d < s->opt.dim; d++)
    PetscCheck(!s->pw.periodic[d] || s->pw.hi[d] - s->pw.lo[d] >= 2 * width, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "Periodic direction %" PetscInt_FMT
               " is %g long, less than twice the halo width %g: use a smaller -fs_dx",
               d, (double)(s->pw.hi[d] - s->pw.lo[d]), (double)width);
  PetscCall(FSDecompSetUp(&s->pw.decomp, comm, s->opt.dim, s->pw.lo, s->pw.hi, s->pw.periodic, width));
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(FSDecompBalance(&s->pw.decomp, comm, n, x, NULL, width));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));

  /* the coupling (the liquid's mass, which the structure's payload may need), the structure, then the
     global DOFs: the structure's state, one dissipated energy per dissipative term */
  PetscCall(DMSwarmGetLocalSize(s->swarm, &n));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(FSCouplingSetUp(s->coupling, (PetscBool)(s->structure && s->boundary && s->pw.nglobal_particles),
                            s->opt.dim, s->opt.gravity, s->boundary, n, x, m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_MASS, NULL, NULL, (void **)&m));
  PetscCall(DMSwarmRestoreField(s->swarm, FS_FIELD_POSITION, NULL, NULL, (void **)&x));
  if (s->structure) {
    FSStructure st = s->structure;
    PetscCall(PetscLogEventBegin(FS_Structure, 0, 0, 0, 0));
    if (st->ops.setup) PetscCall((*st->ops.setup)(st));
    PetscCall(PetscLogEventEnd(FS_Structure, 0, 0, 0, 0));
    PetscCheck(st->ndof >= 0 && (st->ndof == 0 || (st->ops.rhs && st->ops.motion)), comm, PETSC_ERR_PLIB,
               "Structure %s: the model must set ndof and provide rhs and motion", st->name);
    PetscCheck(!st->ncolumns || st->ops.columns, comm, PETSC_ERR_PLIB,
               "Structure %s adds time-series columns but has no columns routine", st->name);
    PetscCall(PetscCalloc2(st->ndof + 1, &s->sy, st->ndof + 1, &s->sydot));
  }
  PetscCall(FSSolverSetUpGlobalBlocks(s));
  if (s->structure && s->structure->ndof && s->structure->ops.initial)
    PetscCall((*s->structure->ops.initial)(s->structure, &s->state.global0[s->state.gstruct]));
  if (!s->ts) PetscCall(FSSolverSetUpTS(s));
  PetscCall(FSSolverSetUpRecord(s));
  if (s->opt.restart[0]) PetscCall(FSSolverLoadCheckpoint(s));
  if (s->opt.restart[0]) {
    PetscCall(TSSetTime(s->ts, s->state.restart_hdr.time));
    PetscCall(TSSetStepNumber(s->ts, s->state.restart_hdr.step));
    PetscCall(TSSetTimeStep(s->ts, s->state.restart_hdr.dt));
  }
  PetscCall(FSSolverPartitionWalls(s)); /* the cuts are final (a restart's are the checkpoint's) */
  /* a restart builds the lists where the checkpoint's run last built them, so that it goes on as that run */
  if (s->opt.restart[0]) PetscCall(FSSolverSwapBuildPositions(s));
  PetscCall(FSSolverMigrate(s, &changed));
  PetscCall(FSSolverSortByCell(s));
  PetscCall(TSGetStepNumber(s->ts, &s->pw.sort_step));
  if (s->opt.restart[0]) PetscCall(FSSolverSwapBuildPositions(s));
  s->pw.resume = (PetscBool)(s->opt.restart[0] != 0);
  PetscCall(FSSolverResize(s, PETSC_TRUE));
  PetscCall(FSSolverBalanceWork(s)); /* on the lists just built */
  if (!s->opt.restart[0]) {
    PetscReal dt;
    PetscCall(FSSolverComputeStableDt(s, &dt));
    PetscCall(TSSetTimeStep(s->ts, dt));
    PetscCall(FSSolverStructureDtAdvice(s)); /* a mode's period that sets the step: said, with what to do */
  }
  /* the probe file read and checked here, the snapshots' interval against the final time: their errors are set-up's */
  PetscCall(FSSolverBuiltinMonitorsSetUp(s));
  PetscCall(FSSolverCheckOptions(s, PETSC_TRUE)); /* every object has read its options: before the first step */
  s->setupcalled = PETSC_TRUE;
  if (s->opt.geometry_view) { /* into a folder of its own: a run's results in the output directory stay as they are */
    size_t len;
    PetscCall(PetscStrlen(s->opt.outdir, &len));
    PetscCall(FSSolverOutputDirChoose(s)); /* the run's own directory, without -fs_output_dir */
    PetscCall(PetscStrlen(s->opt.outdir, &len));
    PetscCheck(len + 10 < sizeof(s->opt.outdir), comm, PETSC_ERR_ARG_SIZ, "-fs_output_dir %s: too long", s->opt.outdir);
    PetscCall(PetscStrcat(s->opt.outdir, "/geometry"));
    PetscCall(FSSolverOpenOutputDir(s));
    PetscCall(FSSolverGeometryView(s, s->opt.outdir));
    PetscCall(FSSolverMonitorBegin(s)); /* the particles at step 0: snapshot_000000.h5 in particles.xdmf */
    if (s->opt.write_output && !s->opt.restart[0] && s->pw.nglobal_particles)
      PetscCall(PetscPrintf(comm, "Geometry view: the particles at step 0 are in %s/particles.xdmf\n", s->opt.outdir));
  }
  PetscFunctionReturn(0);
}

/* the seconds a particle-step takes on one core, 2-D and 3-D: the dam breaks of docs/performance.md on the project's
   2-core test machine, 1 rank (2-D: bench_dam_break.py, 20,000 particles, 2.41e5 particle-steps/s; 3-D:
   bench_dam_break_3d.py, 310,675 particles, 1.75e4 particle-steps/s); a machine of its own takes its
   particle_steps_per_second from a short run's summary.json */
#define FS_SECONDS_PER_PARTICLE_STEP_2D (1 / 2.41e5)
#define FS_SECONDS_PER_PARTICLE_STEP_3D (1 / 1.75e4)

/* the estimate of FSSolverView: particles, wall elements, the time step of the set-up's state and what limits it,
   the steps to the final time and the wall time they take at the measured cost of a particle-step; collective */
static PetscErrorCode FSSolverViewEstimate(FSSolver s, PetscViewer viewer)
{
  const PetscReal per = s->opt.dim == 3 ? FS_SECONDS_PER_PARTICLE_STEP_3D : FS_SECONDS_PER_PARTICLE_STEP_2D;
  PetscReal       nu, dt, t = 0, tmax = 0, secs, lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  PetscInt        source, limit, nel = 0, maxsteps = PETSC_MAX_INT, step = 0;
  double          steps, run;
  PetscBool       limited;
  const char     *why;
  PetscMPIInt     size;

  PetscFunctionBegin;
  if (!s->setupcalled || !s->ts) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)s), &size));
  if (s->boundary) {
    const FSWallView *B;
    const PetscInt   *wstart, *wk;
    const PetscReal  *wW;
    PetscCall(FSBoundaryGetView(s->boundary, &B, &wstart, &wk, &wW));
    if (B) PetscCall(FSBoundaryGetElementCounts(s->boundary, NULL, &nel, NULL));
    PetscCall(FSBoundaryGetBoundingBox(s->boundary, lo, hi));
  }
  PetscCall(FSSolverViscosityBound(s, &nu, &source));
  if (s->pw.nglobal_particles > 0) FSSolverStableDtOf(s, s->state.umax, nu, source, &dt, &limit);
  else {
    PetscCall(FSSolverStructureDt(s, &dt));
    limit = FS_DT_STRUCTURE;
  }
  PetscCall(FSSolverDtLimitName(s, limit, &why));
  PetscCall(TSGetMaxTime(s->ts, &tmax));
  PetscCall(TSGetMaxSteps(s->ts, &maxsteps));
  PetscCall(TSGetTime(s->ts, &t));
  PetscCall(TSGetStepNumber(s->ts, &step));
  steps   = dt > 0 ? PetscMax(0.0, PetscCeilReal((tmax - t) / dt)) : 0;
  limited = (PetscBool)(maxsteps >= 0 && (double)(maxsteps - step) < steps);
  run     = limited ? (double)PetscMax(0, maxsteps - step) : steps;
  secs    = (PetscReal)(run * (double)s->pw.nglobal_particles / size * per);
  if (s->boundary) {
    char box[160];
    PetscCall(PetscSNPrintf(box, sizeof(box), "[%g, %g] x [%g, %g]", (double)lo[0], (double)hi[0], (double)lo[1],
                            (double)hi[1]));
    if (s->opt.dim == 3)
      PetscCall(
          PetscSNPrintf(box + strlen(box), sizeof(box) - strlen(box), " x [%g, %g]", (double)lo[2], (double)hi[2]));
    PetscCall(PetscViewerASCIIPrintf(viewer, "walls: %" PetscInt_FMT " elements, bounding box %s\n", nel, box));
  }
  PetscCall(PetscViewerASCIIPrintf(
      viewer,
      "estimate: %" PetscInt64_FMT " particles; time step %.4g s at the start (limit: %s; "
      "the acoustic CFL h/c0 %.4g s), %.0f steps to -ts_max_time %g s%s; about %.3g s of "
      "wall time for %.0f steps on %d rank(s) at %.3g s a particle-step on a core "
      "(measured, docs/running.md)\n",
      s->pw.nglobal_particles, (double)dt, why, (double)(s->opt.cfl * s->opt.h / s->opt.c0), steps, (double)tmax,
      limited ? " (-ts_max_steps stops the run first)" : "", (double)secs, run, (int)size, per));
  PetscFunctionReturn(0);
}

/*
   FSSolverView - prints the run's set-up: case, particles, decomposition, parameters, terms, TS.

   Options Database Key:
.  -fs_view - view the solver after set-up
*/
PetscErrorCode FSSolverView(FSSolver s, PetscViewer viewer)
{
  PetscBool   iascii;
  PetscMPIInt size;

  PetscFunctionBegin;
  if (!viewer) PetscCall(PetscViewerASCIIGetStdout(PetscObjectComm((PetscObject)s), &viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (!iascii) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)s), &size));
  PetscCall(PetscObjectPrintClassNamePrefixType((PetscObject)s, viewer));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "case %s, %" PetscInt_FMT "-D, %" PetscInt64_FMT " particles on %d rank(s)\n",
                                   s->opt.casename, s->opt.dim, s->pw.nglobal_particles, (int)size));
  PetscCall(PetscViewerASCIIPrintf(viewer, "dx = %g, h = %g (h/dx = %g), Wendland C2 kernel, support 2h\n",
                                   (double)s->opt.dx, (double)s->opt.h, (double)s->opt.h_over_dx));
  PetscCall(
      PetscViewerASCIIPrintf(viewer, "rho0 = %g, c0 = %g, nu = %g, gravity = (%g, %g, %g), background pressure %g\n",
                             (double)s->opt.rho0, (double)s->opt.c0, (double)s->opt.nu, (double)s->opt.gravity[0],
                             (double)s->opt.gravity[1], (double)s->opt.gravity[2], (double)s->opt.background_pressure));
  PetscCall(PetscViewerASCIIPrintf(viewer, "domain [%g, %g] x [%g, %g]", (double)s->pw.lo[0], (double)s->pw.hi[0],
                                   (double)s->pw.lo[1], (double)s->pw.hi[1]));
  if (s->opt.dim == 3)
    PetscCall(PetscViewerASCIIPrintf(viewer, " x [%g, %g]", (double)s->pw.lo[2], (double)s->pw.hi[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, ", periodic (%d, %d, %d), ranks grid %d x %d x %d\n", s->pw.periodic[0],
                                   s->pw.periodic[1], s->pw.periodic[2], s->pw.decomp.np[0], s->pw.decomp.np[1],
                                   s->pw.decomp.np[2]));
  if (s->liquid[0] > 0)
    PetscCall(PetscViewerASCIIPrintf(
        viewer,
        "liquid: volume %.10g (exact, from the walls), mass %.10g; the lattice's mass %.10g "
        "(%.6f of it)\n",
        (double)s->liquid[0], (double)s->liquid[1], (double)s->liquid[2], (double)(s->liquid[2] / s->liquid[1])));
  PetscCall(PetscViewerASCIIPrintf(viewer, "time step: CFL %g, viscous %g, force %g\n", (double)s->opt.cfl,
                                   (double)s->opt.cfl_visc, (double)s->opt.cfl_force));
  PetscCall(FSSolverViewEstimate(s, viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "terms (%" PetscInt_FMT "):\n", s->terms.nterms));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  for (PetscInt t = 0; t < s->terms.nterms; t++) {
    FSTerm term = s->terms.term[t];
    if (term->ops.view) PetscCall((*term->ops.view)(term, viewer));
    else PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", term->name));
  }
  PetscCall(PetscViewerASCIIPopTab(viewer));
  if (s->structure) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "structure %s, %" PetscInt_FMT " DOFs\n", s->structure->name,
                                     s->structure->ndof));
    PetscCall(PetscViewerASCIIPushTab(viewer));
    if (s->structure->ops.view) PetscCall((*s->structure->ops.view)(s->structure, viewer));
    PetscCall(PetscViewerASCIIPopTab(viewer));
  } else PetscCall(PetscViewerASCIIPrintf(viewer, "no structure\n"));
  if (s->ts) PetscCall(TSView(s->ts, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(0);
}

/* FSSolverDestroy - frees everything the solver holds. */
PetscErrorCode FSSolverDestroy(FSSolver *solver)
{
  FSSolver s;

  PetscFunctionBegin;
  if (!*solver) PetscFunctionReturn(0);
  s = *solver;
  if (--((PetscObject)s)->refct > 0) {
    *solver = NULL;
    PetscFunctionReturn(0);
  }
  for (PetscInt t = 0; t < s->terms.nterms; t++) PetscCall(FSTermDestroy(&s->terms.term[t]));
  PetscCall(FSStructureDestroy(&s->structure));
  PetscCall(FSSolverSetOptionsChecked(s, 0, NULL));
  PetscCall(PetscFree2(s->sy, s->sydot));
  if (s->casedata) PetscCall(PetscFree(s->casedata));
  PetscCall(FSSolverMonitorCancel(s)); /* the user's monitors and callbacks */
  for (PetscInt k = 0; k < s->mon.nlist; k++) PetscCall(FSMonitorDestroy(&s->mon.list[k])); /* the run's own */
  PetscCall(FSMonitorRowBatchDestroy(&s->mon.rows));
  PetscCall(PetscFree(s->mon.reduce));
  s->mon.nlist = s->mon.nbuiltin = 0;
  PetscCall(FSSolverBuiltinMonitorsDestroy(s));
  PetscCall(FSOutputDirUnlock(&s->mon.lock)); /* the output is closed: another run may write there */
  PetscCall(TSDestroy(&s->ts));
  PetscCall(VecDestroy(&s->state.U));
  PetscCall(VecDestroy(&s->state.Uprev));
  PetscCall(VecDestroy(&s->state.Fout));
  PetscCall(DMDestroy(&s->swarm));
  PetscCall(FSDecompDestroy(&s->pw.decomp));
  PetscCall(FSBoundaryDestroy(&s->boundary));
  PetscCall(FSCouplingDestroy(&s->coupling));
  PetscCall(PetscFree2(s->pw.gamma, s->pw.invgamma));
  PetscCall(PetscFree2(s->pw.gammav, s->pw.invgammav));
  PetscCall(FSHaloDestroy(&s->pw.halo));
  PetscCall(FSNeighboursDestroy(&s->pw.nbrs));
  PetscCall(PetscFree4(s->pw.rec, s->pw.aux, s->pw.vol, s->pw.pressure));
  PetscCall(PetscFree2(s->pw.scratch, s->pw.scratchj));
  PetscCall(PetscFree(s->pw.pairstart));
  PetscCall(PetscFree2(s->pw.pairj, s->pw.pairF));
  PetscCall(PetscFree(s->pw.split));
  PetscCall(PetscFree(s->pw.passorder));
  PetscCall(PetscFree(s->mon.setup));
  PetscCall(PetscHeaderDestroy(solver));
  PetscFunctionReturn(0);
}
