/* The Gauss-Newton stiffness assembled from its factors against the same stiffness expanded first, in parallel.

   On the perturbed two-piece cloth with every angle kind (tests/data/jacobian_two_pieces.yaml) and contact constraints
   of every kind (free, held against a plane with a random normal, stuck, on owned particles and so on ghosts), the
   implicit system assembled from each element's factors (S_a q_r, then sum_r lambda_r (S q_r)(S q_r)^T and K v from
   the factors) must equal the system assembled from the expanded element matrices filtered block by block
   (S_a H_ab S_b, K v = H v): matrix and right-hand side to 1e-12 relative (the same sums in another order). The step
   h = 1 s makes h^2 K and h^2 K v dominate the masses and forces, so that the comparison is one of the stiffness. */
#include <petscmat.h>
#include "scene.h"
#include "cloth.h"
#include "test_support.h"

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

/* The system assembled with the factored or the expanded path. */
static PetscErrorCode Assemble(Cloth cloth, PetscBool factored, PetscReal h, Mat *A, Vec *rhs)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothSetFactoredStiffness(cloth, factored));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, A));
  PetscCall(ClothCreateStateVec(cloth, rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, *A, *rhs));
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
  PetscCall(Assemble(cloth, PETSC_TRUE, h, &Af, &rf));
  PetscCall(Assemble(cloth, PETSC_FALSE, h, &Ae, &re));
  PetscCall(MatNorm(Ae, NORM_FROBENIUS, &nA));
  PetscCall(MatAXPY(Ae, -1.0, Af, SAME_NONZERO_PATTERN));
  PetscCall(MatNorm(Ae, NORM_FROBENIUS, &dA));
  PetscCall(VecNorm(re, NORM_2, &nr));
  PetscCall(VecAXPY(re, -1.0, rf));
  PetscCall(VecNorm(re, NORM_2, &dr));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "factored against expanded: matrix %g (|A| %g), rhs %g (|rhs| %g)\n", (double)dA, (double)nA, (double)dr, (double)nr));
  PetscCheck(nA > 0 && nr > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Empty system: |A| %g, |rhs| %g", (double)nA, (double)nr);
  PetscCheck(dA <= 1e-12 * nA, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Factored and expanded stiffness differ: |dA| %g against |A| %g", (double)dA, (double)nA);
  PetscCheck(dr <= 1e-12 * nr, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Factored and expanded K v differ: |d rhs| %g against |rhs| %g", (double)dr, (double)nr);
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
