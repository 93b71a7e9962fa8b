/* How clothsim ends on an error: see errors.h. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "errors.h"
#include "watchdog.h"

/* How long a failing rank waits for the others to fail too before it aborts them: long enough for ranks
   that raise the same collective error on a loaded machine, short against a run that would hang. */
#define CLOTH_ERROR_WAIT_SECONDS 10.0

/* A duplicate of PETSC_COMM_WORLD for the handler's barrier alone, so that it never matches a collective
   that the other ranks are in. */
static MPI_Comm ClothErrorComm = MPI_COMM_NULL;

/* The exit status of a user error, or 0 for an internal error. PETSc's own option parser reports a
   malformed value (-dt abc, -cloth_partition foo) as an argument error raised in its options code, and a
   misspelled type (-ksp_type foo) as an unknown type. */
static int ClothErrorExitStatus(PetscErrorCode n, const char file[])
{
  const char *base       = file ? strrchr(file, '/') : NULL;
  const int   in_options = base && (!strcmp(base, "/options.c") || !strcmp(base, "/aoptions.c"));

  switch (n) {
  case PETSC_ERR_USER_INPUT:
    return CLOTH_EXIT_INPUT;
  case PETSC_ERR_FILE_OPEN:
  case PETSC_ERR_FILE_READ:
  case PETSC_ERR_FILE_WRITE:
  case PETSC_ERR_FILE_UNEXPECTED:
    return CLOTH_EXIT_FILE;
  case PETSC_ERR_NOT_CONVERGED:
    return CLOTH_EXIT_DIVERGED;
  case PETSC_ERR_ARG_UNKNOWN_TYPE:
    return CLOTH_EXIT_INPUT;
  case PETSC_ERR_ARG_OUTOFRANGE:
  case PETSC_ERR_ARG_WRONG:
  case PETSC_ERR_USER:
    return in_options ? CLOTH_EXIT_INPUT : 0;
  default:
    return 0;
  }
}

/* Polls request for up to CLOTH_ERROR_WAIT_SECONDS; whether it completed. */
static int ClothErrorWaitBriefly(MPI_Request *request)
{
  const double          start = MPI_Wtime();
  const struct timespec pause = {0, 1000000}; /* 1 ms between polls: a failed rank must not steal the cores */
  int                   done  = 0;

  while (!done && MPI_Wtime() - start < CLOTH_ERROR_WAIT_SECONDS) {
    if (MPI_Test(request, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) break;
    if (!done) nanosleep(&pause, NULL);
  }
  return done;
}

static void ClothErrorPrint(const char mess[])
{
  size_t len = mess ? strlen(mess) : 0;

  while (len > 0 && (mess[len - 1] == '\n' || mess[len - 1] == ' ')) len--;
  fflush(stdout);
  fprintf(stderr, "ERROR: %.*s\n", (int)len, mess ? mess : "");
  fflush(stderr);
}

/* Ends the run after a user error on this rank; does not return. When every rank has failed (a collective
   error, the usual case) rank 0 alone prints the message and all finalize MPI; when the others have not
   failed within CLOTH_ERROR_WAIT_SECONDS, this rank prints its message and aborts them. */
static void ClothErrorEnd(int status, const char mess[])
{
  MPI_Request request;
  int         all_failed = 0, rank = 0;

  ClothWatchdogCancel(); /* this ends the run, with its own deadline */
  MPI_Comm_rank(ClothErrorComm, &rank);
  if (MPI_Ibarrier(ClothErrorComm, &request) == MPI_SUCCESS) all_failed = ClothErrorWaitBriefly(&request);
  if (!all_failed || rank == 0) ClothErrorPrint(mess);
  if (!all_failed) MPI_Abort(MPI_COMM_WORLD, status);
  MPI_Finalize();
  exit(status);
}

PetscErrorCode ClothAgreeOnFailure(MPI_Comm agree, PetscBool failed, const char message[], int status, const char remove_path[], PetscBool *any_failed)
{
  MPI_Request request;
  int         local = failed ? 1 : 0, any = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Iallreduce(&local, &any, 1, MPI_INT, MPI_LOR, agree, &request));
  if (!failed)
    PetscCallMPI(MPI_Wait(&request, MPI_STATUS_IGNORE));
  else if (!ClothErrorWaitBriefly(&request)) {
    if (remove_path) (void)remove(remove_path);
    ClothErrorPrint(message);
    MPI_Abort(MPI_COMM_WORLD, status);
  }
  *any_failed = any ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothErrorHandler(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  const int status = ClothErrorExitStatus(n, file);

  if (status && p == PETSC_ERROR_INITIAL) ClothErrorEnd(status, mess);
  return PetscTraceBackErrorHandler(comm, line, func, file, n, p, mess, ctx);
}

PetscErrorCode ClothErrorHandlerPush(void)
{
  PetscFunctionBeginUser;
  if (ClothErrorComm == MPI_COMM_NULL) PetscCallMPI(MPI_Comm_dup(PETSC_COMM_WORLD, &ClothErrorComm));
  PetscCall(PetscPushErrorHandler(ClothErrorHandler, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}
