/* File-system helpers for the I/O modules: rank 0 acts, every rank learns the outcome, so that all
   ranks take the same error path. All functions are collective on comm. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* Creates dir and its missing parents (mkdir -p); an existing directory is fine. */
PetscErrorCode ClothFileMakeDirectory(MPI_Comm comm, const char dir[]);
/* Whether path names an existing regular file (or a link to one). */
PetscErrorCode ClothFileExists(MPI_Comm comm, const char path[], PetscBool *exists);
/* Errors unless path names a regular file (or a link to one) that rank 0 can open for reading; the message
   starts with what (e.g. "Checkpoint") and says why: missing, a directory (suggesting expected, e.g.
   "a checkpoint_NNNNNN.h5 in it"), or the OS reason. */
PetscErrorCode ClothFileCheckReadable(MPI_Comm comm, const char what[], const char path[], const char in_directory[]);
/* After a barrier (everyone has finished writing from), atomically renames from to to (rename(2)),
   replacing to if it exists. */
PetscErrorCode ClothFileRename(MPI_Comm comm, const char from[], const char to[]);
