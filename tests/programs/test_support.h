/* Helpers shared by the test programs (linked into each by clothsim_add_test_program). */
#pragma once
#include "scene.h"
#include "cloth.h"
#include "run.h"

/* Adds seeded uniform noise in [-1, 1] times amplitude to the positions and times speed to the
   velocities (the same seed gives the same state on a given rank count). Collective. */
PetscErrorCode TestPerturbState(Cloth cloth, PetscInt seed, PetscReal amplitude, PetscReal speed);
/* Reads -scene FILE (required) and -grid N (optional), and sets up the cloth. Collective. */
PetscErrorCode TestClothFromOptions(Scene *scene, Cloth *cloth);
/* Reads -scene FILE (required) and creates and sets up a run from the options, ready to solve. Collective. */
PetscErrorCode TestRunFromOptions(Scene *scene, ClothRun *run);
/* Reads the expectation -NAME (an option such as "-expect_levels"), which must be given: a missing one is an error
   naming it, not a check against a default (a default of 0 as a lower bound would turn the check into ">= 0").
   Collective. */
PetscErrorCode TestGetExpectationInt(const char name[], PetscInt *value);
PetscErrorCode TestGetExpectationReal(const char name[], PetscReal *value);
/* Refuses -expect_* options that nothing read (a misspelled expectation would otherwise turn a test into
   "runs without crashing"). Call at the end, after every expectation has been read. Collective. */
PetscErrorCode TestCheckExpectationsUsed(void);
