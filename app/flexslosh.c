static const char help[] =
    "flexslosh: liquid sloshing in tanks on flexible structures (delta-LES-SPH, PETSc TS).\n"
    "  flexslosh -options_file cases/taylor_green.opts [-fs_dx 0.01 -ts_type ssp ...]\n"
    "  -fs_case_view lists the cases, -fs_terms_view the physics terms, -fs_view the set-up.\n"
    "  -fs_ options that nothing reads stop the run before its first step (-fs_options_check 0: not);\n"
    "  other options given but never used are reported at the end (-fs_options_left 0: not).\n\n";

#include <flexslosh.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/*
   -options_file FILE makes PETSc read FILE while it initializes, and an -options_file inside FILE
   too, with no limit: a file that includes itself, directly or through others, recurses until the
   stack overflows (a segmentation fault inside PetscInitialize, PETSc 3.18). Before PetscInitialize,
   OptionsFileCycle() follows the files as PETSc reads them ('#' starts a comment; a line holds an
   option and its value, so "-options_file FILE" is one line) and writes the chain of a cycle,
   or of nesting deeper than FS_OPTIONS_FILE_DEPTH, to msg. It also refuses, by name, an options file that is a pipe,
   a socket or a device (`-options_file <(cat case.opts)`, `-options_file /dev/stdin`): PETSc 3.18 opens an options
   file twice, and the second read of a pipe finds it empty, so that its options were lost without a word and the
   run went on as the default case; a file that starts with a byte-order mark (FSTextByteOrderMark(): PETSc took
   it for part of the first option, invisibly); and a file that does not exist (in one line, where PETSc printed its
   full report). A file that cannot be opened otherwise, or a directory, is left to PETSc, which reports it.
*/
#define FS_OPTIONS_FILE_DEPTH 16

static int OptionsWordsCycle(const char *text, char real[][PATH_MAX], const char *given[], int depth, char msg[],
                             size_t len);

static int OptionsFileCycle(const char *path, char real[][PATH_MAX], const char *given[], int depth, char msg[],
                            size_t len)
{
  FILE       *fp;
  char       *text;
  long        size;
  int         cycle = -1;
  struct stat sb;

  given[depth] = path;
  if (!stat(path, &sb) && !S_ISREG(sb.st_mode) && !S_ISDIR(sb.st_mode)) {
    size_t n = (size_t)snprintf(msg, len, "-options_file %s is %s, not a regular file", path,
                                S_ISFIFO(sb.st_mode)   ? "a pipe"
                                : S_ISSOCK(sb.st_mode) ? "a socket"
                                : S_ISCHR(sb.st_mode)  ? "a character device"
                                                       : "a device");
    for (int d = 0; d < depth && n < len; d++)
      n += (size_t)snprintf(msg + n, len - n, "%s-options_file %s", d ? " -> " : " (in ", given[d]);
    if (depth && n < len) n += (size_t)snprintf(msg + n, len - n, ")");
    if (n < len)
      (void)snprintf(msg + n, len - n,
                     ": PETSc reads an options file twice and would find the second read of it empty, losing its "
                     "options; write them to a file and give its name");
    return 1;
  }
  if (stat(path, &sb) &&
      !strpbrk(path, "$~")) { /* PETSc would report it in its full report ('$', '~': PETSc expands) */
    size_t n = (size_t)snprintf(msg, len, "cannot read options file %s: %s", path, strerror(errno));
    for (int d = 0; d < depth && n < len; d++)
      n += (size_t)snprintf(msg + n, len - n, "%s-options_file %s", d ? " -> " : " (in ", given[d]);
    if (depth && n < len) (void)snprintf(msg + n, len - n, ")");
    return 1;
  }
  if (!realpath(path, real[depth])) return 0;
  for (int d = 0; d < depth && cycle < 0; d++)
    if (!strcmp(real[d], real[depth])) cycle = d;
  if (cycle >= 0 || depth + 1 >= FS_OPTIONS_FILE_DEPTH) {
    const int first = cycle >= 0 ? cycle : 0;
    size_t    n;
    if (cycle >= 0) n = (size_t)snprintf(msg, len, "options file \"%s\" includes itself: ", path);
    else n = (size_t)snprintf(msg, len, "options files nested deeper than %d: ", FS_OPTIONS_FILE_DEPTH);
    for (int d = first; d <= depth && n < len; d++)
      n += (size_t)snprintf(msg + n, len - n, "%s-options_file %s", d > first ? " -> " : "", given[d]);
    return 1;
  }
  fp = fopen(path, "rb");
  if (!fp) return 0;
  if (fseek(fp, 0, SEEK_END) || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) ||
      !(text = malloc((size_t)size + 1))) {
    fclose(fp); /* a directory, or no memory: PETSc reports it */
    return 0;
  }
  size       = (long)fread(text, 1, (size_t)size, fp);
  text[size] = 0;
  fclose(fp);
  if (FSTextByteOrderMark(text, (size_t)size)) { /* PETSc would read it as part of the first option */
    snprintf(msg, len, "options file \"%s\" starts with %s: save it as plain text, ASCII or UTF-8 without the mark",
             path, FSTextByteOrderMark(text, (size_t)size));
    free(text);
    return 1;
  }
  for (char *c = text; c < text + size; c++) /* comments out, NUL bytes as blanks */
    if (*c == '#')
      while (c < text + size && *c != '\n') *c++ = ' ';
    else if (!*c) *c = ' ';
  cycle = 0;
  for (char *line = text, *end; line && !cycle; line = end ? end + 1 : NULL) { /* each line its own words */
    if ((end = strchr(line, '\n'))) *end = 0;
    cycle = OptionsWordsCycle(line, real, given, depth + 1, msg, len);
  }
  free(text);
  return cycle;
}

