/* ClothBlockPtAP (see block_ptap.h). */
#include "block_ptap.h"
#include "block_matrix.h"
#include "log.h"

#define BS 3
#define BS2 9

struct _n_ClothBlockPtAP {
  PetscInt       nlocal, nghost; /* A's owned block rows; its off-process block columns (garray) */
  PetscInt      *poffset;        /* nlocal + nghost + 1: where the parents of fine particle k start (owned, then ghosts) */
  PetscInt      *parent;         /* the coarse (global block) indices each fine particle interpolates from */
  PetscScalar   *weight;         /* and their weights */
  PetscInt       cstart, cend;   /* C's owned block rows */
  PetscInt       nremote;        /* coarse rows owned elsewhere that this rank's fine rows add to */
  PetscInt      *remote;         /* sorted */
  Mat            L;              /* SEQBAIJ: the sums of this rank, rows cstart..cend-1 then remote[], global columns */
  Mat            C;
  PetscBool      upper;  /* A is SBAIJ: L holds S of FormRow and C = S + S^T */
  PetscBool      cupper; /* C is SBAIJ: it keeps the blocks added on and above its diagonal */
  PetscScalar   *tval;   /* room for one block row of L, laid out by rows */
  PetscInt       rmax;   /* room in rcol, rval: R = A(i,:) P of one fine row */
  PetscInt      *rcol;
  PetscScalar   *rval;
  PetscLogDouble flops; /* of the current product, for -log_view */
};

/* The parents of the fine particles from the scalar interpolation rows (one per particle), the k-th particle's from
   row qstart + k of Q; pass 0 counts into poffset[first + k + 1], pass 1 fills. */
static PetscErrorCode ReadParents(ClothBlockPtAP ptap, Mat Q, PetscInt qstart, PetscInt n, PetscInt first, PetscInt pass)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt    *cols;
    const PetscScalar *vals;
    PetscInt           ncols;
    PetscCall(MatGetRow(Q, qstart + k, &ncols, &cols, &vals));
    if (pass == 0) ptap->poffset[first + k + 1] = ncols;
    for (PetscInt c = 0; pass == 1 && c < ncols; c++) {
      ptap->parent[ptap->poffset[first + k] + c] = cols[c];
      ptap->weight[ptap->poffset[first + k] + c] = vals[c];
    }
    PetscCall(MatRestoreRow(Q, qstart + k, &ncols, &cols, &vals));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The interpolation rows of the owned fine particles and of A's ghosts (fetched from their owners), from P's
   scalar weights (P is MAIJ with 3 components, gridhierarchy.h). */
static PetscErrorCode GetParents(ClothBlockPtAP ptap, Mat P, const ClothBlockRows *rows)
{
  PetscInt  rstart, ncols, dof;
  IS        isrow, iscol;
  Mat      *ghost = NULL, Q;
  PetscBool maij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)P, &maij, MATSEQMAIJ, MATMPIMAIJ, ""));
  PetscCall(MatGetBlockSize(P, &dof));
  PetscCheck(maij && dof == BS, PetscObjectComm((PetscObject)P), PETSC_ERR_ARG_WRONG, "Block Galerkin product: the interpolation must be MAIJ with %d components (scalar weights times the 3x3 identity)", BS);
  PetscCall(MatMAIJGetAIJ(P, &Q));
  PetscCall(MatGetOwnershipRange(Q, &rstart, NULL));
  PetscCall(MatGetSize(Q, NULL, &ncols));
  if (rows->Ao) { /* collective: also on a rank without ghosts */
    PetscInt *prow;
    PetscCall(PetscMalloc1(ptap->nghost, &prow));
    for (PetscInt k = 0; k < ptap->nghost; k++) prow[k] = rows->garray[k];
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, ptap->nghost, prow, PETSC_OWN_POINTER, &isrow));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, ncols, 0, 1, &iscol));
    PetscCall(MatCreateSubMatrices(Q, 1, &isrow, &iscol, MAT_INITIAL_MATRIX, &ghost));
    PetscCall(ISDestroy(&isrow));
    PetscCall(ISDestroy(&iscol));
  }
  PetscCall(PetscMalloc1(ptap->nlocal + ptap->nghost + 1, &ptap->poffset));
  ptap->poffset[0] = 0;
  for (PetscInt pass = 0; pass < 2; pass++) {
    PetscCall(ReadParents(ptap, Q, rstart, ptap->nlocal, 0, pass));
    if (ghost) PetscCall(ReadParents(ptap, ghost[0], 0, ptap->nghost, ptap->nlocal, pass));
    if (pass == 0) {
      for (PetscInt k = 0; k < ptap->nlocal + ptap->nghost; k++) ptap->poffset[k + 1] += ptap->poffset[k];
      PetscCall(PetscMalloc2(ptap->poffset[ptap->nlocal + ptap->nghost], &ptap->parent, ptap->poffset[ptap->nlocal + ptap->nghost], &ptap->weight));
    }
  }
  if (ghost) PetscCall(MatDestroySubMatrices(1, &ghost));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* R += a P(f, :) for the 3x3 block a of A in fine column f. */
