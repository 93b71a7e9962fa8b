/* Scene reader: loads input/hanging_sheet.yaml and a two-piece scene and checks every value read, the
   resolution of pins, -grid resizing and the fingerprint. Prints nothing unless a check fails.

   Run from the source directory (ctest does): mpiexec -n P build/test_scene [-hanging FILE] [-two_pieces FILE] */
#include <petscsys.h>
#include "scene.h"
#include "test_support.h"

#define CheckInt(comm, got, want, what) PetscCheck((got) == (want), comm, PETSC_ERR_PLIB, "%s: got %" PetscInt_FMT ", expected %" PetscInt_FMT, what, (PetscInt)(got), (PetscInt)(want))
#define CheckReal(comm, got, want, what) PetscCheck(PetscAbsReal((got) - (want)) <= 1e-12 * (1 + PetscAbsReal(want)), comm, PETSC_ERR_PLIB, "%s: got %.17g, expected %.17g", what, (double)(got), (double)(want))

static PetscErrorCode CheckVector(MPI_Comm comm, const PetscReal got[3], PetscReal x, PetscReal y, PetscReal z, const char what[])
{
  PetscFunctionBeginUser;
  CheckReal(comm, got[0], x, what);
  CheckReal(comm, got[1], y, what);
  CheckReal(comm, got[2], z, what);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckPins(MPI_Comm comm, const ScenePiece *piece, PetscInt i1, PetscInt j1)
{
  PetscFunctionBeginUser;
  CheckInt(comm, piece->npins, 2, "number of pins");
  CheckInt(comm, piece->pins[0], 0, "pin 1, i");
  CheckInt(comm, piece->pins[1], 0, "pin 1, j");
  CheckInt(comm, piece->pins[2], i1, "pin 2, i");
  CheckInt(comm, piece->pins[3], j1, "pin 2, j");
  CheckInt(comm, piece->pins_given[2], -1, "pin 2 as given, i");
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The same fingerprint on every rank. */
static PetscErrorCode CheckFingerprintAgrees(MPI_Comm comm, PetscInt64 fingerprint)
{
  PetscInt64 min = fingerprint, max = fingerprint;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &min, 1, MPIU_INT64, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &max, 1, MPIU_INT64, MPI_MAX, comm));
  PetscCheck(min == max, comm, PETSC_ERR_PLIB, "fingerprints differ between ranks");
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode TestHangingSheet(MPI_Comm comm, const char path[])
{
  Scene        scene;
  SceneFabric *fabric;
  ScenePiece  *piece;
  PetscInt64   file_fingerprint;
  PetscBool    same;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateFromFile(comm, path, &scene));
  PetscCall(PetscStrcmp(scene->name, "hanging_sheet", &same));
  PetscCheck(same, comm, PETSC_ERR_PLIB, "scene name '%s', expected 'hanging_sheet'", scene->name);
  PetscCall(CheckVector(comm, scene->gravity, 0, -9.81, 0, "gravity"));
  CheckInt(comm, scene->nfabrics, 1, "number of fabrics");
  CheckInt(comm, scene->npieces, 1, "number of pieces");
  PetscCheck(scene->single_grid, comm, PETSC_ERR_PLIB, "a one-piece scene must be single_grid");

  fabric = &scene->fabrics[0];
  CheckReal(comm, fabric->density, 0.2, "density");
  CheckReal(comm, fabric->stretch_warp, 1000, "stretch_warp");
  CheckReal(comm, fabric->stretch_weft, 1000, "stretch_weft");
  CheckReal(comm, fabric->shear, 1000, "shear");
  CheckInt(comm, fabric->shear_model, CLOTH_SHEAR_LINK, "shear_model");
  CheckReal(comm, fabric->bend_warp, 10, "bend_warp");
  CheckReal(comm, fabric->bend_weft, 10, "bend_weft");
  CheckInt(comm, fabric->bend_model, CLOTH_BEND_LINK, "bend_model");
  CheckReal(comm, fabric->damping, 0, "damping");
  CheckReal(comm, fabric->repulsion, 0, "repulsion");
  CheckReal(comm, fabric->repulsion_stiffness, 10, "repulsion_stiffness default");

  piece = &scene->pieces[0];
  CheckInt(comm, piece->fabric, 0, "piece fabric");
  CheckInt(comm, piece->nu, 65, "nu");
  CheckInt(comm, piece->nv, 65, "nv");
  CheckReal(comm, piece->size[0], 1, "size u");
  CheckReal(comm, piece->size[1], 1, "size v");
  PetscCall(CheckVector(comm, piece->origin, 0, 1, 0, "origin"));
  PetscCall(CheckVector(comm, piece->u_axis, 1, 0, 0, "u_axis"));
  PetscCall(CheckVector(comm, piece->v_axis, 0, 0, 1, "v_axis"));
  CheckInt(comm, piece->mass_distribution, CLOTH_MASS_UNIFORM, "mass");
  PetscCall(CheckPins(comm, piece, 64, 0));

  PetscCall(PetscStrcmp(scene->run.integrator, "implicit", &same));
  PetscCheck(same, comm, PETSC_ERR_PLIB, "run integrator '%s', expected 'implicit'", scene->run.integrator);
  CheckReal(comm, scene->run.dt, 1.0 / 240, "run dt");
  CheckReal(comm, scene->run.t_final, 1, "run t_final");
  CheckInt(comm, scene->run.steps, 0, "run steps (not given)");
  CheckInt(comm, scene->run.output_every, 24, "run output_every");
  CheckInt(comm, scene->run.checkpoint_every, 0, "run checkpoint_every (not given)");

  /* -grid 33: pins follow the edges, size stays, fingerprint changes; -grid 65 (the file's grid) restores it */
  file_fingerprint = scene->fingerprint;
  PetscCheck(file_fingerprint == scene->file_fingerprint, comm, PETSC_ERR_PLIB, "fingerprint before -grid differs from the file's");
  PetscCall(CheckFingerprintAgrees(comm, file_fingerprint));
  PetscCall(SceneSetGridSize(scene, 33));
  CheckInt(comm, piece->nu, 33, "nu after -grid 33");
  CheckInt(comm, piece->nv, 33, "nv after -grid 33");
  CheckReal(comm, piece->size[0], 1, "size u after -grid 33");
  PetscCall(CheckPins(comm, piece, 32, 0));
  PetscCheck(scene->fingerprint != file_fingerprint, comm, PETSC_ERR_PLIB, "-grid 33 left the fingerprint unchanged");
  PetscCall(SceneSetGridSize(scene, 65));
  PetscCall(CheckPins(comm, piece, 64, 0));
  PetscCheck(scene->fingerprint == file_fingerprint, comm, PETSC_ERR_PLIB, "-grid 65 on a 65 x 65 scene changed the fingerprint");
  PetscCall(SceneDestroy(&scene));
  PetscCheck(!scene, comm, PETSC_ERR_PLIB, "SceneDestroy left the handle set");
  PetscCall(SceneDestroy(&scene)); /* NULL-safe */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Two pieces, warp/weft stiffnesses, angle models, unnormalised axes, default name, refusal of -grid. */
static PetscErrorCode TestTwoPieces(MPI_Comm comm, const char path[])
{
  Scene          scene;
  PetscErrorCode ierr;
  PetscBool      same;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateFromFile(comm, path, &scene));
  PetscCall(PetscStrcmp(scene->name, "two_pieces", &same));
  PetscCheck(same, comm, PETSC_ERR_PLIB, "scene name '%s', expected the file's base name 'two_pieces'", scene->name);
  PetscCall(CheckVector(comm, scene->gravity, 0, -9.81, 0, "default gravity"));
  CheckInt(comm, scene->nfabrics, 2, "number of fabrics");
  CheckInt(comm, scene->npieces, 2, "number of pieces");
  PetscCheck(!scene->single_grid, comm, PETSC_ERR_PLIB, "a two-piece scene must not be single_grid");
  CheckReal(comm, scene->fabrics[1].stretch_warp, 500, "silk stretch_warp");
  CheckReal(comm, scene->fabrics[1].stretch_weft, 300, "silk stretch_weft");
  CheckReal(comm, scene->fabrics[1].bend_warp, 2e-6, "silk bend_warp");
  CheckReal(comm, scene->fabrics[1].bend_weft, 1e-6, "silk bend_weft");
  CheckInt(comm, scene->fabrics[1].shear_model, CLOTH_SHEAR_ANGLE, "silk shear_model");
  CheckInt(comm, scene->fabrics[1].bend_model, CLOTH_BEND_ANGLE, "silk bend_model");
  CheckReal(comm, scene->fabrics[1].repulsion, 0.5, "silk repulsion");
  CheckInt(comm, scene->pieces[1].fabric, 1, "back fabric");
  CheckInt(comm, scene->pieces[1].nu, 9, "back nu");
  CheckInt(comm, scene->pieces[1].nv, 5, "back nv");
  CheckInt(comm, scene->pieces[1].mass_distribution, CLOTH_MASS_AREA, "back mass (default)");
  CheckInt(comm, scene->pieces[1].npins, 0, "back pins");
  PetscCall(CheckVector(comm, scene->pieces[1].u_axis, 0.6, 0.8, 0, "back u_axis, normalised"));
  PetscCall(CheckVector(comm, scene->pieces[1].v_axis, 0, 0, -1, "back v_axis, normalised"));
  CheckInt(comm, scene->pieces[0].pins[2], 2, "front pin [-3, -1], i");
  CheckInt(comm, scene->pieces[0].pins[3], 3, "front pin [-3, -1], j");
  CheckInt(comm, scene->run.steps, 100, "run steps");
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = SceneSetGridSize(scene, 17);
  PetscCall(PetscPopErrorHandler());
  PetscCheck(ierr == PETSC_ERR_USER_INPUT, comm, PETSC_ERR_PLIB, "SceneSetGridSize on a two-piece scene returned %d, expected PETSC_ERR_USER_INPUT", (int)ierr);
  PetscCall(SceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char hanging[PETSC_MAX_PATH_LEN] = "input/hanging_sheet.yaml", two_pieces[PETSC_MAX_PATH_LEN] = "tests/data/two_pieces.yaml";

  PetscCall(PetscInitialize(&argc, &argv, NULL, "Tests the scene reader"));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-hanging", hanging, sizeof(hanging), NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-two_pieces", two_pieces, sizeof(two_pieces), NULL));
  PetscCall(TestHangingSheet(PETSC_COMM_WORLD, hanging));
  PetscCall(TestTwoPieces(PETSC_COMM_WORLD, two_pieces));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
