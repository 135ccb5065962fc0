/*
   Small file-system helpers shared by the output writers: creating the output directory,
   creating a file without following links, testing for a file and renaming a finished
   "<name>.tmp" into place, each done by rank 0 with the outcome broadcast so every rank raises
   the same error.
*/
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* flock() */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <stdio.h>
#include <time.h>
#include <sys/file.h>
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
      if (*err == EEXIST) { /* made meanwhile by another process (two runs making their parents), or there but not a
                               directory that can be entered */
        PetscBool r;

        PetscCall(PetscTestDirectory(buf, 'x', &isdir));
        PetscCall(PetscTestDirectory(buf, 'r', &r));
        PetscCall(PetscTestDirectory(buf, 'w', &w));
        *err = isdir ? 0 : r || w ? EACCES : ENOTDIR;
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

/*
   FSProbeDirectory - whether this rank can create a file in dir: it creates and removes a file of its own there
   ("<dir>/.flexslosh_probe_<rank>_<pid>.tmp", made as the writers make theirs). Returns 0 or an errno value. access(2)
   would not do: it says yes to root in a directory that refuses files (a read-only mount seen by one rank only, /proc).
*/
static int FSProbeDirectory(const char dir[], PetscMPIInt rank)
{
  char probe[PETSC_MAX_PATH_LEN];
  int  err;

  if (snprintf(probe, sizeof(probe), "%s/.flexslosh_probe_%d_%ld.tmp", dir, (int)rank, (long)getpid()) >=
      (int)sizeof(probe))
    return ENAMETOOLONG;
  if ((err = FSFileCreate_Private(probe, NULL, NULL))) return err;
  return unlink(probe) != 0 && errno != ENOENT ? (errno ? errno : EIO) : 0;
}

/*@C
   FSMakeDirectory - Creates an output directory (with its parents, like mkdir -p) and checks that
   every rank can create files in it.

   Collective

   Input Parameters:
+  comm   - communicator; rank 0 creates the directory, then every rank creates and removes a file in it
.  path   - directory to create (an existing directory is fine)
-  option - name of the option that set path (e.g. "-fs_output_dir"), quoted in the error message; may be NULL

   Notes:
   New directories get PetscMkdir()'s mode, rwxr-x--- less the umask. On failure every rank raises
   PETSC_ERR_FILE_OPEN with the directory, the option, the first rank that cannot write there and the system's reason.
   Every rank checks because every rank writes the particles' HDF5 files: a directory that one node sees read-only
   (another mount, a mount namespace) would otherwise leave the others waiting in HDF5's collective open.
@*/
PetscErrorCode FSMakeDirectory(MPI_Comm comm, const char path[], const char option[])
{
  PetscMPIInt rank, size;
  int         err = 0, mine[2], first[2], nbad, bad;

  PetscFunctionBegin;
  PetscCheck(path, comm, PETSC_ERR_ARG_NULL, "FSMakeDirectory: path is required");
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (rank == 0) PetscCall(FSMkdirParents(path, &err));
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot create or write output directory \"%s\"%s%s%s: %s", path,
             option ? " (option " : "", option ? option : "", option ? ")" : "", strerror(err));
  /* every rank, one decision: the lowest rank that cannot write, its reason, and how many cannot */
  err     = FSProbeDirectory(path, rank);
  bad     = err != 0;
  mine[0] = err ? (int)rank : (int)size;
  mine[1] = err;
  PetscCallMPI(MPI_Allreduce(&bad, &nbad, 1, MPI_INT, MPI_SUM, comm));
  if (!nbad) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Allreduce(mine, first, 1, MPI_2INT, MPI_MINLOC, comm)); /* (rank, its errno) */
  SETERRQ(comm, PETSC_ERR_FILE_OPEN,
          "Cannot write output directory \"%s\"%s%s%s on rank %d of %d%s: %s (every rank writes the particle files: "
          "the directory must be writable from every node)",
          path, option ? " (option " : "", option ? option : "", option ? ")" : "", first[0], (int)size,
          nbad > 1 ? " and other ranks" : "", strerror(first[1]));
}

