/* A file that opens on some ranks and not on others (its directory deleted between their opens, as in
   tests/drivers/output_dir_ownership.sh) must fail on every rank, not hang them: Open MPI's ompio hung here,
   so clothsim chooses ROMIO, which agrees on the failure (src/h5util.h). The ranks are given different paths on
   purpose: rank 0 an existing file (or directory), the others a missing one, and every rank must see the same
   refusal and go on to open the next file. Run on 2 or more ranks; ctest's timeout catches a hang. */
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>
#include <petscsys.h>
#include "h5util.h"

static const char help[] = "Checks that HDF5 opens and creates that fail on some ranks fail on all: -dir DIR (scratch).\n";

/* ierr on this rank, and whether every rank failed alike. */
static PetscErrorCode CheckAllFailed(MPI_Comm comm, PetscErrorCode ierr, const char what[])
{
  int failed = ierr != 0, all, any;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&failed, &all, 1, MPI_INT, MPI_LAND, comm));
  PetscCallMPI(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_LOR, comm));
  PetscCheck(all && any, comm, PETSC_ERR_PLIB, "%s: failed on %s ranks, expected on every rank", what, any ? "some" : "no");
  PetscCall(PetscPrintf(comm, "%s: refused on every rank\n", what));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An open of an existing file on rank 0 and of a missing one elsewhere: *opened false on every rank. */
static PetscErrorCode CheckOpenAgreement(MPI_Comm comm, const char existing[], const char missing[], PetscMPIInt rank)
{
  hid_t     file   = -1;
  PetscBool opened = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(ClothH5FileOpen(comm, rank == 0 ? existing : missing, H5F_ACC_RDWR, &file, &opened));
  PetscCheck(!opened && file < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Open of %s reported opened on rank %d although another rank's path is missing", rank == 0 ? existing : missing, rank);
  PetscCall(PetscPrintf(comm, "open of a file that exists on rank 0 only: refused on every rank\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A create in an existing directory on rank 0 and in a missing one elsewhere: an error on every rank. */
static PetscErrorCode CheckCreateAgreement(MPI_Comm comm, const char dir[], PetscMPIInt rank)
{
  char           path[CLOTH_PATH_LEN];
  hid_t          file = -1;
  PetscErrorCode ierr;
  H5E_auto2_t    print_errors;
  void          *print_errors_data;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(path, sizeof(path), rank == 0 ? "%s/created.h5" : "%s/missing_directory/created.h5", dir));
  ClothCallHDF5(H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data));
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, NULL, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = ClothH5FileCreate(comm, path, &file);
  PetscCall(PetscPopErrorHandler());
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data));
  if (!ierr) PetscCall(ClothH5FileClose(&file));
  PetscCall(CheckAllFailed(comm, ierr, "create in a directory that exists on rank 0 only"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char        dir[CLOTH_PATH_LEN] = "test_h5_open_agreement", existing[CLOTH_PATH_LEN], missing[CLOTH_PATH_LEN];
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  hid_t       file   = -1;
  PetscBool   opened = PETSC_FALSE;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(size >= 2, comm, PETSC_ERR_ARG_SIZ, "Run on 2 or more ranks: the check gives the ranks different paths");
  PetscCall(PetscOptionsGetString(NULL, NULL, "-dir", dir, sizeof(dir), NULL));
  if (rank == 0) PetscCheck(mkdir(dir, 0755) == 0 || errno == EEXIST, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "Cannot create %s: %s", dir, strerror(errno));
  PetscCall(PetscSNPrintf(existing, sizeof(existing), "%s/existing.h5", dir));
  PetscCall(PetscSNPrintf(missing, sizeof(missing), "%s/missing.h5", dir));
  PetscCall(ClothH5FileCreate(comm, existing, &file));
  PetscCall(ClothH5FileClose(&file));
  if (rank == 0) (void)unlink(missing);
  PetscCallMPI(MPI_Barrier(comm));

  PetscCall(CheckOpenAgreement(comm, existing, missing, rank));
  PetscCall(CheckCreateAgreement(comm, dir, rank));
  /* and the ranks go on together: the same file opens on all */
  PetscCall(ClothH5FileOpen(comm, existing, H5F_ACC_RDONLY, &file, &opened));
  PetscCheck(opened, comm, PETSC_ERR_PLIB, "The existing file %s did not open on every rank after the refusals", existing);
  PetscCall(ClothH5FileClose(&file));
  PetscCall(PetscPrintf(comm, "then the same file opened on all %d ranks\n", size));
  PetscCall(PetscFinalize());
  return 0;
}
