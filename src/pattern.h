/* Pattern meshing: the flat 2D grid of a pattern piece (MODEL.md section 3). */
#pragma once
#include "scene.h"

/* Fills uv (2 * nu * nv reals, caller-allocated) with the flat pattern coordinates, in metres, of
   particle (i, j) at uv[2 * (j * nu + i)]. Rejects folded or inverted cells with a clear error. */
PetscErrorCode PatternMeshPiece(const ScenePiece *piece, PetscReal uv[]);
/* Signed area of grid cell (i, j) of a piece with nu columns, from its flat coordinates. */
PetscReal PatternCellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j);
