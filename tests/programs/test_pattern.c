/* Pattern meshing from four boundaries, fabric presets and the KES-F mapping.

   1. Arc-length placement: nodes on an unevenly split polyline land at equal arc length.
   2. Transfinite interpolation of a square given as four polylines (with extra vertices) reproduces the
      uniform rectangle grid to round-off.
   3. KES-F units: FabricSetFromKES against values converted by hand (1 gf = 9.80665e-3 N); the biphasic
      curve reaches Fm at EMT and encloses the work WT = LT Fm EMT / 2.
   4. Presets: a preset's values equal the cited source numbers (fabric_presets.c).
   5. With -scene FILE -expect_area A: every piece of the scene meshes with positive cells, its outline
      encloses A m^2 (-area_rtol, default 1e-2) and its particles' total mass is density x A within 1%.
   6. With -scene (a flat scene): the start imperfections (-cloth_perturbation) leave pinned particles
      where they are, move free ones only out of the fabric's plane (perpendicular to every link, to
      1e-12 of the amplitude) by at most the amplitude, with the mean and mean square of a uniform
      distribution (0 and 1/3 of the amplitude, squared, within 4 standard errors); the same seed gives the
      same start, another seed another one. The smooth field (a wavelength given): within the amplitude,
      no steeper than its shortest wave allows, and the same at the same pattern point at grid n and 2n - 1.
   Prints nothing unless a check fails. */
#include <petscsys.h>
#include "fabric.h"
#include "fabric_presets.h"
#include "model.h"
#include "pattern.h"
#include "vec3.h"
#include "test_support.h"

