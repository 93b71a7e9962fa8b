/* The user-error handler (src/errors.h) on its own, for tests/drivers/error_exit.sh. With -fail all every rank raises the
   same user error, as collective errors are raised; with -fail one only the last rank raises it while the others
   wait in a barrier, which without the handler's timeout would hang for ever. Either way the run must end with
   exit status 2 (CLOTH_EXIT_INPUT) and the message once. */
#include <petscsys.h>
#include "errors.h"

static PetscErrorCode RaiseUserError(MPI_Comm comm, const char who[])
{
  PetscFunctionBeginUser;
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "test user error raised by %s", who);
}

int main(int argc, char **argv)
{
  char        fail[16] = "all";
  PetscMPIInt rank, size;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(ClothErrorHandlerPush());
  PetscCall(PetscOptionsGetString(NULL, NULL, "-fail", fail, sizeof(fail), NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  if (!strcmp(fail, "all")) PetscCall(RaiseUserError(PETSC_COMM_WORLD, "every rank"));
  if (rank == size - 1) PetscCall(RaiseUserError(PETSC_COMM_SELF, "the last rank alone"));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscFinalize());
  return 0;
}
