/* For the C tests that write files: the folder they made under /tmp (mkdtemp) removed with all it holds
   when the test ends, so that test runs leave nothing behind. */
#pragma once
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <petscsys.h>

/* removes dir and everything below it (symbolic links are removed, not followed) */
static inline PetscErrorCode FSTestRemoveTree(const char dir[])
{
  DIR           *d = opendir(dir);
  struct dirent *e;
  char           path[PETSC_MAX_PATH_LEN];
  struct stat    st;

  PetscFunctionBegin;
  PetscCheck(d, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open the folder %s", dir);
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s", dir, e->d_name));
    if (!lstat(path, &st) && S_ISDIR(st.st_mode)) PetscCall(FSTestRemoveTree(path));
    else PetscCheck(!remove(path), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot remove %s", path);
  }
  closedir(d);
  PetscCheck(!rmdir(dir), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot remove the folder %s", dir);
  PetscFunctionReturn(0);
}
