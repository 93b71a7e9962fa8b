/* STREAM-style triad on PETSc vectors: the memory bandwidth that bounds the implicit step.

     mpiexec -n P build/stream_triad [-n N] [-repeats R]

   a = b + s c (VecWAXPY) on N doubles per rank (default 2^24 = 128 MiB per vector, far beyond any cache),
   timed R times between barriers; the best repeat gives the bandwidth as STREAM counts it: 3 x 8 bytes per
   element (read b and c, write a; the write-allocate read of a is not counted). Prints one line:

     stream_triad ranks P n_per_rank N best_s T bandwidth_GBps B */
#include <petscvec.h>
#include "util.h" /* PETSC_SUCCESS before PETSc 3.19 */

static PetscErrorCode TimeTriad(Vec a, Vec b, Vec c, PetscInt repeats, double *best)
{
  PetscFunctionBeginUser;
  *best = 1e300;
  for (PetscInt r = 0; r < repeats; r++) {
    double start, elapsed;

    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    start = MPI_Wtime();
    PetscCall(VecWAXPY(a, 3.0, c, b));
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    elapsed = MPI_Wtime() - start;
    *best   = PetscMin(*best, elapsed);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Vec         a, b, c;
  PetscInt    n = 1 << 24, repeats = 10;
  PetscMPIInt size;
  double      best;

  PetscCall(PetscInitialize(&argc, &argv, NULL, "STREAM-style triad a = b + s c on PETSc vectors\n"));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Triad bandwidth", "stream_triad");
  PetscCall(PetscOptionsInt("-n", "Doubles per rank", "stream_triad", n, &n, NULL));
  PetscCall(PetscOptionsInt("-repeats", "Timed repeats (the best counts)", "stream_triad", repeats, &repeats, NULL));
  PetscOptionsEnd();
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(VecCreateMPI(PETSC_COMM_WORLD, n, PETSC_DETERMINE, &a));
  PetscCall(VecDuplicate(a, &b));
  PetscCall(VecDuplicate(a, &c));
  PetscCall(VecSet(a, 0.0)); /* touch every page before timing */
  PetscCall(VecSet(b, 1.0));
  PetscCall(VecSet(c, 2.0));
  PetscCall(TimeTriad(a, b, c, repeats, &best));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "stream_triad ranks %d n_per_rank %" PetscInt_FMT " best_s %.6f bandwidth_GBps %.3f\n", size, n, best, 24.0 * n * size / best / 1e9));
  PetscCall(VecDestroy(&a));
  PetscCall(VecDestroy(&b));
  PetscCall(VecDestroy(&c));
  PetscCall(PetscFinalize());
  return 0;
}
