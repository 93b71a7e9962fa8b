/* Checkpoints: see checkpoint.h.

   File layout, group /state:
     datasets  position, velocity        (N, 3) float64, natural particle order
     attributes format_version (int64), step (int64), time, dt (float64), integrator, scene_name (string),
                scene_fingerprint, nparticles, nranks (int64, the ranks that wrote it),
                code_version, git_revision (string),
                checksum (uint64, see CheckpointChecksum), checksum_method (string),
                complete (int64 = 1, written last: the end marker). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "checkpoint.h"
#include "fileutil.h"
#include "h5util.h"

#ifndef CLOTHSIM_VERSION
#define CLOTHSIM_VERSION "unknown"
#endif
#ifndef CLOTHSIM_GIT_REVISION
#define CLOTHSIM_GIT_REVISION "unknown"
#endif

#define CHECKPOINT_FORMAT_VERSION 1
#define CHECKPOINT_CHECKSUM_METHOD "xor over entries k of splitmix64(bits(value_k) ^ splitmix64(k)), k = 3*particle+component, velocity after position"

/* Attributes every checkpoint of this format carries (besides the end marker). */
static const char *const CheckpointAttributes[] = {"format_version", "step", "time", "dt", "integrator", "scene_name", "scene_fingerprint", "nparticles", "checksum"};

/* Why a checkpoint is refused; code 0 when it is accepted. */
typedef struct {
  PetscErrorCode code;
  char           reason[512];
} CheckpointRefusal;

