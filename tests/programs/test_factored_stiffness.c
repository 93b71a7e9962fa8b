/* The Gauss-Newton stiffness assembled from its factors against the same stiffness expanded first, in parallel.

   On the perturbed two-piece cloth with every angle kind (tests/data/jacobian_two_pieces.yaml) and contact constraints
   of every kind (free, held against a plane with a random normal, stuck, on owned particles and so on ghosts), the
   implicit system assembled from each element's factors (S_a q_r, then sum_r lambda_r (S q_r)(S q_r)^T and K v from
   the factors) must equal the system assembled from the expanded element matrices filtered block by block
   (S_a H_ab S_b, K v = H v): matrix and right-hand side to 1e-12 relative (the same sums in another order). The step
   h = 1 s makes h^2 K and h^2 K v dominate the masses and forces, so that the comparison is one of the stiffness.
   The same system assembled again into the assembled matrix, where ClothBlockAdder (block_matrix.h) adds the owned
   rows' blocks in place, must equal the first assembly, made through MatSetValuesBlockedLocal, exactly (the same
   additions in the same order). -matrix_type baij (default) or sbaij. */
#include <petscmat.h>
#include "scene.h"
#include "cloth.h"
#include "test_support.h"
#include "block_matrix.h"

/* Contact constraints on the owned particles: every third held against a plane of random normal, every seventh stuck
   (CLOTH_CONTACT_STUCK times a unit normal), the rest free. */
static PetscErrorCode SetContacts(Cloth cloth, PetscRandom rnd)
{
  Vec          normals;
  PetscScalar *c;
  PetscInt     nlocal, nglobal, rstart;

  PetscFunctionBeginUser;
  PetscCall(ClothGetContactNormals(cloth, &normals));
  PetscCall(ClothGetSizes(cloth, &nlocal, &nglobal));
  PetscCall(VecGetOwnershipRange(normals, &rstart, NULL));
  PetscCall(VecGetArray(normals, &c));
  for (PetscInt i = 0; i < nlocal; i++) {
    const PetscInt g = rstart / 3 + i;
    PetscReal      n[3], len = 0, scale = (g % 7 == 0) ? CLOTH_CONTACT_STUCK : (g % 3 == 0 ? 1.0 : 0.0);

    for (PetscInt k = 0; k < 3; k++) {
      PetscCall(PetscRandomGetValueReal(rnd, &n[k]));
      n[k] -= 0.5;
      len += n[k] * n[k];
    }
    for (PetscInt k = 0; k < 3; k++) c[3 * i + k] = scale * n[k] / PetscSqrtReal(len);
  }
  PetscCall(VecRestoreArray(normals, &c));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The system assembled with the factored or the expanded path into a new matrix of the given type. */
static PetscErrorCode Assemble(Cloth cloth, PetscBool factored, MatType type, PetscReal h, Mat *A, Vec *rhs)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothSetFactoredStiffness(cloth, factored));
  PetscCall(ClothCreateMatrix(cloth, type, A));
  PetscCall(ClothCreateStateVec(cloth, rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, *A, *rhs));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* |(A - B) x| and |A x| over three random x: compares matrices of any type (MatAXPY of two MPISBAIJ matrices was
   measured wrong in PETSc 3.18: a difference as large as the matrix between two equal ones). */
