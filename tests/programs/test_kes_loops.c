/* Virtual KES-F tests: the loops of KES-FB1 (shear) and KES-FB2 (pure bending) on the model a scene's
   KES values build, read back in KES units and compared with those values.

   -scene FILE (tests/data/kes_specimens.yaml): one fabric with a kes block, pieces "shear", "bend_warp" and
   "bend_weft". Each piece is deformed as the instrument deforms its specimen, through one loop, in small
   increments, the friction sliders moved at each increment (ClothAngleSlide, as the integrator does at each
   step's start):
   - shear: the uniform simple shear x = X + tan(phi) Y of KES-FB1 through phi = 0 -> 8 -> -8 -> 8 degrees.
     The shear force per unit width is F = (1/A) dE/d(tan phi) of the cell shear elements (A the piece's area;
     the clamp moves by Y tan phi). G is the slope of F between 0.5 and 5 degrees, 2HG the loop's width at
     +-0.5 degree (the KES definitions), each taken on both branches and averaged.
   - bending: the uniform curvature K of KES-FB2 (the strip rolled onto a cylinder) through K = 0 -> 2.5 ->
     -2.5 -> 2.5 1/cm. The moment per unit width is M = (1/A) dE/dK of the thread-bending elements along the
     bent threads, A = width x (length - one segment): the first and last particles carry no bending
     element, so the springs cover the length less half a segment at either end. B is the slope of M
     between 0.5 and 1.5 1/cm, 2HB the loop's width at +-1 1/cm.
   Options: -expect_G, -expect_2HG (gf/cm/degree, gf/cm), -expect_B_warp, -expect_B_weft (gf cm^2/cm),
   -expect_2HB_warp, -expect_2HB_weft (gf cm/cm), all required, -rtol (default 0.02); any other -expect_*
   option is refused. Prints the measured values. */
#include <petscsys.h>
#include "fabric.h"
#include "test_support.h"
#include "model.h"

#define LOOP_INCREMENTS 400 /* per quarter of the loop */

typedef enum { LOOP_SHEAR, LOOP_BEND_WARP, LOOP_BEND_WEFT } LoopKind;

typedef struct {
  PetscInt   offset, n; /* the piece's particles in natural order */
  PetscReal *flat;      /* 3 n: their flat positions */
  PetscReal *x, *dxdp;  /* 3 n: deformed positions and their derivative by the loop's parameter */
  PetscReal  area;      /* the area F or M is per (see above) */
} Specimen;

/* Whether an angle element of the model belongs to the loop: the piece's cell shear elements, or its
   thread-bending chains along u (warp; neighbours 1 apart) or v (weft). */
static PetscBool LoopElement(const ClothAngle *angle, LoopKind kind, const Specimen *sp)
{
  if (angle->p[0] < sp->offset || angle->p[0] >= sp->offset + sp->n) return PETSC_FALSE;
  if (kind == LOOP_SHEAR) return angle->kind == CLOTH_ANGLE_CELL ? PETSC_TRUE : PETSC_FALSE;
  if (angle->kind != CLOTH_ANGLE_CHAIN) return PETSC_FALSE;
  return (angle->p[1] - angle->p[0] == 1) == (kind == LOOP_BEND_WARP) ? PETSC_TRUE : PETSC_FALSE;
}

/* The specimen at parameter p (tan phi, or K in 1/m), and the derivative of every position by p. The scene's
   pieces lie in the plane z = 0 with u along x and v along y. Bending rolls the strip about an axis across the
   bent threads: a point at distance s along them goes to (sin(K s) / K, (1 - cos(K s)) / K) in the plane of the
   threads and the normal. */
static void DeformSpecimen(LoopKind kind, PetscReal p, Specimen *sp)
{
  for (PetscInt q = 0; q < sp->n; q++) {
    const PetscReal *X = &sp->flat[3 * q];
    PetscReal       *x = &sp->x[3 * q], *d = &sp->dxdp[3 * q];
    const PetscInt   along = kind == LOOP_BEND_WEFT ? 1 : 0;
    const PetscReal  s = X[along], ks = p * s;

    for (PetscInt c = 0; c < 3; c++) x[c] = X[c], d[c] = 0;
    if (kind == LOOP_SHEAR) {
      x[0] = X[0] + p * X[1];
      d[0] = X[1];
      continue;
    }
    if (PetscAbsReal(ks) < 1e-6) { /* series: sin(ks)/K = s - K^2 s^3 / 6, (1 - cos(ks))/K = K s^2 / 2 */
      x[along] = s - p * p * s * s * s / 6;
      x[2]     = p * s * s / 2;
      d[along] = -p * s * s * s / 3;
      d[2]     = s * s / 2;
    } else {
      x[along] = PetscSinReal(ks) / p;
      x[2]     = (1 - PetscCosReal(ks)) / p;
      d[along] = s * PetscCosReal(ks) / p - PetscSinReal(ks) / (p * p);
      d[2]     = s * PetscSinReal(ks) / p - (1 - PetscCosReal(ks)) / (p * p);
    }
  }
}

