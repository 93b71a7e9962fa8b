/* Bending along the bias: each piece of tests/data/bias_bending.yaml (B = 1e-5 N m along warp and weft; "threads"
   without, "twist" with bend_bias = B) is rolled, isometrically, onto a cylinder of curvature kappa = 20 1/m whose
   bend runs at phi = 0, 30, 45, 60, 90 degrees to the warp, and the energy of its bending and twist elements whose
   centre lies in the middle half of the square (away from the edges, where chains end) is summed. Per the area
   those elements stand for it must be 0.5 B_phi kappa^2 with
   - threads: B_phi = B (cos^4 phi + sin^4 phi), the thread springs alone (B/2 on the bias);
   - twist:   B_phi = B at every angle (Bt = B/2 completes an isotropic plate).
   Relative tolerance -rtol (default 0.01: the discretisation, kappa h = 0.1). Prints the measured ratios. */
#include <petscsys.h>
#include "fabric.h"
#include "model.h"
#include "test_support.h"

/* Rolls the piece's flat positions flat[3 n] (pattern plane x, y; centre c) onto the cylinder of curvature kappa
   bending along the direction phi: the coordinate s along phi becomes an arc. */
static void RollOntoCylinder(PetscInt n, const PetscReal flat[], const PetscReal c[2], PetscReal kappa, PetscReal phi, PetscReal x[])
{
  const PetscReal R = 1 / kappa, cs = PetscCosReal(phi), sn = PetscSinReal(phi);

  for (PetscInt i = 0; i < n; i++) {
    const PetscReal u = flat[3 * i] - c[0], v = flat[3 * i + 1] - c[1];
    const PetscReal s = u * cs + v * sn, t = -u * sn + v * cs, s_rolled = R * PetscSinReal(s / R);

    x[3 * i]     = c[0] + s_rolled * cs - t * sn;
    x[3 * i + 1] = c[1] + s_rolled * sn + t * cs;
    x[3 * i + 2] = flat[3 * i + 2] + R * (1 - PetscCosReal(s / R));
  }
}

/* Bending rigidity B_phi measured on the piece rolled to x: the energy of its thread-bending chains and twist
   elements whose centre (mean flat position of their particles) lies within half of the piece's extent around its
   centre c, each kind per the area its elements there stand for (h^2 each; two chain families), over 0.5 kappa^2. */
static PetscErrorCode MeasureBendingRigidity(ClothModel model, PetscInt offset, PetscInt n, const PetscReal flat[], const PetscReal c[2], PetscReal half, PetscReal h, PetscReal kappa, const PetscReal x[], PetscReal *B_phi)
{
  PetscReal energy[2] = {0, 0};
  PetscInt  count[2]  = {0, 0}; /* chains, twists */

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < model->nangles; a++) {
    const ClothAngle *angle = &model->angles[a];
    const PetscInt    np = ClothAngleParticleCount(angle->kind), kind = angle->kind == CLOTH_ANGLE_TWIST ? 1 : 0;
    const PetscReal  *xs[CLOTH_ANGLE_MAX_PARTICLES];
    PetscReal         centre[2] = {0, 0}, e;

    if (angle->p[0] < offset || angle->p[0] >= offset + n) continue;
    PetscCheck(angle->kind == CLOTH_ANGLE_CHAIN || angle->kind == CLOTH_ANGLE_TWIST, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "expected only bending chains and twist elements (shear 0)");
    for (PetscInt k = 0; k < np; k++) {
      xs[k] = &x[3 * (angle->p[k] - offset)];
      for (PetscInt d = 0; d < 2; d++) centre[d] += flat[3 * (angle->p[k] - offset) + d] / np;
    }
    if (PetscAbsReal(centre[0] - c[0]) > half || PetscAbsReal(centre[1] - c[1]) > half) continue;
    PetscCall(ClothAngleEvaluate(angle, xs, CLOTH_STIFFNESS_EXACT, &e, NULL, NULL));
    energy[kind] += e;
    count[kind]++;
  }
  *B_phi = energy[0] / (0.5 * kappa * kappa * h * h * 0.5 * count[0]) + (count[1] ? energy[1] / (0.5 * kappa * kappa * h * h * count[1]) : 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal deg = PETSC_PI / 180, kappa = 20, B = 1e-5;
  const PetscReal angles[]                 = {0, 30, 45, 60, 90};
  char            path[PETSC_MAX_PATH_LEN] = "tests/data/bias_bending.yaml";
  PetscReal       rtol                     = 0.01;
  Scene           scene;
  ClothModel      model;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-rtol", &rtol, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(ClothModelCreate(scene, &model));
  for (PetscInt p = 0; p < scene->npieces; p++) {
    const PetscInt   offset = model->piece_offset[p], n = model->piece_offset[p + 1] - offset;
    const PetscReal *flat = &model->position[3 * offset];
    const PetscReal  side = scene->pieces[p].size[0], c[2] = {flat[0] + 0.5 * side, flat[1] + 0.5 * side};
    const PetscReal  h = side / (scene->pieces[p].nu - 1), half = 0.25 * side + 0.01 * h; /* middle half, its nodes included */
    const PetscBool  isotropic = FabricTwistRigidity(&scene->fabrics[scene->pieces[p].fabric]) > 0;
    PetscReal       *x;

    PetscCall(PetscMalloc1(3 * n, &x));
    for (size_t k = 0; k < sizeof(angles) / sizeof(angles[0]); k++) {
      const PetscReal phi = angles[k] * deg, c4 = PetscPowReal(PetscCosReal(phi), 4), s4 = PetscPowReal(PetscSinReal(phi), 4);
      const PetscReal expected = isotropic ? B : B * (c4 + s4);
      PetscReal       measured;

      RollOntoCylinder(n, flat, c, kappa, phi, x);
      PetscCall(MeasureBendingRigidity(model, offset, n, flat, c, half, h, kappa, x, &measured));
      PetscCall(
          PetscPrintf(PETSC_COMM_WORLD, "%-8s bend at %2.0f degrees to the warp: B_phi %.5e N m (expected %.5e, relative %+.2e)\n", scene->pieces[p].name, (double)angles[k], (double)measured, (double)expected, (double)(measured / expected - 1)));
      PetscCheck(PetscAbsReal(measured / expected - 1) <= rtol, PETSC_COMM_SELF, PETSC_ERR_PLIB, "piece %s bent at %g degrees: B_phi %g N m, expected %g within %g", scene->pieces[p].name, (double)angles[k], (double)measured, (double)expected,
                 (double)rtol);
    }
    PetscCall(PetscFree(x));
  }
  PetscCall(ClothModelDestroy(&model));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
