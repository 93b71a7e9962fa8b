/* Checkpoints: exact write/read round trip (also read back on one rank), pruning to the newest `keep`,
   and refusal, with the expected message, of files that are missing, not HDF5, truncated, corrupt,
   unfinished, lacking a required dataset, from another scene or with another particle count. Prints nothing unless a check fails.

   Usage: mpiexec -n P test_checkpoint -dir DIR [-info] (-info shows the refusal messages) */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "checkpoint.h"
#include "h5util.h"
#include "test_support.h"

static const char help[] = "Checkpoint write/read and refusal tests.\n";

/* A state of n particles whose values depend on the global index only (not on the rank count). */
static PetscErrorCode CreateState(MPI_Comm comm, PetscInt n, Vec *position, Vec *velocity)
{
  PetscInt     lo, hi;
  PetscScalar *x, *v;

  PetscFunctionBeginUser;
  PetscCall(VecCreate(comm, position));
  PetscCall(VecSetSizes(*position, PETSC_DECIDE, 3 * n));
  PetscCall(VecSetBlockSize(*position, 3));
  PetscCall(VecSetFromOptions(*position));
  PetscCall(VecDuplicate(*position, velocity));
  PetscCall(VecGetOwnershipRange(*position, &lo, &hi));
  PetscCall(VecGetArray(*position, &x));
  PetscCall(VecGetArray(*velocity, &v));
  for (PetscInt i = lo; i < hi; i++) {
    x[i - lo] = PetscSinReal(0.37 * i + 0.1) * (1.0 + i);
    v[i - lo] = PetscCosReal(1.13 * i) / 3.0 - 1e-300 * i;
  }
  PetscCall(VecRestoreArray(*position, &x));
  PetscCall(VecRestoreArray(*velocity, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode DestroyState(Vec *position, Vec *velocity)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(position));
  PetscCall(VecDestroy(velocity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The run writing the test's checkpoints (ClothCheckpointInfo.run_id); TestKeep switches it to write another run's. */
static uint64_t TestRunId = 1;

static PetscErrorCode MakeInfo(PetscInt64 step, PetscInt n, ClothCheckpointInfo *info)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(info, sizeof(*info)));
  info->step              = step;
  info->time              = 0.1 * (PetscReal)step + 1.0 / 3.0;
  info->dt                = 1.0 / 7.0;
  info->scene_fingerprint = (PetscInt64)0x1234567890abcdefLL;
  info->nparticles        = n;
  info->run_id            = TestRunId;
  PetscCall(PetscStrncpy(info->integrator, "implicit", sizeof(info->integrator)));
  PetscCall(PetscStrncpy(info->scene_name, "test_scene", sizeof(info->scene_name)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The fields of a test state: position and velocity (required), and optionally a third one, "extra"
   (the velocity's values again), that a reader may or may not require. */
static PetscErrorCode MakeFields(Vec x, Vec v, PetscBool extra_required, ClothCheckpointField fields[3])
{
  PetscFunctionBeginUser;
  fields[0] = (ClothCheckpointField){"position", x, PETSC_TRUE, PETSC_FALSE};
  fields[1] = (ClothCheckpointField){"velocity", v, PETSC_TRUE, PETSC_FALSE};
  fields[2] = (ClothCheckpointField){"extra", v, extra_required, PETSC_FALSE};
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes a checkpoint of n particles at step on comm (with the field "extra" when asked); returns its path. */
static PetscErrorCode WriteCheckpointFields(MPI_Comm comm, const char dir[], PetscInt64 step, PetscInt n, PetscBool with_extra, PetscInt keep, char path[], size_t len)
{
  ClothCheckpointInfo  info;
  ClothCheckpointField fields[3];
  Vec                  x, v;

  PetscFunctionBeginUser;
  PetscCall(MakeInfo(step, n, &info));
  PetscCall(CreateState(comm, n, &x, &v));
  PetscCall(MakeFields(x, v, PETSC_FALSE, fields));
  PetscCall(ClothCheckpointWrite(comm, dir, &info, with_extra ? 3 : 2, fields, keep, path, len));
  PetscCall(DestroyState(&x, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteCheckpoint(MPI_Comm comm, const char dir[], PetscInt64 step, PetscInt n, PetscInt keep, char path[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(WriteCheckpointFields(comm, dir, step, n, PETSC_TRUE, keep, path, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads path on comm and compares state and info exactly with what WriteCheckpoint wrote. */
static PetscErrorCode CheckRoundTrip(MPI_Comm comm, const char path[], PetscInt64 step, PetscInt n)
{
  ClothCheckpointInfo  expect, info;
  ClothCheckpointField fields[3];
  Vec                  x, v, x_read, v_read, extra_read;
  PetscBool            same_x, same_v, same_extra, same_strings;

  PetscFunctionBeginUser;
  PetscCall(MakeInfo(step, n, &expect));
  PetscCall(CreateState(comm, n, &x, &v));
  PetscCall(VecDuplicate(x, &x_read));
  PetscCall(VecDuplicate(v, &v_read));
  PetscCall(VecDuplicate(v, &extra_read));
  PetscCall(MakeFields(x_read, v_read, PETSC_TRUE, fields));
  fields[2].vec = extra_read;
  PetscCall(ClothCheckpointRead(comm, path, &expect, &info, 3, fields));
  PetscCall(VecEqual(x, x_read, &same_x));
  PetscCall(VecEqual(v, v_read, &same_v));
  PetscCall(VecEqual(v, extra_read, &same_extra));
  PetscCheck(same_x && same_v && same_extra && fields[2].found, comm, PETSC_ERR_PLIB, "%s: state read back differs (position %d, velocity %d, extra %d)", path, same_x, same_v, same_extra);
  PetscCall(VecDestroy(&extra_read));
  same_strings = (PetscBool)(!strcmp(info.integrator, expect.integrator) && !strcmp(info.scene_name, expect.scene_name));
  PetscCheck(same_strings && info.step == expect.step && info.time == expect.time && info.dt == expect.dt && info.scene_fingerprint == expect.scene_fingerprint && info.nparticles == n, comm, PETSC_ERR_PLIB, "%s: info read back differs", path);
  PetscCall(DestroyState(&x, &v));
  PetscCall(DestroyState(&x_read, &v_read));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads path (requiring the field "extra"), which must be refused with a message containing `words`. */
static PetscErrorCode CheckRefused(MPI_Comm comm, const char path[], const ClothCheckpointInfo *expect, PetscInt n, const char words[])
{
  Vec                  x, v;
  ClothCheckpointField fields[3];
  PetscErrorCode       ierr;
  const char          *text;
  char                *message;

  PetscFunctionBeginUser;
  PetscCall(CreateState(comm, n, &x, &v));
  PetscCall(MakeFields(x, v, PETSC_TRUE, fields));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = ClothCheckpointRead(comm, path, expect, NULL, 3, fields);
  PetscCall(PetscPopErrorHandler());
  PetscCheck(ierr != 0, comm, PETSC_ERR_PLIB, "%s was accepted; expected a refusal saying '%s'", path, words);
  PetscCall(PetscErrorMessage(ierr, &text, &message));
  PetscCheck(message && strstr(message, words) && strstr(message, path), comm, PETSC_ERR_PLIB, "%s was refused with '%s'; expected the path and '%s'", path, message ? message : "(none)", words);
  PetscCall(PetscInfo(NULL, "Refused as expected: %s\n", message));
  PetscCall(DestroyState(&x, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0 damages a written file; the others wait for it. */
static PetscErrorCode TruncateToHalf(MPI_Comm comm, const char path[])
{
  PetscMPIInt rank;
  struct stat st;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    PetscCheck(stat(path, &st) == 0 && truncate(path, st.st_size / 2) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot truncate %s", path);
  }
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode FlipByteInPositions(MPI_Comm comm, const char path[], PetscInt n)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    hid_t   file, dset;
    haddr_t offset;
    FILE   *fp;
    int     byte;

    ClothCallHDF5(file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT));
    ClothCallHDF5(dset = H5Dopen2(file, "/state/position", H5P_DEFAULT));
    offset = H5Dget_offset(dset);
    PetscCheck(offset != HADDR_UNDEF, PETSC_COMM_SELF, PETSC_ERR_LIB, "No offset for /state/position in %s", path);
    ClothCallHDF5(H5Dclose(dset));
    ClothCallHDF5(H5Fclose(file));
    offset += (haddr_t)(3 * n * sizeof(double) / 2 + 3);
    PetscCheck((fp = fopen(path, "r+b")), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "Cannot open %s", path);
    PetscCheck(fseek(fp, (long)offset, SEEK_SET) == 0 && (byte = fgetc(fp)) != EOF, PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "Cannot read %s", path);
    PetscCheck(fseek(fp, (long)offset, SEEK_SET) == 0 && fputc(byte ^ 0x10, fp) != EOF && fclose(fp) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot write %s", path);
  }
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode DeleteEndMarker(MPI_Comm comm, const char path[])
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    hid_t file;

    ClothCallHDF5(file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT));
    ClothCallHDF5(H5Adelete_by_name(file, "state", "complete", H5P_DEFAULT));
    ClothCallHDF5(H5Fclose(file));
  }
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteTextFile(MPI_Comm comm, const char path[])
{
  FILE *fp;

  PetscFunctionBeginUser;
  PetscCall(PetscFOpen(comm, path, "w", &fp));
  PetscCall(PetscFPrintf(comm, fp, "this is not an HDF5 file\n"));
  PetscCall(PetscFClose(comm, fp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode TestRefusals(MPI_Comm comm, const char dir[], PetscInt n)
{
  char                path[CLOTH_PATH_LEN];
  ClothCheckpointInfo expect;

  PetscFunctionBeginUser;
  PetscCall(MakeInfo(1, n, &expect));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/no_such_checkpoint.h5", dir));
  PetscCall(CheckRefused(comm, path, &expect, n, "does not exist"));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/text.h5", dir));
  PetscCall(WriteTextFile(comm, path));
  PetscCall(CheckRefused(comm, path, &expect, n, "cannot be opened as an HDF5 file"));

  PetscCall(WriteCheckpoint(comm, dir, 1, n, 0, path, sizeof(path)));
  PetscCall(TruncateToHalf(comm, path));
  PetscCall(CheckRefused(comm, path, &expect, n, "truncated"));

  PetscCall(WriteCheckpoint(comm, dir, 2, n, 0, path, sizeof(path)));
  PetscCall(FlipByteInPositions(comm, path, n));
  PetscCall(CheckRefused(comm, path, NULL, n, "is corrupt"));

  PetscCall(WriteCheckpoint(comm, dir, 3, n, 0, path, sizeof(path)));
  PetscCall(DeleteEndMarker(comm, path));
  PetscCall(CheckRefused(comm, path, NULL, n, "no end marker"));

  PetscCall(WriteCheckpointFields(comm, dir, 5, n, PETSC_FALSE, 0, path, sizeof(path)));
  PetscCall(CheckRefused(comm, path, NULL, n, "lacks the dataset /state/extra"));

  PetscCall(WriteCheckpoint(comm, dir, 4, n, 0, path, sizeof(path)));
  PetscCall(CheckRefused(comm, path, &expect, n + 5, "particles, the scene has"));
  expect.scene_fingerprint += 1;
  PetscCall(PetscStrncpy(expect.scene_name, "other_scene", sizeof(expect.scene_name)));
  PetscCall(CheckRefused(comm, path, &expect, n, "was written for scene 'test_scene'"));
  PetscCall(CheckRoundTrip(comm, path, 4, n)); /* nothing is left over from the refusals */
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckExists(MPI_Comm comm, const char dir[], const char name[], PetscBool expected)
{
  char      path[CLOTH_PATH_LEN];
  PetscBool exists;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s", dir, name));
  PetscCall(PetscTestFile(path, 'r', &exists));
  PetscCheck(exists == expected, comm, PETSC_ERR_PLIB, "%s %s", path, expected ? "is missing" : "should have been removed");
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* keep = 2: only the two newest checkpoints of this run up to the current step stay; a later one (left by an
   earlier run that went further) and an earlier one of another run sharing the directory are not touched. */
static PetscErrorCode TestKeep(MPI_Comm comm, const char dir[], PetscInt n)
{
  char path[CLOTH_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(WriteCheckpoint(comm, dir, 99, n, 0, path, sizeof(path)));
  TestRunId = 2;
  PetscCall(WriteCheckpoint(comm, dir, 5, n, 0, path, sizeof(path)));
  TestRunId = 1;
  for (PetscInt64 step = 10; step < 15; step++) PetscCall(WriteCheckpoint(comm, dir, step, n, 2, path, sizeof(path)));
  PetscCall(CheckExists(comm, dir, "checkpoint_000010.h5", PETSC_FALSE));
  PetscCall(CheckExists(comm, dir, "checkpoint_000012.h5", PETSC_FALSE));
  PetscCall(CheckExists(comm, dir, "checkpoint_000013.h5", PETSC_TRUE));
  PetscCall(CheckExists(comm, dir, "checkpoint_000014.h5", PETSC_TRUE));
  PetscCall(CheckExists(comm, dir, "checkpoint_000099.h5", PETSC_TRUE));
  PetscCall(CheckExists(comm, dir, "checkpoint_000005.h5", PETSC_TRUE));
  PetscCall(CheckExists(comm, dir, ".checkpoint_000014.h5.tmp", PETSC_FALSE));
  PetscCall(CheckRoundTrip(comm, path, 14, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Written on all ranks, read on all ranks and on rank 0 alone. */
static PetscErrorCode TestRoundTrip(MPI_Comm comm, const char dir[], PetscInt64 step, PetscInt n)
{
  char        path[CLOTH_PATH_LEN];
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(WriteCheckpoint(comm, dir, step, n, 0, path, sizeof(path)));
  PetscCall(CheckRoundTrip(comm, path, step, n));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(CheckRoundTrip(PETSC_COMM_SELF, path, step, n));
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char     dir[CLOTH_PATH_LEN] = "test_checkpoint_output", subdir[CLOTH_PATH_LEN];
  MPI_Comm comm;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-dir", dir, sizeof(dir), NULL));
  PetscCall(TestRoundTrip(comm, dir, 42, 37));
  PetscCall(TestRoundTrip(comm, dir, 1234567, 1)); /* ranks without particles; a seven-digit step */
  PetscCall(TestRefusals(comm, dir, 29));
  PetscCall(PetscSNPrintf(subdir, sizeof(subdir), "%s/keep", dir));
  PetscCall(TestKeep(comm, subdir, 5));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
