/* Fabric coefficient mapping (see fabric.h for the formulas). */
#include "fabric.h"

PetscReal FabricStretchLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width)
{
  return (warp ? fabric->stretch_warp : fabric->stretch_weft) * width / rest;
}

PetscReal FabricShearLinkStiffness(const SceneFabric *fabric, PetscReal rest, PetscReal cell_area)
{
  return fabric->shear * cell_area / (0.5 * rest * rest);
}

PetscReal FabricShearAngleStiffness(const SceneFabric *fabric, PetscReal cell_area)
{
  return fabric->shear * cell_area / 4.0;
}

PetscReal FabricBendLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width)
{
  return (warp ? fabric->bend_warp : fabric->bend_weft) * width / (0.5 * rest);
}

PetscReal FabricBendAngleStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal segment, PetscReal width)
{
  return (warp ? fabric->bend_warp : fabric->bend_weft) * width / segment;
}
