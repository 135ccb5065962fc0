/*
   Small file-system helpers shared by the output writers: creating the output directory,
   creating a file without following links, testing for a file and renaming a finished
   "<name>.tmp" into place, each done by rank 0 with the outcome broadcast so every rank raises
   the same error.
*/
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>
#include "fsoutput.h"

/*
   FSFileCreate_Private - creates path as a new, empty regular file for writing, never through a link and never into a
   file already there: an entry of that name (a "<name>.tmp" left by a killed run, a symbolic link, a file) is removed
   first (a link's target is not touched), then the file is created with O_CREAT | O_EXCL | O_NOFOLLOW, so that
   whatever appears under the name in between makes the creation fail (EEXIST) instead of being written into.

   Not collective

   Input Parameter:
.  path - the file

   Output Parameters:
+  fp - the file opened for writing ("w"), or NULL: the file is created and closed (for a writer that opens it
        itself, HDF5); NULL on failure
-  id - the file created (device and inode), for FSFileReplace_Private(); may be NULL

   Returns 0 or an errno value: EISDIR for a directory under the name, ELOOP where a link took its place
*/
int FSFileCreate_Private(const char path[], FILE **fp, FSFileId *id)
{
  struct stat sb;
  int         fd;

  if (fp) *fp = NULL;
  if (lstat(path, &sb) == 0) {
    if (S_ISDIR(sb.st_mode)) return EISDIR;
    if (unlink(path) != 0 && errno != ENOENT) return errno ? errno : EIO;
  }
  fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) return errno ? errno : EIO;
  if (fstat(fd, &sb) != 0) {
    const int err = errno ? errno : EIO;
    (void)close(fd);
    return err;
  }
  if (id) {
    id->dev = (unsigned long long)sb.st_dev;
    id->ino = (unsigned long long)sb.st_ino;
  }
  if (!fp) return close(fd) != 0 ? (errno ? errno : EIO) : 0;
  if (!(*fp = fdopen(fd, "w"))) {
    const int err = errno ? errno : EIO;
    (void)close(fd);
    return err;
  }
  return 0;
}

/*
   FSFileReplace_Private - renames from (a file made by FSFileCreate_Private(), whose id is given) to to, when from is
   still that file: a link or another file put under the temporary name while it was written is not moved into place
   (ELOOP for a link, EEXIST for another file). rename() replaces an entry to, a link included, without following it.

   Not collective; returns 0 or an errno value
*/
int FSFileReplace_Private(const char from[], const char to[], const FSFileId *id)
{
  struct stat sb;

  if (lstat(from, &sb) != 0) return errno ? errno : EIO;
  if (S_ISLNK(sb.st_mode)) return ELOOP;
  if (id && ((unsigned long long)sb.st_dev != id->dev || (unsigned long long)sb.st_ino != id->ino)) return EEXIST;
  return rename(from, to) != 0 ? (errno ? errno : EIO) : 0;
}

/*
   FSFileOpenAppend_Private - opens an existing regular file for appending, never through a link (ELOOP) and never a
   pipe or a device (EINVAL).

   Not collective; returns 0 or an errno value
*/
int FSFileOpenAppend_Private(const char path[], FILE **fp)
{
  struct stat sb;
  int         fd, err = 0;

  *fp = NULL;
  fd  = open(path, O_WRONLY | O_APPEND | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC); /* a pipe: no wait for a reader */
  if (fd < 0) return errno ? errno : EIO;
  if (fstat(fd, &sb) != 0) err = errno ? errno : EIO;
  else if (!S_ISREG(sb.st_mode)) err = EINVAL;
  else if (fcntl(fd, F_SETFL, O_APPEND) != 0 || !(*fp = fdopen(fd, "a"))) err = errno ? errno : EIO;
  if (err) (void)close(fd);
  return err;
}

/*
   FSFileCreateShared_Private - the file that the ranks of comm then open together (an HDF5 file, which HDF5 opens
   following links and truncating what it finds): rank 0 creates it empty with FSFileCreate_Private() (so that it is a
   regular file of this run, not a link planted under the name nor a file left there) and keeps its id for the rename;
   a failure is raised on every rank, naming the file.

   Collective
*/
PetscErrorCode FSFileCreateShared_Private(MPI_Comm comm, const char path[], FSFileId *id)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = FSFileCreate_Private(path, NULL, id);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot create \"%s\": %s", path, strerror(err));
  PetscFunctionReturn(0);
}

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
   are in the same directory) when from is still the file that FSFileCreate_Private() made (id, rank 0's; NULL: any
   regular file); every rank of comm raises the error if it fails.
   Collective on comm; call with PETSC_COMM_SELF from code that runs on rank 0 only.
*/
PetscErrorCode FSRenameFile_Private(MPI_Comm comm, const char from[], const char to[], const FSFileId *id)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = FSFileReplace_Private(from, to, id);
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
