/*
   Small file-system helpers shared by the output writers: creating the output directory,
   testing for a file and renaming a finished "<name>.tmp" into place, each done by rank 0
   with the outcome broadcast so every rank raises the same error.
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <string.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include "fsoutput.h"

/* mkdir -p on one rank; returns 0 or an errno value */
static int FSMkdirParents(const char path[])
{
  char        buf[PETSC_MAX_PATH_LEN];
  size_t      len = strlen(path), i;
  struct stat st;

  if (len == 0) return ENOENT;
  if (len >= sizeof(buf)) return ENAMETOOLONG;
  memcpy(buf, path, len + 1);
  for (i = 1; i <= len; i++) {
    if (buf[i] == '/' || buf[i] == '\0') {
      char saved = buf[i];

      if (buf[i - 1] == '/') continue; /* repeated separators */
      buf[i] = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) return errno;
      buf[i] = saved;
    }
  }
  if (stat(path, &st) != 0) return errno;
  if (!S_ISDIR(st.st_mode)) return ENOTDIR;
  return 0;
}

/* create and remove a probe file inside dir; returns 0 or an errno value */
static int FSProbeWritable(const char dir[])
{
  char  probe[PETSC_MAX_PATH_LEN];
  FILE *fp;
  int   n;

  n = snprintf(probe, sizeof(probe), "%s/.fs_write_probe_%ld", dir, (long)getpid());
  if (n < 0 || (size_t)n >= sizeof(probe)) return ENAMETOOLONG;
  fp = fopen(probe, "w");
  if (!fp) return errno;
  if (fputs("probe\n", fp) == EOF) {
    int err = errno ? errno : EIO;

    (void)fclose(fp);
    (void)remove(probe);
    return err;
  }
  if (fclose(fp) != 0) {
    int err = errno ? errno : EIO;

    (void)remove(probe);
    return err;
  }
  if (remove(probe) != 0) return errno;
  return 0;
}

/*@C
   FSMakeDirectory - Creates an output directory (with its parents, like mkdir -p) and checks that
   files can be written in it.

   Collective

   Input Parameters:
+  comm   - communicator; rank 0 does the work, the outcome is broadcast
.  path   - directory to create (an existing directory is fine)
-  option - name of the option that set path (e.g. "-fs_output_dir"), quoted in the error message; may be NULL

   Notes:
   Writability is checked by creating and removing a probe file. On failure every rank raises
   PETSC_ERR_FILE_OPEN with the directory, the option and the system's reason.
@*/
PetscErrorCode FSMakeDirectory(MPI_Comm comm, const char path[], const char option[])
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCheck(path, comm, PETSC_ERR_ARG_NULL, "FSMakeDirectory: path is required");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    err = FSMkdirParents(path);
    if (!err) err = FSProbeWritable(path);
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot create or write output directory \"%s\"%s%s%s: %s", path, option ? " (option " : "", option ? option : "", option ? ")" : "", strerror(err));
  PetscFunctionReturn(0);
}

/*
   FSRenameFile_Private - Rank 0 of comm renames from into to (atomic on POSIX file systems when both
   are in the same directory); every rank of comm raises the error if it fails.
   Collective on comm; call with PETSC_COMM_SELF from code that runs on rank 0 only.
*/
PetscErrorCode FSRenameFile_Private(MPI_Comm comm, const char from[], const char to[])
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0 && rename(from, to) != 0) err = errno ? errno : EIO;
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot rename \"%s\" to \"%s\": %s", from, to, strerror(err));
  PetscFunctionReturn(0);
}

/*
   FSTestFile_Private - Whether path exists and is a readable regular file, as seen by rank 0 of comm
   (the answer is broadcast). Collective on comm.
*/
PetscErrorCode FSTestFile_Private(MPI_Comm comm, const char path[], PetscBool *exists)
{
  PetscMPIInt rank;
  int         flag = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    PetscBool flg;

    PetscCall(PetscTestFile(path, 'r', &flg));
    flag = flg ? 1 : 0;
  }
  PetscCallMPI(MPI_Bcast(&flag, 1, MPI_INT, 0, comm));
  *exists = flag ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}