/* Moves the loop's sliders to the deformed specimen and returns (1/A) dE/dp of its elements. */
static PetscErrorCode LoopResponse(ClothModel model, LoopKind kind, Specimen *sp, PetscReal *response)
{
  PetscReal dedp = 0;

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < model->nangles; a++) {
    ClothAngle      *angle = &model->angles[a];
    const PetscInt   np    = ClothAngleParticleCount(angle->kind);
    const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES];
    PetscReal        force[3 * CLOTH_ANGLE_MAX_PARTICLES];

    if (!LoopElement(angle, kind, sp)) continue;
    for (PetscInt k = 0; k < np; k++) xs[k] = &sp->x[3 * (angle->p[k] - sp->offset)];
    if (angle->slip > 0) ClothAngleSlide(angle, xs);
    PetscCall(ClothAngleEvaluate(angle, xs, CLOTH_STIFFNESS_EXACT, NULL, force, NULL));
    for (PetscInt k = 0; k < np; k++)
      for (PetscInt c = 0; c < 3; c++) dedp -= force[3 * k + c] * sp->dxdp[3 * (angle->p[k] - sp->offset) + c];
  }
  *response = dedp / sp->area;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Linear interpolation of the branch (p[k], r[k]), k = 0..n-1, p monotonic, at p = at. */
static PetscReal BranchAt(const PetscReal p[], const PetscReal r[], PetscInt n, PetscReal at)
{
  for (PetscInt k = 0; k + 1 < n; k++) {
    const PetscReal lo = PetscMin(p[k], p[k + 1]), hi = PetscMax(p[k], p[k + 1]);
    if (at >= lo && at <= hi) return r[k] + (r[k + 1] - r[k]) * (at - p[k]) / (p[k + 1] - p[k]);
  }
  return NAN;
}

/* Runs the loop 0 -> pmax -> -pmax -> pmax and measures the slope between p1 and p2 and the loop's width at
   +-ph on both branches (averaged), in the loop's own units (per unit of p). */