static inline void AddBlockTimesParents(ClothBlockPtAP ptap, PetscInt f, const PetscScalar a[], PetscInt *nr)
{
  for (PetscInt q = ptap->poffset[f]; q < ptap->poffset[f + 1]; q++) {
    const PetscInt    J = ptap->parent[q];
    const PetscScalar w = ptap->weight[q];
    PetscInt          t = 0;
    while (t < *nr && ptap->rcol[t] != J) t++;
    if (t == *nr) {
      ptap->rcol[t] = J;
      for (PetscInt s = 0; s < BS2; s++) ptap->rval[BS2 * t + s] = 0;
      (*nr)++;
    }
    for (PetscInt s = 0; s < BS2; s++) ptap->rval[BS2 * t + s] += w * a[s];
    ptap->flops += 2 * BS2;
  }
}

/* R = A(i,:) P, its coarse columns in rcol[0, nr) and 3x3 blocks (column-major, as BAIJ stores them) in rval. */
static void FormRow(ClothBlockPtAP ptap, const ClothBlockRows *rows, PetscInt i, PetscInt *nr)
{
  PetscInt k = rows->ia[i];

  *nr = 0;
  if (rows->upper && k < rows->ia[i + 1] && rows->ja[k] == i) {
    /* SBAIJ stores U, the upper triangle with the diagonal D: A = U + U^T - D, so P^T A P = S + S^T with
       S = P^T (U - D/2) P. The diagonal block enters S at half weight, made symmetric from its upper triangle. */
    const PetscScalar *d = rows->va + BS2 * k;
    PetscScalar        half[BS2];
    ClothBlockSymmetricFromUpper(d, 0.5, half);
    AddBlockTimesParents(ptap, i, half, nr);
    k++;
  }
  for (; k < rows->ia[i + 1]; k++) AddBlockTimesParents(ptap, rows->ja[k], rows->va + BS2 * k, nr);
  if (rows->Ao)
    for (PetscInt k = rows->ib[i]; k < rows->ib[i + 1]; k++) AddBlockTimesParents(ptap, ptap->nlocal + rows->jb[k], rows->vb + BS2 * k, nr);
}

/* The most coarse columns any R can have: the parents of a fine row's neighbours, counted with repeats. */
static PetscInt RowBound(ClothBlockPtAP ptap, const ClothBlockRows *rows)
{
  PetscInt bound = 1;
  for (PetscInt i = 0; i < ptap->nlocal; i++) {
    PetscInt n = 0;
    for (PetscInt k = rows->ia[i]; k < rows->ia[i + 1]; k++) n += ptap->poffset[rows->ja[k] + 1] - ptap->poffset[rows->ja[k]];
    if (rows->Ao)
      for (PetscInt k = rows->ib[i]; k < rows->ib[i + 1]; k++) n += ptap->poffset[ptap->nlocal + rows->jb[k] + 1] - ptap->poffset[ptap->nlocal + rows->jb[k]];
    bound = PetscMax(bound, n);
  }
  return bound;
}

