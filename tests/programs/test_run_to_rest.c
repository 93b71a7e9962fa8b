/* Runs a scene with the given run options (-scene, -integrator, -dt, -t_final, ...), then checks:
   -expect_ke_below J        final kinetic energy below J
   -expect_elongation M      the lowest particle has dropped M metres below its start (spring-mass),
   -expect_rtol R            ... within relative error R (default 1e-6; only with -expect_elongation).
   At least one expectation is required and any other -expect_* option is refused, so that a misspelled
   one cannot turn the test into "runs without crashing".    Prints the measured values on rank 0 (they do not depend on the rank count beyond round-off). */
#include <petscvec.h>
#include "scene.h"
#include "run.h"
#include "test_support.h"

/* The largest drop of any particle below its initial height (y), over the whole cloth. */
static PetscErrorCode LargestDrop(Cloth cloth, PetscReal *drop)
{
  ClothModel         model;
  Vec                x, natural;
  const PetscScalar *a;
  PetscInt           lo, hi;
  PetscReal          local = -PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(ClothGetState(cloth, &x, NULL));
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(ClothScatterToNatural(cloth, x, natural, SCATTER_FORWARD));
  PetscCall(VecGetOwnershipRange(natural, &lo, &hi));
  PetscCall(VecGetArrayRead(natural, &a));
  for (PetscInt i = lo / 3; i < hi / 3; i++) local = PetscMax(local, model->position[3 * i + 1] - a[3 * (i - lo / 3) + 1]);
  PetscCall(VecRestoreArrayRead(natural, &a));
  PetscCallMPI(MPI_Allreduce(&local, drop, 1, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene       scene;
  ClothRun    run;
  Cloth       cloth;
  Vec         x, v;
  ClothEnergy e;
  PetscReal   ke_below = -1, elongation = -1, rtol = 1e-6, drop;
  PetscBool   check_ke, check_elongation;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_ke_below", &ke_below, &check_ke));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_elongation", &elongation, &check_elongation));
  if (check_elongation) PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_rtol", &rtol, NULL));
  PetscCall(TestCheckExpectationsUsed());
  PetscCheck(check_ke || check_elongation, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give -expect_ke_below and/or -expect_elongation: a run without an expectation checks nothing");
  PetscCall(TestRunFromOptions(&scene, &run));
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothRunGetCloth(run, &cloth));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  PetscCall(LargestDrop(cloth, &drop));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "final kinetic energy %.6e J, largest drop %.9e m\n", (double)e.kinetic, (double)drop));
  if (check_ke) PetscCheck(e.kinetic < ke_below, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "kinetic energy %g J is not below %g J: not at rest", (double)e.kinetic, (double)ke_below);
  if (check_elongation) PetscCheck(PetscAbsReal(drop - elongation) <= rtol * elongation, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "elongation %.9e m differs from %.9e m by more than %g relative", (double)drop, (double)elongation, (double)rtol);
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
