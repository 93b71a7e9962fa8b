/* ClothBlockPtAP: the Galerkin product C = P^T A P of the implicit system's block matrix A (BAIJ or SBAIJ, block size 3) and
   an interpolation P whose rows are scalar weights times the 3x3 identity (the pattern grids' bilinear interpolation,
   gridhierarchy.h), computed from A's blocks as they are.

   Why not MatPtAP: PETSc 3.18 has no Galerkin product of a BAIJ matrix, so the multigrid used to convert A to AIJ
   before every refresh (1.5 KB per particle) and, in parallel, MatPtAP keeps its fine-sized intermediate A P for
   reuse (1.5 KB per particle kept, 0.8 KB more during the product): together 3.8 KB per particle at 1025 x 1025 on
   2 ranks, the largest part of the implicit run's memory (docs/performance.md, "Memory per particle").

   How: each rank takes its own rows of A. For a fine row i it forms R = A(i,:) P, at most a few coarse blocks, from
   the interpolation rows of i's neighbours (the ghost ones fetched once per nonzero pattern with
   MatCreateSubMatrices), and adds w R to the coarse rows I that i interpolates from (weight w). The sums go into a
   local block matrix over the coarse rows this rank touches, whose rows are then added into C (block size 3,
   partitioned as P's columns; rows owned elsewhere travel in the matrix assembly). Nothing of the fine level's size
   is stored: the local sums and C are coarse-level sized (1/16 of the particles at the default ratio 4).
   Of an SBAIJ matrix, which stores only U, the upper triangle with the diagonal D, the rows give S = P^T (U - D/2) P
   and C = S + S^T: each row of the sums is added to C once as it is and once transposed, as a block column.
   C itself can be AIJ, BAIJ or SBAIJ (SBAIJ keeps the blocks on and above the diagonal of what is added: MatSetValues
   ignores the lower triangle), so a coarse level can be the fine level of the next product. */
#pragma once
#include <petscmat.h>
#include "util.h"

typedef struct _n_ClothBlockPtAP *ClothBlockPtAP;

/* The symbolic product: C's nonzero pattern from A's pattern and P. A is (SEQ|MPI)(S)BAIJ with block size 3; P is
   MAIJ with 3 components and A's row layout: its scalar matrix's row i holds the weights of fine particle i.
   ctype: C's type, MATAIJ, MATBAIJ or MATSBAIJ. Collective. */
PetscErrorCode ClothBlockPtAPCreate(Mat A, Mat P, MatType ctype, ClothBlockPtAP *ptap);
/* The numeric product of A's current values (same nonzero pattern as at Create). Collective. */
PetscErrorCode ClothBlockPtAPCompute(ClothBlockPtAP ptap, Mat A);
/* C (borrowed; valid until Destroy). */
PetscErrorCode ClothBlockPtAPGetProduct(ClothBlockPtAP ptap, Mat *C);
PetscErrorCode ClothBlockPtAPDestroy(ClothBlockPtAP *ptap);
