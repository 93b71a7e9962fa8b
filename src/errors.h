/* How clothsim ends on an error. A user error (bad scene, option, mesh or checkpoint; a file that cannot be
   read or written; a run that diverged) ends with its message alone, once, on stderr, and a dedicated exit
   status; any other error (a bug) keeps PETSc's full traceback. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* Exit statuses of user errors (README "Exit status"); internal errors exit with PETSc's error code. */
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
