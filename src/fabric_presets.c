/* Fabric presets (see fabric_presets.h).

   Source: H. Wang, J. F. O'Brien, R. Ramamoorthi, "Data-driven elastic models for cloth: modeling and
   measurement", ACM Trans. Graph. 30(4):71, 2011 (SIGGRAPH 2011). Its ten measured fabrics are
   distributed as material files with the ARCSim simulator (materials/<name>.json; fibre content in
   materials/README). The files give, per fabric:
     "density"     areal density, kg/m^2 (used as is);
     "stretching"  rows of [k11, k12, k22, k33] membrane stiffnesses, N/m, row 0 at zero strain. ARCSim's
                   material_model (cloth physics.cpp) gives the energy per area
                   0.5 (k11 E11^2 + 2 k12 E11 E22 + k22 E22^2) + 0.5 k33 E12^2 with E the Green strain, so
                   at small strain the tensile modulus along u is k11, along v k22, and with E12 = gamma/2
                   the shear modulus (0.5 G gamma^2) is G = k33 / 4;
     "bending"     rows of 5 stiffnesses k_e (N m) for hinges at 0, 45, 90 degrees to the material u axis,
                   at curvatures 0, 5, 10, 15, 20 1/m; column 0 (the flat state) is used. A hinge along u
                   bends the threads that run along v. ARCSim's hinge energy is k_e l^2 / (2 a) theta^2 / 4
                   (a: the two faces' area); summed over an equilateral mesh under curvature kappa this is
                   k_e kappa^2 / 16 per area, so the continuum rigidity (0.5 B kappa^2) is B = k_e / 8.
                   Row 1 (hinges at 45 degrees) is the rigidity along the bias, bend_bias = row 1 / 8 (the
                   thread-angle springs alone give (bend_warp + bend_weft) / 4 there; the twist elements add
                   the rest: docs/validation.md, section 5.1).
   The files do not say which of u and v is the warp; here u = warp (i), v = weft (j), so
   stretch_warp = k11, stretch_weft = k22, bend_warp = row 2 (hinge along v) / 8, bend_weft = row 0 / 8. */
#include "fabric_presets.h"
#include <string.h>

typedef struct {
  const char *name;
  PetscReal   density;                    /* kg/m^2 */
  PetscReal   stretch_warp, stretch_weft; /* N/m */
  PetscReal   shear;                      /* N/m (cell model: 0.5 G gamma^2 per area) */
  PetscReal   bend_warp, bend_weft;       /* N m (angle model) */
  PetscReal   bend_bias;                  /* N m, along the bias; 0: not measured (no twist elements) */
} FabricPreset;