/* the files named after -options_file in the words of text (a line of a file, the command line), followed */
static int OptionsWordsCycle(const char *text, char real[][PATH_MAX], const char *given[], int depth, char msg[],
                             size_t len)
{
  const char *p    = text;
  int         next = 0, found = 0;

  while (!found && *p) {
    const char *w;
    char        word[PATH_MAX];
    while (*p && strchr(" \t\r\n\f\v", *p)) p++;
    w = p;
    while (*p && !strchr(" \t\r\n\f\v", *p)) p++;
    if (p == w || (size_t)(p - w) >= sizeof(word)) continue;
    memcpy(word, w, (size_t)(p - w));
    word[p - w] = 0;
    if (next) found = OptionsFileCycle(word, real, given, depth, msg, len);
    next = !strcmp(word, "-options_file");
  }
  return found;
}

/* OptionsFilesCheck - 0, or 1 with the message printed (by the first rank of an MPI launch only) */
static int OptionsFilesCheck(int argc, char **argv)
{
  static char real[FS_OPTIONS_FILE_DEPTH][PATH_MAX];
  const char *given[FS_OPTIONS_FILE_DEPTH];
  const char *env = getenv("PETSC_OPTIONS"), *rank = getenv("OMPI_COMM_WORLD_RANK");
  char        msg[4096];
  int         found = 0;

  if (!rank) rank = getenv("PMI_RANK");
  for (int a = 1; a + 1 < argc && !found; a++)
    if (!strcmp(argv[a], "-options_file")) found = OptionsFileCycle(argv[a + 1], real, given, 0, msg, sizeof(msg));
  if (!found && env) found = OptionsWordsCycle(env, real, given, 0, msg, sizeof(msg));
  if (found && (!rank || !strcmp(rank, "0"))) fprintf(stderr, "[0] flexslosh: error: %s\n", msg);
  return found;
}

/* -fs_output_name's default: the name of the last -options_file of the command line without its folder and suffix
   (cases/dam_break.opts: dam_break), so that the default output directory, output/<name>-<time stamp>, says which
   case file ran; the case's name without one */
