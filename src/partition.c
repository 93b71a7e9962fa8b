/* METIS partitioning (see partition.h). */
#include <metis.h>
#include "partition.h"

const char *const ClothPartitionTypes[] = {"metis", "block", "ClothPartitionType", "CLOTH_PARTITION_", NULL};

static PetscErrorCode PartitionBlock(PetscInt n, PetscInt nparts, PetscInt part[])
{
  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < nparts; p++) {
    const PetscInt start = (n / nparts) * p + PetscMin(p, n % nparts), count = n / nparts + (p < n % nparts ? 1 : 0);
    for (PetscInt i = start; i < start + count; i++) part[i] = p;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0 alone: returns METIS's status (METIS_OK = 1 on success, so never "nonzero is an error") instead of
   raising, so that the caller can tell every rank. */
static PetscErrorCode PartitionMETIS(PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[], int *status)
{
  idx_t  nvtxs = (idx_t)n, ncon = 1, np = (idx_t)nparts, objval, options[METIS_NOPTIONS];
  idx_t *mxadj, *madj, *mpart;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(n + 1, &mxadj, xadj[n], &madj, n, &mpart));
  for (PetscInt i = 0; i <= n; i++) mxadj[i] = (idx_t)xadj[i];
  for (PetscInt i = 0; i < xadj[n]; i++) madj[i] = (idx_t)adjncy[i];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED]      = 1; /* the same partition on every run */
  options[METIS_OPTION_NUMBERING] = 0;
  *status                         = METIS_PartGraphKway(&nvtxs, &ncon, mxadj, madj, NULL, NULL, NULL, &np, NULL, NULL, options, &objval, mpart);
  if (*status == METIS_OK)
    for (PetscInt i = 0; i < n; i++) part[i] = (PetscInt)mpart[i];
  PetscCall(PetscFree3(mxadj, madj, mpart));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static const char *MetisStatusName(int status)
{
  switch (status) {
  case METIS_ERROR_INPUT:
    return "METIS_ERROR_INPUT, an input error";
  case METIS_ERROR_MEMORY:
    return "METIS_ERROR_MEMORY, out of memory";
  default:
    return "METIS_ERROR";
  }
}

/* Rank 0 partitions and broadcasts the partition with METIS's status: a METIS failure is raised on every rank
   (raised on rank 0 alone, before the broadcast, it left the others waiting in it forever). */
PetscErrorCode ClothPartitionGraph(MPI_Comm comm, ClothPartitionType type, PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[])
{
  PetscMPIInt rank;
  int         status = METIS_OK;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    if (nparts == 1) {
      for (PetscInt i = 0; i < n; i++) part[i] = 0;
    } else if (type == CLOTH_PARTITION_METIS) {
      PetscCall(PartitionMETIS(n, xadj, adjncy, nparts, part, &status));
    } else {
      PetscCall(PartitionBlock(n, nparts, part));
    }
  }
  PetscCallMPI(MPI_Bcast(&status, 1, MPI_INT, 0, comm));
  PetscCheck(status == METIS_OK, comm, PETSC_ERR_LIB, "METIS_PartGraphKway failed (status %d, %s) splitting %" PetscInt_FMT " particles into %" PetscInt_FMT " parts: try -cloth_partition block", status, MetisStatusName(status), n, nparts);
  PetscCallMPI(MPI_Bcast(part, (PetscMPIInt)n, MPIU_INT, 0, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscInt ClothPartitionEdgeCut(PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], const PetscInt part[])
{
  PetscInt cut = 0;

  for (PetscInt i = 0; i < n; i++)
    for (PetscInt k = xadj[i]; k < xadj[i + 1]; k++)
      if (adjncy[k] > i && part[adjncy[k]] != part[i]) cut++;
  return cut;
}
