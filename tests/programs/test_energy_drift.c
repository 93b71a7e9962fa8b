/* Undamped symplectic Euler on a free sheet (tests/data/free_sheet.yaml) with a pseudo-random initial
   velocity field (the same on any number of ranks), 10,000 steps of 1e-5 s (h omega_max ~ 0.05). Symplectic Euler's energy error is
   bounded and oscillates (order h omega), it does not drift: the test asserts
   - the largest deviation from the initial energy stays below 1%, and
   - the drift, mean energy over the last 1,000 steps against the first 1,000, below 0.1%.
   Prints both. */
#include <petscvec.h>
#include "scene.h"
#include "cloth.h"
#include "integrator.h"
#include "test_support.h"

/* v_k = 0.5 sin(1.7 k + 2.3 c + c^2) m/s for particle k (natural order), component c. */
static PetscErrorCode SetInitialVelocity(Cloth cloth, Vec v)
{
  Vec          natural;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(VecGetOwnershipRange(natural, &lo, &hi));
  PetscCall(VecGetArray(natural, &a));
  for (PetscInt i = lo; i < hi; i++) a[i - lo] = 0.5 * PetscSinReal(1.7 * (i / 3) + 2.3 * (i % 3) + (i % 3) * (i % 3));
  PetscCall(VecRestoreArray(natural, &a));
  PetscCall(ClothScatterToNatural(cloth, v, natural, SCATTER_REVERSE));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal bound = 0.01, drift_bound = 1e-3;
  PetscReal       dt = 1e-5;
  const PetscInt  steps = 10000;
  Scene           scene;
  Cloth           cloth;
  ClothIntegrator integ;
  Vec             x, v;
  ClothEnergy     e;
  PetscReal       e0, worst = 0, first = 0, last = 0, drift;
  PetscBool       ok;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-dt", &dt, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, "tests/data/free_sheet.yaml", &scene));
  PetscCall(ClothCreate(PETSC_COMM_WORLD, scene, &cloth));
  PetscCall(ClothSetUp(cloth));
  PetscCall(ClothIntegratorCreate(cloth, &integ));
  PetscCall(ClothIntegratorSetType(integ, "symplectic"));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(SetInitialVelocity(cloth, v));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  e0 = e.kinetic + e.gravity + e.elastic;
  for (PetscInt n = 0; n < steps; n++) {
    PetscCall(ClothIntegratorStep(integ, dt, &ok, NULL));
    PetscCheck(ok, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "step %" PetscInt_FMT " failed", n);
    if (n % 10 == 0) {
      PetscReal total;
      PetscCall(ClothComputeEnergy(cloth, x, v, &e));
      total = e.kinetic + e.gravity + e.elastic;
      worst = PetscMax(worst, PetscAbsReal(total - e0) / e0);
      if (n < 1000) first += total / 100;
      if (n >= steps - 1000) last += total / 100;
    }
  }
  drift = PetscAbsReal(last - first) / e0;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "initial energy %.6e J; over %" PetscInt_FMT " steps largest relative deviation %.3e, drift of the mean %.3e\n", (double)e0, steps, (double)worst, (double)drift));
  PetscCheck(worst < bound, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "energy deviated by %g (relative), bound %g", (double)worst, (double)bound);
  PetscCheck(drift < drift_bound, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "mean energy drifted by %g (relative), bound %g", (double)drift, (double)drift_bound);
  PetscCall(ClothIntegratorDestroy(&integ));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
