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