/* ---------------- one run per output directory ---------------- */

#define FS_LOCK_NAME "flexslosh.lock"

struct _n_FSOutputLock {
  int  fd; /* rank 0: the lock file, held with flock() until FSOutputDirUnlock(); -1 elsewhere or unlocked */
  char path[PETSC_MAX_PATH_LEN];
};

/*
   Rank 0: takes <dir>/flexslosh.lock (created if missing, never through a link) with flock(LOCK_EX | LOCK_NB) and
   writes who holds it; 0, EWOULDBLOCK with the holder's line in holder (another run holds it), or another errno value.
   A lock file whose holder ended (a killed run leaves it) is taken over: flock() locks die with their process. The
   holder removes the file when it unlocks: a lock taken on a file that was removed meanwhile is taken again.
*/
static int FSLockTake(const char path[], int *fd, char holder[], size_t len)
{
  holder[0] = '\0';
  for (int attempt = 0; attempt < 16; attempt++) {
    struct stat a, b;
    int         f = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644), err;

    if (f < 0) return errno ? errno : EIO;
    if (fstat(f, &a) != 0) err = errno ? errno : EIO;
    else err = S_ISREG(a.st_mode) ? 0 : EINVAL; /* a pipe or a device planted under the name */
    if (err) {
      (void)close(f);
      return err;
    }
    if (flock(f, LOCK_EX | LOCK_NB) != 0) {
      err = errno ? errno : EIO;
      if (err == EWOULDBLOCK) {
        const ssize_t n               = pread(f, holder, len - 1, 0);
        holder[n > 0 ? n : 0]         = '\0';
        holder[strcspn(holder, "\n")] = '\0';
      }
      (void)close(f);
      return err;
    }
    if (lstat(path, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
      char      host[256] = "", when[64] = "", line[512];
      time_t    now = time(NULL);
      struct tm tm;
      int       n;

      (void)gethostname(host, sizeof(host) - 1);
      if (localtime_r(&now, &tm)) (void)strftime(when, sizeof(when), "%Y-%m-%d %H:%M:%S", &tm);
      n = snprintf(line, sizeof(line), "flexslosh, pid %ld on host %s, started %s\n", (long)getpid(), host, when);
      if (ftruncate(f, 0) != 0 || pwrite(f, line, (size_t)n, 0) != (ssize_t)n) {
        err = errno ? errno : EIO;
        (void)close(f);
        return err;
      }
      *fd = f;
      return 0;
    }
    (void)close(f); /* its holder removed it as it was opened here: take the new one */
  }
  return EAGAIN;
}