static uint64_t SplitMix64(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/* XORs into *sum the hash of every local entry of v, entry k (global index) keyed by offset + k. */
static PetscErrorCode VecChecksumLocal(Vec v, PetscInt64 offset, uint64_t *sum)
{
  const PetscScalar *array;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecGetArrayRead(v, &array));
  for (PetscInt i = 0; i < hi - lo; i++) {
    uint64_t bits;

    memcpy(&bits, &array[i], sizeof(bits));
    *sum ^= SplitMix64(bits ^ SplitMix64((uint64_t)(offset + lo + i)));
  }
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A checksum of the exact bits of the state that is the same for any partition of the Vecs: the
   per-entry hashes (keyed by global index) are combined by XOR, which is exact and order-free. */
static PetscErrorCode CheckpointChecksum(MPI_Comm comm, Vec position, Vec velocity, uint64_t *checksum)
{
  uint64_t local = 0;
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(position, &n));
  PetscCall(VecChecksumLocal(position, 0, &local));
  PetscCall(VecChecksumLocal(velocity, n, &local));
  PetscCallMPI(MPI_Allreduce(&local, checksum, 1, MPI_UINT64_T, MPI_BXOR, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The particle count of a state (position, velocity), checking that both hold whole particles. */
static PetscErrorCode CheckpointParticleCount(Vec position, Vec velocity, PetscInt64 *nparticles)
{
  PetscInt np, nv;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(position, &np));
  PetscCall(VecGetSize(velocity, &nv));
  PetscCheck(np == nv && np % 3 == 0, PetscObjectComm((PetscObject)position), PETSC_ERR_ARG_SIZ, "Position (%" PetscInt_FMT ") and velocity (%" PetscInt_FMT ") must have the same size, 3 per particle", np, nv);
  *nparticles = np / 3;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckpointWriteAttributes(MPI_Comm comm, hid_t state, const ClothCheckpointInfo *info, PetscInt64 nparticles)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(ClothH5AttributeWriteInt64(state, "format_version", CHECKPOINT_FORMAT_VERSION));
  PetscCall(ClothH5AttributeWriteInt64(state, "step", info->step));
  PetscCall(ClothH5AttributeWriteReal(state, "time", info->time));
  PetscCall(ClothH5AttributeWriteReal(state, "dt", info->dt));
  PetscCall(ClothH5AttributeWriteString(state, "integrator", info->integrator));
  PetscCall(ClothH5AttributeWriteString(state, "scene_name", info->scene_name));
  PetscCall(ClothH5AttributeWriteInt64(state, "scene_fingerprint", info->scene_fingerprint));
  PetscCall(ClothH5AttributeWriteInt64(state, "nparticles", nparticles));
  PetscCall(ClothH5AttributeWriteInt64(state, "nranks", size));
  PetscCall(ClothH5AttributeWriteString(state, "code_version", CLOTHSIM_VERSION));
  PetscCall(ClothH5AttributeWriteString(state, "git_revision", CLOTHSIM_GIT_REVISION));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes the whole checkpoint into an open file; the end marker goes last, after a flush. */
static PetscErrorCode CheckpointWriteFile(MPI_Comm comm, hid_t file, const ClothCheckpointInfo *info, Vec position, Vec velocity)
{
  hid_t      state;
  PetscInt64 nparticles;
  uint64_t   checksum;

  PetscFunctionBeginUser;
  PetscCall(CheckpointParticleCount(position, velocity, &nparticles));
  PetscCheck(info->nparticles == 0 || info->nparticles == nparticles, comm, PETSC_ERR_ARG_SIZ, "Checkpoint info says %" PetscInt64_FMT " particles, the state holds %" PetscInt64_FMT, info->nparticles, nparticles);
  PetscCall(CheckpointChecksum(comm, position, velocity, &checksum));
  ClothCallHDF5(state = H5Gcreate2(file, "/state", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(CheckpointWriteAttributes(comm, state, info, nparticles));
  PetscCall(ClothH5WriteVec(state, "position", position, 3));
  PetscCall(ClothH5WriteVec(state, "velocity", velocity, 3));
  PetscCall(ClothH5AttributeWriteUInt64(state, "checksum", checksum));
  PetscCall(ClothH5AttributeWriteString(state, "checksum_method", CHECKPOINT_CHECKSUM_METHOD));
  ClothCallHDF5(H5Fflush(file, H5F_SCOPE_GLOBAL));
  PetscCall(ClothH5AttributeWriteInt64(state, "complete", 1));
  ClothCallHDF5(H5Gclose(state));
  ClothCallHDF5(H5Fflush(file, H5F_SCOPE_GLOBAL)); /* MPI_File_sync: on disk before the rename */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Step of a file named checkpoint_<digits>.h5; returns 0 for any other name. */
static int CheckpointNameStep(const char name[], PetscInt64 *step)
{
  const char *digits = name + strlen("checkpoint_");
  char       *end;

  if (strncmp(name, "checkpoint_", strlen("checkpoint_")) != 0 || *digits < '0' || *digits > '9') return 0;
  errno = 0;
  *step = (PetscInt64)strtoll(digits, &end, 10);
  return errno == 0 && strcmp(end, ".h5") == 0;
}

static int CompareInt64Descending(const void *a, const void *b)
{
  PetscInt64 x = *(const PetscInt64 *)a, y = *(const PetscInt64 *)b;

  return (x < y) - (x > y);
}

/* Rank 0 only, hence plain C that reports an errno value instead of raising a PETSc error (which would
   leave the other ranks waiting): deletes checkpoint_*.h5 in dir with step <= newest beyond the
   `keep` latest of them. Checkpoints after `newest` (left by an earlier run that went further) are
   not this run's to delete. */
static int CheckpointRemoveOldLocal(const char dir[], PetscInt64 newest, PetscInt keep)
{
  DIR           *d;
  struct dirent *entry;
  PetscInt64    *steps = NULL, step;
  size_t         n = 0, cap = 0;
  int            err = 0;

  if (!(d = opendir(dir))) return errno;
  while (!err && (entry = readdir(d))) {
    if (!CheckpointNameStep(entry->d_name, &step) || step > newest) continue;
    if (n == cap) {
      PetscInt64 *grown = realloc(steps, (cap = 2 * cap + 16) * sizeof(*steps));

      if (!grown)
        err = ENOMEM;
      else
        steps = grown;
    }
    if (!err) steps[n++] = step;
  }
  closedir(d);
  if (n) qsort(steps, n, sizeof(*steps), CompareInt64Descending);
  for (size_t i = (size_t)keep; !err && i < n; i++) {
    char path[CLOTH_PATH_LEN];

    snprintf(path, sizeof(path), "%s/checkpoint_%06" PetscInt64_FMT ".h5", dir, steps[i]);
    if (remove(path) != 0 && errno != ENOENT) err = errno;
  }
  free(steps);
  return err;
}

static PetscErrorCode CheckpointRemoveOld(MPI_Comm comm, const char dir[], PetscInt64 newest, PetscInt keep)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = CheckpointRemoveOldLocal(dir, newest, keep);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot remove old checkpoints in %s: %s", dir, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointWrite(MPI_Comm comm, const char dir[], const ClothCheckpointInfo *info, Vec position, Vec velocity, PetscInt keep, char path_out[], size_t path_len)
{
  char  path[CLOTH_PATH_LEN], tmp[CLOTH_PATH_LEN];
  hid_t file;

  PetscFunctionBeginUser;
  PetscCheck(info->step >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Checkpoint step %" PetscInt64_FMT " must be >= 0", info->step);
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/checkpoint_%06" PetscInt64_FMT ".h5", dir, info->step));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s/.checkpoint_%06" PetscInt64_FMT ".h5.tmp", dir, info->step));
  PetscCall(ClothFileMakeDirectory(comm, dir));
  PetscCall(ClothH5FileCreate(comm, tmp, &file));
  PetscCall(CheckpointWriteFile(comm, file, info, position, velocity));
  PetscCall(ClothH5FileClose(&file));
  PetscCall(ClothFileRename(comm, tmp, path));
  if (keep > 0) PetscCall(CheckpointRemoveOld(comm, dir, info->step, keep));
  if (path_out) PetscCall(PetscStrncpy(path_out, path, path_len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckpointRefuse(CheckpointRefusal *refusal, PetscErrorCode code, const char reason[])
{
  PetscFunctionBeginUser;
  refusal->code = code;
  PetscCall(PetscStrncpy(refusal->reason, reason, sizeof(refusal->reason)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks the end marker and the attributes' presence, then reads them into info. */
static PetscErrorCode CheckpointReadInfo(hid_t state, ClothCheckpointInfo *info, CheckpointRefusal *refusal)
{
  PetscBool  exists = PETSC_FALSE;
  PetscInt64 format;
  char       reason[256];

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeExists(state, "complete", &exists));
  if (!exists) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, "has no end marker (attribute /state/complete): it was not completely written"));
  for (size_t i = 0; exists && i < PETSC_STATIC_ARRAY_LENGTH(CheckpointAttributes); i++) {
    PetscCall(ClothH5AttributeExists(state, CheckpointAttributes[i], &exists));
    if (exists) continue;
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "lacks the attribute /state/%s: it is not a clothsim checkpoint of format %d", CheckpointAttributes[i], CHECKPOINT_FORMAT_VERSION));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  }
  if (refusal->code) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothH5AttributeReadInt64(state, "format_version", &format));
  if (format != CHECKPOINT_FORMAT_VERSION) {
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "is in checkpoint format %" PetscInt64_FMT "; this clothsim reads format %d", format, CHECKPOINT_FORMAT_VERSION));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(ClothH5AttributeReadInt64(state, "step", &info->step));
  PetscCall(ClothH5AttributeReadReal(state, "time", &info->time));
  PetscCall(ClothH5AttributeReadReal(state, "dt", &info->dt));
  PetscCall(ClothH5AttributeReadString(state, "integrator", info->integrator, sizeof(info->integrator)));
  PetscCall(ClothH5AttributeReadString(state, "scene_name", info->scene_name, sizeof(info->scene_name)));
  PetscCall(ClothH5AttributeReadInt64(state, "scene_fingerprint", &info->scene_fingerprint));
  PetscCall(ClothH5AttributeReadInt64(state, "nparticles", &info->nparticles));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks that the checkpoint fits this run: its particle count and its scene. */
static PetscErrorCode CheckpointCheckScene(const ClothCheckpointInfo *info, const ClothCheckpointInfo *expect, PetscInt64 nparticles, CheckpointRefusal *refusal)
{
  char reason[512];

  PetscFunctionBeginUser;
  if (expect && info->scene_fingerprint != expect->scene_fingerprint) {
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "was written for scene '%s' (fingerprint %" PetscInt64_FMT "), not this scene '%s' (fingerprint %" PetscInt64_FMT ")", info->scene_name, info->scene_fingerprint, expect->scene_name,
                            expect->scene_fingerprint));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  } else if (info->nparticles != nparticles) {
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "holds %" PetscInt64_FMT " particles, the scene has %" PetscInt64_FMT, info->nparticles, nparticles));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads the datasets and compares their checksum with the stored one. */
static PetscErrorCode CheckpointReadState(MPI_Comm comm, hid_t state, Vec position, Vec velocity, CheckpointRefusal *refusal)
{
  uint64_t stored, computed;
  char     reason[256];

  PetscFunctionBeginUser;
  PetscCall(ClothH5ReadVec(state, "position", position, 3));
  PetscCall(ClothH5ReadVec(state, "velocity", velocity, 3));
  PetscCall(ClothH5AttributeReadUInt64(state, "checksum", &stored));
  PetscCall(CheckpointChecksum(comm, position, velocity, &computed));
  PetscCall(PetscSNPrintf(reason, sizeof(reason), "is corrupt: the checksum of its data is %016llx, it was written with %016llx", (unsigned long long)computed, (unsigned long long)stored));
  if (computed != stored) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_READ, reason));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads and checks everything in an open file; the first problem found ends up in refusal. Every
   check is made on data that all ranks hold alike, so all ranks reach the same verdict. */
static PetscErrorCode CheckpointReadFile(MPI_Comm comm, hid_t file, const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, Vec position, Vec velocity, CheckpointRefusal *refusal)
{
  PetscBool  exists = PETSC_FALSE;
  hid_t      state;
  PetscInt64 nparticles;

  PetscFunctionBeginUser;
  PetscCall(CheckpointParticleCount(position, velocity, &nparticles));
  PetscCall(ClothH5LinkExists(file, "state", &exists));
  if (!exists) {
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, "has no group /state: it is not a clothsim checkpoint"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  ClothCallHDF5(state = H5Gopen2(file, "state", H5P_DEFAULT));
  PetscCall(CheckpointReadInfo(state, info, refusal));
  if (!refusal->code) PetscCall(CheckpointCheckScene(info, expect, nparticles, refusal));
  if (!refusal->code) PetscCall(CheckpointReadState(comm, state, position, velocity, refusal));
  ClothCallHDF5(H5Gclose(state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointRead(MPI_Comm comm, const char path[], const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, Vec position, Vec velocity)
{
  PetscBool           exists = PETSC_FALSE, opened = PETSC_FALSE;
  hid_t               file;
  ClothCheckpointInfo found;
  CheckpointRefusal   refusal = {0, ""};

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&found, sizeof(found)));
  PetscCall(ClothFileExists(comm, path, &exists));
  PetscCheck(exists, comm, PETSC_ERR_FILE_OPEN, "Checkpoint %s does not exist", path);
  PetscCall(ClothH5FileOpen(comm, path, H5F_ACC_RDONLY, &file, &opened));
  PetscCheck(opened, comm, PETSC_ERR_FILE_READ, "Checkpoint %s cannot be opened as an HDF5 file: it is truncated or not a checkpoint", path);
  PetscCall(CheckpointReadFile(comm, file, expect, &found, position, velocity, &refusal));
  PetscCall(ClothH5FileClose(&file));
  PetscCheck(!refusal.code, comm, refusal.code, "Checkpoint %s %s", path, refusal.reason);
  if (info) *info = found;
  PetscFunctionReturn(PETSC_SUCCESS);
}
