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
/* Claims dir for this run: rank 0 takes a write lock (fcntl) on dir/.clothsim.lock, held until
   ClothFileUnlockDirectory or the process ends (also by a crash or SIGKILL, so a lock is never stale), and
   writes into it who holds it: holder (e.g. the scene), the pid, host and start time. Errors naming the holder
   when another live run holds it; warns and goes on without a lock where the file system has no locks.
   *fd: the lock's descriptor on rank 0, -1 elsewhere. */
PetscErrorCode ClothFileLockDirectory(MPI_Comm comm, const char dir[], const char holder[], int *fd);
/* Releases the lock of ClothFileLockDirectory (NULL-safe on fd < 0). Not collective. */
PetscErrorCode ClothFileUnlockDirectory(int *fd);
/* Opens tmp for writing on rank 0 (*fp NULL elsewhere) for PetscFPrintf(comm, fp, ...); errors on every rank,
   naming tmp and the OS reason, when it cannot (PetscFOpen fails on rank 0 alone, without the reason). */
PetscErrorCode ClothFileOpenText(MPI_Comm comm, const char tmp[], FILE **fp);
/* Closes a text file that ClothFileOpenText opened (written on rank 0), checking every write (a full
   disk shows only when the buffer is flushed) and syncing it, then renames tmp onto path. On a write error
   tmp is removed and path left as it was; the error names the file and the OS reason (ENOSPC). */
PetscErrorCode ClothFileCommitText(MPI_Comm comm, FILE *fp, const char tmp[], const char path[]);
/* Errors (naming what, dir and the sizes) when the file system of dir has less than bytes free for an
   unprivileged user, before anything is written: a full disk found half-way through an HDF5 write leaves
   only "H5Dwrite failed". */
PetscErrorCode ClothFileCheckSpace(MPI_Comm comm, const char dir[], double bytes, const char what[]);
/* After a barrier (everyone has finished writing from), atomically renames from to to (rename(2)),
   replacing to if it exists. */
PetscErrorCode ClothFileRename(MPI_Comm comm, const char from[], const char to[]);
