/* Seam-block Jacobi (see seam_blocks.h). */
#include "seam_blocks.h"
#include "seam_links.h"
#include "block_matrix.h"
#include <petscblaslapack.h>

#define BS 3
#define BS2 9
#define MAX_DOFS (BS * CLOTH_SEAM_BLOCK_MAX_PARTICLES)

struct _n_ClothSeamBlocks {
  PetscInt           nlocal;    /* owned particles */
  PetscInt          *block_of;  /* owned particle -> its joined block, -1 when it stands alone */
  PetscInt           nblocks;   /* joined blocks */
  PetscInt          *start;     /* block b's particles: member[start[b] .. start[b + 1]) (local numbers, owned) */
  PetscInt          *member;    /* (each block's in increasing local number) */
  PetscScalar       *inverse;   /* block b's inverse, dense row-major (3 m)^2 at inverse[offset[b]] */
  PetscInt          *offset;    /* nblocks + 1 */
  const PetscScalar *diagonal;  /* every owned particle's inverted 3x3 diagonal block (MatInvertBlockDiagonal, column-major) */
  PetscBool         *usable;    /* block b's inverse exists (else its particles keep their 3x3 blocks) */
  PetscInt           fallbacks; /* blocks that were not positive definite at the last set-up */
};

/* Of a seam link's other side, the node that carries the most of the sewn point (p[1] when it is a node). */
static PetscInt SeamPartner(const ClothSeamLink *link)
{
  PetscInt best = 1;

  for (PetscInt k = 2; k < link->np; k++)
    if (PetscAbsReal(link->c[k]) > PetscAbsReal(link->c[best])) best = k;
  return link->p[best];
}

/* Greedy: each link joins its node and partner when both are owned, into a new block or the block one of them is in
   (while it has room); two particles already in different blocks stay apart. */