/* The row r of L that holds coarse row crow. */
static PetscErrorCode LocalRowOf(ClothBlockPtAP ptap, PetscInt crow, PetscInt *r)
{
  PetscInt loc;

  PetscFunctionBeginUser;
  if (crow >= ptap->cstart && crow < ptap->cend) {
    *r = crow - ptap->cstart;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscFindInt(crow, ptap->nremote, ptap->remote, &loc));
  PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Block Galerkin product: coarse row %" PetscInt_FMT " is neither owned nor a known remote row", crow);
  *r = ptap->cend - ptap->cstart + loc;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The coarse rows owned elsewhere that the owned fine rows interpolate from. */
static PetscErrorCode FindRemoteRows(ClothBlockPtAP ptap)
{
  PetscInt n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(ptap->poffset[ptap->nlocal], &ptap->remote));
  for (PetscInt q = 0; q < ptap->poffset[ptap->nlocal]; q++)
    if (ptap->parent[q] < ptap->cstart || ptap->parent[q] >= ptap->cend) ptap->remote[n++] = ptap->parent[q];
  PetscCall(PetscSortRemoveDupsInt(&n, ptap->remote));
  ptap->nremote = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* L's nonzero pattern, block CSR: row r holds every column of R of every owned fine row that interpolates from
   coarse row r. Built by counting, filling with repeats and sorting each row: at 1025 x 1025 on 1 rank the whole
   symbolic product takes 1.7 s so, 6.9 s with a MATPREALLOCATOR's hash taking every fine row's entries. */
static PetscErrorCode SumsPattern(ClothBlockPtAP ptap, const ClothBlockRows *rows, PetscInt nrows, PetscInt **li, PetscInt **lj)
{
  PetscInt *start, *fill;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nrows + 1, &start));
  PetscCall(PetscMalloc1(nrows, &fill));
  for (PetscInt pass = 0; pass < 2; pass++) { /* count, then fill */
    for (PetscInt i = 0; i < ptap->nlocal; i++) {
      PetscInt nr;
      FormRow(ptap, rows, i, &nr);
      for (PetscInt q = ptap->poffset[i]; q < ptap->poffset[i + 1]; q++) {
        PetscInt r = -1;
        PetscCall(LocalRowOf(ptap, ptap->parent[q], &r));
        if (pass == 0)
          start[r + 1] += nr;
        else {
          PetscCall(PetscArraycpy(*lj + fill[r], ptap->rcol, nr));
          fill[r] += nr;
        }
      }
    }
    if (pass == 0) {
      for (PetscInt r = 0; r < nrows; r++) start[r + 1] += start[r];
      PetscCall(PetscArraycpy(fill, start, nrows));
      PetscCall(PetscMalloc1(start[nrows], lj));
    }
  }
  /* sort each row, drop repeats, close the gaps */
  PetscCall(PetscMalloc1(nrows + 1, li));
  (*li)[0] = 0;
  for (PetscInt r = 0; r < nrows; r++) {
    PetscInt n = start[r + 1] - start[r];
    PetscCall(PetscSortRemoveDupsInt(&n, *lj + start[r]));
    PetscCall(PetscArraymove(*lj + (*li)[r], *lj + start[r], n));
    (*li)[r + 1] = (*li)[r] + n;
  }
  PetscCall(PetscFree(start));
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Adds L's rows into M (C, or its preallocator with lv NULL: zeros) as rows of C and, for SBAIJ A, each also transposed
   as a block column (the S^T of FormRow): its blocks B_k at coarse columns J_k go to rows J_k, column crow, as B_k^T.
   Input row-oriented: a block row of L's column-major blocks is transposed into tval; the block column of the B_k^T,
   laid out by rows, is L's blocks as they are. (PETSc 3.18's column-oriented input of blocks for rows owned by another
   rank of an MPIBAIJ or MPISBAIJ matrix reads the wrong entries: MatStashValuesColBlocked_Private.) */