static PetscErrorCode OutputNameDefault(int argc, char **argv)
{
  const char *file = NULL, *slash;
  char        name[64], *dot;
  PetscBool   set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-fs_output_name", &set));
  for (int a = 1; a + 1 < argc; a++)
    if (!strcmp(argv[a], "-options_file")) file = argv[a + 1];
  if (set || !file) PetscFunctionReturn(0);
  slash = strrchr(file, '/');
  PetscCall(PetscStrncpy(name, slash ? slash + 1 : file, sizeof(name)));
  if ((dot = strrchr(name, '.')) && dot != name) *dot = 0;
  if (name[0] && strcmp(name, ".") && strcmp(name, ".."))
    PetscCall(PetscOptionsSetValue(NULL, "-fs_output_name", name));
  PetscFunctionReturn(0);
}

/* the run: the solver set up from the options and solved, the options nothing used reported */
static PetscErrorCode Run(void)
{
  FSSolver  solver;
  PetscBool help_only; /* -help lists the options (the solver's, its terms', its cases' and its TS's) and stops */

  PetscFunctionBeginUser;
  PetscCall(FSCheckPlugins(PETSC_COMM_WORLD));
  PetscCall(FSSolverCreate(PETSC_COMM_WORLD, &solver));
  PetscCall(FSSolverSetFromOptions(solver));
  PetscCall(PetscOptionsHasHelp(NULL, &help_only));
  if (!help_only) {
    PetscCall(FSSolverSetUp(solver));
    PetscCall(PetscObjectViewFromOptions((PetscObject)solver, NULL, "-fs_view"));
    PetscCall(FSSolverSolve(solver));
  }
  PetscCall(FSSolverDestroy(&solver));
  if (!help_only) PetscCall(FSOptionsLeft(PETSC_COMM_WORLD, 0, NULL)); /* a misspelt option: a warning */
  PetscFunctionReturn(0);
}

/*
   End - the program's end after an error, its report printed (FSErrorHandler(), or PETSc's with -fs_error_trace):
   one process returns the error code (without MPI_Abort()'s notice of several lines); on several, MPI_Abort() ends
   every rank, however far the others are (in a collective call that the failed rank never joins), at once on the
   rank that printed the report and after two seconds on the others, so that another rank's abort does not cut the
   report off. The exit status is the error code (1 if it does not fit in one).
*/
static int End(PetscErrorCode ierr)
{
  PetscMPIInt size   = 1;
  int         status = ierr > 0 && ierr < 256 ? (int)ierr : 1;

  (void)MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size == 1) return status;
  if (!FSErrorPrinted()) (void)PetscSleep(2.0);
  (void)MPI_Abort(MPI_COMM_WORLD, status);
  return status;
}

/*
   main - the command line. An error prints a short report (FSErrorHandler(): what, where, the option for more);
   -fs_error_trace prints PETSc's full report instead (an error inside PetscInitialize() prints it too, the handler
   being pushed after).
*/
int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  PetscBool      trace = PETSC_FALSE;

  if (OptionsFilesCheck(argc, argv)) return PETSC_ERR_FILE_UNEXPECTED;
  ierr = PetscInitialize(&argc, &argv, NULL, help);
  if (ierr) return End(ierr);
  ierr = PetscOptionsGetBool(NULL, NULL, "-fs_error_trace", &trace, NULL);
  if (!ierr && !trace) ierr = PetscPushErrorHandler(FSErrorHandler, NULL);
  if (!ierr) ierr = OutputNameDefault(argc, argv);
  if (!ierr) ierr = Run();
  if (ierr) return End(ierr);
  if (!trace) ierr = PetscPopErrorHandler(); /* its node is PETSc's memory: freed before PetscFinalize */
  if (ierr) return End(ierr);
  return (int)PetscFinalize();
}
