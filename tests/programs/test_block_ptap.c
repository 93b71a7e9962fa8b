/* The block Galerkin product (src/block_ptap.c) against PETSc's MatPtAP of an AIJ copy, an independent computation.

   The implicit system of a perturbed cloth (positions moved by up to 2 mm, random velocities, so that every element's
   stiffness is generic) is assembled into the block (BAIJ) matrix; for the pattern grids' first interpolation P,
   C = P^T A P by ClothBlockPtAPCompute must equal MatPtAP(AIJ copy of A, P) to 1e-13 relative in the Frobenius
   norm (measured 0 on 1 to 3 ranks: the same sums in the same order; the tolerance allows another order). C is stored
   as A is (BAIJ or SBAIJ), as the multigrid's middle levels are, and where the grids give a third level the product
   of C itself with the next interpolation, stored as AIJ (the coarsest level's storage), must equal MatPtAP of C's
   AIJ copy alike. A second pair of products after assembling the system again at another step size (new values,
   same pattern) must match too: the sums are cleared between products. Run on 1, 2 and 3 ranks, on scenes with
   several pieces, seams and pins, so that coarse rows owned by another rank and ghost rows of P are exercised; in
   parallel the test also requires that some fine row interpolates from another rank's coarse row. A product 10 %
   off fails it (checked by hand). With -implicit_mat_type sbaij the matrix stores only its upper triangle
   (src/block_matrix.c reads it, the product is S + S^T): the same comparisons, and point-block Jacobi's inverted
   diagonal blocks of the SBAIJ matrix (added by src/block_matrix.c; PETSc 3.18 has none) must equal PETSc's own of
   the AIJ copy to 1e-12 relative (measured below 1e-15). */
#include <petscksp.h>
#include "test_support.h"
#include "block_ptap.h"
#include "gridhierarchy.h"

