/* How clothsim ends on an error. A user error (bad scene, option, mesh or checkpoint; a file that cannot be
   read or written; a run that diverged) ends with its message alone, once, on stderr, and a dedicated exit
   status; any other error (a bug) keeps PETSc's full traceback. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* Exit statuses of user errors (docs/guide.md, "Errors and exit status"); internal errors exit with PETSc's error code. */
typedef enum {
  CLOTH_EXIT_INPUT    = 2, /* bad scene, option, mesh, checkpoint or output directory (PETSC_ERR_USER_INPUT, ...) */
  CLOTH_EXIT_FILE     = 3, /* a file could not be read or written (PETSC_ERR_FILE_*): missing, disk full, ... */
  CLOTH_EXIT_DIVERGED = 4  /* a step failed even at the smallest step (PETSC_ERR_NOT_CONVERGED) */
} ClothExitStatus;

/* Pushes the handler that ends user errors with one message and a ClothExitStatus. Collective on
   PETSC_COMM_WORLD (it duplicates it for its own use); call once, after PetscInitialize. An error raised
   on some ranks only still ends the whole run: a rank that waits more than a few seconds for the others
   to fail too aborts them (MPI_Abort). */
PetscErrorCode ClothErrorHandlerPush(void);
/* Whether any rank of agree failed, where a rank that failed may have left the others inside a collective call
   that now waits for it forever (an HDF5 write that failed on one rank only, measured with ROMIO on a full disk).
   A failed rank waits a few seconds for the others; when they do not come it removes remove_path (if not NULL),
   prints "ERROR: message" and aborts the run with status (MPI_Abort). agree must be a communicator used for
   nothing else, duplicated before the collective calls began. Collective on agree. */
PetscErrorCode ClothAgreeOnFailure(MPI_Comm agree, PetscBool failed, const char message[], int status, const char remove_path[], PetscBool *any_failed);
