/* Partitioning of the particle graph (see partition.h). */
#include <metis.h>
#include <petscmat.h>
#include "partition.h"

const char *const ClothPartitionTypes[] = {"metis", "block", "ptscotch", "parmetis", "ClothPartitionType", "CLOTH_PARTITION_", NULL};

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

/* This rank's block of rows of the natural order: the rows a parallel partitioner is given. */
static void NaturalBlock(PetscInt n, PetscMPIInt size, PetscMPIInt rank, PetscInt *start, PetscInt *count)
{
  *start = (n / size) * rank + PetscMin(rank, n % size);
  *count = n / size + (rank < n % size ? 1 : 0);
}

/* PETSc's MatPartitioning (PT-Scotch or ParMETIS) on the graph distributed by blocks of rows: no rank holds more than
   its block of the graph in the partitioner (the whole part[] is then gathered, as the rest of the set-up needs it).
   Its own options take the prefix cloth_partition_ (e.g. -cloth_partition_mat_partitioning_ptscotch_imbalance). */
static PetscErrorCode PartitionParallel(MPI_Comm comm, ClothPartitionType type, PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[])
{
  PetscMPIInt     size, rank, *counts, *displs;
  PetscInt        start, count, *ia, *ja;
  Mat             adj;
  MatPartitioning mp;
  IS              is;
  const PetscInt *local;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  NaturalBlock(n, size, rank, &start, &count);
  /* MatCreateMPIAdj takes ia and ja and frees them with the matrix */
  PetscCall(PetscMalloc1(count + 1, &ia));
  PetscCall(PetscMalloc1(xadj[start + count] - xadj[start], &ja));
  for (PetscInt i = 0; i <= count; i++) ia[i] = xadj[start + i] - xadj[start];
  PetscCall(PetscArraycpy(ja, adjncy + xadj[start], ia[count]));
  PetscCall(MatCreateMPIAdj(comm, count, n, ia, ja, NULL, &adj));
  PetscCall(MatPartitioningCreate(comm, &mp));
  PetscCall(MatPartitioningSetAdjacency(mp, adj));
  PetscCall(MatPartitioningSetNParts(mp, nparts));
  PetscCall(MatPartitioningSetType(mp, type == CLOTH_PARTITION_PTSCOTCH ? MATPARTITIONINGPTSCOTCH : MATPARTITIONINGPARMETIS));
  PetscCall(PetscObjectSetOptionsPrefix((PetscObject)mp, "cloth_partition_"));
  PetscCall(MatPartitioningSetFromOptions(mp));
  PetscCall(MatPartitioningApply(mp, &is));
  PetscCall(PetscMalloc2(size, &counts, size, &displs));
  for (PetscMPIInt r = 0; r < size; r++) {
    PetscInt rs, rc;
    NaturalBlock(n, size, r, &rs, &rc);
    displs[r] = (PetscMPIInt)rs;
    counts[r] = (PetscMPIInt)rc;
  }
  PetscCall(ISGetIndices(is, &local));
  PetscCallMPI(MPI_Allgatherv(local, (PetscMPIInt)count, MPIU_INT, part, counts, displs, MPIU_INT, comm));
  PetscCall(ISRestoreIndices(is, &local));
  PetscCall(PetscFree2(counts, displs));
  PetscCall(ISDestroy(&is));
  PetscCall(MatPartitioningDestroy(&mp));
  PetscCall(MatDestroy(&adj));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every particle in one of the nparts parts and no part empty: the rest of the set-up (numbering, ghosts) relies on it,
   and a partitioner (an external library) is checked rather than trusted. */
static PetscErrorCode CheckPartition(MPI_Comm comm, ClothPartitionType type, PetscInt n, PetscInt nparts, const PetscInt part[])
{
  PetscInt *size_of, empty = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nparts, &size_of));
  for (PetscInt i = 0; i < n; i++) {
    PetscCheck(part[i] >= 0 && part[i] < nparts, comm, PETSC_ERR_LIB, "Partitioner %s put particle %" PetscInt_FMT " in part %" PetscInt_FMT ", expected 0..%" PetscInt_FMT, ClothPartitionTypes[type], i, part[i], nparts - 1);
    size_of[part[i]]++;
  }
  for (PetscInt p = 0; p < nparts && empty < 0; p++)
    if (!size_of[p]) empty = p;
  PetscCall(PetscFree(size_of));
  PetscCheck(empty < 0, comm, PETSC_ERR_LIB, "Partitioner %s left part %" PetscInt_FMT " of %" PetscInt_FMT " empty (%" PetscInt_FMT " particles): try -cloth_partition metis", ClothPartitionTypes[type], empty, nparts, n);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0 partitions and broadcasts the partition with METIS's status: a METIS failure is raised on every rank
   (raised on rank 0 alone, before the broadcast, it left the others waiting in it forever). */
PetscErrorCode ClothPartitionGraph(MPI_Comm comm, ClothPartitionType type, PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[])
{
  PetscMPIInt rank;
  int         status = METIS_OK;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (nparts > 1 && (type == CLOTH_PARTITION_PTSCOTCH || type == CLOTH_PARTITION_PARMETIS)) {
#if !defined(PETSC_HAVE_PARMETIS)
    PetscCheck(type != CLOTH_PARTITION_PARMETIS, comm, PETSC_ERR_USER_INPUT, "-cloth_partition parmetis: this PETSc was built without ParMETIS; expected metis, block or ptscotch");
#endif
#if !defined(PETSC_HAVE_PTSCOTCH)
    PetscCheck(type != CLOTH_PARTITION_PTSCOTCH, comm, PETSC_ERR_USER_INPUT, "-cloth_partition ptscotch: this PETSc was built without PT-Scotch; expected metis, block or parmetis");
#endif
    PetscCall(PartitionParallel(comm, type, n, xadj, adjncy, nparts, part));
    PetscCall(CheckPartition(comm, type, n, nparts, part));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
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
  PetscCall(CheckPartition(comm, type, n, nparts, part));
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
