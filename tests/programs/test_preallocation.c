/* Exact preallocation of the implicit system matrix (ClothCreateMatrix), on any number of ranks.

   Options: -scene FILE [-grid N]. For BAIJ and SBAIJ (-implicit_mat_type), assembles the implicit
   system twice (at the initial state and at a perturbed one) and checks with MatGetInfo
   (MAT_GLOBAL_SUM) that
   - no malloc happened during assembly (info.mallocs == 0),
   - every preallocated entry is used (nz_allocated == nz_used),
   - the number of entries is the interaction graph's: 9 (N + 2E) for BAIJ, 9 (N + E) stored by
     SBAIJ (upper triangle), N particles and E graph edges (ClothModelGetAdjacency);
   and that both formats hold the same operator (A x for one x, to 1e-13 relative).
   Prints nothing unless a check fails. */
#include <petscmat.h>
#include "scene.h"
#include "cloth.h"
#include "test_support.h"

/* Creates the matrix in format `type`, assembles it at the current state, and checks MatGetInfo. */
static PetscErrorCode AssembleAndCheck(Cloth cloth, const char type[], PetscLogDouble expected_nz, Mat *A)
{
  const PetscReal h = 1.0 / 240.0;
  Vec             x, v, rhs;
  MatInfo         info;
  MatType         actual;
  PetscBool       match;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsSetValue(NULL, "-implicit_mat_type", type));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, A));
  PetscCall(MatGetType(*A, &actual));
  PetscCall(PetscStrendswith(actual, type, &match));
  PetscCheck(match, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "-implicit_mat_type %s gave a matrix of type %s", type, actual);
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothCreateStateVec(cloth, &rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, *A, rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, *A, rhs)); /* re-assembly reuses the pattern */
  PetscCall(MatGetInfo(*A, MAT_GLOBAL_SUM, &info));
  PetscCheck(info.mallocs == 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%s: %g mallocs during assembly: the preallocation is too small", type, info.mallocs);
  PetscCheck(info.nz_allocated == info.nz_used, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%s: %g entries preallocated but %g used: the preallocation is not exact", type, info.nz_allocated, info.nz_used);
  PetscCheck(info.nz_used == expected_nz, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%s: %g entries used, the interaction graph has %g", type, info.nz_used, expected_nz);
  PetscCall(VecDestroy(&rhs));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* |A x - B x| / |A x| for a random x. */
static PetscErrorCode OperatorDifference(Mat A, Mat B, PetscReal *difference)
{
  Vec         x, ax, bx;
  PetscRandom rnd;
  PetscReal   norm;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(A, &x, &ax));
  PetscCall(VecDuplicate(ax, &bx));
  PetscCall(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  PetscCall(VecSetRandom(x, rnd));
  PetscCall(MatMult(A, x, ax));
  PetscCall(MatMult(B, x, bx));
  PetscCall(VecNorm(ax, NORM_2, &norm));
  PetscCall(VecAXPY(bx, -1.0, ax));
  PetscCall(VecNorm(bx, NORM_2, difference));
  *difference /= norm;
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&ax));
  PetscCall(VecDestroy(&bx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscInt   *xadj, *adjncy, edges, n;
  Scene      scene;
  Cloth      cloth;
  ClothModel model;
  Mat        baij, sbaij;
  PetscReal  difference;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(ClothModelGetAdjacency(model, &xadj, &adjncy));
  n     = model->nparticles;
  edges = xadj[n] / 2;
  PetscCall(TestPerturbState(cloth, 7, 1e-3, 0.1));
  PetscCall(AssembleAndCheck(cloth, MATBAIJ, 9.0 * (n + 2 * edges), &baij));
  PetscCall(AssembleAndCheck(cloth, MATSBAIJ, 9.0 * (n + edges), &sbaij));
  PetscCall(OperatorDifference(baij, sbaij, &difference));
  PetscCheck(difference < 1e-13, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "BAIJ and SBAIJ assemblies differ: |A x - S x| / |A x| = %g", (double)difference);
  PetscCall(MatDestroy(&baij));
  PetscCall(MatDestroy(&sbaij));
  PetscCall(PetscFree(xadj));
  PetscCall(PetscFree(adjncy));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