/* |C - Cref|_F / |Cref|_F, C of any storage (an SBAIJ one holds half of its rows). */
static PetscErrorCode RelativeDifference(Mat C, Mat Cref, PetscReal *rel)
{
  Mat       D, Caij;
  PetscReal nd, nref;

  PetscFunctionBeginUser;
  PetscCall(MatConvert(C, MATAIJ, MAT_INITIAL_MATRIX, &Caij));
  PetscCall(MatDuplicate(Cref, MAT_COPY_VALUES, &D));
  PetscCall(MatAXPY(D, -1, Caij, DIFFERENT_NONZERO_PATTERN));
  PetscCall(MatNorm(D, NORM_FROBENIUS, &nd));
  PetscCall(MatNorm(Cref, NORM_FROBENIUS, &nref));
  *rel = nd / nref;
  PetscCall(MatDestroy(&D));
  PetscCall(MatDestroy(&Caij));
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

/* ptap's product of its fine matrix F against MatPtAP(AIJ copy of F, P): the relative difference. */
static PetscErrorCode CompareProduct(ClothBlockPtAP ptap, Mat F, Mat P, PetscReal *rel)
{
  Mat Faij, Cref, C;

  PetscFunctionBeginUser;
  PetscCall(ClothBlockPtAPCompute(ptap, F));
  PetscCall(ClothBlockPtAPGetProduct(ptap, &C));
  PetscCall(MatConvert(F, MATAIJ, MAT_INITIAL_MATRIX, &Faij));
  PetscCall(MatPtAP(Faij, P, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &Cref));
  PetscCall(RelativeDifference(C, Cref, rel));
  PetscCall(MatDestroy(&Cref));
  PetscCall(MatDestroy(&Faij));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Assembles the implicit system at step h and compares the products: A's with P[0] and, with a second level, its
   product's with P[1]; rel[0..1] the largest relative difference at each level (0 without the second). */
static PetscErrorCode CompareAt(Cloth cloth, PetscReal h, Mat A, Vec rhs, ClothBlockPtAP ptap[2], Mat P[2], PetscReal rel[2])
{
  Vec x, v;
  Mat C;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, A, rhs));
  PetscCall(CompareProduct(ptap[0], A, P[0], &rel[0]));
  rel[1] = 0;
  if (ptap[1]) {
    PetscCall(ClothBlockPtAPGetProduct(ptap[0], &C));
    PetscCall(CompareProduct(ptap[1], C, P[1], &rel[1]));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "h = %g: |C - MatPtAP| / |MatPtAP| = %.2e (first level), %.2e (second level)\n", (double)h, (double)rel[0], (double)rel[1]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene              scene;
  Cloth              cloth;
  ClothGridHierarchy gh;
  ClothBlockPtAP     ptap[2] = {NULL, NULL};
  Mat                A, P[2] = {NULL, NULL}, C;
  Vec                rhs;
  PetscInt           ratio = 4, nlevels, cstart, cend, nrows, sent = 0, expect_levels;
  PetscReal          rel[2][2];
  PetscMPIInt        size;
  MatType            type, ctype;
  char              *type_name;
  PetscBool          sbaij;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-ratio", &ratio, NULL));
  PetscCall(TestGetExpectationInt("-expect_levels", &expect_levels));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(TestPerturbState(cloth, 2026, 2e-3, 0.3));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, &A));
  PetscCall(ClothCreateStateVec(cloth, &rhs));
  PetscCall(ClothGridHierarchyCreate(cloth, ratio, 3, 1, PETSC_TRUE, &gh));
  PetscCall(ClothGridHierarchyGetLevels(gh, &nlevels));
  PetscCheck(nlevels == expect_levels, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the scene's grids give %" PetscInt_FMT " levels, expected %" PetscInt_FMT " (-expect_levels)", nlevels, expect_levels);
  PetscCheck(nlevels >= 2, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the scene's grids cannot be coarsened: %" PetscInt_FMT " level", nlevels);
  for (PetscInt k = 0; k < nlevels - 1; k++) PetscCall(ClothGridHierarchyGetInterpolation(gh, nlevels - 1 - k, &P[k]));
  {
    Vec x, v;
    PetscCall(ClothGetState(cloth, &x, &v));
    PetscCall(ClothAssembleImplicitSystem(cloth, 0.01, x, v, A, rhs)); /* the pattern the product is made for */
  }
  PetscCall(MatGetType(A, &type));
  PetscCall(PetscStrallocpy(type, &type_name)); /* reading an MPISBAIJ matrix's parts renames it for a moment */
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &sbaij, MATSEQSBAIJ, MATMPISBAIJ, ""));
  ctype = sbaij ? MATSBAIJ : MATBAIJ;
  /* the first product stored as A is (a middle level of the multigrid), the second as AIJ (its coarsest level);
     both made before MatPtAP, which converts an MPIMAIJ interpolation to MPIAIJ in place */
  PetscCall(ClothBlockPtAPCreate(A, P[0], ctype, &ptap[0]));
  PetscCall(ClothBlockPtAPGetProduct(ptap[0], &C));
  if (P[1]) PetscCall(ClothBlockPtAPCreate(C, P[1], MATAIJ, &ptap[1]));
  /* in parallel, some fine row must interpolate from a coarse row owned by another rank (else the remote path is untested) */
  PetscCall(MatGetOwnershipRange(C, &cstart, &cend));
  PetscCall(MatGetSize(C, &nrows, NULL));
  { /* the interpolation's scalar weights (it is MAIJ): row i, column J for fine particle i, coarse particle J */
    const PetscInt *cols;
    PetscInt        rstart, rend, ncols;
    Mat             Q;
    PetscCall(MatMAIJGetAIJ(P[0], &Q));
    PetscCall(MatGetOwnershipRange(Q, &rstart, &rend));
    for (PetscInt row = rstart; row < rend; row++) {
      PetscCall(MatGetRow(Q, row, &ncols, &cols, NULL));
      for (PetscInt k = 0; k < ncols; k++)
        if (cols[k] < cstart / 3 || cols[k] >= cend / 3) sent++;
      PetscCall(MatRestoreRow(Q, row, &ncols, &cols, NULL));
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &sent, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  }
  PetscCall(CompareAt(cloth, 0.01, A, rhs, ptap, P, rel[0]));
  PetscCall(CompareAt(cloth, 0.0025, A, rhs, ptap, P, rel[1]));
  for (PetscInt k = 0; k < 2; k++)
    PetscCheck(rel[0][k] <= 1e-13 && rel[1][k] <= 1e-13, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the block Galerkin product of level %" PetscInt_FMT " differs from MatPtAP: %g, %g (tolerance 1e-13)", k + 1, (double)rel[0][k], (double)rel[1][k]);
  PetscCall(CompareInverseBlocks(A, &rel[0][0]));
  PetscCheck(rel[0][0] <= 1e-12, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the inverted diagonal blocks differ from the AIJ copy's: %g (tolerance 1e-12)", (double)rel[0][0]);
  PetscCall(CompareInverseBlocks(C, &rel[0][0]));
  PetscCheck(rel[0][0] <= 1e-12, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the coarse level's inverted diagonal blocks differ from its AIJ copy's: %g (tolerance 1e-12)", (double)rel[0][0]);
  PetscCheck(size == 1 || sent > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "no fine row interpolates from another rank's coarse row: the test does not reach the remote rows");
  PetscCall(
      PetscPrintf(PETSC_COMM_WORLD, "block Galerkin products (%s, %" PetscInt_FMT " levels): %" PetscInt_FMT " coarse rows, %" PetscInt_FMT " interpolation entries across ranks, equal to MatPtAP within 1e-13\n", type_name, nlevels, nrows / 3, sent));
  for (PetscInt k = 0; k < 2; k++) PetscCall(ClothBlockPtAPDestroy(&ptap[k]));
  PetscCall(PetscFree(type_name));
  PetscCall(ClothGridHierarchyDestroy(&gh));
  PetscCall(VecDestroy(&rhs));
  PetscCall(MatDestroy(&A));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
