/* The implicit system's block matrix (BAIJ or SBAIJ, block size 3) read in place, and what PETSc 3.18 lacks for SBAIJ.

   SBAIJ stores only the upper triangle of blocks: half the bytes of BAIJ that every MatMult streams (measured on the
   hanging sheet at 257 x 257: MatMult 1.3x faster on 1 rank and on 2, 440 bytes per particle less). PETSc 3.18 gives
   no access to an MPISBAIJ matrix's parts and no inverse of its diagonal blocks, which point-block Jacobi (the
   smoother of the multigrid and the preconditioner of small scenes) needs; this module adds both. */
#pragma once
#include <petscmat.h>
#include "util.h"

/* A rank's own block rows: the diagonal part Ad (columns owned here, local indices) and, in parallel, the off-process
   part Ao (columns through garray, global block indices). For SBAIJ (upper = true) only blocks (i, j) with j >= i are
   stored, the diagonal one first in its row and kept whole; Ao then holds the columns on later ranks only. Blocks are
   column-major. */
typedef struct {
  Mat             Ad, Ao;
  const PetscInt *garray;
  const PetscInt *ia, *ja, *ib, *jb;
  PetscScalar    *va, *vb;
  PetscBool       upper;
} ClothBlockRows;

/* out = scale * the 3x3 block d (column-major) made symmetric from its upper triangle: SBAIJ's diagonal blocks, whose
   products read only that triangle. */
static inline void ClothBlockSymmetricFromUpper(const PetscScalar d[9], PetscScalar scale, PetscScalar out[9])
{
  for (PetscInt c = 0; c < 3; c++)
    for (PetscInt r = 0; r < 3; r++) out[3 * c + r] = scale * d[3 * PetscMax(r, c) + PetscMin(r, c)];
}

/* A is SEQBAIJ, MPIBAIJ, SEQSBAIJ or MPISBAIJ with block size 3 (else an error naming its type). */
PetscErrorCode ClothBlockRowsGet(Mat A, ClothBlockRows *rows);
PetscErrorCode ClothBlockRowsRestore(ClothBlockRows *rows);
/* Does A store blocks that ClothBlockRowsGet reads? */
PetscErrorCode ClothBlockMatrixIsBlock(Mat A, PetscBool *block);
/* Does A store only the upper triangle of blocks (SEQSBAIJ or MPISBAIJ)? Compared by type, not by MatGetType's name,
   which ClothBlockRowsGet renames for a moment. */
PetscErrorCode ClothBlockMatrixIsUpper(Mat A, PetscBool *upper);
/* An SBAIJ matrix gets MatInvertBlockDiagonal (point-block Jacobi); other types are left as they are. */
PetscErrorCode ClothBlockMatrixSetUpOperations(Mat A);

/* Adds elements' 3x3 blocks to an assembled block matrix in place. Each owned row's block is found among the columns
   that row stores and added there, which skips MatSetValuesBlockedLocal's index translation and general insertion
   (most of the assembly's cost in the dress's profile); the rows of ghosts (another rank's particles) still go through
   MatSetValuesBlockedLocal and its stash. Active on a (S)BAIJ matrix that was assembled before: its pattern is final
   (ClothCreateMatrix sets MAT_NEW_NONZERO_ALLOCATION_ERR), so every block an element adds is stored already; a block
   that is not is an error, as MatSetValues would make it. Otherwise (the first assembly, AIJ) every block goes through
   MatSetValuesBlockedLocal. Values end up as MatSetValuesBlockedLocal would put them, in the same order. */
typedef struct {
  Mat             A;
  PetscBool       active;
  ClothBlockRows  rows;
  PetscInt        nlocal; /* owned particles: local indices 0 .. nlocal - 1, then ghosts */
  const PetscInt *global; /* each local particle's global block index (A's local-to-global mapping) */
  PetscInt       *column; /* each ghost's column in Ao (index into garray), by local index; -1: none */
} ClothBlockAdder;

/* Begins adding to A, whose local-to-global mapping numbers the nlocal owned particles first. Not collective. */
PetscErrorCode ClothBlockAdderBegin(Mat A, PetscInt nlocal, ClothBlockAdder *adder);
/* Adds an element's blocks: H is 3np x 3np, row-major, over the local particles p (ADD_VALUES). */
PetscErrorCode ClothBlockAdderAdd(ClothBlockAdder *adder, PetscInt np, const PetscInt p[], const PetscScalar H[]);
PetscErrorCode ClothBlockAdderEnd(ClothBlockAdder *adder);
