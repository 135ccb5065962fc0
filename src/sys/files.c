/*
   Opening a file that every rank reads: the ranks agree on whether it opened, so that a path
   missing on one node ends every rank with the same error instead of leaving the others waiting.
*/
#include "sys/fssys.h"
#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

/*
   FSFileOpenOnEveryRank - fopen() on every rank of comm, then one decision for all.

   Collective

   Input Parameters:
+  comm - the ranks that read the file
.  path - the file
-  mode - as for fopen()

   Output Parameters:
+  fp        - the open file, or NULL on every rank when any rank could not open it
.  elsewhere - PETSC_TRUE when this rank opened it but another rank could not (for the message)
-  why       - why this rank could not open it (strerror(), "a directory"), "" if it could
*/
PetscErrorCode FSFileOpenOnEveryRank(MPI_Comm comm, const char path[], const char mode[], FILE **fp,
                                     PetscBool *elsewhere, const char **why)
{
  FILE       *f = fopen(path, mode);
  struct stat sb;
  int         mine, all;

  PetscFunctionBegin;
  *why = f ? "" : strerror(errno);
  if (f && fstat(fileno(f), &sb) == 0 && S_ISDIR(sb.st_mode)) {
    fclose(f);
    f    = NULL;
    *why = "a directory";
  }
  mine = f != NULL;
  PetscCallMPI(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm));
  if (!all && f) fclose(f);
  *fp        = all ? f : NULL;
  *elsewhere = (PetscBool)(!all && mine);
  PetscFunctionReturn(0);
}

/*
   FSFileReadAll - the whole of an open file (read to its end, so that a file whose size cannot be known
   beforehand reads too), NUL-terminated; the file may hold NUL bytes (size tells where it ends). Closes fp.

   Not collective

   Output Parameters:
+  text - the bytes and a NUL after them (PetscFree() it)
-  size - their number
*/
PetscErrorCode FSFileReadAll(FILE *fp, char **text, size_t *size)
{
  char  *buf = NULL;
  size_t n = 0, cap = 0, got;

  PetscFunctionBegin;
  do {
    if (n + 1 >= cap) {
      char *t;
      cap = PetscMax(4096, 2 * cap);
      PetscCall(PetscMalloc1(cap, &t));
      if (n) PetscCall(PetscArraycpy(t, buf, n));
      PetscCall(PetscFree(buf));
      buf = t;
    }
    got = fread(buf + n, 1, cap - n - 1, fp);
    n += got;
  } while (got);
  fclose(fp);
  buf[n] = 0;
  *text  = buf;
  *size  = n;
  PetscFunctionReturn(0);
}
