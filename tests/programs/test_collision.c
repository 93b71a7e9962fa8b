/* Runs a scene with bodies through ClothRun and checks its contacts:
   -expect_inside_at_most K      at the end, at most K particles inside a body by the robust inside test
                                 (generalized winding number for meshes; signed distance for spheres, planes);
   -expect_verified_at_least N   with -collision_verify, the grid and brute-force searches agreed on at least N
                                 crossings (a difference stops the run with an error at once);
   -expect_contacts_at_least N   at least N particles in contact at the last step (the cloth did land).
   Each is required (-expect_verified_at_least with -collision_verify, and only then): a missing one is an error,
   not a check against a default. Any other -expect_* option is refused. Prints the measured counts on rank 0; they do not depend on the
   number of ranks. */
#include "scene.h"
#include "run.h"
#include "test_support.h"

int main(int argc, char **argv)
{
  Scene               scene;
  ClothRun            run;
  ClothCollision      collision;
  ClothCollisionStats stats;
  PetscInt            inside, inside_max, verified_min = 0, contacts_min;
  PetscBool           verify = PETSC_FALSE;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(TestGetExpectationInt("-expect_inside_at_most", &inside_max));
  PetscCall(TestGetExpectationInt("-expect_contacts_at_least", &contacts_min));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-collision_verify", &verify, NULL));
  if (verify) PetscCall(TestGetExpectationInt("-expect_verified_at_least", &verified_min)); /* without -collision_verify nothing is verified: refused below as unused */
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(TestRunFromOptions(&scene, &run));
  PetscCall(ClothRunGetCollision(run, &collision));
  PetscCheck(collision, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "scene %s has no bodies", scene->path);
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothCollisionGetStats(collision, &stats));
  PetscCall(ClothCollisionCountInside(collision, &inside));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "pushed out at set-up %" PetscInt_FMT ", contacts at the last step %" PetscInt_FMT " (held %" PetscInt_FMT "), crossings verified against brute force %" PetscInt_FMT ", particles inside a body at the end %" PetscInt_FMT "\n",
                        stats.pushed_out, stats.contacts, stats.held, stats.verified, inside));
  PetscCheck(inside <= inside_max, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%" PetscInt_FMT " particles end inside a body (at most %" PetscInt_FMT " allowed)", inside, inside_max);
  PetscCheck(stats.verified >= verified_min, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "only %" PetscInt_FMT " crossings were verified against brute force, expected at least %" PetscInt_FMT, stats.verified, verified_min);
  PetscCheck(stats.contacts >= contacts_min, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "only %" PetscInt_FMT " particles in contact at the end, expected at least %" PetscInt_FMT, stats.contacts, contacts_min);
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