static PetscErrorCode RunLoop(ClothModel model, LoopKind kind, Specimen *sp, PetscReal pmax, PetscReal p1, PetscReal p2, PetscReal ph, PetscReal *slope, PetscReal *width)
{
  const PetscInt n = 2 * LOOP_INCREMENTS + 1;
  PetscReal     *pd, *rd, *pu, *ru, r;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(n, &pd, n, &rd, n, &pu, n, &ru));
  for (PetscInt k = 0; k <= LOOP_INCREMENTS; k++) { /* first loading, 0 -> pmax */
    DeformSpecimen(kind, pmax * k / LOOP_INCREMENTS, sp);
    PetscCall(LoopResponse(model, kind, sp, &r));
  }
  for (PetscInt k = 0; k < n; k++) { /* unloading pmax -> -pmax */
    pd[k] = pmax * (1 - 2.0 * k / (n - 1));
    DeformSpecimen(kind, pd[k], sp);
    PetscCall(LoopResponse(model, kind, sp, &rd[k]));
  }
  for (PetscInt k = 0; k < n; k++) { /* loading -pmax -> pmax */
    pu[k] = -pd[k];
    DeformSpecimen(kind, pu[k], sp);
    PetscCall(LoopResponse(model, kind, sp, &ru[k]));
  }
  *slope = 0.5 * ((BranchAt(pu, ru, n, p2) - BranchAt(pu, ru, n, p1)) + (BranchAt(pd, rd, n, -p1) - BranchAt(pd, rd, n, -p2))) / (p2 - p1);
  *width = 0.5 * ((BranchAt(pu, ru, n, ph) - BranchAt(pd, rd, n, ph)) + (BranchAt(pu, ru, n, -ph) - BranchAt(pd, rd, n, -ph)));
  PetscCall(PetscFree4(pd, rd, pu, ru));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SpecimenCreate(Scene scene, ClothModel model, const char name[], LoopKind kind, Specimen *sp)
{
  const ScenePiece *piece = NULL;
  PetscInt          index = -1;
  PetscBool         same;

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < scene->npieces && index < 0; p++) {
    PetscCall(PetscStrcmp(scene->pieces[p].name, name, &same));
    if (same) index = p;
  }
  PetscCheck(index >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "The scene has no piece '%s'", name);
  piece      = &scene->pieces[index];
  sp->offset = model->piece_offset[index];
  sp->n      = model->piece_offset[index + 1] - sp->offset;
  PetscCall(PetscMalloc3(3 * sp->n, &sp->flat, 3 * sp->n, &sp->x, 3 * sp->n, &sp->dxdp));
  PetscCall(PetscArraycpy(sp->flat, &model->position[3 * sp->offset], 3 * sp->n));
  if (kind == LOOP_SHEAR)
    sp->area = piece->size[0] * piece->size[1];
  else if (kind == LOOP_BEND_WARP)
    sp->area = piece->size[1] * piece->size[0] * (piece->nu - 2) / (piece->nu - 1);
  else
    sp->area = piece->size[0] * piece->size[1] * (piece->nv - 2) / (piece->nv - 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SpecimenDestroy(Specimen *sp)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(sp->flat, sp->x, sp->dxdp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckValue(const char what[], PetscReal measured, const char option[], const char unit[], PetscReal rtol)
{
  PetscReal expected = 0;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(NULL, NULL, option, &expected, &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "%s measured %g %s, but no %s given: every value of this test must be checked", what, (double)measured, unit, option);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: %.6g %s (given %.6g, relative %+.2e)\n", what, (double)measured, unit, (double)expected, (double)(measured / expected - 1)));
  PetscCheck(PetscAbsReal(measured / expected - 1) <= rtol, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s %g %s differs from the given %g by more than %g", what, (double)measured, unit, (double)expected, (double)rtol);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal deg = PETSC_PI / 180, per_cm = 100; /* 1 degree in rad, 1 1/cm in 1/m */
  char            path[PETSC_MAX_PATH_LEN];
  PetscReal       rtol = 0.02, slope, width;
  Scene           scene;
  ClothModel      model;
  Specimen        sp;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-rtol", &rtol, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(ClothModelCreate(scene, &model));

  /* KES-FB1: F in N/m per tan(phi); slope per degree and width in gf/cm (1 gf/cm = FABRIC_KES_FORCE_SI N/m) */
  PetscCall(SpecimenCreate(scene, model, "shear", LOOP_SHEAR, &sp));
  PetscCall(RunLoop(model, LOOP_SHEAR, &sp, PetscTanReal(8 * deg), PetscTanReal(0.5 * deg), PetscTanReal(5 * deg), PetscTanReal(0.5 * deg), &slope, &width));
  PetscCall(CheckValue("KES-FB1 G", slope * (PetscTanReal(5 * deg) - PetscTanReal(0.5 * deg)) / 4.5 / FABRIC_KES_FORCE_SI, "-expect_G", "gf/cm/degree", rtol));
  PetscCall(CheckValue("KES-FB1 2HG", width / FABRIC_KES_FORCE_SI, "-expect_2HG", "gf/cm", rtol));
  PetscCall(SpecimenDestroy(&sp));

  /* KES-FB2: M in N m/m per K (1/m); B in gf cm^2/cm, 2HB in gf cm/cm */
  PetscCall(SpecimenCreate(scene, model, "bend_warp", LOOP_BEND_WARP, &sp));
  PetscCall(RunLoop(model, LOOP_BEND_WARP, &sp, 2.5 * per_cm, 0.5 * per_cm, 1.5 * per_cm, 1.0 * per_cm, &slope, &width));
  PetscCall(CheckValue("KES-FB2 B warp", slope / FABRIC_KES_BEND_SI, "-expect_B_warp", "gf cm^2/cm", rtol));
  PetscCall(CheckValue("KES-FB2 2HB warp", width / FABRIC_KES_MOMENT_SI, "-expect_2HB_warp", "gf cm/cm", rtol));
  PetscCall(SpecimenDestroy(&sp));
  PetscCall(SpecimenCreate(scene, model, "bend_weft", LOOP_BEND_WEFT, &sp));
  PetscCall(RunLoop(model, LOOP_BEND_WEFT, &sp, 2.5 * per_cm, 0.5 * per_cm, 1.5 * per_cm, 1.0 * per_cm, &slope, &width));
  PetscCall(CheckValue("KES-FB2 B weft", slope / FABRIC_KES_BEND_SI, "-expect_B_weft", "gf cm^2/cm", rtol));
  PetscCall(CheckValue("KES-FB2 2HB weft", width / FABRIC_KES_MOMENT_SI, "-expect_2HB_weft", "gf cm/cm", rtol));
  PetscCall(SpecimenDestroy(&sp));
  PetscCall(TestCheckExpectationsUsed());

  PetscCall(ClothModelDestroy(&model));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
