/*
   The error reports: a short one by default (what, where, what to do), PETSc's full report with -fs_error_trace.

   PETSc's traceback report of an error (PetscTraceBackErrorHandler()) is 30 to 60 lines: the error's class, the
   message, the options left, the release, the configure line, every frame, the option table and a request to mail
   petsc-maint. The line that matters, the message given where the error was raised, is the second. FSErrorHandler()
   prints that message and where it was raised in a few lines; -fs_error_trace gives PETSc's full report instead.
*/
#include "sys/fssys.h"

#ifndef FS_SOURCE_DIR
#  define FS_SOURCE_DIR "" /* the build gives it (CMakeLists.txt); without it every frame counts as flexslosh's */
#endif

/* the current error's report in this process */
static struct {
  PetscBool   print;   /* this process prints it (rank 0 of the error's communicator) */
  PetscBool   located; /* its 'where' is out: a frame in flexslosh's sources (or a signal's, which has none) */
  PetscBool   printed; /* this process printed a report (FSErrorPrinted()) */
  int         frame;   /* FSErrorTraceHandler()'s frame count */
  int         skipped; /* frames outside flexslosh's sources since the innermost one (PETSc's own calls) */
  const char *outer;   /* the outermost of them (the PETSc function flexslosh called; a __func__, never freed) */
} fserr = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE, 1, 0, NULL};

/* a frame in flexslosh's sources (the library, the program, the example plug-ins), not PETSc's or the system's */
static PetscBool FSErrorOwnFile(const char *file)
{
  return (PetscBool)(file && !strncmp(file, FS_SOURCE_DIR, strlen(FS_SOURCE_DIR)));
}

/* a file of flexslosh's sources relative to the source tree (src/solver/solver.c), other files as given */
static const char *FSErrorFileName(const char *file)
{
  if (!file) return "?";
  return FSErrorOwnFile(file) ? file + strlen(FS_SOURCE_DIR) : file;
}

/* each line of text, prefixed with "[rank] flexslosh: " and lead (the first line) or an indent (the others) */
static void FSErrorPrintLines(const char *lead, const char *text)
{
  const char *line = text;
  do {
    const char *end = strchr(line, '\n');
    int         len = end ? (int)(end - line) : (int)strlen(line);
    (void)fprintf(PETSC_STDERR, "[%d] flexslosh: %s%.*s\n", PetscGlobalRank, line == text ? lead : "       ", len,
                  line);
    line = end ? end + 1 : NULL;
  } while (line && *line);
}

/* the 'where' line of a frame, and once a frame of flexslosh's is reached (or there is no frame), what to do */
static void FSErrorPrintFrame(const char *how, int line, const char *fun, const char *file, const char *tail)
{
  if (fun || file)
    (void)fprintf(PETSC_STDERR, "[%d] flexslosh:   %s %s%s at %s:%d%s\n", PetscGlobalRank, how, fun ? fun : "",
                  fun ? "()" : "", FSErrorFileName(file), line, tail);
  else (void)fprintf(PETSC_STDERR, "[%d] flexslosh:  %s\n", PetscGlobalRank, tail);
  if (!fun && !file) fserr.located = PETSC_TRUE; /* a signal: no frames follow */
  if (FSErrorOwnFile(file) || (fun && !strcmp(fun, "main"))) fserr.located = PETSC_TRUE;
  if (fserr.located)
    (void)fprintf(PETSC_STDERR, "[%d] flexslosh:   -fs_error_trace prints PETSc's full report\n", PetscGlobalRank);
  (void)fflush(PETSC_STDERR);
}

