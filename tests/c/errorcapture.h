/* For the C tests of errors: an error handler that keeps the message of the error raised (without its
   traceback), so that a test can check what the message says, not only its code. Push it with
   PetscPushErrorHandler(FSTestCaptureError, &text) around the call expected to fail. */
#pragma once
#include <string.h>
#include <petscsys.h>

typedef struct {
  char text[2048];
} ErrorText;

static inline PetscErrorCode FSTestCaptureError(MPI_Comm comm, int line, const char *func, const char *file,
                                                PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  ErrorText *e = (ErrorText *)ctx;

  (void)comm;
  (void)line;
  (void)func;
  (void)file;
  if (p == PETSC_ERROR_INITIAL && mess) {
    strncpy(e->text, mess, sizeof(e->text) - 1);
    e->text[sizeof(e->text) - 1] = 0;
  }
  return n;
}

/* runs call with the handler above pushed: its error code in ierr, its message in e (an ErrorText) */
#define FS_TEST_CAPTURE(call, e, ierr)                          \
  do {                                                          \
    PetscCall(PetscPushErrorHandler(FSTestCaptureError, &(e))); \
    (ierr) = (call);                                            \
    PetscCall(PetscPopErrorHandler());                          \
  } while (0)
