/* A deadline for the collective file writes (frames, checkpoints). Parallel HDF5 can leave every rank waiting
   forever inside one call when a write failed on some ranks only (measured: a disk that filled during a
   checkpoint's metadata flush on 2 ranks, with Open MPI's ROMIO: one rank in a collective write, the other in the
   file's truncation, both inside H5Fflush). No error reaches clothsim and no MPI call can end that wait, so a
   timer (SIGALRM) does: when the process is still inside the write after the deadline, it prints its message,
   removes a temporary file and ends with a status; mpiexec then ends the other ranks. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* The default -io_timeout, s: far beyond a healthy write (a 4.2 M-particle checkpoint of 302 MB takes about 1 s
   here; 600 s is 0.5 MB/s), short against a hung batch job's time limit. */
#define CLOTH_IO_TIMEOUT_DEFAULT 600.0

/* Sets the deadline of every later ClothWatchdogArm, s (0: none). Not collective. */
PetscErrorCode ClothWatchdogSetTimeout(PetscReal seconds);
/* Starts the deadline of a write: past it, the process prints "ERROR: " what " did not finish within S s
   (-io_timeout) ...", removes remove_path (if not NULL) and exits with status. Not collective; not nested. */
PetscErrorCode ClothWatchdogArm(const char what[], const char remove_path[], int status);
/* Ends the deadline started by ClothWatchdogArm. Not collective. */
PetscErrorCode ClothWatchdogDisarm(void);
/* The same for the error handler, which ends the run itself (errors.h). */
void ClothWatchdogCancel(void);
