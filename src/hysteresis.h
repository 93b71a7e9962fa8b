/* Bending and shear hysteresis: the friction elements (forces.h, ClothAngle with slip > 0) beside the elastic angle
   springs, and the state of their sliders. A contribution of the cloth (cloth.h): it owns this rank's friction
   elements, adds them to the cloth's pass, moves the sliders when a (sub-)step starts (ClothBeginStep), saves and
   restores them with the integrator's slots (ClothSaveState, ClothRestoreState), and declares, writes and reads them as
   its checkpoint fields (cloth.h, checkpoint_fields and checkpoint_load): one per family of sliders the fabric has,
   natural order, 0 where there is none. */
#pragma once
#include "cloth.h"

/* Creates the hysteresis contribution and registers it with the cloth (ClothSetUp does, for every cloth). Not
   collective. */
PetscErrorCode ClothHysteresisRegister(Cloth cloth);

typedef enum {
  CLOTH_SLIDERS_BEND, /* checkpoint field bend_slider: 4 per particle, cos and sin of the slider angle of the warp chain centred on it, then of the weft chain */
  CLOTH_SLIDERS_SHEAR /* checkpoint field shear_slider: 2 per particle, cos and sin of the slider angle of the cell whose first corner (i, j) it is */
} ClothSliderFamily;
#define CLOTH_SLIDER_FAMILIES 2
