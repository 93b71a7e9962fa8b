/* A partitioner of src/partition.c on a graph built here, independently of the model: the n x n grid with its
   8-neighbour stencil (the links and shear diagonals of a sheet), split into as many parts as ranks.

   Options: -n N (default 65), -partition TYPE (the one under test), -expect_max_imbalance R (largest part / mean part),
   -expect_max_cut_ratio Q (its edge cut / METIS's on the same graph), both required. Checks that
   - every rank got the same part[] (the set-up numbers particles from it on every rank);
   - every vertex is in a part 0..size-1 and no part is empty;
   - the largest part is at most R times the mean;
   - the edge cut, counted here, is at most Q times METIS's on the same graph.
   Prints the largest part and both edge cuts on rank 0. */
#include <petscsys.h>
#include "partition.h"
#include "test_support.h"

/* The grid's graph in CSR form, natural order (row by row), no self loops. */
static PetscErrorCode GridGraph(PetscInt n, PetscInt **xadj, PetscInt **adjncy)
{
  PetscInt nv = n * n, e = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nv + 1, xadj));
  PetscCall(PetscMalloc1(8 * nv, adjncy));
  (*xadj)[0] = 0;
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < n; j++) {
      for (PetscInt di = -1; di <= 1; di++)
        for (PetscInt dj = -1; dj <= 1; dj++)
          if ((di || dj) && i + di >= 0 && i + di < n && j + dj >= 0 && j + dj < n) (*adjncy)[e++] = (i + di) * n + j + dj;
      (*xadj)[i * n + j + 1] = e;
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscInt EdgeCut(PetscInt nv, const PetscInt xadj[], const PetscInt adjncy[], const PetscInt part[])
{
  PetscInt cut = 0;

  for (PetscInt v = 0; v < nv; v++)
    for (PetscInt k = xadj[v]; k < xadj[v + 1]; k++)
      if (adjncy[k] > v && part[adjncy[k]] != part[v]) cut++;
  return cut;
}

/* Every rank holds the same part[]: its elementwise min and max over the ranks agree. */
static PetscErrorCode CheckSameOnEveryRank(PetscInt nv, const PetscInt part[])
{
  PetscInt *lo, *hi, differ = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nv, &lo, nv, &hi));
  PetscCallMPI(MPI_Allreduce(part, lo, (PetscMPIInt)nv, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Allreduce(part, hi, (PetscMPIInt)nv, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  for (PetscInt v = 0; v < nv; v++)
    if (lo[v] != hi[v]) differ++;
  PetscCall(PetscFree2(lo, hi));
  PetscCheck(!differ, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the ranks disagree on the part of %" PetscInt_FMT " vertices", differ);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscInt           n = 65, nv, *xadj, *adjncy, *part, *metis, *count, largest = 0, cut, metis_cut;
  PetscMPIInt        size;
  ClothPartitionType type = CLOTH_PARTITION_METIS;
  PetscReal          max_imbalance = 0, max_cut_ratio = 0, imbalance;
  PetscBool          set_imbalance, set_cut;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-n", &n, NULL));
  PetscCall(PetscOptionsGetEnum(NULL, NULL, "-partition", ClothPartitionTypes, (PetscEnum *)&type, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_max_imbalance", &max_imbalance, &set_imbalance));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_max_cut_ratio", &max_cut_ratio, &set_cut));
  PetscCheck(set_imbalance && set_cut, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "expected -expect_max_imbalance and -expect_max_cut_ratio");
  PetscCheck(size > 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "expected at least 2 ranks (1 rank is not partitioned)");
  nv = n * n;
  PetscCall(GridGraph(n, &xadj, &adjncy));
  PetscCall(PetscMalloc3(nv, &part, nv, &metis, size, &count));
  PetscCall(ClothPartitionGraph(PETSC_COMM_WORLD, type, nv, xadj, adjncy, size, part));
  PetscCall(ClothPartitionGraph(PETSC_COMM_WORLD, CLOTH_PARTITION_METIS, nv, xadj, adjncy, size, metis));
  PetscCall(CheckSameOnEveryRank(nv, part));
  PetscCall(PetscArrayzero(count, size));
  for (PetscInt v = 0; v < nv; v++) {
    PetscCheck(part[v] >= 0 && part[v] < size, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "vertex %" PetscInt_FMT " in part %" PetscInt_FMT ", expected 0..%d", v, part[v], size - 1);
    count[part[v]]++;
  }
  for (PetscMPIInt p = 0; p < size; p++) {
    PetscCheck(count[p] > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "part %d is empty", p);
    largest = PetscMax(largest, count[p]);
  }
  imbalance = (PetscReal)largest * size / (PetscReal)nv;
  cut       = EdgeCut(nv, xadj, adjncy, part);
  metis_cut = EdgeCut(nv, xadj, adjncy, metis);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s on %d parts of a %" PetscInt_FMT " x %" PetscInt_FMT " grid: largest part %" PetscInt_FMT " (imbalance %.4f), edge cut %" PetscInt_FMT " (METIS %" PetscInt_FMT ")\n",
                        ClothPartitionTypes[type], size, n, n, largest, (double)imbalance, cut, metis_cut));
  PetscCheck(imbalance <= max_imbalance, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "imbalance %.4f above %.4f", (double)imbalance, (double)max_imbalance);
  PetscCheck(cut <= max_cut_ratio * metis_cut, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "edge cut %" PetscInt_FMT " above %g x METIS's %" PetscInt_FMT, cut, (double)max_cut_ratio, metis_cut);
  PetscCall(PetscFree3(part, metis, count));
  PetscCall(PetscFree(xadj));
  PetscCall(PetscFree(adjncy));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
