/* Fabric coefficient mapping (see fabric.h for the formulas). */
#include "fabric.h"

PetscErrorCode FabricBiphasicFromKES(PetscReal emt_percent, PetscReal lt, PetscReal *soft, PetscReal *stiff, PetscReal *knee)
{
  const PetscReal strain = emt_percent / 100, secant = FABRIC_KES_TENSILE_FM / strain;

  PetscFunctionBeginUser;
  PetscCheck(emt_percent > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "KES tensile strain EMT = %g %%: expected a positive percentage", (double)emt_percent);
  PetscCheck(lt > 0.5 && lt < 1.5, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "KES tensile linearity LT = %g: a biphasic curve with its knee at EMT/2 needs 0.5 < LT < 1.5", (double)lt);
  /* F = E0 e below e_k = EMT/2, E0 e_k + E1 (e - e_k) above. F(EMT) = Fm gives E0 + E1 = 2 Fm/EMT; the work
     WT = EMT^2 (3 E0 + E1)/8 = LT Fm EMT/2 gives E0 = (2 LT - 1) Fm/EMT, E1 = (3 - 2 LT) Fm/EMT. */
  *soft  = (2 * lt - 1) * secant;
  *stiff = (3 - 2 * lt) * secant;
  *knee  = strain / 2;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode FabricSetFromKES(const FabricKES *kes, SceneFabric *fabric)
{
  PetscFunctionBeginUser;
  PetscCheck(kes->weight > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "KES weight W = %g mg/cm^2: expected a positive number", (double)kes->weight);
  PetscCheck((kes->lt_warp > 0) == (kes->lt_weft > 0), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "KES tensile linearity: give LT for both warp and weft, or for neither");
  fabric->density    = kes->weight * FABRIC_KES_WEIGHT_SI;
  fabric->bend_warp  = kes->bend_warp * FABRIC_KES_BEND_SI;
  fabric->bend_weft  = kes->bend_weft * FABRIC_KES_BEND_SI;
  fabric->bend_model = CLOTH_BEND_ANGLE;
  /* the loop of KES-FB2 is M = B K +- HB: its width 2HB is twice the friction moment */
  fabric->bend_hysteresis_warp = 0.5 * kes->hysteresis_warp * FABRIC_KES_MOMENT_SI;
  fabric->bend_hysteresis_weft = 0.5 * kes->hysteresis_weft * FABRIC_KES_MOMENT_SI;
  fabric->shear                = kes->shear * FABRIC_KES_SHEAR_SI;
  fabric->shear_model          = CLOTH_SHEAR_CELL;
  /* the loop of KES-FB1 is F = G phi +- HG: its width 2HG is twice the friction force */
  fabric->shear_hysteresis = 0.5 * kes->shear_hysteresis * FABRIC_KES_FORCE_SI;
  if (kes->lt_warp > 0) {
    PetscCall(FabricBiphasicFromKES(kes->emt_warp, kes->lt_warp, &fabric->stretch_warp, &fabric->stretch_stiff_warp, &fabric->stretch_knee_warp));
    PetscCall(FabricBiphasicFromKES(kes->emt_weft, kes->lt_weft, &fabric->stretch_weft, &fabric->stretch_stiff_weft, &fabric->stretch_knee_weft));
  } else {
    PetscCheck(kes->emt_warp > 0 && kes->emt_weft > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "KES tensile strain EMT = %g/%g %% (warp/weft): expected positive percentages", (double)kes->emt_warp, (double)kes->emt_weft);
    fabric->stretch_warp = fabric->stretch_stiff_warp = FABRIC_KES_TENSILE_FM / (kes->emt_warp / 100);
    fabric->stretch_weft = fabric->stretch_stiff_weft = FABRIC_KES_TENSILE_FM / (kes->emt_weft / 100);
    fabric->stretch_knee_warp = fabric->stretch_knee_weft = 0;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscReal FabricStretchLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width)
{
  return (warp ? fabric->stretch_warp : fabric->stretch_weft) * width / rest;
}

PetscReal FabricStretchLinkStiffStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width)
{
  return (warp ? fabric->stretch_stiff_warp : fabric->stretch_stiff_weft) * width / rest;
}

PetscReal FabricShearLinkStiffness(const SceneFabric *fabric, PetscReal rest, PetscReal cell_area)
{
  return fabric->shear * cell_area / (0.5 * rest * rest);
}

PetscReal FabricShearAngleStiffness(const SceneFabric *fabric, PetscReal cell_area)
{
  return fabric->shear * cell_area / 4.0;
}

PetscReal FabricShearCellStiffness(const SceneFabric *fabric, PetscReal cell_area)
{
  return fabric->shear * cell_area;
}

PetscReal FabricBendLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width)
{
  return (warp ? fabric->bend_warp : fabric->bend_weft) * width / (0.5 * rest);
}

PetscReal FabricBendAngleStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal segment, PetscReal width)
{
  return (warp ? fabric->bend_warp : fabric->bend_weft) * width / segment;
}

PetscReal FabricTwistRigidity(const SceneFabric *fabric)
{
  return fabric->bend_bias > 0 ? fabric->bend_bias - 0.25 * (fabric->bend_warp + fabric->bend_weft) : 0.0;
}

PetscReal FabricTwistStiffness(const SceneFabric *fabric, PetscReal cell_area, PetscReal lu, PetscReal lv)
{
  return FabricTwistRigidity(fabric) / (2 * cell_area * lu * lu * lv * lv);
}
