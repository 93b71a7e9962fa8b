/* clothsim driver: reads the scene and runs it; every object is set up from the options database. */
#include <petscsys.h>
#include "util.h"
#include "scene.h"
#include "run.h"
#include "errors.h"
#include "log.h"
#include "options.h"

static const char help[] = "clothsim: woven fabric as a particle system (MPI + PETSc).\n"
                           "Usage: mpiexec -n P clothsim -scene input/NAME.yaml [options]\n"
                           "Run-level options override the scene's run: block; PETSc's -ksp_*, -pc_*, -log_view pass through.\n"
                           "Options that nothing used (misspelled, or meant for another integrator) are listed at the end of the run.\n";

/* The scene, and how errors end the run: a user error (bad input, a file that cannot be read or written, a
   diverged run) prints its message alone with a dedicated exit status (errors.h), unless -debug_errors asks
   for PETSc's traceback. */
static PetscErrorCode GetScenePath(char path[], size_t size)
{
  PetscBool has_scene = PETSC_FALSE, debug_errors = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "clothsim", "main");
  PetscCall(PetscOptionsString("-scene", "Scene file (YAML) to simulate", "SceneCreateFromFile", path, path, size, &has_scene));
  PetscCall(PetscOptionsBool("-debug_errors", "Report user errors (bad input, files, divergence) with PETSc's full traceback instead of one message", "ClothErrorHandlerPush", debug_errors, &debug_errors, NULL));
  PetscOptionsEnd();
  if (!debug_errors) PetscCall(ClothErrorHandlerPush());
  PetscCall(ClothOptionsCheckStringLength(PETSC_COMM_WORLD, "-scene", size - 1, NULL)); /* PETSc cut a longer one to size - 1 */
  PetscCheck(has_scene, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "No scene given: run as clothsim -scene input/NAME.yaml (see -help)");
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PETSc ignores options nobody asked for, so a misspelled -dtt would silently run with the default step.
   Lists them on stderr (rank 0). With -options_left PETSc prints its own list in PetscFinalize instead. */
static PetscErrorCode WarnUnusedOptions(MPI_Comm comm)
{
  PetscBool options_left = PETSC_FALSE, set;
  PetscInt  nunused;
  char    **names, **values;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-options_left", &options_left, &set));
  if (set && options_left) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscOptionsLeftGet(NULL, &nunused, &names, &values));
  if (nunused > 0) {
    PetscCall(PetscFPrintf(comm, PETSC_STDERR, "WARNING: %" PetscInt_FMT " option(s) were given but never used (misspelled, or not meant for this run):\n", nunused));
    for (PetscInt i = 0; i < nunused; i++) PetscCall(PetscFPrintf(comm, PETSC_STDERR, "  -%s %s\n", names[i], values[i] ? values[i] : ""));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &nunused, &names, &values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char     scene_path[PETSC_MAX_PATH_LEN] = "";
  Scene    scene;
  ClothRun run;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(GetScenePath(scene_path, sizeof(scene_path)));
  PetscCall(ClothLogRegister());
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_SCENE));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, scene_path, &scene));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_SCENE));
  PetscCall(ClothRunCreate(PETSC_COMM_WORLD, scene, &run));
  PetscCall(ClothRunSetFromOptions(run));
  PetscCall(ClothOptionsCheckMisspelled(PETSC_COMM_WORLD)); /* before the run, not only in its last words */
  PetscCall(SceneView(scene, PETSC_VIEWER_STDOUT_WORLD));
  PetscCall(ClothRunSetUp(run));
  PetscCall(ClothRunSolve(run));
  PetscCall(ClothRunDestroy(&run));
  PetscCall(SceneDestroy(&scene));
  PetscCall(WarnUnusedOptions(PETSC_COMM_WORLD));
  PetscCall(PetscFinalize());
  return 0;
}
