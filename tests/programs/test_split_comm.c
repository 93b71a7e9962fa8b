/* Two independent simulations side by side on the two halves of MPI_COMM_WORLD (issue 23, item 4): every library
   object must use its own communicator, never PETSC_COMM_WORLD, or the halves would wait for each other or mix
   their data. Each half runs -scene with its own -output_dir (the options database is per process), -output_dir_0
   for the first half, -output_dir_1 for the second. tests/drivers/check_split_comm.sh compares each half's checkpoint with
   a run of the same scene alone on as many ranks. */
#include <petscsys.h>
#include "scene.h"
#include "run.h"
#include "test_support.h"

int main(int argc, char **argv)
{
  char        scene_path[PETSC_MAX_PATH_LEN] = "", dir[PETSC_MAX_PATH_LEN] = "", option[32];
  PetscMPIInt rank, size;
  int         half;
  MPI_Comm    comm;
  Scene       scene;
  ClothRun    run;
  PetscBool   set;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCheck(size % 2 == 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "Run on an even number of ranks, got %d", (int)size);
  half = rank < size / 2 ? 0 : 1;
  PetscCallMPI(MPI_Comm_split(PETSC_COMM_WORLD, half, rank, &comm));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", scene_path, sizeof(scene_path), &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give -scene");
  PetscCall(PetscSNPrintf(option, sizeof(option), "-output_dir_%d", half));
  PetscCall(PetscOptionsGetString(NULL, NULL, option, dir, sizeof(dir), &set));
  PetscCheck(set, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Give %s", option);
  PetscCall(PetscOptionsSetValue(NULL, "-output_dir", dir)); /* this process's database only */
  PetscCall(SceneCreateFromFile(comm, scene_path, &scene));
  PetscCall(ClothRunCreate(comm, scene, &run));
  PetscCall(ClothRunSetFromOptions(run));
  PetscCall(ClothRunSetUp(run));
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCallMPI(MPI_Comm_free(&comm));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
