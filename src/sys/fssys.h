/*
   The library's own machinery (src/sys): registration tables of implementations by name, and the
   log events that -log_view reports.
*/
#pragma once
#include <flexslosh.h>
#include <petsc/private/petscimpl.h>

/* A registration table (src/sys/registry.c): creation routines by name, with descriptions. */
typedef struct _n_FSRegistryEntry {
  char name[64], description[256];
  void (*create)(void);
  struct _n_FSRegistryEntry *next;
} FSRegistryEntry;
typedef struct {
  FSRegistryEntry *first; /* registration order */
} FSRegistry;

PETSC_INTERN PetscErrorCode FSRegistryAdd(FSRegistry *, const char[], const char[], void (*)(void));
PETSC_INTERN PetscErrorCode FSRegistryFind(FSRegistry *, const char[], void (**)(void));
PETSC_INTERN PetscErrorCode FSRegistryView(FSRegistry *, PetscViewer, const char[], const char[]);
PETSC_INTERN PetscErrorCode FSRegistryNames(FSRegistry *, char[], size_t);

/* a file every rank reads, opened on all or on none (src/sys/files.c) */
PETSC_INTERN PetscErrorCode FSFileOpenOnEveryRank(MPI_Comm, const char[], const char[], FILE **, PetscBool *,
                                                  const char **);

/* the whole of a file read into a string (src/sys/files.c) */
PETSC_INTERN PetscErrorCode FSFileReadAll(FILE *, char **, size_t *);

/* an integer option PETSc reads itself, checked first as FSOptionsInt() checks (src/sys/options.c) */
PETSC_INTERN PetscErrorCode FSOptionsCheckPetscInt(MPI_Comm, const char[], PetscInt, PetscInt);

/* the size checks (src/sys/sizes.c): the memory this process may use in bytes (0 if unknown), a lattice's points,
   and whether (and the check that) a count of particles fits in an index and the memory */
#define FS_PARTICLE_BYTES 1024.0 /* a particle's memory at the least (a run takes 1.7 kB measured) */
#define FS_PARTICLE_REALS 16     /* the reals per particle of a rank's widest array: its record, and room for ghosts */
typedef enum { FS_SIZE_FITS, FS_SIZE_INDEX, FS_SIZE_MEMORY } FSSizeVerdict;
PETSC_INTERN double         FSMemoryTotal(void);
PETSC_INTERN double         FSLatticeCount(PetscInt, const PetscReal[], PetscReal);
PETSC_INTERN double         FSParticleBytes(PetscInt);
PETSC_INTERN FSSizeVerdict  FSParticleCountFits(double, PetscMPIInt, double, double, double *);
PETSC_INTERN PetscErrorCode FSCheckParticleCount(MPI_Comm, PetscInt, PetscReal, double, const char[], const char[]);

/* fault injection for the tests (src/sys/fault.c): FLEXSLOSH_FAULT=alloc|leak:RANK:STEP */
PETSC_INTERN PetscErrorCode FSDebugFault(MPI_Comm, const char[], PetscInt, PetscBool *);

/* the options every object reads, collected from the -help table by a survey (src/sys/optionssurvey.c) */
typedef struct {
  char      name[64];  /* without the '-', lower case */
  char      owner[96]; /* the object that reads it: "" (the solver), "case tank", "term shifting", ... */
  PetscBool prefix;    /* name is a prefix: the owner's PETSc objects read every option beginning with it */
} FSOptionsEntry;
typedef struct _n_FSOptionsTable *FSOptionsTable;
PETSC_INTERN PetscErrorCode       FSOptionsSurveyBegin(const char[]);
PETSC_INTERN PetscErrorCode       FSOptionsSurveyEnd(void);
PETSC_INTERN PetscErrorCode       FSOptionsSurveyTake(FSOptionsTable *);
PETSC_INTERN PetscBool            FSOptionsSurveyActive(void);
PETSC_INTERN PetscErrorCode       FSOptionsSurveyOwner(const char[], const char[]);
PETSC_INTERN PetscErrorCode       FSOptionsSurveyPrefix(const char[]);
PETSC_INTERN PetscErrorCode       FSOptionsSurveyBlock(PetscOptionItems *);
PETSC_INTERN PetscErrorCode       FSOptionsTableGet(FSOptionsTable, PetscInt *, const FSOptionsEntry **);
PETSC_INTERN PetscErrorCode       FSOptionsTableDestroy(FSOptionsTable *);
PETSC_INTERN PetscInt             FSOptionsDistance(const char[], const char[]);

/* log events */
PETSC_EXTERN PetscLogEvent FS_Structure, FS_Coupling;
PETSC_EXTERN PetscLogEvent FS_Step, FS_Neighbours, FS_Halo, FS_FirstPass, FS_PairPass, FS_WallPass, FS_Walls,
    FS_Migrate, FS_Output, FS_RHS, FS_Split, FS_FillPacking;
