/* Helpers shared by the test programs (see test_support.h). */
#include "test_support.h"

PetscErrorCode TestPerturbState(Cloth cloth, PetscInt seed, PetscReal amplitude, PetscReal speed)
{
  Vec         x, v, noise;
  PetscRandom rnd;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  PetscCall(PetscRandomSetInterval(rnd, -1.0, 1.0));
  PetscCall(PetscRandomSetSeed(rnd, (unsigned long)seed));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(VecDuplicate(x, &noise));
  PetscCall(VecSetRandom(noise, rnd));
  PetscCall(VecAXPY(x, amplitude, noise));
  PetscCall(VecSetRandom(noise, rnd));
  PetscCall(VecAXPY(v, speed, noise));
  PetscCall(VecDestroy(&noise));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode TestClothFromOptions(Scene *scene, Cloth *cloth)
{
  char      path[PETSC_MAX_PATH_LEN];
  PetscInt  grid = 0;
  PetscBool flg;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &flg));
  PetscCheck(flg, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give -scene FILE");
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-grid", &grid, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, scene));
  if (grid > 0) PetscCall(SceneSetGridSize(*scene, grid));
  PetscCall(ClothCreate(PETSC_COMM_WORLD, *scene, cloth));
  PetscCall(ClothSetFromOptions(*cloth));
  PetscCall(ClothSetUp(*cloth));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode TestRunFromOptions(Scene *scene, ClothRun *run)
{
  char      path[PETSC_MAX_PATH_LEN];
  PetscBool flg;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &flg));
  PetscCheck(flg, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give -scene FILE");
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, scene));
  PetscCall(ClothRunCreate(PETSC_COMM_WORLD, *scene, run));
  PetscCall(ClothRunSetFromOptions(*run));
  PetscCall(ClothRunSetUp(*run));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode TestGetExpectationInt(const char name[], PetscInt *value)
{
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetInt(NULL, NULL, name, value, &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give %s: this test's expectation has no default, so that a missing one cannot turn its check into one that always passes", name);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode TestGetExpectationReal(const char name[], PetscReal *value)
{
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(NULL, NULL, name, value, &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give %s: this test's expectation has no default, so that a missing one cannot turn its check into one that always passes", name);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode TestCheckExpectationsUsed(void)
{
  PetscInt N;
  char   **names, **values;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &N, &names, &values));
  for (PetscInt i = 0; i < N; i++) {
    const char *name = names[i][0] == '-' ? names[i] + 1 : names[i];
    PetscBool   expectation;

    PetscCall(PetscStrncmp(name, "expect_", 7, &expectation));
    PetscCheck(!expectation, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "The option -%s %s was given but this test reads no such expectation (misspelled, or not meaningful here)", name, values[i] ? values[i] : "");
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &N, &names, &values));
  PetscFunctionReturn(PETSC_SUCCESS);
}