static PetscErrorCode AddSums(ClothBlockPtAP ptap, Mat M, PetscInt nrows, const PetscInt li[], const PetscInt lj[], const PetscScalar lv[], InsertMode mode)
{
  PetscFunctionBeginUser;
  for (PetscInt r = 0; r < nrows; r++) {
    const PetscInt     crow = r < ptap->cend - ptap->cstart ? ptap->cstart + r : ptap->remote[r - (ptap->cend - ptap->cstart)];
    const PetscInt     n    = li[r + 1] - li[r];
    const PetscScalar *row  = lv ? lv + BS2 * li[r] : ptap->tval;
    if (n == 0) continue;
    for (PetscInt k = 0; lv && k < n; k++)
      for (PetscInt a = 0; a < BS; a++)
        for (PetscInt b = 0; b < BS; b++) ptap->tval[a * BS * n + BS * k + b] = row[BS2 * k + BS * b + a];
    PetscCall(MatSetValuesBlocked(M, 1, &crow, n, lj + li[r], ptap->tval, mode));
    if (ptap->upper) PetscCall(MatSetValuesBlocked(M, n, lj + li[r], 1, &crow, row, mode));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The nonzero patterns of L (this rank's sums) and C (every rank's rows added, through a MATPREALLOCATOR that takes
   L's rows once each: coarse-level sized work). */
static PetscErrorCode PreallocateProducts(ClothBlockPtAP ptap, const ClothBlockRows *rows, MPI_Comm comm, PetscInt ncoarse, MatType ctype)
{
  Mat      Cpre;
  PetscInt nrows = ptap->cend - ptap->cstart + ptap->nremote, *li, *lj, longest = 1;

  PetscFunctionBeginUser;
  PetscCall(SumsPattern(ptap, rows, nrows, &li, &lj));
  PetscCall(MatCreate(PETSC_COMM_SELF, &ptap->L));
  PetscCall(MatSetSizes(ptap->L, BS * nrows, BS * ncoarse, BS * nrows, BS * ncoarse));
  PetscCall(MatSetType(ptap->L, MATSEQBAIJ));
  PetscCall(MatSeqBAIJSetPreallocationCSR(ptap->L, BS, li, lj, NULL));
  PetscCall(MatCreate(comm, &Cpre));
  PetscCall(MatSetType(Cpre, MATPREALLOCATOR));
  PetscCall(MatSetSizes(Cpre, BS * (ptap->cend - ptap->cstart), BS * (ptap->cend - ptap->cstart), PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(Cpre, BS));
  PetscCall(MatSetUp(Cpre));
  for (PetscInt r = 0; r < nrows; r++) longest = PetscMax(longest, li[r + 1] - li[r]);
  PetscCall(PetscCalloc1(BS2 * longest, &ptap->tval));
  PetscCall(AddSums(ptap, Cpre, nrows, li, lj, NULL, INSERT_VALUES));
  PetscCall(PetscFree(li));
  PetscCall(PetscFree(lj));
  PetscCall(MatAssemblyBegin(Cpre, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(Cpre, MAT_FINAL_ASSEMBLY));
  PetscCall(MatCreate(comm, &ptap->C));
  PetscCall(MatSetSizes(ptap->C, BS * (ptap->cend - ptap->cstart), BS * (ptap->cend - ptap->cstart), PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(ptap->C, ctype));
  PetscCall(ClothBlockMatrixIsUpper(ptap->C, &ptap->cupper));
  PetscCall(MatSetBlockSize(ptap->C, BS));
  /* SBAIJ: the preallocation counts the upper blocks, and its zero fill (of every block added) keeps those only, as
     PETSc 3.18's SBAIJ ignores the lower triangle by default (set again for the products) */
  PetscCall(MatPreallocatorPreallocate(Cpre, PETSC_TRUE, ptap->C));
  PetscCall(MatDestroy(&Cpre));
  if (ptap->cupper) PetscCall(MatSetOption(ptap->C, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  PetscCall(ClothBlockMatrixSetUpOperations(ptap->C));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockPtAPCreate(Mat A, Mat P, MatType ctype, ClothBlockPtAP *ptap)
{
  ClothBlockPtAP p;
  ClothBlockRows rows;
  PetscInt       bs, m, mp, ncoarse, cstart, cend;
  MPI_Comm       comm = PetscObjectComm((PetscObject)A);

  PetscFunctionBeginUser;
  PetscCall(MatGetBlockSize(A, &bs));
  PetscCheck(bs == BS, comm, PETSC_ERR_ARG_WRONG, "Block Galerkin product: block size %" PetscInt_FMT ", expected %d", bs, BS);
  PetscCall(MatGetLocalSize(A, &m, NULL));
  PetscCall(MatGetLocalSize(P, &mp, NULL));
  PetscCheck(m == mp, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "Block Galerkin product: %" PetscInt_FMT " local rows of A against %" PetscInt_FMT " of P", m, mp);
  PetscCall(MatGetOwnershipRangeColumn(P, &cstart, &cend));
  PetscCall(MatGetSize(P, NULL, &ncoarse));
  PetscCall(PetscLogEventBegin(ClothLog.block_ptap_symbolic, A, 0, 0, 0));
  PetscCall(PetscNew(&p));
  p->nlocal = m / BS;
  p->cstart = cstart / BS;
  p->cend   = cend / BS;
  PetscCall(ClothBlockRowsGet(A, &rows));
  p->upper = rows.upper;
  if (rows.Ao) {
    PetscInt nghost;
    PetscCall(MatGetSize(rows.Ao, NULL, &nghost));
    p->nghost = nghost / BS;
  }
  PetscCall(GetParents(p, P, &rows));
  PetscCall(FindRemoteRows(p));
  p->rmax = RowBound(p, &rows);
  PetscCall(PetscMalloc2(p->rmax, &p->rcol, BS2 * p->rmax, &p->rval));
  PetscCall(PreallocateProducts(p, &rows, comm, ncoarse / BS, ctype));
  PetscCall(ClothBlockRowsRestore(&rows));
  PetscCall(PetscLogEventEnd(ClothLog.block_ptap_symbolic, A, 0, 0, 0));
  *ptap = p;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Adds w R into row r of L (whose pattern holds every column of R). */
static PetscErrorCode AddRowToSums(ClothBlockPtAP ptap, PetscInt r, PetscScalar w, PetscInt nr, const PetscInt li[], const PetscInt lj[], PetscScalar lv[])
{
  PetscFunctionBeginUser;
  for (PetscInt t = 0; t < nr; t++) {
    PetscInt           loc;
    PetscScalar       *dst;
    const PetscScalar *src = ptap->rval + BS2 * t;
    PetscCall(PetscFindInt(ptap->rcol[t], li[r + 1] - li[r], lj + li[r], &loc));
    PetscCheck(loc >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Block Galerkin product: coarse column %" PetscInt_FMT " missing from the pattern (the matrix's nonzero pattern changed)", ptap->rcol[t]);
    dst = lv + BS2 * (li[r] + loc);
    for (PetscInt s = 0; s < BS2; s++) dst[s] += w * src[s];
  }
  ptap->flops += 2 * BS2 * nr;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockPtAPCompute(ClothBlockPtAP ptap, Mat A)
{
  ClothBlockRows  rows;
  const PetscInt *li, *lj;
  PetscScalar    *lv;
  PetscInt        nrows;
  PetscBool       done;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.block_ptap_numeric, A, 0, 0, 0));
  ptap->flops = 0;
  PetscCall(MatZeroEntries(ptap->L));
  PetscCall(MatGetRowIJ(ptap->L, 0, PETSC_FALSE, PETSC_TRUE, &nrows, &li, &lj, &done));
  PetscCall(MatSeqBAIJGetArray(ptap->L, &lv));
  PetscCall(ClothBlockRowsGet(A, &rows));
  PetscCheck(rows.upper == ptap->upper, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Block Galerkin product: the matrix's storage (%s) is not the one it was created for", rows.upper ? "sbaij" : "baij");
  for (PetscInt i = 0; i < ptap->nlocal; i++) {
    PetscInt nr;
    FormRow(ptap, &rows, i, &nr);
    for (PetscInt q = ptap->poffset[i]; q < ptap->poffset[i + 1]; q++) {
      PetscInt r = -1;
      PetscCall(LocalRowOf(ptap, ptap->parent[q], &r));
      PetscCall(AddRowToSums(ptap, r, ptap->weight[q], nr, li, lj, lv));
    }
  }
  PetscCall(ClothBlockRowsRestore(&rows));
  PetscCall(MatZeroEntries(ptap->C));
  PetscCall(AddSums(ptap, ptap->C, nrows, li, lj, lv, ADD_VALUES));
  PetscCall(MatSeqBAIJRestoreArray(ptap->L, &lv));
  PetscCall(MatRestoreRowIJ(ptap->L, 0, PETSC_FALSE, PETSC_TRUE, &nrows, &li, &lj, &done));
  PetscCall(MatAssemblyBegin(ptap->C, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(ptap->C, MAT_FINAL_ASSEMBLY));
  PetscCall(PetscLogFlops(ptap->flops));
  PetscCall(PetscLogEventEnd(ClothLog.block_ptap_numeric, A, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockPtAPGetProduct(ClothBlockPtAP ptap, Mat *C)
{
  PetscFunctionBeginUser;
  *C = ptap->C;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBlockPtAPDestroy(ClothBlockPtAP *ptap)
{
  PetscFunctionBeginUser;
  if (!*ptap) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree((*ptap)->poffset));
  PetscCall(PetscFree2((*ptap)->parent, (*ptap)->weight));
  PetscCall(PetscFree((*ptap)->remote));
  PetscCall(PetscFree2((*ptap)->rcol, (*ptap)->rval));
  PetscCall(PetscFree((*ptap)->tval));
  PetscCall(MatDestroy(&(*ptap)->L));
  PetscCall(MatDestroy(&(*ptap)->C));
  PetscCall(PetscFree(*ptap));
  PetscFunctionReturn(PETSC_SUCCESS);
}
