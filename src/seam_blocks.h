/* Seam-block Jacobi: point-block Jacobi whose blocks join each sewn node with its partner on the other piece.

   A sewn seam holds a node to a point of the other piece with a spring 2.5 times as stiff as a stretch link. Point-block
   Jacobi divides every particle's residual by its own 3x3 diagonal block, which carries that spring; the mode in which
   the node and its partner move together, which the spring does not resist, is then scaled down by the spring's
   stiffness as well, and CG needs many iterations to resolve it (docs/performance.md, "Seams against the multigrid").
   Here the node and its partner (the other side's node with the larger weight in the sewn point, and at most
   CLOTH_SEAM_BLOCK_MAX_PARTICLES particles joined along a seam) form one block, inverted whole, so that the spring
   acts inside the block and the pair's common motion is scaled by the fabric's stiffness alone. A block whose
   particles are owned by different ranks is not formed: those particles keep their own 3x3 blocks.

   Used as a PCSHELL on the implicit matrix (BAIJ or SBAIJ, block size 3, the cloth's solver numbering). */
#pragma once
#include <petscksp.h>
#include "util.h"
#include "cloth.h"

#define CLOTH_SEAM_BLOCK_MAX_PARTICLES 3

typedef struct _n_ClothSeamBlocks *ClothSeamBlocks;

/* The blocks from this rank's seam links (the cloth set up; not collective). */
PetscErrorCode ClothSeamBlocksCreate(Cloth cloth, ClothSeamBlocks *sb);
/* Makes pc a PCSHELL applying the seam blocks (pc takes sb over and destroys it with itself). */
PetscErrorCode ClothSeamBlocksSetPC(ClothSeamBlocks sb, PC pc);
/* Is pc the seam-block Jacobi preconditioner? */
PetscErrorCode ClothSeamBlocksIsPC(PC pc, PetscBool *is);
/* This rank's joined blocks: block b holds the owned particles (local numbers) member[start[b] .. start[b + 1]);
   every other owned particle is a block of its own. Borrowed. */
PetscErrorCode ClothSeamBlocksGetBlocks(ClothSeamBlocks sb, PetscInt *nblocks, const PetscInt *start[], const PetscInt *member[]);
PetscErrorCode ClothSeamBlocksDestroy(ClothSeamBlocks *sb);