static PetscErrorCode CheckClose(PetscReal value, PetscReal expected, PetscReal rtol, const char what[])
{
  PetscFunctionBeginUser;
  PetscCheck(PetscAbsReal(value - expected) <= rtol * PetscAbsReal(expected), PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s: got %.12g, expected %.12g (relative tolerance %g)", what, (double)value, (double)expected, (double)rtol);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckArcLength(void)
{
  const PetscReal line[6] = {0, 0, 0.1, 0, 1, 0};
  PetscReal       nodes[10];

  PetscFunctionBeginUser;
  PetscCall(PatternResampleByArcLength(3, line, 5, nodes));
  for (PetscInt k = 0; k < 5; k++)
    PetscCheck(PetscAbsReal(nodes[2 * k] - 0.25 * k) < 1e-14 && nodes[2 * k + 1] == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Arc-length node %" PetscInt_FMT " at (%g, %g), expected (%g, 0)", k, (double)nodes[2 * k], (double)nodes[2 * k + 1], 0.25 * k);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckTransfiniteSquare(void)
{
  PetscReal  bottom[6] = {0, 0, 0.3, 0, 2, 0}, right[4] = {2, 0, 2, 1}, top[8] = {0, 1, 0.5, 1, 1.7, 1, 2, 1}, left[6] = {0, 0, 0, 0.9, 0, 1};
  ScenePiece piece = {0}, rectangle = {0};
  PetscReal  uv[2 * 9 * 5], expected[2 * 9 * 5];

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(piece.name, "square", sizeof(piece.name)));
  piece.nu = rectangle.nu = 9;
  piece.nv = rectangle.nv   = 5;
  piece.has_boundaries      = PETSC_TRUE;
  piece.boundary_npoints[0] = 3;
  piece.boundary_points[0]  = bottom;
  piece.boundary_npoints[1] = 2;
  piece.boundary_points[1]  = right;
  piece.boundary_npoints[2] = 4;
  piece.boundary_points[2]  = top;
  piece.boundary_npoints[3] = 3;
  piece.boundary_points[3]  = left;
  rectangle.size[0]         = 2;
  rectangle.size[1]         = 1;
  PetscCall(PatternMeshPiece(&piece, uv));
  PetscCall(PatternMeshPiece(&rectangle, expected));
  for (PetscInt k = 0; k < 2 * 9 * 5; k++)
    PetscCheck(PetscAbsReal(uv[k] - expected[k]) < 1e-14, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Transfinite square: coordinate %" PetscInt_FMT " is %.17g, the rectangle grid's %.17g", k, (double)uv[k], (double)expected[k]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckKES(void)
{
  /* W 15 mg/cm^2, B 0.1/0.08 gf cm^2/cm, G 0.8 gf/cm/deg, EMT 5/8 %, LT 0.75/0.6, 2HB 0.06/0.04 gf cm/cm, 2HG 1.2 gf/cm */
  const FabricKES kes = {15, 0.1, 0.08, 0.8, 5, 8, 0.75, 0.6, 0.06, 0.04, 1.2};
  const PetscReal fm  = 500 * 9.80665e-3 / 1e-2; /* 490.3325 N/m */
  SceneFabric     fabric;
  PetscReal       soft, stiff, knee, work = 0;
  const PetscInt  n = 100000;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&fabric, sizeof(fabric)));
  PetscCall(FabricSetFromKES(&kes, &fabric));
  PetscCall(CheckClose(fabric.density, 0.15, 1e-14, "KES W 15 mg/cm^2 -> kg/m^2"));
  PetscCall(CheckClose(fabric.bend_warp, 0.1 * 9.80665e-5, 1e-14, "KES B 0.1 gf cm^2/cm -> N m"));
  PetscCall(CheckClose(fabric.bend_weft, 0.08 * 9.80665e-5, 1e-14, "KES B 0.08 gf cm^2/cm -> N m"));
  PetscCall(CheckClose(fabric.shear, 0.8 * 0.980665 * 180 / PETSC_PI, 1e-14, "KES G 0.8 gf/cm/degree -> N/m per radian"));
  PetscCall(CheckClose(fabric.shear, 44.950372, 1e-7, "KES G 0.8 gf/cm/degree = 44.950372 N/m"));
  /* the friction moment is half the loop's width: HB = 0.03 gf cm/cm = 0.03 x 9.80665e-3 N m/m */
  PetscCall(CheckClose(fabric.bend_hysteresis_warp, 2.941995e-4, 1e-12, "KES 2HB 0.06 gf cm/cm -> HB 2.941995e-4 N m/m"));
  PetscCall(CheckClose(fabric.bend_hysteresis_weft, 1.96133e-4, 1e-12, "KES 2HB 0.04 gf cm/cm -> HB 1.96133e-4 N m/m"));
  /* and the friction force of shear: HG = 0.6 gf/cm = 0.6 x 0.980665 N/m */
  PetscCall(CheckClose(fabric.shear_hysteresis, 0.588399, 1e-12, "KES 2HG 1.2 gf/cm -> HG 0.588399 N/m"));
  PetscCheck(fabric.bend_model == CLOTH_BEND_ANGLE && fabric.shear_model == CLOTH_SHEAR_CELL, PETSC_COMM_SELF, PETSC_ERR_PLIB, "KES values are rigidities: expected the angle bending and cell shear models");
  /* warp: LT 0.75 -> below the knee (2 LT - 1) Fm/EMT = 0.5 x 9806.65, beyond (3 - 2 LT) Fm/EMT = 1.5 x 9806.65 */
  PetscCall(CheckClose(fabric.stretch_warp, 0.5 * fm / 0.05, 1e-14, "KES warp modulus below the knee"));
  PetscCall(CheckClose(fabric.stretch_stiff_warp, 1.5 * fm / 0.05, 1e-14, "KES warp modulus beyond the knee"));
  PetscCall(CheckClose(fabric.stretch_knee_warp, 0.025, 1e-14, "KES warp knee = EMT_warp/2"));
  PetscCall(CheckClose(fabric.stretch_knee_weft, 0.04, 1e-14, "KES weft knee = EMT_weft/2"));
  /* the curve of the weft: F(EMT) = Fm and its work is LT Fm EMT / 2 (midpoint rule) */
  PetscCall(FabricBiphasicFromKES(8, 0.6, &soft, &stiff, &knee));
  PetscCall(CheckClose(soft * knee + stiff * (0.08 - knee), fm, 1e-13, "biphasic curve at EMT"));
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal e = 0.08 * (k + 0.5) / n;
    work += (e < knee ? soft * e : soft * knee + stiff * (e - knee)) * 0.08 / n;
  }
  PetscCall(CheckClose(work, 0.6 * fm * 0.08 / 2, 1e-8, "biphasic curve's work WT = LT Fm EMT / 2"));
  /* without LT: linear, the secant modulus */
  {
    FabricKES linear = kes;
    linear.lt_warp = linear.lt_weft = 0;
    PetscCall(FabricSetFromKES(&linear, &fabric));
    PetscCall(CheckClose(fabric.stretch_weft, fm / 0.08, 1e-14, "KES weft secant modulus Fm / EMT"));
    PetscCheck(fabric.stretch_knee_warp == 0 && fabric.stretch_knee_weft == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "KES without LT: expected a linear curve");
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckPresets(void)
{
  SceneFabric fabric;
  PetscBool   found;
  char        names[1024];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&fabric, sizeof(fabric)));
  PetscCall(FabricPresetApply("denim", &fabric, &found));
  PetscCheck(found, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Preset 'denim' not found");
  PetscCall(CheckClose(fabric.density, 0.324, 1e-15, "denim density (11oz-black-denim.json)"));
  PetscCall(CheckClose(fabric.bend_warp, 96.951576e-6 / 8, 1e-15, "denim warp rigidity (bending row 2 / 8)"));
  PetscCall(CheckClose(fabric.bend_weft, 64.196457e-6 / 8, 1e-15, "denim weft rigidity (bending row 0 / 8)"));
  PetscCall(CheckClose(fabric.shear, 53.387184 / 4, 1e-15, "denim shear modulus (k33 / 4)"));
  PetscCall(FabricPresetApply("petrak_m6_cotton_twill", &fabric, &found));
  PetscCheck(found, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Preset 'petrak_m6_cotton_twill' not found");
  PetscCall(CheckClose(fabric.density, 0.25336, 1e-15, "Petrak M6 density (253.36 g/m^2)"));
  PetscCall(CheckClose(fabric.bend_warp, 7430e-9, 1e-15, "Petrak M6 warp rigidity (7430 g mm^2/s^2)"));
  PetscCall(CheckClose(fabric.bend_weft, 3700e-9, 1e-15, "Petrak M6 weft rigidity (3700 g mm^2/s^2)"));
  PetscCall(CheckClose(fabric.shear, 126.0, 1e-15, "Petrak M6 shear (126000 g/s^2)"));
  PetscCall(FabricPresetApply("velvet", &fabric, &found));
  PetscCheck(!found, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Preset 'velvet' should not exist");
  PetscCall(FabricPresetListNames(names, sizeof(names)));
  PetscCheck(strstr(names, "cotton_knit") != NULL, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Preset list '%s' lacks cotton_knit", names);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every piece of the scene: positive cells, outline area, total mass = density x area. */
static PetscErrorCode CheckSceneAreas(const char path[], PetscReal expected_area, PetscReal rtol)
{
  Scene      scene;
  ClothModel model;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(ClothModelCreate(scene, &model));
  for (PetscInt p = 0; p < scene->npieces; p++) {
    const ScenePiece *piece = &scene->pieces[p];
    PetscReal        *uv, outline, mass = 0, min_area = PETSC_MAX_REAL;

    PetscCall(PetscMalloc1(2 * piece->nu * piece->nv, &uv));
    PetscCall(PatternMeshPiece(piece, uv));
    for (PetscInt j = 0; j + 1 < piece->nv; j++)
      for (PetscInt i = 0; i + 1 < piece->nu; i++) min_area = PetscMin(min_area, PatternCellArea(piece->nu, uv, i, j));
    PetscCheck(min_area > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Piece '%s': smallest cell area %g m^2, expected > 0", piece->name, (double)min_area);
    PetscCall(PatternOutlineArea(piece, &outline));
    if (piece->cut_disc[2] > 0) { /* a grid cut to a disc: the area of the cells it keeps */
      outline = 0;
      for (PetscInt j = 0; j + 1 < piece->nv; j++)
        for (PetscInt i = 0; i + 1 < piece->nu; i++) outline += PatternCellKept(piece, uv, i, j) ? PatternCellArea(piece->nu, uv, i, j) : 0;
    }
    PetscCall(CheckClose(outline, expected_area, rtol, piece->cut_disc[2] > 0 ? "area of the cells kept by cut_disc" : "outline area of the given boundaries"));
    for (PetscInt k = model->piece_offset[p]; k < model->piece_offset[p + 1]; k++) mass += model->mass[k];
    PetscCall(CheckClose(mass, scene->fabrics[piece->fabric].density * expected_area, 1e-2, "total mass vs density x outline area"));
    PetscCall(PetscFree(uv));
  }
  PetscCall(ClothModelDestroy(&model));
  PetscCall(SceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Displacement of each particle by ClothModelPerturbPositions(amplitude, wavelength, seed) (3 N values, freed by the caller). */
static PetscErrorCode PerturbationDisplacement(Scene scene, PetscReal amplitude, PetscReal wavelength, PetscInt seed, ClothModel *model, PetscReal **displacement)
{
  ClothModel perturbed;

  PetscFunctionBeginUser;
  PetscCall(ClothModelCreate(scene, model));
  PetscCall(ClothModelCreate(scene, &perturbed));
  PetscCall(ClothModelPerturbPositions(perturbed, amplitude, wavelength, seed));
  PetscCall(PetscMalloc1(3 * (*model)->nparticles, displacement));
  for (PetscInt k = 0; k < 3 * (*model)->nparticles; k++) (*displacement)[k] = perturbed->position[k] - (*model)->position[k];
  PetscCall(ClothModelDestroy(&perturbed));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckPerturbation(const char path[])
{
  const PetscReal amplitude = 1e-3;
  Scene           scene;
  ClothModel      model;
  PetscReal      *d, *same, *other;
  PetscReal       sum = 0, sum2 = 0, moved = 0, differ = 0;
  PetscInt        nfree = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(PerturbationDisplacement(scene, amplitude, 0, 5, &model, &d));
  for (PetscInt l = 0; l < model->nlinks; l++) { /* out of the plane: perpendicular to every thread segment */
    const PetscInt *p = model->links[l].p;
    PetscReal       e[3], len;

    for (PetscInt c = 0; c < 3; c++) e[c] = model->position[3 * p[1] + c] - model->position[3 * p[0] + c];
    len = PetscSqrtReal(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    for (PetscInt k = 0; k < 2; k++)
      PetscCheck(PetscAbsReal(d[3 * p[k]] * e[0] + d[3 * p[k] + 1] * e[1] + d[3 * p[k] + 2] * e[2]) <= 1e-12 * amplitude * len, PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle %" PetscInt_FMT " moved along its link to %" PetscInt_FMT, p[k], p[1 - k]);
  }
  for (PetscInt i = 0; i < model->nparticles; i++) {
    const PetscReal h = PetscSqrtReal(d[3 * i] * d[3 * i] + d[3 * i + 1] * d[3 * i + 1] + d[3 * i + 2] * d[3 * i + 2]);

    if (model->pinned[i]) {
      PetscCheck(h == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "pinned particle %" PetscInt_FMT " moved by %g m", i, (double)h);
      continue;
    }
    PetscCheck(h <= amplitude * (1 + 1e-12), PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle %" PetscInt_FMT " moved by %g m, more than the amplitude", i, (double)h);
    /* the signed displacement along y (the scene's normal) over the amplitude: uniform in [-1, 1] */
    sum += d[3 * i + 1] / amplitude;
    sum2 += PetscSqr(d[3 * i + 1] / amplitude);
    moved += h > 0;
    nfree++;
  }
  PetscCheck(nfree > 100 && moved == nfree, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%g of %" PetscInt_FMT " free particles moved", (double)moved, nfree);
  PetscCheck(PetscAbsReal(sum / nfree) <= 4 * PetscSqrtReal(1.0 / (3.0 * nfree)), PETSC_COMM_SELF, PETSC_ERR_PLIB, "mean displacement %g of the amplitude, expected 0", (double)(sum / nfree));
  PetscCheck(PetscAbsReal(sum2 / nfree - 1.0 / 3.0) <= 4 * PetscSqrtReal(4.0 / (45.0 * nfree)), PETSC_COMM_SELF, PETSC_ERR_PLIB, "mean square displacement %g of the amplitude squared, expected 1/3", (double)(sum2 / nfree));
  PetscCall(ClothModelDestroy(&model));
  PetscCall(PerturbationDisplacement(scene, amplitude, 0, 5, &model, &same));
  PetscCall(ClothModelDestroy(&model));
  PetscCall(PerturbationDisplacement(scene, amplitude, 0, 6, &model, &other));
  for (PetscInt k = 0; k < 3 * model->nparticles; k++) {
    PetscCheck(same[k] == d[k], PETSC_COMM_SELF, PETSC_ERR_PLIB, "seed 5 gave two different starts");
    differ += PetscAbsReal(other[k] - d[k]) > 0;
  }
  PetscCheck(differ >= nfree, PETSC_COMM_SELF, PETSC_ERR_PLIB, "seeds 5 and 6 gave the same displacement to %g of %" PetscInt_FMT " free particles", (double)(nfree - differ), nfree);
  PetscCall(PetscFree(d));
  PetscCall(PetscFree(same));
  PetscCall(PetscFree(other));
  PetscCall(ClothModelDestroy(&model));
  PetscCall(SceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The smooth imperfection field (-cloth_perturbation_wavelength L): within the amplitude, pinned particles
   unmoved, no steeper than its shortest wave allows (|w(x1) - w(x0)| <= 2 pi A |x1 - x0| / L along every link),
   not zero, and, on a scene of one piece, the same at the same point of the pattern at grid n and 2n - 1
   (whose every other node is the coarser grid's node). */
static PetscErrorCode CheckSmoothPerturbation(const char path[])
{
  const PetscReal amplitude = 1e-3, wavelength = 0.02;
  Scene           scene;
  ClothModel      model, fine;
  PetscReal      *d, *df, largest = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(PerturbationDisplacement(scene, amplitude, wavelength, 3, &model, &d));
  for (PetscInt l = 0; l < model->nlinks; l++) {
    const PetscInt *p = model->links[l].p;
    PetscReal       e[3], dd[3];

    for (PetscInt c = 0; c < 3; c++) {
      e[c]  = model->position[3 * p[1] + c] - model->position[3 * p[0] + c];
      dd[c] = d[3 * p[1] + c] - d[3 * p[0] + c];
    }
    if (model->pinned[p[0]] || model->pinned[p[1]]) continue;
    PetscCheck(PetscSqrtReal(Dot3(dd, dd)) <= 2 * PETSC_PI * amplitude * PetscSqrtReal(Dot3(e, e)) / wavelength * (1 + 1e-9), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "smooth imperfections: particles %" PetscInt_FMT " and %" PetscInt_FMT " differ by %g m over %g m, steeper than wavelength %g m allows", p[0], p[1], (double)PetscSqrtReal(Dot3(dd, dd)), (double)PetscSqrtReal(Dot3(e, e)),
               (double)wavelength);
  }
  for (PetscInt i = 0; i < model->nparticles; i++) {
    const PetscReal h = PetscSqrtReal(Dot3(&d[3 * i], &d[3 * i]));

    PetscCheck(!model->pinned[i] || h == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "smooth imperfections moved pinned particle %" PetscInt_FMT, i);
    PetscCheck(h <= amplitude * (1 + 1e-12), PETSC_COMM_SELF, PETSC_ERR_PLIB, "smooth imperfections moved particle %" PetscInt_FMT " by %g m, more than the amplitude", i, (double)h);
    largest = PetscMax(largest, h);
  }
  PetscCheck(largest > 0.1 * amplitude, PETSC_COMM_SELF, PETSC_ERR_PLIB, "smooth imperfections: largest displacement %g m, expected above a tenth of the amplitude %g m", (double)largest, (double)amplitude);
  if (scene->single_grid && scene->pieces[0].nu == scene->pieces[0].nv) {
    const PetscInt n = scene->pieces[0].nu;

    PetscCall(ClothModelDestroy(&model));
    PetscCall(PetscFree(d));
    PetscCall(SceneSetGridSize(scene, n));
    PetscCall(PerturbationDisplacement(scene, amplitude, wavelength, 3, &model, &d));
    PetscCall(SceneSetGridSize(scene, 2 * n - 1));
    PetscCall(PerturbationDisplacement(scene, amplitude, wavelength, 3, &fine, &df));
    for (PetscInt j = 0; j < n; j++)
      for (PetscInt i = 0; i < n; i++) {
        const PetscInt coarse = j * n + i, same = 2 * j * (2 * n - 1) + 2 * i;

        if (model->pinned[coarse] != fine->pinned[same]) continue; /* the edge of a cut grid (cut_disc) steps differently at the two grids */
        for (PetscInt c = 0; c < 3; c++)
          PetscCheck(PetscAbsReal(d[3 * coarse + c] - df[3 * same + c]) <= 1e-9 * amplitude, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                     "smooth imperfections: node (%" PetscInt_FMT ", %" PetscInt_FMT ") of grid %" PetscInt_FMT " moved %g m, the same node of grid %" PetscInt_FMT " %g m", i, j, n, (double)d[3 * coarse + c], 2 * n - 1, (double)df[3 * same + c]);
      }
    PetscCall(ClothModelDestroy(&fine));
    PetscCall(PetscFree(df));
  }
  PetscCall(PetscFree(d));
  PetscCall(ClothModelDestroy(&model));
  PetscCall(SceneDestroy(&scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char      path[PETSC_MAX_PATH_LEN];
  PetscBool has_scene, has_area;
  PetscReal area = 0, rtol = 1e-2;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(CheckArcLength());
  PetscCall(CheckTransfiniteSquare());
  PetscCall(CheckKES());
  PetscCall(CheckPresets());
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &has_scene));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_area", &area, &has_area));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-area_rtol", &rtol, NULL));
  PetscCheck(has_scene == has_area, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "-scene and -expect_area go together (the scene's outline area is checked against it)");
  PetscCall(TestCheckExpectationsUsed());
  if (has_scene) PetscCall(CheckSceneAreas(path, area, rtol));
  if (has_scene) PetscCall(CheckPerturbation(path));
  if (has_scene) PetscCall(CheckSmoothPerturbation(path));
  PetscCall(PetscFinalize());
  return 0;
}
