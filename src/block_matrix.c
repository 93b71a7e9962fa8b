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