/*@C
   FSOutputDirLock - Takes the output directory for this run: one run at a time writes in a directory.

   Collective

   Input Parameters:
+  comm   - communicator; rank 0 holds the lock, the outcome is broadcast
.  dir    - the output directory (made with FSMakeDirectory())
-  option - the option that set dir, for the message; may be NULL

   Output Parameter:
.  lock - the lock, given back with FSOutputDirUnlock()

   Notes:
   The lock is <dir>/flexslosh.lock, held with flock() and removed when unlocked; it holds the holder's process id,
   host and start. A directory locked by another process (another run, or another solver of this process) is
   PETSC_ERR_FILE_OPEN on every rank, naming the directory and the holder. A lock file left by a killed run is free:
   its lock ended with its process. Where the file system has no locks (ENOLCK, ENOSYS, EOPNOTSUPP) a warning says
   that the directory is not protected, and the run goes on.
@*/
PetscErrorCode FSOutputDirLock(MPI_Comm comm, const char dir[], const char option[], FSOutputLock *lock)
{
  FSOutputLock l;
  PetscMPIInt  rank;
  int          err         = 0;
  char         holder[256] = "";

  PetscFunctionBegin;
  PetscCall(PetscNew(&l));
  l->fd = -1;
  PetscCall(PetscSNPrintf(l->path, sizeof(l->path), "%s/" FS_LOCK_NAME, dir));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = FSLockTake(l->path, &l->fd, holder, sizeof(holder));
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  if (err == ENOLCK || err == ENOSYS || err == EOPNOTSUPP) {
    PetscCall(PetscPrintf(comm,
                          "Warning: cannot lock \"%s\" (%s): another run in this directory would not be stopped\n",
                          l->path, strerror(err)));
    err = 0;
  }
  if (err == EWOULDBLOCK) {
    PetscCallMPI(MPI_Bcast(holder, (PetscMPIInt)sizeof(holder), MPI_CHAR, 0, comm));
    PetscCall(PetscFree(l));
    SETERRQ(comm, PETSC_ERR_FILE_OPEN,
            "Output directory \"%s\"%s%s%s is in use by another run (%s; it holds %s/" FS_LOCK_NAME
            "): one run at a time writes in a directory. Wait for it to end, or give this run another %s",
            dir, option ? " (option " : "", option ? option : "", option ? ")" : "",
            holder[0] ? holder : "which has not said who it is yet", dir, option ? option : "directory");
  }
  if (err) PetscCall(PetscFree(l));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot lock output directory \"%s\" with \"%s/" FS_LOCK_NAME "\": %s",
             dir, dir, strerror(err));
  *lock = l;
  PetscFunctionReturn(0);
}

/*@C
   FSOutputDirUnlock - Gives the output directory back: rank 0 removes the lock file, then releases the lock.

   Not collective

   Input Parameter:
.  lock - the lock of FSOutputDirLock() (set to NULL); NULL is fine
@*/
PetscErrorCode FSOutputDirUnlock(FSOutputLock *lock)
{
  PetscFunctionBegin;
  if (!lock || !*lock) PetscFunctionReturn(0);
  if ((*lock)->fd >= 0) {
    (void)unlink((*lock)->path); /* while still held: a run that opened it meanwhile takes a fresh one */
    (void)close((*lock)->fd);
  }
  PetscCall(PetscFree(*lock));
  PetscFunctionReturn(0);
}