static const FabricPreset FabricPresets[] = {
    /* 11oz-black-denim.json: jeans, 99% cotton 1% spandex (README). density 0.324; stretching row 0
       [205.352005, 10.234077, 1013.88629, 53.387184]; bending row 0 col 0 64.196457e-6, row 1 col 0 73.384567e-6, row 2 col 0 96.951576e-6. */
    {"denim", 0.324, 205.352005, 1013.88629, 53.387184 / 4, 96.951576e-6 / 8, 64.196457e-6 / 8, 73.384567e-6 / 8},
    /* royal-target.json: pants, 65% cotton 35% polyester. density 0.220; stretching row 0
       [2016.55456, 9.170511, 2034.97644, 104.759674]; bending row 0 col 0 125.409805e-6, row 1 col 0 107.997696e-6, row 2 col 0 125.409805e-6. */
    {"cotton_polyester", 0.220, 2016.55456, 2034.97644, 104.759674 / 4, 125.409805e-6 / 8, 125.409805e-6 / 8, 107.997696e-6 / 8},
    /* white-dots-on-blk.json: tablecloth, 100% polyester. density 0.128; stretching row 0
       [2002.08618, 0.345588, 2027.48559, 19.189022]; bending row 0 col 0 51.713814e-6, row 1 col 0 40.659470e-6, row 2 col 0 31.282822e-6. */
    {"polyester", 0.128, 2002.08618, 2027.48559, 19.189022 / 4, 31.282822e-6 / 8, 51.713814e-6 / 8, 40.659470e-6 / 8},
    /* gray-interlock.json: t-shirt (interlock knit), 60% cotton 40% polyester. density 0.187; stretching row 0
       [16.593832, -14.695990, 34.477123, 36.860302]; bending row 0 col 0 23.191698e-6, row 1 col 0 24.749964e-6, row 2 col 0 14.267624e-6. */
    {"cotton_knit", 0.187, 16.593832, 34.477123, 36.860302 / 4, 14.267624e-6 / 8, 23.191698e-6 / 8, 24.749964e-6 / 8},
    /* Six woven fabrics with a measured drape coefficient (docs/validation.md, section 5): Petrak et al.,
       Sustainability 17:1388, 2025, doi:10.3390/su17041388 (CC BY 4.0), as transcribed from its Tables 1, 2,
       4 and 5 in the public repository KAFKA2306/image2outfit, config/materials/kes-woven-fabrics-2025.v1.json
       (commit 1e4a63f; the paper itself could not be read here). The paper measured the fabrics on KES-FB and
       converted the values to CLO3D input units: areal mass g/m^2, stretch and shear g/s^2, bending
       g mm^2/s^2. Taken here by units alone: density = mass x 1e-3 kg/m^2, stretch and shear x 1e-3 N/m,
       bending x 1e-9 N m (g mm^2/s^2 = 1e-9 kg m^2/s^2), as the continuum moduli of the cell shear and angle bending models;
       CLO3D's own scaling of its inputs is not published, so B carries that uncertainty. Transcribed numbers
       (mass; stretch warp, weft; shear; bending warp, weft; measured DC): */
    /* M1, 100% polyester, twill 3/1: 135.17; 477226, 458614; 41000; 1950, 610; DC 0.223 */
    {"petrak_m1_polyester_twill", 0.13517, 477.226, 458.614, 41.000, 1950e-9, 610e-9, 0},
    /* M2, 100% polyester, plain: 83.66; 471944, 373515; 46000; 850, 330; DC 0.228 */
    {"petrak_m2_polyester_plain", 0.08366, 471.944, 373.515, 46.000, 850e-9, 330e-9, 0},
    /* M3, 75% wool 15% polyester 10% elastane, twill 2/1: 178.70; 449656, 439815; 50000; 2140, 2000; DC 0.349 */
    {"petrak_m3_wool_twill", 0.17870, 449.656, 439.815, 50.000, 2140e-9, 2000e-9, 0},
    /* M4, 63% polyester 33% viscose 4% elastane, twill 2/1: 286.13; 403447, 401762; 61000; 2970, 2400; DC 0.286 */
    {"petrak_m4_polyester_viscose_twill", 0.28613, 403.447, 401.762, 61.000, 2970e-9, 2400e-9, 0},
    /* M5, 97% polyester 3% elastane, plain: 242.00; 407166, 415023; 57000; 3220, 3880; DC 0.443 */
    {"petrak_m5_polyester_plain", 0.24200, 407.166, 415.023, 57.000, 3220e-9, 3880e-9, 0},
    /* M6, 65% cotton 31% polyester 4% elastane, twill 2/1: 253.36; 473860, 404746; 126000; 7430, 3700; DC 0.549 */
    {"petrak_m6_cotton_twill", 0.25336, 473.860, 404.746, 126.000, 7430e-9, 3700e-9, 0},
};
static const PetscInt FabricPresetCount = (PetscInt)(sizeof(FabricPresets) / sizeof(FabricPresets[0]));

PetscErrorCode FabricPresetApply(const char name[], SceneFabric *fabric, PetscBool *found)
{
  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  for (PetscInt p = 0; p < FabricPresetCount; p++) {
    const FabricPreset *preset = &FabricPresets[p];

    PetscCall(PetscStrcmp(name, preset->name, found));
    if (!*found) continue;
    fabric->density      = preset->density;
    fabric->stretch_warp = fabric->stretch_stiff_warp = preset->stretch_warp;
    fabric->stretch_weft = fabric->stretch_stiff_weft = preset->stretch_weft;
    fabric->stretch_knee_warp = fabric->stretch_knee_weft = 0;
    fabric->shear                                         = preset->shear;
    fabric->shear_model                                   = CLOTH_SHEAR_CELL;
    fabric->bend_warp                                     = preset->bend_warp;
    fabric->bend_weft                                     = preset->bend_weft;
    fabric->bend_bias                                     = preset->bend_bias;
    fabric->bend_model                                    = CLOTH_BEND_ANGLE;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FabricPresetListNames(char buf[], size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  for (PetscInt p = 0; p < FabricPresetCount; p++) {
    if (p) PetscCall(PetscStrlcat(buf, ", ", len));
    PetscCall(PetscStrlcat(buf, FabricPresets[p].name, len));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
