/* Fabric presets: real fabrics whose model values come from published measurements.

   Each preset fills a SceneFabric (density, stretch, shear, bending, and the bias bending rigidity where its source
   measured it; the cell shear model and the angle bending model, linear tensile curve, no damping); a scene's fabric
   names one with `preset:` and may override any value (`bend_bias: 0` drops the bias rigidity). Sources and derivations are cited beside every number in fabric_presets.c
   and summarised in docs/validation.md. */
#pragma once
#include "scene.h"

/* Fills *fabric with preset `name` (keeps its name field); *found tells whether the preset exists. Not collective. */
PetscErrorCode FabricPresetApply(const char name[], SceneFabric *fabric, PetscBool *found);
/* Writes the preset names, comma separated, into buf. */
PetscErrorCode FabricPresetListNames(char buf[], size_t len);
