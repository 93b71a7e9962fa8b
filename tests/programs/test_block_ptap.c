/* The block Galerkin product (src/block_ptap.c) against PETSc's MatPtAP of an AIJ copy, an independent computation.

   The implicit system of a perturbed cloth (positions moved by up to 2 mm, random velocities, so that every element's
   stiffness is generic) is assembled into the block (BAIJ) matrix; for the pattern grids' first interpolation P,
   C = P^T A P by ClothBlockPtAPCompute must equal MatPtAP(AIJ copy of A, P) to 1e-13 relative in the Frobenius
   norm (measured 0 on 1 to 3 ranks: the same sums in the same order; the tolerance allows another order). A second
   product after assembling the system again at another step size (new values, same pattern) must match too: the
   sums are cleared between products. Run on 1, 2 and 3 ranks, on scenes with several pieces, seams and pins, so
   that coarse rows owned by another rank and ghost rows of P are exercised; in parallel the test also requires that
   some fine row interpolates from another rank's coarse row. A product 10 % off fails it (checked by hand).
   With -implicit_mat_type sbaij the matrix stores only its upper triangle (src/block_matrix.c reads it, the product
   is S + S^T): the same comparison, and point-block Jacobi's inverted diagonal blocks of the SBAIJ matrix (added by
   src/block_matrix.c; PETSc 3.18 has none) must equal PETSc's own of the AIJ copy to 1e-12 relative (measured
   below 1e-15). */
#include <petscksp.h>
#include "test_support.h"
#include "block_ptap.h"
#include "gridhierarchy.h"

