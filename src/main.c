/* clothsim driver: reads the scene, wires the objects together and runs the time loop. */
#include <petscsys.h>
#include "scene.h"

static const char help[] = "clothsim: woven fabric as a particle system (MPI + PETSc).\n"
                           "Usage: mpiexec -n P clothsim -scene input/NAME.yaml [options]\n";

int main(int argc, char **argv)
{
  char      scene_path[PETSC_MAX_PATH_LEN] = "";
  PetscBool has_scene;
  Scene     scene;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", scene_path, sizeof(scene_path), &has_scene));
  PetscCheck(has_scene, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "No scene given: run as clothsim -scene input/NAME.yaml (see -help)");
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, scene_path, &scene));
  PetscCall(SceneView(scene, PETSC_VIEWER_STDOUT_WORLD));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
