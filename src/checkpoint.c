/* Checkpoints: see checkpoint.h and docs/checkpoint.md.

   File layout, group /state:
     datasets   position, velocity, and the further fields of the writer (implicit_dv), each (N, bs)
                float64 in natural particle order, each with the attribute checksum (uint64, see
                VecChecksum)
     attributes format_version (int64), step (int64), time, dt (float64), dt_start_step (int64),
                dt_start_time (float64), integrator, scene_name (string), scene_fingerprint,
                nparticles, nranks (int64, the ranks that wrote it), code_version, git_revision
                (string), checksum_method (string), info_checksum (uint64, see
                CheckpointInfoChecksum), run_id (uint64, optional: the run that wrote it), history_dt
                (float64, optional: the step of bdf2's history in bdf2_history_*), complete
                (int64 = 1, written last: the end marker). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "checkpoint.h"
#include "errors.h"
#include "fileutil.h"
#include "h5util.h"
#include "provenance.h"
#include "watchdog.h"

#define CHECKPOINT_FORMAT_VERSION 2
#define CHECKPOINT_CHECKSUM_METHOD "per dataset: xor over entries k of splitmix64(bits(value_k) ^ splitmix64(k)), k = bs*particle+component"

/* Attributes every checkpoint of this format carries (besides the end marker). */
static const char *const CheckpointAttributes[] = {"format_version", "step", "time", "dt", "dt_start_step", "dt_start_time", "integrator", "scene_name", "scene_fingerprint", "nparticles", "info_checksum"};

/* Why a checkpoint is refused; code 0 when it is accepted. */
typedef struct {
  PetscErrorCode code;
  char           reason[1024];
} CheckpointRefusal;