static PetscErrorCode JoinSeamPairs(ClothSeamBlocks sb, PetscInt nlinks, const ClothSeamLink *links, PetscInt size[])
{
  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < nlinks; s++) {
    const PetscInt a = links[s].p[0], b = SeamPartner(&links[s]);
    if (a >= sb->nlocal || b >= sb->nlocal || a == b) continue;
    if (sb->block_of[a] < 0 && sb->block_of[b] < 0) {
      sb->block_of[a] = sb->block_of[b] = sb->nblocks;
      size[sb->nblocks++]               = 2;
    } else if (sb->block_of[a] < 0 && size[sb->block_of[b]] < CLOTH_SEAM_BLOCK_MAX_PARTICLES) {
      sb->block_of[a] = sb->block_of[b];
      size[sb->block_of[a]]++;
    } else if (sb->block_of[b] < 0 && size[sb->block_of[a]] < CLOTH_SEAM_BLOCK_MAX_PARTICLES) {
      sb->block_of[b] = sb->block_of[a];
      size[sb->block_of[b]]++;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamBlocksCreate(Cloth cloth, ClothSeamBlocks *sb)
{
  ClothSeamBlocks b;
  ClothSeamLink  *links;
  PetscInt        nlinks, *size, *fill;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&b));
  PetscCall(ClothGetSizes(cloth, &b->nlocal, NULL));
  PetscCall(ClothSeamLinksGetLocal(cloth, &nlinks, &links, NULL));
  PetscCall(PetscMalloc1(b->nlocal, &b->block_of));
  for (PetscInt i = 0; i < b->nlocal; i++) b->block_of[i] = -1;
  PetscCall(PetscCalloc1(nlinks + 1, &size));
  PetscCall(JoinSeamPairs(b, nlinks, links, size));
  PetscCall(PetscMalloc2(b->nblocks + 1, &b->start, b->nblocks + 1, &b->offset));
  PetscCall(PetscMalloc1(b->nblocks + 1, &fill));
  b->start[0] = b->offset[0] = 0;
  for (PetscInt k = 0; k < b->nblocks; k++) {
    b->start[k + 1]  = b->start[k] + size[k];
    b->offset[k + 1] = b->offset[k] + BS2 * size[k] * size[k];
    fill[k]          = b->start[k];
  }
  PetscCall(PetscMalloc3(b->start[b->nblocks], &b->member, b->offset[b->nblocks], &b->inverse, b->nblocks, &b->usable));
  for (PetscInt i = 0; i < b->nlocal; i++)
    if (b->block_of[i] >= 0) b->member[fill[b->block_of[i]]++] = i;
  PetscCall(PetscFree(size));
  PetscCall(PetscFree(fill));
  *sb = b;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The 3x3 block (i, j) of the diagonal part (local block indices), row-major into out; zero where none is stored.
   SBAIJ stores j >= i only: (j, i) transposed, and diagonal blocks made symmetric from their upper triangle. */
static PetscErrorCode GetBlock(const ClothBlockRows *rows, PetscInt i, PetscInt j, PetscScalar out[9])
{
  const PetscBool swap = (rows->upper && j < i) ? PETSC_TRUE : PETSC_FALSE;
  const PetscInt  r = swap ? j : i, c = swap ? i : j;
  PetscInt        loc;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < BS2; k++) out[k] = 0;
  PetscCall(PetscFindInt(c, rows->ia[r + 1] - rows->ia[r], rows->ja + rows->ia[r], &loc)); /* the row's columns are sorted */
  if (loc < 0) PetscFunctionReturn(PETSC_SUCCESS);
  {
    const PetscScalar *v = rows->va + BS2 * (rows->ia[r] + loc); /* column-major */
    PetscScalar        sym[9];
    if (rows->upper && r == c) {
      ClothBlockSymmetricFromUpper(v, 1.0, sym);
      v = sym;
    }
    for (PetscInt p = 0; p < BS; p++)
      for (PetscInt q = 0; q < BS; q++) out[BS * p + q] = swap ? v[BS * p + q] : v[BS * q + p]; /* row-major of v, or of v^T */
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Block b's dense matrix from the diagonal part, inverted by Cholesky (LAPACK); false when it is not positive definite. */
static PetscErrorCode InvertBlock(ClothSeamBlocks sb, const ClothBlockRows *rows, PetscInt b, PetscBool *ok)
{
  const PetscInt m = sb->start[b + 1] - sb->start[b], n = BS * m;
  PetscScalar   *M = sb->inverse + sb->offset[b], block[9];
  PetscBLASInt   bn, info;

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < m; p++)
    for (PetscInt q = 0; q < m; q++) {
      PetscCall(GetBlock(rows, sb->member[sb->start[b] + p], sb->member[sb->start[b] + q], block));
      for (PetscInt r = 0; r < BS; r++)
        for (PetscInt c = 0; c < BS; c++) M[n * (BS * p + r) + BS * q + c] = block[BS * r + c];
    }
  PetscCall(PetscBLASIntCast(n, &bn));
  /* symmetric: row-major is column-major, the lower triangle of one the upper of the other */
  PetscCallBLAS("LAPACKpotrf", LAPACKpotrf_("L", &bn, M, &bn, &info));
  *ok = info == 0 ? PETSC_TRUE : PETSC_FALSE;
  if (!*ok) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCallBLAS("LAPACKpotri", LAPACKpotri_("L", &bn, M, &bn, &info));
  *ok = info == 0 ? PETSC_TRUE : PETSC_FALSE;
  for (PetscInt r = 0; r < n; r++) /* potri fills the lower triangle (column-major): mirror it */
    for (PetscInt c = r + 1; c < n; c++) M[n * c + r] = M[n * r + c];
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamBlocksSetUp(PC pc)
{
  ClothSeamBlocks sb;
  ClothBlockRows  rows;
  Mat             P;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sb));
  PetscCall(PCGetOperators(pc, NULL, &P));
  PetscCall(ClothBlockMatrixSetUpOperations(P));
  PetscCall(MatInvertBlockDiagonal(P, &sb->diagonal));
  PetscCall(ClothBlockRowsGet(P, &rows));
  sb->fallbacks = 0;
  for (PetscInt b = 0; b < sb->nblocks; b++) {
    PetscCall(InvertBlock(sb, &rows, b, &sb->usable[b]));
    if (!sb->usable[b]) sb->fallbacks++; /* never seen: the filtered system is positive definite, and so is every principal block */
  }
  PetscCall(ClothBlockRowsRestore(&rows));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamBlocksApply(PC pc, Vec x, Vec y)
{
  ClothSeamBlocks    sb;
  const PetscScalar *xa;
  PetscScalar       *ya;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sb));
  PetscCall(VecGetArrayRead(x, &xa));
  PetscCall(VecGetArrayWrite(y, &ya));
  for (PetscInt i = 0; i < sb->nlocal; i++) {
    const PetscScalar *d = sb->diagonal + BS2 * i, *xi = xa + BS * i;
    if (sb->block_of[i] >= 0 && sb->usable[sb->block_of[i]]) continue;
    for (PetscInt r = 0; r < BS; r++) ya[BS * i + r] = d[r] * xi[0] + d[BS + r] * xi[1] + d[2 * BS + r] * xi[2];
  }
  for (PetscInt b = 0; b < sb->nblocks; b++) {
    const PetscInt     m = sb->start[b + 1] - sb->start[b], n = BS * m;
    const PetscScalar *M = sb->inverse + sb->offset[b];
    PetscScalar        xb[MAX_DOFS];
    if (!sb->usable[b]) continue;
    for (PetscInt p = 0; p < m; p++)
      for (PetscInt r = 0; r < BS; r++) xb[BS * p + r] = xa[BS * sb->member[sb->start[b] + p] + r];
    for (PetscInt p = 0; p < m; p++)
      for (PetscInt r = 0; r < BS; r++) {
        PetscScalar sum = 0;
        for (PetscInt c = 0; c < n; c++) sum += M[n * (BS * p + r) + c] * xb[c];
        ya[BS * sb->member[sb->start[b] + p] + r] = sum;
      }
  }
  PetscCall(VecRestoreArrayWrite(y, &ya));
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscCall(PetscLogFlops(2.0 * BS2 * sb->nlocal));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamBlocksView(PC pc, PetscViewer viewer)
{
  ClothSeamBlocks sb;
  PetscInt        counts[3], sums[3];

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sb));
  counts[0] = sb->start[sb->nblocks];
  counts[1] = sb->nblocks;
  counts[2] = sb->fallbacks;
  PetscCall(MPIU_Allreduce(counts, sums, 3, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)pc)));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Seam-block Jacobi: %" PetscInt_FMT " sewn particles in %" PetscInt_FMT " joined blocks (at most %d particles), the others point-block Jacobi; %" PetscInt_FMT " blocks fell back\n", sums[0], sums[1],
                                   CLOTH_SEAM_BLOCK_MAX_PARTICLES, sums[2]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamBlocksDestroyPC(PC pc)
{
  ClothSeamBlocks sb;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &sb));
  PetscCall(ClothSeamBlocksDestroy(&sb));
  PetscFunctionReturn(PETSC_SUCCESS);
}

