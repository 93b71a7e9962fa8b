/* Seam links: the springs between pattern pieces' seams (seam.h evaluates one), pulled together and then held sewn
   by the sewing phases (sewing.h), which set their stiffness. A contribution of the cloth (cloth.h) that owns this
   rank's share of the model's seam links and adds their elements to the cloth's pass. */
#pragma once
#include "cloth.h"

/* Creates the seam links' contribution and registers it with the cloth (ClothSetUp does, for every cloth). Not
   collective. */
PetscErrorCode ClothSeamLinksRegister(Cloth cloth);
/* This rank's seam links (local particle numbering) and their indices in the
   model, for the sewing phases to set their stiffness. Borrowed. */
PetscErrorCode ClothSeamLinksGetLocal(Cloth cloth, PetscInt *n, ClothSeamLink **links, const PetscInt **model_index);
