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

/* The natural-order positions of the cloth now (a new Vec). */
static PetscErrorCode NaturalPositions(Cloth cloth, Vec *natural)
{
  Vec x;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, NULL));
  PetscCall(ClothCreateNaturalVec(cloth, natural));
  PetscCall(ClothScatterToNatural(cloth, x, *natural, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest drop of any particle below its height (y) in start, over the whole cloth. The start is the run's own
   copy taken before it: the model's initial positions are freed once the cloth is set up. */
static PetscErrorCode LargestDrop(Cloth cloth, Vec start, PetscReal *drop)
{
  Vec                natural;
  const PetscScalar *a, *a0;
  PetscInt           n;
  PetscReal          local = -PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  PetscCall(NaturalPositions(cloth, &natural));
  PetscCall(VecGetLocalSize(natural, &n));
  PetscCall(VecGetArrayRead(natural, &a));
  PetscCall(VecGetArrayRead(start, &a0));
  for (PetscInt i = 0; i < n / 3; i++) local = PetscMax(local, PetscRealPart(a0[3 * i + 1] - a[3 * i + 1]));
  PetscCall(VecRestoreArrayRead(start, &a0));
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
  Vec         x, v, start;
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
  PetscCall(ClothRunGetCloth(run, &cloth));
  PetscCall(NaturalPositions(cloth, &start));
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  PetscCall(LargestDrop(cloth, start, &drop));
  PetscCall(VecDestroy(&start));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "final kinetic energy %.6e J, largest drop %.9e m\n", (double)e.kinetic, (double)drop));
  if (check_ke) PetscCheck(e.kinetic < ke_below, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "kinetic energy %g J is not below %g J: not at rest", (double)e.kinetic, (double)ke_below);
  if (check_elongation) PetscCheck(PetscAbsReal(drop - elongation) <= rtol * elongation, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "elongation %.9e m differs from %.9e m by more than %g relative", (double)drop, (double)elongation, (double)rtol);
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
