/* The assembled implicit system against finite differences of the total force, in parallel.

   On a perturbed two-piece cloth with every interaction kind (tests/data/jacobian_two_pieces.yaml),
   with the exact stiffness, A = M + h C + h^2 K must equal M - h dF/dv - h^2 dF/dr column by column,
   dF/dr and dF/dv by central differences of ClothComputeForces (relative error below 1e-6).
   Run at 1, 2 and 3 ranks: ghosts and off-rank matrix blocks take part. */
#include <petscmat.h>
#include "scene.h"
#include "cloth.h"
#include "test_support.h"

/* column = (F(s + eps e_k) - F(s - eps e_k)) / (2 eps), s = position or velocity. */
static PetscErrorCode ForceDifference(Cloth cloth, Vec s, PetscInt k, PetscReal eps, Vec column)
{
  Vec         x, v, fp;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(VecDuplicate(x, &fp));
  /* Only one rank adds the perturbation: ADD_VALUES from every rank would add it once per rank. */
  if (rank == 0) PetscCall(VecSetValue(s, k, eps, ADD_VALUES));
  PetscCall(VecAssemblyBegin(s));
  PetscCall(VecAssemblyEnd(s));
  PetscCall(ClothComputeForces(cloth, x, v, fp));
  if (rank == 0) PetscCall(VecSetValue(s, k, -2 * eps, ADD_VALUES));
  PetscCall(VecAssemblyBegin(s));
  PetscCall(VecAssemblyEnd(s));
  PetscCall(ClothComputeForces(cloth, x, v, column));
  if (rank == 0) PetscCall(VecSetValue(s, k, eps, ADD_VALUES));
  PetscCall(VecAssemblyBegin(s));
  PetscCall(VecAssemblyEnd(s));
  PetscCall(VecAYPX(column, -1.0, fp));
  PetscCall(VecScale(column, 1.0 / (2 * eps)));
  PetscCall(VecDestroy(&fp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal  h = 0.01, eps = 1e-7;
  Scene            scene;
  Cloth            cloth;
  Mat              A;
  Vec              x, v, rhs, e, acol, dfdr, dfdv, expected;
  const PetscReal *mass;
  PetscInt         nlocal, nglobal, rstart;
  PetscReal        worst = 0, scale = 0;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, "tests/data/jacobian_two_pieces.yaml", &scene));
  PetscCall(ClothCreate(PETSC_COMM_WORLD, scene, &cloth));
  PetscCall(ClothSetFromOptions(cloth));
  PetscCall(ClothSetUp(cloth));
  PetscCall(ClothSetExactStiffness(cloth, PETSC_TRUE));
  PetscCall(TestPerturbState(cloth, 2024, 2e-3, 0.3));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothGetSizes(cloth, &nlocal, &nglobal));
  PetscCall(ClothGetMasses(cloth, &mass, NULL));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, &A));
  PetscCall(ClothCreateStateVec(cloth, &rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, h, x, v, A, rhs));
  PetscCall(MatCreateVecs(A, &e, &acol));
  PetscCall(ClothCreateStateVec(cloth, &dfdr)); /* forces need the ghosted layout */
  PetscCall(ClothCreateStateVec(cloth, &dfdv));
  PetscCall(VecDuplicate(acol, &expected));
  PetscCall(VecGetOwnershipRange(acol, &rstart, NULL));
  for (PetscInt k = 0; k < 3 * nglobal; k++) {
    PetscReal err, ref;
    PetscCall(VecZeroEntries(e));
    PetscCall(VecSetValue(e, k, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(e));
    PetscCall(VecAssemblyEnd(e));
    PetscCall(MatMult(A, e, acol));
    PetscCall(ForceDifference(cloth, x, k, eps, dfdr));
    PetscCall(ForceDifference(cloth, v, k, eps, dfdv));
    /* expected = M e - h dF/dv - h^2 dF/dr */
    PetscCall(VecCopy(e, expected));
    {
      PetscScalar *a;
      PetscCall(VecGetArray(expected, &a));
      for (PetscInt i = 0; i < 3 * nlocal; i++) a[i] *= mass[i / 3];
      PetscCall(VecRestoreArray(expected, &a));
    }
    PetscCall(VecAXPBYPCZ(expected, -h, -h * h, 1.0, dfdv, dfdr));
    PetscCall(VecNorm(expected, NORM_INFINITY, &ref));
    PetscCall(VecAXPY(expected, -1.0, acol));
    PetscCall(VecNorm(expected, NORM_INFINITY, &err));
    worst = PetscMax(worst, err);
    scale = PetscMax(scale, ref);
  }
  PetscCheck(worst / scale < 1e-6, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Assembled system differs from finite differences: max error %g, relative %g", (double)worst, (double)(worst / scale));
  PetscCall(VecDestroy(&e));
  PetscCall(VecDestroy(&acol));
  PetscCall(VecDestroy(&dfdr));
  PetscCall(VecDestroy(&dfdv));
  PetscCall(VecDestroy(&expected));
  PetscCall(VecDestroy(&rhs));
  PetscCall(MatDestroy(&A));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
