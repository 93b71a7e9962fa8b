/* The scene file's bytes (scene_impl.h): rank 0 reads the file, up to a size no scene comes near, and broadcasts
   them with the outcome, so that every rank parses the same bytes or fails with the same message. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "scene_impl.h"

/* The largest scene file read: far above any scene (the garment is 10 kB), and a limit for what is not one
   (-scene /dev/zero, a checkpoint given by mistake), which is refused before it fills the memory. */
#define SCENE_MAX_FILE_BYTES (64ll << 20)

/* Rank 0 only, never raises: reads the whole file (up to one byte beyond SCENE_MAX_FILE_BYTES, enough to tell
   that it is too large), or returns the errno of the failure. */
static PetscErrorCode SceneReadFileSerial(const char path[], char **bytes, long long *len, long long *err)
{
  FILE  *fp;
  size_t cap = 1 << 16, n = 0, got;

  PetscFunctionBeginUser;
  *bytes = NULL;
  *len   = 0;
  *err   = 0;
  if (!(fp = fopen(path, "rb"))) {
    *err = errno;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscMalloc1(cap, bytes));
  while (n <= SCENE_MAX_FILE_BYTES && (got = fread(*bytes + n, 1, cap - n, fp)) > 0) {
    n += got;
    if (n == cap) {
      cap *= 2;
      PetscCall(PetscRealloc(cap, bytes));
    }
  }
  if (ferror(fp)) *err = errno ? errno : EIO;
  fclose(fp);
  *len = (long long)n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Collective: every rank gets the file's bytes (NUL-terminated) from rank 0. */
PetscErrorCode SceneReadBytes(MPI_Comm comm, const char path[], char **bytes, size_t *len)
{
  PetscMPIInt rank;
  long long   header[2] = {0, 0}; /* length, errno */
  char       *buf       = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(SceneReadFileSerial(path, &buf, &header[0], &header[1]));
  PetscCallMPI(MPI_Bcast(header, 2, MPI_LONG_LONG, 0, comm));
  if (header[1]) PetscCall(PetscFree(buf));
  PetscCheck(!header[1], comm, PETSC_ERR_FILE_OPEN, "scene %s: cannot read the file (%s): expected a readable YAML scene file", path, strerror((int)header[1]));
  if (header[0] > SCENE_MAX_FILE_BYTES) PetscCall(PetscFree(buf));
  PetscCheck(header[0] <= SCENE_MAX_FILE_BYTES, comm, PETSC_ERR_USER_INPUT, "scene %s: the file is larger than %lld MB: expected a YAML scene file (a few kB)", path, SCENE_MAX_FILE_BYTES >> 20);
  if (rank == 0)
    PetscCall(PetscRealloc((size_t)header[0] + 1, &buf));
  else
    PetscCall(PetscMalloc1((size_t)header[0] + 1, &buf));
  PetscCallMPI(MPI_Bcast(buf, (PetscMPIInt)header[0], MPI_CHAR, 0, comm));
  buf[header[0]] = 0;
  *bytes         = buf;
  *len           = (size_t)header[0];
  PetscFunctionReturn(PETSC_SUCCESS);
}
