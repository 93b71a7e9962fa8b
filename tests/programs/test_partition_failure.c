/* A METIS failure reaches every rank (issue 24, item 8): ClothPartitionGraph asked for 0 parts of a 4-particle ring,
   which METIS refuses (METIS_ERROR_INPUT) on rank 0, must raise PETSC_ERR_LIB on every rank, not leave the others
   waiting in the broadcast of the partition (ctest's timeout would catch that hang). Prints nothing unless a check
   fails. */
#include <petscsys.h>
#include "partition.h"
#include "util.h"

int main(int argc, char **argv)
{
  const PetscInt xadj[5] = {0, 2, 4, 6, 8}, adjncy[8] = {1, 3, 0, 2, 1, 3, 2, 0};
  PetscInt       part[4];
  PetscErrorCode ierr;
  int            raised, everywhere;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = ClothPartitionGraph(PETSC_COMM_WORLD, CLOTH_PARTITION_METIS, 4, xadj, adjncy, 0, part);
  PetscCall(PetscPopErrorHandler());
  raised = ierr == PETSC_ERR_LIB;
  PetscCallMPI(MPI_Allreduce(&raised, &everywhere, 1, MPI_INT, MPI_LAND, PETSC_COMM_WORLD));
  PetscCheck(everywhere, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "a METIS failure was not raised as PETSC_ERR_LIB on every rank (this rank: error %d)", (int)ierr);
  PetscCall(PetscFinalize());
  return 0;
}
