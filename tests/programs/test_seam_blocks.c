/* Seam-block Jacobi (src/seam_blocks.c) against an independent computation.

   The implicit system of a perturbed cloth with seams (positions moved by up to 2 mm, random velocities) is assembled
   (BAIJ, or SBAIJ with -implicit_mat_type sbaij) and the preconditioner set up from it. Checked:
   - the blocks: every joined block holds 2 to CLOTH_SEAM_BLOCK_MAX_PARTICLES owned particles, each of them sewn (a seam
     link joins it to another member); no seam link whose node and other-side nodes are all owned here was left with
     all of them alone; at least -expect_min_joined (required) particles are joined over all ranks;
   - the product: y = B^{-1} r for a random r must equal, block by block, the solution of the block's dense system
     taken from an AIJ copy of the matrix (MatGetValues) by LAPACK's LU (gesv), not the preconditioner's Cholesky, to
     1e-10 relative; particles alone are their 3x3 blocks' solutions, joined ones their whole block's (which differs
     from the 3x3 blocks' wherever a seam couples them: the test requires that difference to exceed 1e-3 relative
     somewhere, so that joining is seen at all).
   Run on 1 to 3 ranks (a pair split between ranks stays apart). */
#include <petscksp.h>
#include <petscblaslapack.h>
#include "test_support.h"
#include "seam_blocks.h"
#include "seam_links.h"

#define MAXN (3 * CLOTH_SEAM_BLOCK_MAX_PARTICLES)

