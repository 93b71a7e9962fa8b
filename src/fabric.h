/* Fabric: from a fabric's measured moduli to the coefficients of the particle model.

   With h_u, h_v the local thread spacings (rest lengths along warp and weft) and w the spacing of
   the neighbouring parallel threads (the width one thread carries):
   - stretch link along a thread:   k = E w / l0        (E: tensile 2D modulus, N/m)
   - shear diagonal link:           k = G A / (l0^2/2)  (A: cell area; k = G on a square grid)
   - shear corner angle:            k = G A / 4         (N m; four corners share a cell)
   - bending skip-one link:         k = bend w / (l0/2) (bend in N/m per link on a square grid)
   - bending thread angle:          k = B w / h         (B: bending rigidity, N m; h: mean segment)
   so that on a uniform square grid the link coefficients equal the scene's values, and the angle
   coefficients give the continuum energies 0.5 G gamma^2 and 0.5 B kappa^2 per unit area. */
#pragma once
#include "scene.h"

PetscReal FabricStretchLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width);
PetscReal FabricShearLinkStiffness(const SceneFabric *fabric, PetscReal rest, PetscReal cell_area);
PetscReal FabricShearAngleStiffness(const SceneFabric *fabric, PetscReal cell_area);
PetscReal FabricBendLinkStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal rest, PetscReal width);
PetscReal FabricBendAngleStiffness(const SceneFabric *fabric, PetscBool warp, PetscReal segment, PetscReal width);
