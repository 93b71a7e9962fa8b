/* clothsim driver: reads the scene and runs it; every object is set up from the options database. */
#include <petscsys.h>
#include "scene.h"
#include "run.h"

static const char help[] = "clothsim: woven fabric as a particle system (MPI + PETSc).\n"
                           "Usage: mpiexec -n P clothsim -scene input/NAME.yaml [options]\n"
                           "Run-level options override the scene's run: block; PETSc's -ksp_*, -pc_*, -log_view pass through.\n";

int main(int argc, char **argv)
{
  char      scene_path[PETSC_MAX_PATH_LEN] = "";
  PetscBool has_scene;
  Scene     scene;
  ClothRun  run;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", scene_path, sizeof(scene_path), &has_scene));
  PetscCheck(has_scene, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "No scene given: run as clothsim -scene input/NAME.yaml (see -help)");
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, scene_path, &scene));
  PetscCall(ClothRunCreate(PETSC_COMM_WORLD, scene, &run));
  PetscCall(ClothRunSetFromOptions(run));
  PetscCall(SceneView(scene, PETSC_VIEWER_STDOUT_WORLD));
  PetscCall(ClothRunSetUp(run));
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