/* whether name is "<prefix><digits><suffix>" with at least 6 digits (the writers' numbered files) */
static PetscBool FSNumberedName(const char name[], const char prefix[], const char suffix[])
{
  const size_t lp = strlen(prefix), ls = strlen(suffix), ln = strlen(name);

  if (ln < lp + 6 + ls || strncmp(name, prefix, lp) || strcmp(name + ln - ls, suffix)) return PETSC_FALSE;
  for (size_t k = lp; k < ln - ls; k++)
    if (!isdigit((unsigned char)name[k])) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* the kind of a file that a run writes into its output directory (an index into FSRunFiles), -2 for a probe of
   FSProbeDirectory() left by a killed run, or -1: not a run's file */
static const char *const FSRunFiles[] = {"snapshot_*.h5",  "checkpoint_*.h5", "beam_shape_*.csv", "summary.json",
                                         "timeseries.csv", "energy.csv",      "probes.csv",       "snapshots.csv",
                                         "particles.xdmf", "walls.h5",        "walls.xdmf",       "geometry.png"};
static int               FSRunFileKind(const char entry[])
{
  char   name[256];
  size_t len = strlen(entry);

  if (len >= sizeof(name)) return -1;
  memcpy(name, entry, len + 1);
  if (len > 4 && !strcmp(name + len - 4, ".tmp")) name[len - 4] = '\0'; /* an unfinished write of one */
  if (FSNumberedName(name, "snapshot_", ".h5")) return 0;
  if (FSNumberedName(name, "checkpoint_", ".h5")) return 1;
  if (FSNumberedName(name, "beam_shape_", ".csv")) return 2;
  if (!strncmp(name, ".flexslosh_probe_", 17)) return -2;
  for (size_t k = 3; k < PETSC_STATIC_ARRAY_LENGTH(FSRunFiles); k++)
    if (!strcmp(name, FSRunFiles[k])) return (int)k;
  return -1;
}

/*@C
   FSOutputDirClear - Removes from an output directory what an earlier run wrote there, so that a new run's directory
   holds its results only: the snapshots, checkpoints and beam shapes (snapshot_NNNNNN.h5, checkpoint_NNNNNN.h5,
   beam_shape_NNNNNN.csv), summary.json, the CSVs (timeseries, energy, probes, snapshots), particles.xdmf, walls.h5,
   walls.xdmf, geometry.png, and the "<name>.tmp" of each. Nothing else is touched (other files, folders). Says on
   stdout what it removed.

   Collective; rank 0 removes, the outcome is broadcast

   Input Parameters:
+  comm - communicator
-  dir  - the output directory, locked for this run (FSOutputDirLock())

   Notes:
   A file that cannot be removed is PETSC_ERR_FILE_WRITE on every rank, naming it. A restart (-fs_restart) keeps what
   it continues and does not call this.
@*/
PetscErrorCode FSOutputDirClear(MPI_Comm comm, const char dir[])
{
  PetscMPIInt rank;
  int         st[2]                                        = {0, 0}; /* errno, files removed */
  int         count[PETSC_STATIC_ARRAY_LENGTH(FSRunFiles)] = {0};
  char        failed[PETSC_MAX_PATH_LEN]                   = "";

  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    DIR           *d = opendir(dir);
    struct dirent *e;

    if (!d) st[0] = errno ? errno : EIO;
    while (d && !st[0] && (errno = 0, e = readdir(d))) {
      const int   kind = FSRunFileKind(e->d_name);
      char        path[PETSC_MAX_PATH_LEN];
      struct stat sb;

      if (kind == -1) continue;
      if (snprintf(path, sizeof(path), "%s/%s", dir, e->d_name) >= (int)sizeof(path)) continue;
      if (lstat(path, &sb) != 0 || S_ISDIR(sb.st_mode)) continue; /* a folder of that name is not a run's */
      if (unlink(path) != 0 && errno != ENOENT) {
        st[0] = errno ? errno : EIO;
        (void)snprintf(failed, sizeof(failed), "%s", path);
      } else if (kind >= 0) {
        count[kind]++;
        st[1]++;
      }
    }
    if (d && !st[0] && errno) st[0] = errno;
    if (d) (void)closedir(d);
  }
  PetscCallMPI(MPI_Bcast(st, 2, MPI_INT, 0, comm));
  if (st[0]) {
    PetscCallMPI(MPI_Bcast(failed, (PetscMPIInt)sizeof(failed), MPI_CHAR, 0, comm));
    SETERRQ(comm, PETSC_ERR_FILE_WRITE, "Cannot remove an earlier run's results from output directory \"%s\"%s%s: %s",
            dir, failed[0] ? ", " : "", failed, strerror(st[0]));
  }
  if (!st[1]) PetscFunctionReturn(0);
  PetscCall(PetscPrintf(comm, "Output directory %s: removed the earlier run's results (", dir));
  for (size_t k = 0, n = 0; k < PETSC_STATIC_ARRAY_LENGTH(FSRunFiles); k++) {
    if (!count[k]) continue;
    if (k < 3) PetscCall(PetscPrintf(comm, "%s%d %s", n++ ? ", " : "", count[k], FSRunFiles[k]));
    else PetscCall(PetscPrintf(comm, "%s%s", n++ ? ", " : "", FSRunFiles[k]));
  }
  PetscCall(PetscPrintf(comm, "): a run without -fs_restart starts afresh\n"));
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