static PetscErrorCode ProductDifference(Mat A, Mat B, PetscReal *diff, PetscReal *norm)
{
  Vec         x, ax, bx;
  PetscRandom rnd;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(A, &x, &ax));
  PetscCall(VecDuplicate(ax, &bx));
  PetscCall(PetscRandomCreate(PetscObjectComm((PetscObject)A), &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 5));
  PetscCall(PetscRandomSeed(rnd));
  *diff = *norm = 0;
  for (PetscInt trial = 0; trial < 3; trial++) {
    PetscReal d, n;
    PetscCall(VecSetRandom(x, rnd));
    PetscCall(MatMult(A, x, ax));
    PetscCall(MatMult(B, x, bx));
    PetscCall(VecNorm(ax, NORM_2, &n));
    PetscCall(VecAXPY(bx, -1.0, ax));
    PetscCall(VecNorm(bx, NORM_2, &d));
    *diff = PetscMax(*diff, d);
    *norm = PetscMax(*norm, n);
  }
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&ax));
  PetscCall(VecDestroy(&bx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether two block matrices of one pattern store the same values, bit for bit (this rank's part). */
static PetscErrorCode SameBlockValues(Mat A, Mat B, PetscBool *same)
{
  ClothBlockRows ra, rb;
  PetscInt       m;

  PetscFunctionBeginUser;
  PetscCall(MatGetLocalSize(A, &m, NULL));
  m /= 3;
  PetscCall(ClothBlockRowsGet(A, &ra));
  PetscCall(ClothBlockRowsGet(B, &rb));
  *same = (ra.ia[m] == rb.ia[m] && (!ra.ib || ra.ib[m] == rb.ib[m])) ? PETSC_TRUE : PETSC_FALSE;
  for (PetscInt k = 0; *same && k < 9 * ra.ia[m]; k++)
    if (ra.va[k] != rb.va[k] || (k % 9 == 0 && ra.ja[k / 9] != rb.ja[k / 9])) *same = PETSC_FALSE;
  for (PetscInt k = 0; *same && ra.ib && k < 9 * ra.ib[m]; k++)
    if (ra.vb[k] != rb.vb[k]) *same = PETSC_FALSE;
  PetscCall(ClothBlockRowsRestore(&ra));
  PetscCall(ClothBlockRowsRestore(&rb));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A system assembled into a new matrix (through MatSetValuesBlockedLocal), then again into that matrix (in place),
   must not change by a bit. */
static PetscErrorCode CheckAssembledInPlace(Cloth cloth, MatType type, PetscReal h)
{
  Mat       A, first;
  Vec       x, v, rhs;
  PetscBool same, all;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(Assemble(cloth, PETSC_TRUE, type, h, &A, &rhs));
  PetscCall(MatDuplicate(A, MAT_COPY_VALUES, &first));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, A, rhs));
  PetscCall(SameBlockValues(first, A, &same));
  PetscCall(MPIU_Allreduce(&same, &all, 1, MPIU_BOOL, MPI_LAND, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "assembled in place against through MatSetValuesBlockedLocal: %s\n", all ? "the same values" : "different values"));
  PetscCheck(all, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "The assembly in place differs from the first assembly");
  PetscCall(MatDestroy(&first));
  PetscCall(MatDestroy(&A));
  PetscCall(VecDestroy(&rhs));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal h = 1.0;
  Scene           scene;
  Cloth           cloth;
  Mat             Af, Ae;
  Vec             rf, re;
  PetscRandom     rnd;
  PetscReal       nA, dA, nr, dr;
  char            type[64] = MATBAIJ;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsSetValue(NULL, "-cloth_stiffness", "gauss_newton"));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, "tests/data/jacobian_two_pieces.yaml", &scene));
  PetscCall(ClothCreate(PETSC_COMM_WORLD, scene, &cloth));
  PetscCall(ClothSetFromOptions(cloth));
  PetscCall(ClothSetUp(cloth));
  PetscCall(TestPerturbState(cloth, 2024, 2e-3, 0.3));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 77));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(SetContacts(cloth, rnd));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-matrix_type", type, sizeof(type), NULL));
  PetscCall(Assemble(cloth, PETSC_TRUE, type, h, &Af, &rf));
  PetscCall(Assemble(cloth, PETSC_FALSE, type, h, &Ae, &re));
  PetscCall(ProductDifference(Ae, Af, &dA, &nA));
  PetscCall(VecNorm(re, NORM_2, &nr));
  PetscCall(VecAXPY(re, -1.0, rf));
  PetscCall(VecNorm(re, NORM_2, &dr));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "factored against expanded: |dA x| %g (|A x| %g), rhs %g (|rhs| %g)\n", (double)dA, (double)nA, (double)dr, (double)nr));
  PetscCheck(nA > 0 && nr > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Empty system: |A| %g, |rhs| %g", (double)nA, (double)nr);
  PetscCheck(dA <= 1e-12 * nA, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Factored and expanded stiffness differ: |dA x| %g against |A x| %g", (double)dA, (double)nA);
  PetscCheck(dr <= 1e-12 * nr, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Factored and expanded K v differ: |d rhs| %g against |rhs| %g", (double)dr, (double)nr);
  PetscCall(CheckAssembledInPlace(cloth, type, h));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(MatDestroy(&Af));
  PetscCall(MatDestroy(&Ae));
  PetscCall(VecDestroy(&rf));
  PetscCall(VecDestroy(&re));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
