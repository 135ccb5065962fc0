/*
   Small file-system helpers shared by the output writers: creating the output directory,
   testing for a file and renaming a finished "<name>.tmp" into place, each done by rank 0
   with the outcome broadcast so every rank raises the same error.
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <string.h>
#include <stdio.h>
#include "fsoutput.h"

/*
   mkdir -p on one rank with PETSc's PetscTestDirectory() and PetscMkdir(), then a check that files can
   be created in path; *err is 0 or an errno value for the message. PetscMkdir() raises a PETSc error
   without the system's reason: it is caught here unprinted, and errno, which mkdir() set, says why.
*/
static PetscErrorCode FSMkdirParents(const char path[], int *err)
{
  char      buf[PETSC_MAX_PATH_LEN];
  size_t    len;
  PetscBool w, x;

  PetscFunctionBegin;
  *err = 0;
  PetscCall(PetscStrlen(path, &len));
  if (len == 0) *err = ENOENT;
  else if (len >= sizeof(buf)) *err = ENAMETOOLONG;
  if (*err) PetscFunctionReturn(0);
  PetscCall(PetscStrcpy(buf, path));
  for (size_t i = 1; i <= len && !*err; i++) {
    const char saved = buf[i];
    PetscBool  isdir;

    if ((saved != '/' && saved != '\0') || buf[i - 1] == '/')
      continue; /* not the end of a name, or repeated separators */
    buf[i] = '\0';
    /* an existing directory that can be entered is kept as it is (it may not be writable, like "/") */
    PetscCall(PetscTestDirectory(buf, 'x', &isdir));
    if (!isdir) {
      PetscErrorCode ierr;

      PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
      errno = 0;
      ierr  = PetscMkdir(buf);
      if (ierr) *err = errno ? errno : EIO;
      PetscCall(PetscPopErrorHandler());
      if (*err == EEXIST) { /* there, but not a directory that can be entered */
        PetscBool r;

        PetscCall(PetscTestDirectory(buf, 'r', &r));
        PetscCall(PetscTestDirectory(buf, 'w', &w));
        *err = r || w ? EACCES : ENOTDIR;
      }
    }
    buf[i] = saved;
  }
  if (*err) PetscFunctionReturn(0);
  PetscCall(PetscTestDirectory(path, 'w', &w));
  PetscCall(PetscTestDirectory(path, 'x', &x));
  if (!w || !x) *err = EACCES;
  PetscFunctionReturn(0);
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
   Writability is checked with PetscTestDirectory() (access(2): write and search permission). New
   directories get PetscMkdir()'s mode, rwxr-x--- less the umask. On failure every rank raises
   PETSC_ERR_FILE_OPEN with the directory, the option and the system's reason.
@*/
PetscErrorCode FSMakeDirectory(MPI_Comm comm, const char path[], const char option[])
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCheck(path, comm, PETSC_ERR_ARG_NULL, "FSMakeDirectory: path is required");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(FSMkdirParents(path, &err));
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot create or write output directory \"%s\"%s%s%s: %s", path,
             option ? " (option " : "", option ? option : "", option ? ")" : "", strerror(err));
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

/*
   FSWriteCheck_Private - turns an error caught while writing file (the writer ran under
   PetscReturnErrorHandler, so nothing was printed) into one error that names the file, with the first
   error's own message (HDF5's names only its call) and, for a full disk or a file-size limit, the
   system's reason syserr (errno after the write; ignored unless ENOSPC, EFBIG, EDQUOT, EIO or EROFS).
   Nothing happens when ierr is 0.

   Not collective: raised on the ranks where the write failed; the others may be waiting in the writer's
   collectives, so the error must end the run: flexslosh's main() ends every rank through MPI_Abort(), the
   Python front when nothing catches the error
*/
PetscErrorCode FSWriteCheck_Private(PetscErrorCode ierr, int syserr, const char file[])
{
  char     *specific = NULL;
  PetscBool sys      = (PetscBool)(syserr == ENOSPC || syserr == EFBIG || syserr == EDQUOT || syserr == EIO ||
                              syserr == EROFS);

  PetscFunctionBegin;
  if (!ierr) PetscFunctionReturn(0);
  (void)PetscErrorMessage(ierr, NULL, &specific);
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write \"%s\"%s%s: %s", file, sys ? ": " : "",
          sys ? strerror(syserr) : "", specific && specific[0] ? specific : "error in the writer");
}