/* |C - Cref|_F / |Cref|_F. */
static PetscErrorCode RelativeDifference(Mat C, Mat Cref, PetscReal *rel)
{
  Mat       D;
  PetscReal nd, nref;

  PetscFunctionBeginUser;
  PetscCall(MatDuplicate(Cref, MAT_COPY_VALUES, &D));
  PetscCall(MatAXPY(D, -1, C, DIFFERENT_NONZERO_PATTERN));
  PetscCall(MatNorm(D, NORM_FROBENIUS, &nd));
  PetscCall(MatNorm(Cref, NORM_FROBENIUS, &nref));
  *rel = nd / nref;
  PetscCall(MatDestroy(&D));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* max |inv(D_i) - inv(D_i)_AIJ| / max |inv(D_i)_AIJ| over the particles' diagonal blocks. */
static PetscErrorCode CompareInverseBlocks(Mat A, PetscReal *rel)
{
  Mat                Aaij;
  const PetscScalar *inv, *ref;
  PetscInt           m;
  PetscReal          d[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCall(MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, &Aaij));
  PetscCall(MatInvertBlockDiagonal(A, &inv));
  PetscCall(MatInvertBlockDiagonal(Aaij, &ref));
  PetscCall(MatGetLocalSize(A, &m, NULL));
  for (PetscInt k = 0; k < 3 * m; k++) {
    d[0] = PetscMax(d[0], PetscAbsScalar(inv[k] - ref[k]));
    d[1] = PetscMax(d[1], PetscAbsScalar(ref[k]));
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, d, 2, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
  *rel = d[0] / d[1];
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "inverted diagonal blocks: largest difference / largest entry = %.2e\n", (double)*rel));
  PetscCall(MatDestroy(&Aaij));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Assembles the implicit system at step h and compares the two products. */
static PetscErrorCode CompareAt(Cloth cloth, PetscReal h, Mat A, Vec rhs, ClothBlockPtAP ptap, Mat P, PetscReal *rel)
{
  Vec x, v;
  Mat Aaij, Cref, C;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, A, rhs));
  PetscCall(ClothBlockPtAPCompute(ptap, A));
  PetscCall(ClothBlockPtAPGetProduct(ptap, &C));
  PetscCall(MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, &Aaij));
  PetscCall(MatPtAP(Aaij, P, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &Cref));
  PetscCall(RelativeDifference(C, Cref, rel));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "h = %g: |C - MatPtAP| / |MatPtAP| = %.2e\n", (double)h, (double)*rel));
  PetscCall(MatDestroy(&Cref));
  PetscCall(MatDestroy(&Aaij));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene              scene;
  Cloth              cloth;
  ClothGridHierarchy gh;
  ClothBlockPtAP     ptap;
  Mat                A, P, C;
  Vec                rhs;
  PetscInt           ratio = 4, nlevels, cstart, cend, nrows, sent = 0;
  PetscReal          rel[2];
  PetscMPIInt        size;
  MatType            type;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-ratio", &ratio, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(TestPerturbState(cloth, 2026, 2e-3, 0.3));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, &A));
  PetscCall(ClothCreateStateVec(cloth, &rhs));
  PetscCall(ClothGridHierarchyCreate(cloth, ratio, 2, 1, &gh));
  PetscCall(ClothGridHierarchyGetLevels(gh, &nlevels));
  PetscCheck(nlevels == 2, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the scene's grids cannot be coarsened: %" PetscInt_FMT " level", nlevels);
  PetscCall(ClothGridHierarchyGetInterpolation(gh, 1, &P));
  {
    Vec x, v;
    PetscCall(ClothGetState(cloth, &x, &v));
    PetscCall(ClothAssembleImplicitSystem(cloth, 0.01, x, v, A, rhs)); /* the pattern the product is made for */
  }
  PetscCall(ClothBlockPtAPCreate(A, P, &ptap));
  /* in parallel, some fine row must interpolate from a coarse row owned by another rank (else the remote path is untested) */
  PetscCall(ClothBlockPtAPGetProduct(ptap, &C));
  PetscCall(MatGetType(A, &type));
  PetscCall(MatGetOwnershipRange(C, &cstart, &cend));
  PetscCall(MatGetSize(C, &nrows, NULL));
  /* counted before MatPtAP, which converts an MPIMAIJ interpolation to MPIAIJ in place */
  { /* the interpolation's scalar weights (it is MAIJ): row i, column J for fine particle i, coarse particle J */
    const PetscInt *cols;
    PetscInt        rstart, rend, ncols;
    Mat             Q;
    PetscCall(MatMAIJGetAIJ(P, &Q));
    PetscCall(MatGetOwnershipRange(Q, &rstart, &rend));
    for (PetscInt row = rstart; row < rend; row++) {
      PetscCall(MatGetRow(Q, row, &ncols, &cols, NULL));
      for (PetscInt k = 0; k < ncols; k++)
        if (cols[k] < cstart / 3 || cols[k] >= cend / 3) sent++;
      PetscCall(MatRestoreRow(Q, row, &ncols, &cols, NULL));
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &sent, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  }
  PetscCall(CompareAt(cloth, 0.01, A, rhs, ptap, P, &rel[0]));
  PetscCall(CompareAt(cloth, 0.0025, A, rhs, ptap, P, &rel[1]));
  PetscCheck(rel[0] <= 1e-13 && rel[1] <= 1e-13, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the block Galerkin product differs from MatPtAP: %g, %g (tolerance 1e-13)", (double)rel[0], (double)rel[1]);
  PetscCall(CompareInverseBlocks(A, &rel[0]));
  PetscCheck(rel[0] <= 1e-12, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the inverted diagonal blocks differ from the AIJ copy's: %g (tolerance 1e-12)", (double)rel[0]);
  PetscCheck(size == 1 || sent > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "no fine row interpolates from another rank's coarse row: the test does not reach the remote rows");
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "block Galerkin product (%s): %" PetscInt_FMT " coarse rows, %" PetscInt_FMT " interpolation entries across ranks, equal to MatPtAP within 1e-13\n", type, nrows / 3, sent));
  PetscCall(ClothBlockPtAPDestroy(&ptap));
  PetscCall(ClothGridHierarchyDestroy(&gh));
  PetscCall(VecDestroy(&rhs));
  PetscCall(MatDestroy(&A));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