static uint64_t SplitMix64(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/* Folds n bytes into the running hash h, 8 at a time (the tail zero-padded). */
static uint64_t HashBytes(uint64_t h, const void *bytes, size_t n)
{
  for (size_t i = 0; i < n; i += 8) {
    uint64_t word = 0;

    memcpy(&word, (const char *)bytes + i, PetscMin(8, n - i));
    h = SplitMix64(h ^ word);
  }
  return h;
}

/* A checksum of the attributes that a restart takes over (step, time, dt, its start, integrator, scene
   fingerprint, particle count and, when there is one, the history's step), so that a damaged attribute is refused like
   damaged data. */
static uint64_t CheckpointInfoChecksum(const ClothCheckpointInfo *info, PetscInt64 nparticles)
{
  const double  reals[3] = {(double)info->time, (double)info->dt, (double)info->dt_start_time};
  const int64_t ints[4]  = {(int64_t)info->step, (int64_t)info->dt_start_step, (int64_t)info->scene_fingerprint, (int64_t)nparticles};
  uint64_t      h        = 0;

  h = HashBytes(h, reals, sizeof(reals));
  h = HashBytes(h, ints, sizeof(ints));
  if (info->history_dt > 0) { /* only then written: files without it keep their checksum */
    const double history_dt = (double)info->history_dt;
    h                       = HashBytes(h, &history_dt, sizeof(history_dt));
  }
  return HashBytes(h, info->integrator, strlen(info->integrator));
}

/* A checksum of the exact bits of a Vec that is the same for any partition of it: the per-entry
   hashes (keyed by global index) are combined by XOR, which is exact and order-free. Collective. */
static PetscErrorCode VecChecksum(Vec v, uint64_t *checksum)
{
  const PetscScalar *array;
  PetscInt           lo, hi;
  uint64_t           local = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecGetArrayRead(v, &array));
  for (PetscInt i = 0; i < hi - lo; i++) {
    uint64_t bits;

    memcpy(&bits, &array[i], sizeof(bits));
    local ^= SplitMix64(bits ^ SplitMix64((uint64_t)(lo + i)));
  }
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscCallMPI(MPI_Allreduce(&local, checksum, 1, MPI_UINT64_T, MPI_BXOR, PetscObjectComm((PetscObject)v)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The particle count of one field (its rows: global size over block size). */
static PetscErrorCode CheckpointFieldRows(const ClothCheckpointField *field, PetscInt64 *rows)
{
  PetscInt n, bs;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(field->vec, &n));
  PetscCall(VecGetBlockSize(field->vec, &bs));
  *rows = n / bs;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The particle count of a set of fields, checking that they all have it and that position and
   velocity are among them. */
static PetscErrorCode CheckpointParticleCount(MPI_Comm comm, PetscInt nfields, const ClothCheckpointField fields[], PetscInt64 *nparticles)
{
  PetscBool has_position = PETSC_FALSE, has_velocity = PETSC_FALSE, same;

  PetscFunctionBeginUser;
  PetscCheck(nfields > 0, comm, PETSC_ERR_ARG_SIZ, "A checkpoint needs at least the fields position and velocity");
  PetscCall(CheckpointFieldRows(&fields[0], nparticles));
  for (PetscInt f = 0; f < nfields; f++) {
    PetscInt64 rows;

    PetscCall(CheckpointFieldRows(&fields[f], &rows));
    PetscCheck(rows == *nparticles, comm, PETSC_ERR_ARG_SIZ, "Checkpoint field %s has %" PetscInt64_FMT " rows, field %s has %" PetscInt64_FMT, fields[f].name, rows, fields[0].name, *nparticles);
    PetscCall(PetscStrcmp(fields[f].name, "position", &same));
    has_position = (PetscBool)(has_position || same);
    PetscCall(PetscStrcmp(fields[f].name, "velocity", &same));
    has_velocity = (PetscBool)(has_velocity || same);
  }
  PetscCheck(has_position && has_velocity, comm, PETSC_ERR_ARG_WRONG, "A checkpoint needs the fields position and velocity");
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
  PetscCall(ClothH5AttributeWriteInt64(state, "dt_start_step", info->dt_start_step));
  PetscCall(ClothH5AttributeWriteReal(state, "dt_start_time", info->dt_start_time));
  PetscCall(ClothH5AttributeWriteString(state, "integrator", info->integrator));
  if (info->history_dt > 0) PetscCall(ClothH5AttributeWriteReal(state, "history_dt", info->history_dt));
  PetscCall(ClothH5AttributeWriteString(state, "scene_name", info->scene_name));
  PetscCall(ClothH5AttributeWriteInt64(state, "scene_fingerprint", info->scene_fingerprint));
  PetscCall(ClothH5AttributeWriteInt64(state, "nparticles", nparticles));
  PetscCall(ClothH5AttributeWriteInt64(state, "nranks", size));
  PetscCall(ClothProvenanceWrite(comm, state, info->scene));
  PetscCall(ClothH5AttributeWriteString(state, "checksum_method", CHECKPOINT_CHECKSUM_METHOD));
  PetscCall(ClothH5AttributeWriteUInt64(state, "info_checksum", CheckpointInfoChecksum(info, nparticles)));
  if (info->run_id) PetscCall(ClothH5AttributeWriteUInt64(state, "run_id", info->run_id));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes one field as /state/<name> with its checksum attribute. */
static PetscErrorCode CheckpointWriteField(hid_t state, const ClothCheckpointField *field)
{
  PetscInt bs;
  uint64_t checksum;
  hid_t    dset;

  PetscFunctionBeginUser;
  PetscCall(VecGetBlockSize(field->vec, &bs));
  PetscCall(VecChecksum(field->vec, &checksum));
  PetscCall(ClothH5WriteVec(state, field->name, field->vec, bs));
  ClothCallHDF5(dset = H5Dopen2(state, field->name, H5P_DEFAULT));
  PetscCall(ClothH5AttributeWriteUInt64(dset, "checksum", checksum));
  ClothCallHDF5(H5Dclose(dset));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes the whole checkpoint into an open file; the end marker goes last, after a flush. */
static PetscErrorCode CheckpointWriteFile(MPI_Comm comm, hid_t file, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  hid_t      state;
  PetscInt64 nparticles;

  PetscFunctionBeginUser;
  PetscCall(CheckpointParticleCount(comm, nfields, fields, &nparticles));
  PetscCheck(info->nparticles == 0 || info->nparticles == nparticles, comm, PETSC_ERR_ARG_SIZ, "Checkpoint info says %" PetscInt64_FMT " particles, the state holds %" PetscInt64_FMT, info->nparticles, nparticles);
  ClothCallHDF5(state = H5Gcreate2(file, "/state", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(CheckpointWriteAttributes(comm, state, info, nparticles));
  for (PetscInt f = 0; f < nfields; f++) PetscCall(CheckpointWriteField(state, &fields[f]));
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

/* Rank 0 only: whether the checkpoint at path was written by run run_id (its attribute /state/run_id), read
   serially with HDF5's errors silenced; a file without it (another run's, or an older clothsim's) is not. */
static PetscBool CheckpointOfRun(const char path[], uint64_t run_id)
{
  H5E_auto2_t print_errors;
  void       *print_errors_data;
  uint64_t    id   = 0;
  hid_t       file = -1, attr = -1;

  if (H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data) < 0 || H5Eset_auto2(H5E_DEFAULT, NULL, NULL) < 0) return PETSC_FALSE;
  if ((file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT)) >= 0 && H5Aexists_by_name(file, "state", "run_id", H5P_DEFAULT) > 0 && (attr = H5Aopen_by_name(file, "state", "run_id", H5P_DEFAULT, H5P_DEFAULT)) >= 0 &&
      H5Aread(attr, H5T_NATIVE_UINT64, &id) < 0)
    id = 0;
  if (attr >= 0) H5Aclose(attr);
  if (file >= 0) H5Fclose(file);
  H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data);
  return run_id && id == run_id ? PETSC_TRUE : PETSC_FALSE;
}

/* Rank 0 only, hence plain C that reports an errno value instead of raising a PETSc error (which would
   leave the other ranks waiting): deletes checkpoint_*.h5 in dir of run run_id with step <= newest beyond the
   `keep` latest of them. Checkpoints after `newest` (left by an earlier run that went further) and those of
   other runs sharing the directory are not this run's to delete. */
static int CheckpointRemoveOldLocal(const char dir[], PetscInt64 newest, PetscInt keep, uint64_t run_id)
{
  DIR           *d;
  struct dirent *entry;
  PetscInt64    *steps = NULL, step;
  size_t         n = 0, cap = 0;
  int            err = 0;

  if (!(d = opendir(dir))) return errno;
  while (!err && (entry = readdir(d))) {
    char path[CLOTH_PATH_LEN];

    if (!CheckpointNameStep(entry->d_name, &step) || step > newest) continue;
    snprintf(path, sizeof(path), "%s/%s", dir, entry->d_name);
    if (!CheckpointOfRun(path, run_id)) continue;
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

static PetscErrorCode CheckpointRemoveOld(MPI_Comm comm, const char dir[], PetscInt64 newest, PetscInt keep, uint64_t run_id)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) err = CheckpointRemoveOldLocal(dir, newest, keep, run_id);
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot remove old checkpoints in %s: %s", dir, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Room for the checkpoint's datasets (8 bytes a value), its provenance (up to the 64 MB of a scene) plus 1 MB of
   metadata, checked before the file is created. */
static PetscErrorCode CheckpointCheckSpace(MPI_Comm comm, const char dir[], const char tmp[], Scene scene, PetscInt nfields, const ClothCheckpointField fields[])
{
  double   bytes;
  PetscInt n;
  char     what[CLOTH_PATH_LEN + 32];

  PetscFunctionBeginUser;
  PetscCall(ClothProvenanceSize(scene, &bytes));
  bytes += 1e6;
  for (PetscInt f = 0; f < nfields; f++) {
    PetscCall(VecGetSize(fields[f].vec, &n));
    bytes += 8.0 * (double)n;
  }
  PetscCall(PetscSNPrintf(what, sizeof(what), "checkpoint %s", tmp));
  PetscCall(ClothFileCheckSpace(comm, dir, bytes, what));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After a read or a write that failed half-way: closes what it left open in the file (a group, a dataset,
   an attribute), since parallel HDF5 closes a file only when nothing in it is open. HDF5's error printing is
   off, and a failure here changes nothing: the file is being refused or deleted anyway. */
static PetscErrorCode CheckpointCloseObjects(hid_t file)
{
  const unsigned types = H5F_OBJ_DATASET | H5F_OBJ_GROUP | H5F_OBJ_ATTR | H5F_OBJ_LOCAL;
  ssize_t        n     = H5Fget_obj_count(file, types);
  hid_t         *ids;

  PetscFunctionBeginUser;
  if (n > 0) {
    PetscCall(PetscMalloc1(n, &ids));
    n = H5Fget_obj_ids(file, types, (size_t)n, ids);
    for (ssize_t i = 0; i < n; i++) (void)(H5Iget_type(ids[i]) == H5I_ATTR ? H5Aclose(ids[i]) : H5Oclose(ids[i]));
    PetscCall(PetscFree(ids));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After a read that failed half-way: closes what it left open, then the file (opened read-only, so its close
   writes nothing and does not fail). */
static PetscErrorCode CheckpointCloseAfterFailure(hid_t *file)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointCloseObjects(*file));
  (void)H5Fclose(*file);
  *file = -1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The message of a failed checkpoint write: the temporary file and the reason. */
#define CHECKPOINT_WRITE_FAILED "Cannot write checkpoint %s: %s; it was deleted, the checkpoints already written are left as they were"

/* The message of this rank's first error ierr. */
static PetscErrorCode CheckpointLocalReason(PetscErrorCode ierr, char reason[], size_t len)
{
  const char *text;
  char       *specific = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscErrorMessage(ierr, &text, &specific));
  PetscCall(PetscStrncpy(reason, specific && specific[0] ? specific : text, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Why the first failing rank failed (the message of its first error), on every rank. Collective. */
static PetscErrorCode CheckpointFailureReason(MPI_Comm comm, PetscErrorCode ierr, char reason[], size_t len)
{
  PetscMPIInt rank, size, first;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  first = ierr ? rank : size;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm));
  reason[0] = 0;
  if (rank == first) PetscCall(CheckpointLocalReason(ierr, reason, len));
  PetscCallMPI(MPI_Bcast(reason, (PetscMPIInt)len, MPI_CHAR, first, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes the whole checkpoint to tmp. Any failure inside it (a disk that fills during HDF5's writes although
   the space check passed, a file size limit, an I/O error) is caught on every rank: the file is deleted and
   the error names it and the reason, so that no half checkpoint is left and the newest complete one stays
   the newest. Collective; the failure is agreed on by all ranks after the write, so a rank whose part
   succeeded does not wait forever; a rank whose failure left the others inside a collective write (ROMIO on a
   full disk) removes the file and aborts the run after a few seconds (ClothAgreeOnFailure), and a write that hangs
   inside HDF5 meets -io_timeout (watchdog.h). The file is emptied before it is closed: closing flushes HDF5's
   metadata into it, and a failed H5Fclose in HDF5 1.10 leaves a dangling identifier that crashes the library's
   clean-up at MPI_Finalize (measured with a file size limit, where emptying does not help: see
   tests/drivers/checkpoint_write_failure.sh). */
static PetscErrorCode CheckpointWriteTemporary(MPI_Comm comm, const char tmp[], const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  PetscErrorCode ierr;
  H5E_auto2_t    print_errors;
  void          *print_errors_data;
  PetscMPIInt    rank;
  PetscBool      failed;
  hid_t          file = -1;
  char           reason[512], message[CLOTH_PATH_LEN + 1024], what[CLOTH_PATH_LEN + 64];
  MPI_Comm       agree;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_dup(comm, &agree)); /* before the writes: a rank whose write failed may leave the others in one */
  PetscCall(PetscSNPrintf(what, sizeof(what), "The write of checkpoint %s", tmp));
  PetscCall(ClothWatchdogArm(what, tmp, CLOTH_EXIT_FILE));
  ClothCallHDF5(H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data));
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, NULL, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = ClothH5FileCreate(comm, tmp, &file);
  if (!ierr) ierr = CheckpointWriteFile(comm, file, info, nfields, fields);
  if (!ierr) ierr = ClothH5FileClose(&file);
  PetscCall(PetscPopErrorHandler());
  message[0] = 0;
  if (ierr) {
    PetscCall(CheckpointLocalReason(ierr, reason, sizeof(reason)));
    PetscCall(PetscSNPrintf(message, sizeof(message), CHECKPOINT_WRITE_FAILED, tmp, reason));
  }
  PetscCall(ClothAgreeOnFailure(agree, ierr ? PETSC_TRUE : PETSC_FALSE, message, CLOTH_EXIT_FILE, tmp, &failed));
  PetscCallMPI(MPI_Comm_free(&agree));
  if (!failed) {
    PetscCall(ClothWatchdogDisarm());
    ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(CheckpointFailureReason(comm, ierr, reason, sizeof(reason)));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (file >= 0) {
    PetscCall(CheckpointCloseObjects(file));
    PetscCallMPI(MPI_Barrier(comm));
    if (rank == 0 && truncate(tmp, 0) != 0) { /* frees the file's blocks: room on a full disk for what the close writes; if not, the close may fail */
    }
    PetscCallMPI(MPI_Barrier(comm));
    (void)H5Fclose(file);
  }
  PetscCallMPI(MPI_Barrier(comm));
  if (rank == 0) (void)remove(tmp);
  PetscCall(ClothWatchdogDisarm());
  PetscCheck(!failed, comm, PETSC_ERR_FILE_WRITE, CHECKPOINT_WRITE_FAILED, tmp, reason);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointWrite(MPI_Comm comm, const char dir[], const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[], PetscInt keep, char path_out[], size_t path_len)
{
  char path[CLOTH_PATH_LEN], tmp[CLOTH_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCheck(info->step >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "Checkpoint step %" PetscInt64_FMT " must be >= 0", info->step);
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/checkpoint_%06" PetscInt64_FMT ".h5", dir, info->step));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s/.checkpoint_%06" PetscInt64_FMT ".h5.tmp", dir, info->step));
  PetscCall(ClothFileMakeDirectory(comm, dir));
  PetscCall(CheckpointCheckSpace(comm, dir, tmp, info->scene, nfields, fields));
  PetscCall(CheckpointWriteTemporary(comm, tmp, info, nfields, fields));
  PetscCall(ClothFileRename(comm, tmp, path));
  if (keep > 0) PetscCall(CheckpointRemoveOld(comm, dir, info->step, keep, info->run_id));
  if (path_out) PetscCall(PetscStrncpy(path_out, path, path_len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointFieldFind(PetscInt nfields, const ClothCheckpointField fields[], const char name[], const ClothCheckpointField **field)
{
  PetscBool same;

  PetscFunctionBeginUser;
  *field = NULL;
  for (PetscInt f = 0; f < nfields && !*field; f++) {
    PetscCall(PetscStrcmp(fields[f].name, name, &same));
    if (same) *field = &fields[f];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointFindNewest(MPI_Comm comm, const char dir[], char path[], size_t len, PetscInt *count)
{
  PetscMPIInt rank;
  PetscInt64  found[2] = {-1, 0}; /* newest step, count */

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    DIR *d = opendir(dir);

    for (struct dirent *entry; d && (entry = readdir(d));) {
      PetscInt64 step;

      if (!CheckpointNameStep(entry->d_name, &step)) continue;
      found[0] = PetscMax(found[0], step);
      found[1]++;
    }
    if (d) closedir(d);
  }
  PetscCallMPI(MPI_Bcast(found, 2, MPIU_INT64, 0, comm));
  path[0] = 0;
  if (found[1]) PetscCall(PetscSNPrintf(path, len, "%s/checkpoint_%06" PetscInt64_FMT ".h5", dir, found[0]));
  *count = (PetscInt)found[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckpointRefuse(CheckpointRefusal *refusal, PetscErrorCode code, const char reason[])
{
  PetscFunctionBeginUser;
  refusal->code = code;
  PetscCall(PetscStrncpy(refusal->reason, reason, sizeof(refusal->reason)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks the end marker and the attributes' presence, then reads them into info and checks them
   against their checksum. */
static PetscErrorCode CheckpointReadInfo(hid_t state, ClothCheckpointInfo *info, CheckpointRefusal *refusal)
{
  PetscBool  exists = PETSC_FALSE;
  PetscInt64 format;
  uint64_t   stored;
  char       reason[256];

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeExists(state, "complete", &exists));
  if (!exists) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, "has no end marker (attribute /state/complete): it was not completely written"));
  if (exists) PetscCall(ClothH5AttributeExists(state, "format_version", &exists));
  if (exists) { /* first, so that a checkpoint of another format is named as such */
    PetscCall(ClothH5AttributeReadInt64(state, "format_version", &format));
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "is in checkpoint format %" PetscInt64_FMT "; this clothsim reads format %d", format, CHECKPOINT_FORMAT_VERSION));
    if (format != CHECKPOINT_FORMAT_VERSION) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  }
  for (size_t i = 0; !refusal->code && i < PETSC_STATIC_ARRAY_LENGTH(CheckpointAttributes); i++) {
    PetscCall(ClothH5AttributeExists(state, CheckpointAttributes[i], &exists));
    if (exists) continue;
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "lacks the attribute /state/%s: it is not a clothsim checkpoint of format %d", CheckpointAttributes[i], CHECKPOINT_FORMAT_VERSION));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  }
  if (refusal->code) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothH5AttributeReadInt64(state, "step", &info->step));
  PetscCall(ClothH5AttributeReadReal(state, "time", &info->time));
  PetscCall(ClothH5AttributeReadReal(state, "dt", &info->dt));
  PetscCall(ClothH5AttributeReadInt64(state, "dt_start_step", &info->dt_start_step));
  PetscCall(ClothH5AttributeReadReal(state, "dt_start_time", &info->dt_start_time));
  PetscCall(ClothH5AttributeReadString(state, "integrator", info->integrator, sizeof(info->integrator)));
  PetscCall(ClothH5AttributeReadString(state, "scene_name", info->scene_name, sizeof(info->scene_name)));
  PetscCall(ClothH5AttributeReadInt64(state, "scene_fingerprint", &info->scene_fingerprint));
  PetscCall(ClothH5AttributeReadInt64(state, "nparticles", &info->nparticles));
  PetscCall(ClothH5AttributeReadUInt64(state, "info_checksum", &stored));
  PetscCall(ClothH5AttributeExists(state, "history_dt", &exists));
  info->history_dt = 0;
  if (exists) PetscCall(ClothH5AttributeReadReal(state, "history_dt", &info->history_dt));
  PetscCall(ClothH5AttributeExists(state, "run_id", &exists));
  info->run_id = 0;
  if (exists) PetscCall(ClothH5AttributeReadUInt64(state, "run_id", &info->run_id));
  if (stored != CheckpointInfoChecksum(info, info->nparticles))
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_READ, "is corrupt: its attributes step, time, dt, dt_start_step, dt_start_time, integrator, scene_fingerprint, nparticles and history_dt do not match their checksum info_checksum"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks that the checkpoint fits this run: its particle count and its scene. */
static PetscErrorCode CheckpointCheckScene(const ClothCheckpointInfo *info, const ClothCheckpointInfo *expect, PetscInt64 nparticles, CheckpointRefusal *refusal)
{
  char        reason[sizeof(((CheckpointRefusal *)0)->reason)];
  const char *differs;
  PetscBool   same_name;

  PetscFunctionBeginUser;
  if (expect && info->scene_fingerprint != expect->scene_fingerprint) {
    PetscCall(PetscStrcmp(info->scene_name, expect->scene_name, &same_name));
    if (info->nparticles != expect->nparticles)
      differs = same_name ? "other grids (grid: in the scene, or -grid): a restart needs the same particles" : "another scene: a restart needs the same particles";
    else if (!same_name)
      differs = "another scene of as many particles; if it is this one renamed on purpose, add -restart_any_scene to continue with it";
    else
      differs = "the same name and particle count, but the scene file was edited (a value, or only a comment) or -grid changed; if on purpose, add -restart_any_scene to continue with this scene";
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "was written for scene '%s' (fingerprint %016" PRIx64 ", %" PetscInt64_FMT " particles), not this scene '%s' (fingerprint %016" PRIx64 ", %" PetscInt64_FMT " particles): %s", info->scene_name,
                            (uint64_t)info->scene_fingerprint, info->nparticles, expect->scene_name, (uint64_t)expect->scene_fingerprint, expect->nparticles, differs));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  } else if (info->nparticles != nparticles) {
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "holds %" PetscInt64_FMT " particles, the scene has %" PetscInt64_FMT, info->nparticles, nparticles));
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads one field when the file holds it (refusing a missing required one) and compares its checksum
   with the stored one. */
static PetscErrorCode CheckpointReadField(hid_t state, ClothCheckpointField *field, CheckpointRefusal *refusal)
{
  PetscInt bs;
  uint64_t stored, computed;
  hid_t    dset;
  char     reason[256];

  PetscFunctionBeginUser;
  PetscCall(ClothH5LinkExists(state, field->name, &field->found));
  if (!field->found) {
    PetscCall(PetscSNPrintf(reason, sizeof(reason), "lacks the dataset /state/%s", field->name));
    if (field->required) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, reason));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecGetBlockSize(field->vec, &bs));
  PetscCall(ClothH5ReadVec(state, field->name, field->vec, bs));
  ClothCallHDF5(dset = H5Dopen2(state, field->name, H5P_DEFAULT));
  PetscCall(ClothH5AttributeReadUInt64(dset, "checksum", &stored));
  ClothCallHDF5(H5Dclose(dset));
  PetscCall(VecChecksum(field->vec, &computed));
  PetscCall(PetscSNPrintf(reason, sizeof(reason), "is corrupt: the checksum of /state/%s is %016llx, it was written with %016llx", field->name, (unsigned long long)computed, (unsigned long long)stored));
  if (computed != stored) PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_READ, reason));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads and checks everything in an open file; the first problem found ends up in refusal. Every
   check is made on data that all ranks hold alike, so all ranks reach the same verdict. */
static PetscErrorCode CheckpointReadFile(MPI_Comm comm, hid_t file, const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, PetscInt nfields, ClothCheckpointField fields[], CheckpointRefusal *refusal)
{
  PetscBool  exists = PETSC_FALSE;
  hid_t      state;
  PetscInt64 nparticles;

  PetscFunctionBeginUser;
  PetscCall(CheckpointParticleCount(comm, nfields, fields, &nparticles));
  PetscCall(ClothH5LinkExists(file, "state", &exists));
  if (!exists) {
    PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_UNEXPECTED, "has no group /state: it is not a clothsim checkpoint"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  ClothCallHDF5(state = H5Gopen2(file, "state", H5P_DEFAULT));
  PetscCall(CheckpointReadInfo(state, info, refusal));
  if (!refusal->code) PetscCall(CheckpointCheckScene(info, expect, nparticles, refusal));
  for (PetscInt f = 0; f < nfields && !refusal->code; f++) PetscCall(CheckpointReadField(state, &fields[f], refusal));
  ClothCallHDF5(H5Gclose(state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads an opened file with errors returned, not raised: an HDF5 failure inside a damaged file (its
   metadata read collectively, so every rank fails alike) becomes a refusal that names the file, and
   the file is closed. */
static PetscErrorCode CheckpointReadFileGuarded(MPI_Comm comm, hid_t *file, const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, PetscInt nfields, ClothCheckpointField fields[], CheckpointRefusal *refusal)
{
  PetscErrorCode ierr;
  H5E_auto2_t    print_errors;
  void          *print_errors_data;
  const char    *text;
  char          *specific, reason[sizeof(refusal->reason)];

  PetscFunctionBeginUser;
  ClothCallHDF5(H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data));
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, NULL, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = CheckpointReadFile(comm, *file, expect, info, nfields, fields, refusal);
  PetscCall(PetscPopErrorHandler());
  if (ierr) PetscCall(CheckpointCloseAfterFailure(file));
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data));
  if (!ierr) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscErrorMessage(ierr, &text, &specific));
  PetscCall(PetscSNPrintf(reason, sizeof(reason), "is corrupt: it cannot be read (%s)", specific ? specific : text));
  PetscCall(CheckpointRefuse(refusal, PETSC_ERR_FILE_READ, reason));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCheckpointRead(MPI_Comm comm, const char path[], const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, PetscInt nfields, ClothCheckpointField fields[])
{
  PetscBool           opened = PETSC_FALSE;
  hid_t               file;
  ClothCheckpointInfo found;
  CheckpointRefusal   refusal = {0, ""};

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&found, sizeof(found)));
  PetscCall(ClothFileCheckReadable(comm, "Checkpoint", path, "one of the checkpoint_NNNNNN.h5 in it, the newest for the latest state"));
  PetscCall(ClothH5FileOpen(comm, path, H5F_ACC_RDONLY, &file, &opened));
  PetscCheck(opened, comm, PETSC_ERR_FILE_READ, "Checkpoint %s cannot be opened as an HDF5 file: it is truncated or not a checkpoint", path);
  PetscCall(CheckpointReadFileGuarded(comm, &file, expect, &found, nfields, fields, &refusal));
  PetscCall(ClothH5FileClose(&file));
  PetscCheck(!refusal.code, comm, refusal.code, "Checkpoint %s %s", path, refusal.reason);
  if (info) *info = found;
  PetscFunctionReturn(PETSC_SUCCESS);
}