/* Does a seam link of this rank join particle i to another member of block b? */
static PetscBool SewnWithin(PetscInt nlinks, const ClothSeamLink *links, const PetscInt block_of[], PetscInt nlocal, PetscInt i, PetscInt b)
{
  for (PetscInt s = 0; s < nlinks; s++) {
    PetscBool has_i = PETSC_FALSE, has_other = PETSC_FALSE;
    for (PetscInt k = 0; k < links[s].np; k++) {
      const PetscInt p = links[s].p[k];
      if (p == i)
        has_i = PETSC_TRUE;
      else if (p < nlocal && block_of[p] == b)
        has_other = PETSC_TRUE;
    }
    if (has_i && has_other) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

static PetscErrorCode CheckBlocks(Cloth cloth, ClothSeamBlocks sb, PetscInt expect_min_joined, PetscInt block_of[])
{
  const PetscInt *start, *member;
  ClothSeamLink  *links;
  PetscInt        nblocks, nlinks, nlocal, joined;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(ClothSeamLinksGetLocal(cloth, &nlinks, &links, NULL));
  PetscCall(ClothSeamBlocksGetBlocks(sb, &nblocks, &start, &member));
  for (PetscInt i = 0; i < nlocal; i++) block_of[i] = -1;
  for (PetscInt b = 0; b < nblocks; b++) {
    const PetscInt m = start[b + 1] - start[b];
    PetscCheck(m >= 2 && m <= CLOTH_SEAM_BLOCK_MAX_PARTICLES, PETSC_COMM_SELF, PETSC_ERR_PLIB, "block %" PetscInt_FMT " holds %" PetscInt_FMT " particles", b, m);
    for (PetscInt k = start[b]; k < start[b + 1]; k++) {
      PetscCheck(member[k] >= 0 && member[k] < nlocal && block_of[member[k]] < 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle %" PetscInt_FMT " is not owned or in two blocks", member[k]);
      block_of[member[k]] = b;
    }
  }
  for (PetscInt b = 0; b < nblocks; b++)
    for (PetscInt k = start[b]; k < start[b + 1]; k++)
      PetscCheck(SewnWithin(nlinks, links, block_of, nlocal, member[k], b), PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle %" PetscInt_FMT " of block %" PetscInt_FMT " is sewn to no other member", member[k], b);
  for (PetscInt s = 0; s < nlinks; s++) {
    PetscBool owned = PETSC_TRUE, alone = PETSC_TRUE;
    for (PetscInt k = 0; k < links[s].np; k++) {
      owned = (owned && links[s].p[k] < nlocal) ? PETSC_TRUE : PETSC_FALSE;
      if (owned && block_of[links[s].p[k]] >= 0) alone = PETSC_FALSE;
    }
    PetscCheck(!owned || !alone, PETSC_COMM_SELF, PETSC_ERR_PLIB, "seam link %" PetscInt_FMT ": its owned particles were all left alone", s);
  }
  joined = nblocks ? start[nblocks] : 0;
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &joined, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " particles in joined blocks\n", joined));
  PetscCheck(joined >= expect_min_joined, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%" PetscInt_FMT " particles joined, expected at least %" PetscInt_FMT " (-expect_min_joined)", joined, expect_min_joined);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Solves the dense system of the given owned particles (global rows of the AIJ copy) for r there, by LU. */
static PetscErrorCode SolveGroup(Mat Aaij, PetscInt rstart, PetscInt m, const PetscInt particles[], const PetscScalar r[], PetscScalar z[])
{
  PetscInt     rows[MAXN];
  PetscScalar  M[MAXN * MAXN];
  PetscBLASInt n, one = 1, ipiv[MAXN], info;

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < m; p++)
    for (PetscInt c = 0; c < 3; c++) rows[3 * p + c] = 3 * (rstart + particles[p]) + c;
  PetscCall(MatGetValues(Aaij, 3 * m, rows, 3 * m, rows, M)); /* row-major = the transpose column-major: symmetric */
  for (PetscInt k = 0; k < 3 * m; k++) z[k] = r[rows[k] - 3 * rstart];
  PetscCall(PetscBLASIntCast(3 * m, &n));
  PetscCallBLAS("LAPACKgesv", LAPACKgesv_(&n, &one, M, &n, ipiv, z, &n, &info));
  PetscCheck(info == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "LAPACK gesv failed with info %d", (int)info);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene              scene;
  Cloth              cloth;
  ClothSeamBlocks    sb;
  PC                 pc;
  Mat                A, Aaij;
  Vec                rhs, x, v, r, y;
  PetscRandom        rnd;
  const PetscScalar *ra, *ya;
  const PetscInt    *start, *member;
  PetscInt           expect_min_joined, nlocal, rstart, nblocks, *block_of;
  PetscReal          d[4]              = {0, 0, 0, 0}; /* largest |y - z|, |z|, |z - z_alone| over joined particles */

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(TestGetExpectationInt("-expect_min_joined", &expect_min_joined));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(TestPerturbState(cloth, 2027, 2e-3, 0.3));
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, &A));
  PetscCall(ClothCreateStateVec(cloth, &rhs));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothAssembleImplicitSystem(cloth, 0.01, x, v, A, rhs));
  PetscCall(ClothSeamBlocksCreate(cloth, &sb));
  PetscCall(PCCreate(PETSC_COMM_WORLD, &pc));
  PetscCall(ClothSeamBlocksSetPC(sb, pc)); /* pc owns sb from here */
  PetscCall(PCSetOperators(pc, A, A));
  PetscCall(PCSetUp(pc));
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(PetscMalloc1(nlocal, &block_of));
  PetscCall(CheckBlocks(cloth, sb, expect_min_joined, block_of));

  PetscCall(MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, &Aaij)); /* SBAIJ: both triangles */
  PetscCall(MatCreateVecs(A, &r, &y));
  PetscCall(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 7));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(VecSetRandom(r, rnd));
  PetscCall(PCApply(pc, r, y));
  PetscCall(VecGetOwnershipRange(r, &rstart, NULL));
  rstart /= 3;
  PetscCall(VecGetArrayRead(r, &ra));
  PetscCall(VecGetArrayRead(y, &ya));
  PetscCall(ClothSeamBlocksGetBlocks(sb, &nblocks, &start, &member));
  for (PetscInt i = 0; i < nlocal; i++) {
    PetscScalar z[MAXN], alone[3];
    PetscInt    b = block_of[i], m = b >= 0 ? start[b + 1] - start[b] : 1, k = 0;
    if (b >= 0 && member[start[b]] != i) continue; /* each block once, from its first member */
    PetscCall(SolveGroup(Aaij, rstart, m, b >= 0 ? &member[start[b]] : &i, ra, z));
    for (PetscInt p = 0; p < m; p++) {
      const PetscInt q = b >= 0 ? member[start[b] + p] : i;
      if (b >= 0) PetscCall(SolveGroup(Aaij, rstart, 1, &q, ra, alone));
      for (PetscInt c = 0; c < 3; c++, k++) {
        d[0] = PetscMax(d[0], PetscAbsScalar(ya[3 * q + c] - z[k]));
        d[1] = PetscMax(d[1], PetscAbsScalar(z[k]));
        if (b >= 0) d[2] = PetscMax(d[2], PetscAbsScalar(z[k] - alone[c]));
      }
    }
  }
  PetscCall(VecRestoreArrayRead(y, &ya));
  PetscCall(VecRestoreArrayRead(r, &ra));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, d, 3, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "B^-1 r against the blocks' LU solves: largest difference / largest entry = %.2e; joined against alone: %.2e\n", (double)(d[0] / d[1]), (double)(d[2] / d[1])));
  PetscCheck(d[0] <= 1e-10 * d[1], PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the preconditioner differs from the blocks' solves by %g relative (tolerance 1e-10)", (double)(d[0] / d[1]));
  PetscCheck(d[2] > 1e-3 * d[1], PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the joined blocks' solves equal the 3x3 blocks' (%g relative): no seam coupling was seen", (double)(d[2] / d[1]));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "PASS\n"));
  PetscCall(PetscFree(block_of));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(VecDestroy(&r));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&rhs));
  PetscCall(MatDestroy(&Aaij));
  PetscCall(MatDestroy(&A));
  PetscCall(PCDestroy(&pc));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
