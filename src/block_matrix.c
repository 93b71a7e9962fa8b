/* The implicit system's block matrix (see block_matrix.h). */
#include "block_matrix.h"
#include <petsc/private/kernels/blockinvert.h>

#define BS 3
#define BS2 9

PetscErrorCode ClothBlockMatrixIsBlock(Mat A, PetscBool *block)
{
  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, block, MATSEQBAIJ, MATMPIBAIJ, MATSEQSBAIJ, MATMPISBAIJ, ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockMatrixIsUpper(Mat A, PetscBool *upper)
{
  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, upper, MATSEQSBAIJ, MATMPISBAIJ, ""));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PETSc 3.18 has no accessor for an MPISBAIJ matrix's parts. Its data begins with the same MPIBAIJHEADER as an
   MPIBAIJ matrix's (src/mat/impls/sbaij/mpi/mpisbaij.h: the diagonal part A, the off-process part B, garray), so
   MatMPIBAIJGetSeqBAIJ reads them while the type name says MPIBAIJ; the parts' types are checked after. */
static PetscErrorCode MPISBAIJGetParts(Mat A, Mat *Ad, Mat *Ao, const PetscInt **garray)
{
  PetscBool sbaij, baij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectChangeTypeName((PetscObject)A, MATMPIBAIJ));
  PetscCall(MatMPIBAIJGetSeqBAIJ(A, Ad, Ao, garray));
  PetscCall(PetscObjectChangeTypeName((PetscObject)A, MATMPISBAIJ));
  PetscCall(PetscObjectTypeCompare((PetscObject)*Ad, MATSEQSBAIJ, &sbaij));
  PetscCall(PetscObjectTypeCompare((PetscObject)*Ao, MATSEQBAIJ, &baij));
  PetscCheck(sbaij && baij, PETSC_COMM_SELF, PETSC_ERR_SUP, "This PETSc's MPISBAIJ layout is not the one of PETSc 3.18");
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode GetPartArray(Mat part, PetscBool sbaij, PetscScalar **values)
{
  PetscFunctionBeginUser;
  if (sbaij)
    PetscCall(MatSeqSBAIJGetArray(part, values));
  else
    PetscCall(MatSeqBAIJGetArray(part, values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode RestorePartArray(Mat part, PetscBool sbaij, PetscScalar **values)
{
  PetscFunctionBeginUser;
  if (sbaij)
    PetscCall(MatSeqSBAIJRestoreArray(part, values));
  else
    PetscCall(MatSeqBAIJRestoreArray(part, values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockRowsGet(Mat A, ClothBlockRows *rows)
{
  PetscBool block, mpi, done;
  PetscInt  n, bs;
  MatType   type;

  PetscFunctionBeginUser;
  PetscCall(ClothBlockMatrixIsBlock(A, &block));
  PetscCall(MatGetBlockSize(A, &bs));
  PetscCall(MatGetType(A, &type));
  PetscCheck(block && bs == BS, PetscObjectComm((PetscObject)A), PETSC_ERR_SUP, "Block rows of a %s matrix of block size %" PetscInt_FMT ": expected (s)baij of block size %d", type, bs, BS);
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &mpi, MATMPIBAIJ, MATMPISBAIJ, ""));
  PetscCall(ClothBlockMatrixIsUpper(A, &rows->upper));
  rows->Ao = NULL, rows->garray = NULL, rows->ib = rows->jb = NULL, rows->vb = NULL;
  if (!mpi)
    rows->Ad = A;
  else if (rows->upper)
    PetscCall(MPISBAIJGetParts(A, &rows->Ad, &rows->Ao, &rows->garray));
  else
    PetscCall(MatMPIBAIJGetSeqBAIJ(A, &rows->Ad, &rows->Ao, &rows->garray));
  PetscCall(MatGetRowIJ(rows->Ad, 0, PETSC_FALSE, PETSC_TRUE, &n, &rows->ia, &rows->ja, &done));
  PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "No block row structure of the diagonal part");
  PetscCall(GetPartArray(rows->Ad, rows->upper, &rows->va));
  if (rows->Ao) {
    PetscCall(MatGetRowIJ(rows->Ao, 0, PETSC_FALSE, PETSC_TRUE, &n, &rows->ib, &rows->jb, &done));
    PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "No block row structure of the off-process part");
    PetscCall(MatSeqBAIJGetArray(rows->Ao, &rows->vb));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockRowsRestore(ClothBlockRows *rows)
{
  PetscBool done;
  PetscInt  n;

  PetscFunctionBeginUser;
  PetscCall(RestorePartArray(rows->Ad, rows->upper, &rows->va));
  PetscCall(MatRestoreRowIJ(rows->Ad, 0, PETSC_FALSE, PETSC_TRUE, &n, &rows->ia, &rows->ja, &done));
  if (rows->Ao) {
    PetscCall(MatSeqBAIJRestoreArray(rows->Ao, &rows->vb));
    PetscCall(MatRestoreRowIJ(rows->Ao, 0, PETSC_FALSE, PETSC_TRUE, &n, &rows->ib, &rows->jb, &done));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

#define INVERSE_BLOCKS_KEY "ClothInverseDiagonalBlocks"

/* MatInvertBlockDiagonal of an SBAIJ matrix: each owned particle's diagonal block, made symmetric from its upper
   triangle (the one SBAIJ's products read), inverted; column-major, as point-block Jacobi applies them. The inverses
   live in a container composed with the matrix, as PETSc keeps its own in the matrix. */
static PetscErrorCode InvertDiagonalBlocksSBAIJ(Mat A, const PetscScalar **values)
{
  ClothBlockRows rows;
  PetscContainer container;
  PetscScalar   *inverse;
  PetscInt       m;

  PetscFunctionBeginUser;
  PetscCall(MatGetLocalSize(A, &m, NULL));
  PetscCall(PetscObjectQuery((PetscObject)A, INVERSE_BLOCKS_KEY, (PetscObject *)&container));
  if (!container) {
    PetscCall(PetscMalloc1(BS * m, &inverse));
    PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
    PetscCall(PetscContainerSetPointer(container, inverse));
    PetscCall(PetscContainerSetUserDestroy(container, PetscContainerUserDestroyDefault));
    PetscCall(PetscObjectCompose((PetscObject)A, INVERSE_BLOCKS_KEY, (PetscObject)container));
    PetscCall(PetscContainerDestroy(&container));
    PetscCall(PetscObjectQuery((PetscObject)A, INVERSE_BLOCKS_KEY, (PetscObject *)&container));
  }
  PetscCall(PetscContainerGetPointer(container, (void **)&inverse));
  PetscCall(ClothBlockRowsGet(A, &rows));
  for (PetscInt i = 0; i < m / BS; i++) {
    const PetscScalar *d = rows.va + BS2 * rows.ia[i];
    PetscScalar       *b = inverse + BS2 * i;
    PetscCheck(rows.ia[i + 1] > rows.ia[i] && rows.ja[rows.ia[i]] == i, PETSC_COMM_SELF, PETSC_ERR_PLIB, "SBAIJ block row %" PetscInt_FMT " does not begin with its diagonal block", i);
    ClothBlockSymmetricFromUpper(d, 1.0, b);
    PetscCall(PetscKernel_A_gets_inverse_A_3(b, 0.0, PETSC_FALSE, NULL));
  }
  PetscCall(ClothBlockRowsRestore(&rows));
  PetscCall(PetscLogFlops(33.0 * m));
  *values = inverse;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockMatrixSetUpOperations(Mat A)
{
  PetscBool sbaij;

  PetscFunctionBeginUser;
  PetscCall(ClothBlockMatrixIsUpper(A, &sbaij));
  if (sbaij) PetscCall(MatSetOperation(A, MATOP_INVERT_BLOCK_DIAGONAL, (void (*)(void))InvertDiagonalBlocksSBAIJ));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each ghost's column in the off-process part (its global block index found in garray, which PETSc keeps sorted);
   false when A's mapping does not number the owned particles first, in A's row order. */
static PetscErrorCode MapAdderColumns(ClothBlockAdder *ad, PetscInt nblocks, PetscInt rstart, PetscBool *ok)
{
  PetscInt nb = 0;

  PetscFunctionBeginUser;
  *ok = PETSC_TRUE;
  for (PetscInt i = 0; i < ad->nlocal; i++)
    if (ad->global[i] != rstart + i) *ok = PETSC_FALSE;
  if (ad->rows.Ao) PetscCall(MatGetLocalSize(ad->rows.Ao, NULL, &nb));
  nb /= BS;
  if (ad->rows.garray) {
    PetscBool sorted;
    PetscCall(PetscSortedInt(nb, ad->rows.garray, &sorted));
    if (!sorted) *ok = PETSC_FALSE;
  }
  PetscCall(PetscMalloc1(nblocks, &ad->column));
  for (PetscInt j = 0; j < nblocks; j++) {
    ad->column[j] = -1;
    if (j >= ad->nlocal && ad->rows.garray) PetscCall(PetscFindInt(ad->global[j], nb, ad->rows.garray, &ad->column[j]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockAdderBegin(Mat A, PetscInt nlocal, ClothBlockAdder *ad)
{
  ISLocalToGlobalMapping l2g;
  PetscBool              block, assembled, ok;
  PetscInt               bs, size, rstart;

  PetscFunctionBeginUser;
  ad->A      = A;
  ad->active = PETSC_FALSE;
  ad->nlocal = nlocal;
  ad->column = NULL;
  ad->global = NULL;
  PetscCall(ClothBlockMatrixIsBlock(A, &block));
  PetscCall(MatGetBlockSize(A, &bs));
  PetscCall(MatAssembled(A, &assembled));
  if (!block || bs != BS || !assembled) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(MatGetLocalToGlobalMapping(A, &l2g, NULL));
  PetscCall(ISLocalToGlobalMappingGetSize(l2g, &size));
  PetscCall(ISLocalToGlobalMappingGetBlockSize(l2g, &bs));
  PetscCall(ISLocalToGlobalMappingGetBlockIndices(l2g, &ad->global));
  PetscCall(MatGetOwnershipRange(A, &rstart, NULL));
  PetscCall(ClothBlockRowsGet(A, &ad->rows));
  PetscCall(MapAdderColumns(ad, size / bs, rstart / BS, &ok));
  ad->active = ok;
  if (!ok) PetscCall(ClothBlockAdderEnd(ad));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Where block (row, col) of an owned row is stored: NULL with *skip for a block SBAIJ does not store (below the
   diagonal), NULL without it for one missing from the pattern. */
static PetscScalar *FindAdderBlock(const ClothBlockAdder *ad, PetscInt row, PetscInt col, PetscBool *skip)
{
  const ClothBlockRows *r = &ad->rows;
  PetscInt              loc;

  *skip = (r->upper && ad->global[col] < ad->global[row]) ? PETSC_TRUE : PETSC_FALSE;
  if (*skip) return NULL;
  if (col < ad->nlocal) {
    if (PetscFindInt(col, r->ia[row + 1] - r->ia[row], r->ja + r->ia[row], &loc) || loc < 0) return NULL;
    return r->va + BS2 * (r->ia[row] + loc);
  }
  if (ad->column[col] < 0 || !r->ib) return NULL;
  if (PetscFindInt(ad->column[col], r->ib[row + 1] - r->ib[row], r->jb + r->ib[row], &loc) || loc < 0) return NULL;
  return r->vb + BS2 * (r->ib[row] + loc);
}

PetscErrorCode ClothBlockAdderAdd(ClothBlockAdder *ad, PetscInt np, const PetscInt p[], const PetscScalar H[])
{
  const PetscInt n = BS * np;

  PetscFunctionBeginUser;
  if (!ad->active) {
    PetscCall(MatSetValuesBlockedLocal(ad->A, np, p, np, p, H, ADD_VALUES));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt a = 0; a < np; a++) {
    if (p[a] >= ad->nlocal) { /* a ghost's row: to its owner through the stash */
      PetscCall(MatSetValuesBlockedLocal(ad->A, 1, &p[a], np, p, H + BS * a * n, ADD_VALUES));
      continue;
    }
    for (PetscInt b = 0; b < np; b++) {
      PetscBool    skip;
      PetscScalar *v = FindAdderBlock(ad, p[a], p[b], &skip);

      if (skip) continue;
      PetscCheck(v, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Block (%" PetscInt_FMT ", %" PetscInt_FMT ") is not in the pattern of the assembled matrix", ad->global[p[a]], ad->global[p[b]]);
      for (PetscInt c = 0; c < BS; c++) /* blocks are stored column-major */
        for (PetscInt r = 0; r < BS; r++) v[BS * c + r] += H[(BS * a + r) * n + BS * b + c];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockAdderEnd(ClothBlockAdder *ad)
{
  PetscFunctionBeginUser;
  if (ad->global) {
    ISLocalToGlobalMapping l2g;
    PetscCall(MatGetLocalToGlobalMapping(ad->A, &l2g, NULL));
    PetscCall(ISLocalToGlobalMappingRestoreBlockIndices(l2g, &ad->global));
  }
  if (ad->column) PetscCall(ClothBlockRowsRestore(&ad->rows));
  PetscCall(PetscFree(ad->column));
  ad->global = NULL;
  ad->active = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}
