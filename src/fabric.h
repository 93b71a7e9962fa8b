/* Fabric: from a fabric's measured moduli to the coefficients of the particle model.

   With h_u, h_v the local thread spacings (rest lengths along warp and weft) and w the spacing of
   the neighbouring parallel threads (the width one thread carries):
   - stretch link along a thread:   k = E w / l0        (E: tensile 2D modulus, N/m)
   - shear diagonal link:           k = G A / (l0^2/2)  (A: cell area; k = G on a square grid)
   - shear corner angle:            k = G A / 4         (N m; four corners share a cell)
   - shear cell angle:              k = G A             (N m; one spring on the warp-weft angle at the cell's centre)
   - bending skip-one link:         k = bend w / (l0/2) (bend in N/m per link on a square grid)
   - bending thread angle:          k = B w / h         (B: bending rigidity, N m; h: mean segment)
   so that on a uniform square grid the link coefficients equal the scene's values, and the angle
   coefficients give the continuum energies 0.5 G gamma^2 and 0.5 B kappa^2 per unit area.

   Measured (Kawabata KES-F) values map to a SceneFabric by FabricSetFromKES; docs/validation.md
   derives every factor. */
#pragma once
#include "scene.h"

/* Unit conversions from the units KES-F reports in to SI. */
#define FABRIC_GF_N 9.80665e-3                             /* 1 gram-force in newtons */
#define FABRIC_KES_BEND_SI 9.80665e-5                      /* 1 gf cm^2/cm = 9.80665e-3 N x 1e-4 m^2 / 1e-2 m, in N m */
#define FABRIC_KES_SHEAR_SI (0.980665 * 180.0 / PETSC_PI)  /* 1 gf/cm/degree = 0.980665 N/m per degree, in N/m per radian */
#define FABRIC_KES_WEIGHT_SI 1e-2                          /* 1 mg/cm^2 = 1e-6 kg / 1e-4 m^2, in kg/m^2 */
#define FABRIC_KES_MOMENT_SI 9.80665e-3                    /* 1 gf cm/cm (moment per unit width) in N m/m */
#define FABRIC_KES_FORCE_SI 0.980665                       /* 1 gf/cm (force per unit width) in N/m */
#define FABRIC_KES_TENSILE_FM (500.0 * FABRIC_GF_N / 1e-2) /* KES-FB1 standard maximum load 500 gf/cm, in N/m */

/* One fabric as KES-F measures it, in KES units. LT = 0 means "not measured" (linear curve). */
typedef struct {
  PetscReal weight;               /* W, mg/cm^2 */
  PetscReal bend_warp, bend_weft; /* B, gf cm^2/cm (bending the warp threads: warp; the weft threads: weft) */
  PetscReal shear;                /* G, gf/cm/degree */
  PetscReal emt_warp, emt_weft;   /* EMT, % strain at the maximum load Fm = 500 gf/cm */
  PetscReal lt_warp, lt_weft;     /* LT, tensile linearity (0.5 < LT < 1.5), 0 = not given */
  PetscReal hysteresis_warp;      /* 2HB, gf cm/cm: width of the bending hysteresis loop (0 = not given: elastic) */
  PetscReal hysteresis_weft;
  PetscReal shear_hysteresis; /* 2HG, gf/cm: width of the shear hysteresis loop at 0.5 degree (0 = not given: elastic) */
} FabricKES;

/* Sets density, stretch (secant modulus Fm/EMT, or a biphasic curve through the same work WT when LT is given),
   shear and bending of fabric from KES values; shear uses the cell model, bending the angle model (both take
   the continuum moduli, SI units). */
PetscErrorCode FabricSetFromKES(const FabricKES *kes, SceneFabric *fabric);
/* Biphasic curve with the knee at half the maximum strain that reaches Fm at strain emt and encloses the
   work WT = LT Fm emt / 2: modulus below the knee, modulus beyond it (N/m), knee strain. */
PetscErrorCode FabricBiphasicFromKES(PetscReal emt_percent, PetscReal lt, PetscReal *soft, PetscReal *stiff, PetscReal *knee);

PetscReal FabricStretchLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width);
/* Stiffness of the same link beyond the knee of a biphasic curve (equal to the above when linear). */
PetscReal FabricStretchLinkStiffStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width);
PetscReal FabricShearLinkStiffness(const SceneFabric *fabric, PetscReal rest, PetscReal cell_area);
PetscReal FabricShearAngleStiffness(const SceneFabric *fabric, PetscReal cell_area);
PetscReal FabricShearCellStiffness(const SceneFabric *fabric, PetscReal cell_area);
PetscReal FabricBendLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width);
PetscReal FabricBendAngleStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal segment, PetscReal width);
/* Twisting rigidity Bt = bend_bias - (bend_warp + bend_weft) / 4, N m: what a measured bias bending rigidity adds to
   the thread-angle springs, whose bend along the bias costs (bend_warp + bend_weft) / 4 (0 when bend_bias is 0). */
PetscReal FabricTwistRigidity(const SceneFabric *fabric);
/* Coefficient k of a cell's twist element, energy k T^2 (forces.h, CLOTH_ANGLE_TWIST): Bt / (2 A lu^2 lv^2), A the
   cell's flat area, lu and lv the mean lengths of its warp and weft edges, so that on a rectangle (A = lu lv) a
   twist kappa12 costs 2 Bt kappa12^2 per area and a bend along the bias adds Bt. (Not Bt / (2 A^3): on a skewed
   sliver cell, A << lu lv, a bend along a thread also shows in T, and A^3 would make that spuriously stiff.) */
PetscReal FabricTwistStiffness(const SceneFabric *fabric, PetscReal cell_area, PetscReal lu, PetscReal lv);