#define SEAM_BLOCKS_NAME "seam-block Jacobi"

PetscErrorCode ClothSeamBlocksSetPC(ClothSeamBlocks sb, PC pc)
{
  PetscFunctionBeginUser;
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, sb));
  PetscCall(PCShellSetName(pc, SEAM_BLOCKS_NAME));
  PetscCall(PCShellSetSetUp(pc, SeamBlocksSetUp));
  PetscCall(PCShellSetApply(pc, SeamBlocksApply));
  PetscCall(PCShellSetView(pc, SeamBlocksView));
  PetscCall(PCShellSetDestroy(pc, SeamBlocksDestroyPC));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamBlocksIsPC(PC pc, PetscBool *is)
{
  const char *name = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCSHELL, is));
  if (*is) PetscCall(PCShellGetName(pc, &name));
  *is = (*is && name && !strcmp(name, SEAM_BLOCKS_NAME)) ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamBlocksGetBlocks(ClothSeamBlocks sb, PetscInt *nblocks, const PetscInt *start[], const PetscInt *member[])
{
  PetscFunctionBeginUser;
  *nblocks = sb->nblocks;
  *start   = sb->start;
  *member  = sb->member;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamBlocksDestroy(ClothSeamBlocks *sb)
{
  PetscFunctionBeginUser;
  if (!*sb) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree((*sb)->block_of));
  PetscCall(PetscFree2((*sb)->start, (*sb)->offset));
  PetscCall(PetscFree3((*sb)->member, (*sb)->inverse, (*sb)->usable));
  PetscCall(PetscFree(*sb));
  PetscFunctionReturn(PETSC_SUCCESS);
}
