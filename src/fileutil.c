/* File-system helpers: see fileutil.h. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "fileutil.h"

/* mkdir -p on the calling rank; returns 0 or an errno value. */
static int MakeDirectoryLocal(const char dir[])
{
  char   path[CLOTH_PATH_LEN];
  size_t len = strlen(dir);

  if (len == 0) return 0;
  if (len >= sizeof(path)) return ENAMETOOLONG;
  memcpy(path, dir, len + 1);
  for (char *p = path + 1;; p++) {
    if (*p == '/' || *p == '\0') {
      char        end = *p;
      struct stat st;

      *p = '\0';
      if (mkdir(path, 0777) != 0 && errno != EEXIST) return errno;
      if (stat(path, &st) != 0) return errno;
      if (!S_ISDIR(st.st_mode)) return ENOTDIR;
      *p = end;
      if (end == '\0') break;
    }
  }
  return 0;
}

PetscErrorCode ClothFileMakeDirectory(MPI_Comm comm, const char dir[])
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = MakeDirectoryLocal(dir);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot create directory %s: %s", dir, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFileExists(MPI_Comm comm, const char path[], PetscBool *exists)
{
  PetscMPIInt rank;
  int         found = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    struct stat st;

    found = stat(path, &st) == 0 && S_ISREG(st.st_mode);
  }
  PetscCallMPI(MPI_Bcast(&found, 1, MPI_INT, 0, comm));
  *exists = found ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFileCheckReadable(MPI_Comm comm, const char what[], const char path[], const char in_directory[])
{
  PetscMPIInt rank;
  int         err = 0; /* errno, or -1: a directory, -2: not a regular file */

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    struct stat st;
    FILE       *fp;

    if (stat(path, &st) != 0)
      err = errno;
    else if (S_ISDIR(st.st_mode))
      err = -1;
    else if (!S_ISREG(st.st_mode))
      err = -2;
    else if (!(fp = fopen(path, "rb")))
      err = errno;
    else
      fclose(fp);
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(err != -1, comm, PETSC_ERR_FILE_OPEN, "%s %s is a directory: expected a file (%s)", what, path, in_directory);
  PetscCheck(err != -2, comm, PETSC_ERR_FILE_OPEN, "%s %s is not a regular file: expected a file (%s)", what, path, in_directory);
  PetscCheck(err != ENOENT, comm, PETSC_ERR_FILE_OPEN, "%s %s does not exist", what, path);
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "%s %s cannot be read: %s", what, path, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFileRename(MPI_Comm comm, const char from[], const char to[])
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Barrier(comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0 && rename(from, to) != 0) err = errno;
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot rename %s to %s: %s", from, to, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}