/*@C
   FSErrorHandler - the short report of an error: the message given where it was raised, then where (the function,
   file and line; for an error raised inside PETSc, also the first function of flexslosh's on the way out), then
   the option that prints PETSc's full report instead (-fs_error_trace). Each line starts with
   "[rank] flexslosh: ", the first with "error: ". Printed once per error, by rank 0 of the communicator the error
   was raised on (an error raised on PETSC_COMM_SELF by its own rank); every rank returns the error code, so that
   the program decides how to end (flexslosh's main: app/flexslosh.c; the Python package raises an exception).
   The program pushes it with PetscPushErrorHandler() unless -fs_error_trace is given.

   Not collective

   Input Parameters: those of a PetscErrorHandler (see PetscPushErrorHandler()); ctx is not used

   Options Database Key:
.  -fs_error_trace - PETSc's full report instead (the program pushes no handler, or FSErrorTraceHandler())

   Notes:
   A signal (PETSc's signal handler prints which one) and an allocation that failed (PETSC_ERR_MEM: the
   process's memory is added) are reported the same way.

.seealso: FSErrorTraceHandler(), PetscPushErrorHandler(), PetscTraceBackErrorHandler(), PetscErrorMessage()
@*/
PetscErrorCode FSErrorHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n,
                              PetscErrorType p, const char *mess, void *ctx)
{
  (void)ctx;
  if (p == PETSC_ERROR_INITIAL) {
    PetscMPIInt rank = 0;
    const char *text = NULL;

    if (comm != MPI_COMM_NULL && comm != PETSC_COMM_SELF) MPI_Comm_rank(comm, &rank);
    fserr.print   = (PetscBool)(rank == 0);
    fserr.located = PETSC_FALSE;
    fserr.skipped = 0;
    fserr.outer   = NULL;
    if (!fserr.print) return n;
    fserr.printed = PETSC_TRUE;
    (void)PetscErrorMessage(n, &text, NULL);
    while (mess && (*mess == ' ' || *mess == '\n')) mess++;
    FSErrorPrintLines("error: ", mess && *mess ? mess : (text ? text : "unknown error"));
    if (n == PETSC_ERR_MEM) {
      PetscLogDouble rss = 0;
      (void)PetscMemoryGetCurrentUsage(&rss);
      (void)fprintf(PETSC_STDERR, "[%d] flexslosh:   out of memory: this process holds %.0f MB\n", PetscGlobalRank,
                    rss / 1048576.0);
    }
    {
      char tail[160];
      if (text) (void)PetscSNPrintf(tail, sizeof(tail), " (PETSc error %d: %s)", (int)n, text);
      else (void)PetscSNPrintf(tail, sizeof(tail), " (PETSc error %d)", (int)n);
      FSErrorPrintFrame("in", line, fun, file, tail);
    }
  } else if (fserr.print && !fserr.located) {
    if (FSErrorOwnFile(file) || (fun && !strcmp(fun, "main"))) { /* the first of flexslosh's frames */
      char tail[160] = "";
      if (fserr.skipped && fserr.outer)
        (void)PetscSNPrintf(tail, sizeof(tail), ", through %s()%s", fserr.outer,
                            fserr.skipped > 1 ? " and PETSc's calls inside it" : "");
      FSErrorPrintFrame("called from", line, fun, file, tail);
    } else { /* PETSc's own frames between: counted, not printed */
      fserr.skipped++;
      fserr.outer = fun;
    }
  }
  return n;
}

/*@C
   FSErrorTraceHandler - PETSc's traceback report (the error's class, the message, every frame), for a process that
   lives on after an error (a driver that turns every error into an exception, such as the Python package, pushes it
   with PetscPushErrorHandler() around its calls when -fs_error_trace is given): every error's report is printed in
   full, once, by rank 0 of the communicator the error was raised on, and every rank returns the error code.
   PetscTraceBackErrorHandler() prints the message of the first error in a process's life only, and ends the other
   ranks of the communicator.

   Not collective

   Input Parameters: those of a PetscErrorHandler (see PetscPushErrorHandler())

.seealso: FSErrorHandler(), PetscPushErrorHandler(), PetscTraceBackErrorHandler(), PetscErrorMessage()
@*/
PetscErrorCode FSErrorTraceHandler(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n,
                                   PetscErrorType p, const char *mess, void *ctx)
{
  (void)ctx;
  if (p == PETSC_ERROR_INITIAL) {
    PetscMPIInt rank = 0;
    const char *text = NULL;

    if (comm != MPI_COMM_NULL && comm != PETSC_COMM_SELF) MPI_Comm_rank(comm, &rank);
    fserr.print = (PetscBool)(rank == 0);
    fserr.frame = 1;
    if (fserr.print) {
      fserr.printed = PETSC_TRUE;
      (void)(*PetscErrorPrintf)(
          "--------------------- Error Message --------------------------------------------------------------\n");
      (void)PetscErrorMessage(n, &text, NULL);
      if (text) (void)(*PetscErrorPrintf)("%s\n", text);
      if (mess) (void)(*PetscErrorPrintf)("%s\n", mess);
      (void)(*PetscErrorPrintf)("See https://petsc.org/release/faq/ for trouble shooting.\n");
    }
  }
  if (fserr.print && fun) (void)(*PetscErrorPrintf)("#%d %s() at %s:%d\n", fserr.frame++, fun, file ? file : "?", line);
  else if (fserr.print && file) (void)(*PetscErrorPrintf)("#%d %s:%d\n", fserr.frame++, file, line);
  return n;
}

/*@C
   FSErrorPrinted - whether this process has printed an error's report (FSErrorHandler(), FSErrorTraceHandler()):
   a program ending on an error lets the process that prints end the others (app/flexslosh.c).

   Not collective

.seealso: FSErrorHandler()
@*/
PetscBool FSErrorPrinted(void) { return fserr.printed; }
