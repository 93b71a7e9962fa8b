/* ClothGridHierarchy: geometric multigrid's coarse levels, made from the pattern pieces' structured grids.

   Every piece is a logical nu x nv grid (scene.h). A coarser level keeps every other row and column of each piece
   (the even indices, and the last one: nu -> nu/2 + 1; -implicit_pc_grid_ratio r keeps every r-th), and its interpolation is bilinear in the grid indices: a
   particle between two kept ones gets half of each, one in the middle of a cell a quarter of each corner. The
   three components of a particle are interpolated alike, so the interpolation is a scalar one times the 3x3
   identity. Pieces are coarsened independently; what couples them (seams, contacts) reaches the coarse levels
   through the Galerkin products P^T A P, which PCMG computes. A piece that is down to 2 (or 3) rows or columns is
   not coarsened further along that direction.

   A coarse particle is owned by the rank that owns the fine particle it sits on, so the interpolation is local
   except along partition boundaries. The levels are numbered as PCMG numbers them: 0 the coarsest, nlevels - 1
   the cloth itself. Building a level costs O(N) time and integers on every rank (the same arrays as the cloth's
   own natural-to-solver map, ClothLayout). */
#pragma once
#include "cloth.h"

typedef struct _n_ClothGridHierarchy *ClothGridHierarchy;

/* At most this many levels (a 2^15-particle side would need 16). */
#define CLOTH_GRID_MAX_LEVELS 16

/* Coarsens the cloth's pattern grids by ratio (2: every other row and column) until a level has at most coarse_particles particles, no piece can be coarsened
   further, or there are max_levels levels (the cloth included). all_maij: every interpolation MAIJ (the block
   Galerkin products of block_ptap.h take them at every level); else only the finest. Collective; after ClothSetUp. */
PetscErrorCode ClothGridHierarchyCreate(Cloth cloth, PetscInt ratio, PetscInt max_levels, PetscInt coarse_particles, PetscBool all_maij, ClothGridHierarchy *gh);
PetscErrorCode ClothGridHierarchyGetLevels(ClothGridHierarchy gh, PetscInt *nlevels);
/* The interpolation from level - 1 to level (1 <= level < nlevels) (borrowed): the finest one (level nlevels - 1), and
   with all_maij every one, MAIJ with 3 components (its scalar weights: MatMAIJGetAIJ), the others AIJ with block
   size 3. */
PetscErrorCode ClothGridHierarchyGetInterpolation(ClothGridHierarchy gh, PetscInt level, Mat *P);
/* The particles of a level (global). */
PetscErrorCode ClothGridHierarchyGetLevelSize(ClothGridHierarchy gh, PetscInt level, PetscInt *nparticles);
/* Prints the particles and grids of each level. */
PetscErrorCode ClothGridHierarchyView(ClothGridHierarchy gh, PetscViewer viewer);
PetscErrorCode ClothGridHierarchyDestroy(ClothGridHierarchy *gh);
