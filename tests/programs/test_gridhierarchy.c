/* The pattern-grid multigrid's levels (src/gridhierarchy.c), checked against what its interpolation must do.

   (1) Level sizes: every piece's nu and nv become ceil((n - 1) / r) + 1 per coarsening (n >= 3), computed here from the
       scene's grids, down to a level that no longer changes.
   (2) Every row of every interpolation sums to 1 (to 1e-14): constants, the rigid translations, are reproduced.
   (3) A field linear in the cloth's grid indices lies in the range of every P_l: the flat start positions of
       rectangular pieces, whose least-squares coarse field c = argmin |P c - f| leaves a relative residual below
       1e-10 (measured about 1e-16); c is then the next level's field, so the check reaches the coarsest level,
       where the last, shorter intervals of a grid weigh by the cloth's indices, not the level's.
   (4) A field quadratic in the grid indices (the squared positions) is not reproduced: relative residual above 1e-3
       on the first level (measured 0.02-0.2): the check in (3) can fail.
   (5) With -pinned (a scene with pinned particles; (2)-(4) then do not apply): the coarse space vanishes on pins. On
       the finest interpolation a pinned particle's row is empty or a single 1 (it is a coarse particle itself), and no
       free particle's row reaches a coarse particle that sits on a pin.
   (6) The finest interpolation is MAIJ (its scalar weights stored once for the three components), the others AIJ.
   The interpolation must not depend on the partition: run on 1 and 3 ranks, the sizes and checks are the same. */
#include <petscksp.h>
#include "test_support.h"
#include "gridhierarchy.h"
#include "model.h"

/* Particles of a level after `coarsenings` coarsenings by ratio of the scene's grids (an independent count). */
static PetscInt ExpectedLevelSize(Scene scene, PetscInt ratio, PetscInt coarsenings)
{
  PetscInt total = 0;

  for (PetscInt p = 0; p < scene->npieces; p++) {
    PetscInt nu = scene->pieces[p].nu, nv = scene->pieces[p].nv;
    for (PetscInt c = 0; c < coarsenings; c++) {
      if (nu >= 3) nu = (nu - 1 + ratio - 1) / ratio + 1;
      if (nv >= 3) nv = (nv - 1 + ratio - 1) / ratio + 1;
    }
    total += nu * nv;
  }
  return total;
}

/* The least-squares coarse field c of f under P (normal equations, CG to 1e-14) and the relative residual |P c - f| / |f|. */
static PetscErrorCode LeastSquares(Mat P, Vec f, Vec *c, PetscReal *relative)
{
  Mat       M;
  Vec       rhs, r;
  KSP       ksp;
  PetscReal nr, nf;

  PetscFunctionBeginUser;
  { /* P^T P of an AIJ copy (MatTransposeMatMult does not take the finest level's MAIJ); P itself below */
    Mat Paij;
    PetscCall(MatConvert(P, MATAIJ, MAT_INITIAL_MATRIX, &Paij));
    PetscCall(MatTransposeMatMult(Paij, Paij, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &M));
    PetscCall(MatDestroy(&Paij));
  }
  PetscCall(MatCreateVecs(P, c, &r));
  PetscCall(VecDuplicate(*c, &rhs));
  PetscCall(MatMultTranspose(P, f, rhs));
  PetscCall(KSPCreate(PetscObjectComm((PetscObject)P), &ksp));
  PetscCall(KSPSetOperators(ksp, M, M));
  PetscCall(KSPSetType(ksp, KSPCG));
  PetscCall(KSPSetTolerances(ksp, 1e-14, 1e-300, PETSC_DEFAULT, 2000));
  PetscCall(KSPSolve(ksp, rhs, *c));
  PetscCall(MatMult(P, *c, r));
  PetscCall(VecAXPY(r, -1, f));
  PetscCall(VecNorm(r, NORM_2, &nr));
  PetscCall(VecNorm(f, NORM_2, &nf));
  *relative = nr / nf;
  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&rhs));
  PetscCall(VecDestroy(&r));
  PetscCall(MatDestroy(&M));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest |row sum - 1| of P. */
static PetscErrorCode RowSumError(Mat P, PetscReal *err)
{
  Vec ones, sums;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(P, &ones, &sums));
  PetscCall(VecSet(ones, 1));
  PetscCall(MatMult(P, ones, sums));
  PetscCall(VecShift(sums, -1));
  PetscCall(VecNorm(sums, NORM_INFINITY, err));
  PetscCall(VecDestroy(&ones));
  PetscCall(VecDestroy(&sums));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* out = (x - mean)^2 per component (block size 3): quadratic in the grid indices wherever x is linear in them. */
static PetscErrorCode CentredSquares(Vec x, Vec out)
{
  PetscScalar sum[3], *a;
  PetscInt    n, nlocal;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(x, &n));
  for (PetscInt c = 0; c < 3; c++) PetscCall(VecStrideSum(x, c, &sum[c]));
  PetscCall(VecCopy(x, out));
  PetscCall(VecGetLocalSize(out, &nlocal));
  PetscCall(VecGetArray(out, &a));
  for (PetscInt i = 0; i < nlocal; i++) {
    a[i] -= sum[i % 3] / (n / 3);
    a[i] *= a[i];
  }
  PetscCall(VecRestoreArray(out, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* (5): P's rows of the cloth's pinned particles and the coarse columns they reach. */
static PetscErrorCode CheckPinned(Cloth cloth, Mat P, PetscInt *npinned_rows)
{
  ClothLayout        layout;
  PetscInt           rstart, rend, ncols, ncoarse, *pinned_column, bad = 0, found = 0;
  const PetscInt    *cols;
  const PetscScalar *vals;
  PetscInt          *all;

  PetscFunctionBeginUser;
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCall(MatGetOwnershipRange(P, &rstart, &rend));
  PetscCall(MatGetSize(P, NULL, &ncoarse));
  PetscCall(PetscCalloc1(ncoarse, &pinned_column));
  for (PetscInt row = rstart; row < rend; row++) {
    if (!layout.fixed[row / 3 - layout.rstart]) continue;
    found++;
    PetscCall(MatGetRow(P, row, &ncols, &cols, &vals));
    if (ncols > 1 || (ncols == 1 && PetscAbsScalar(vals[0] - 1) > 0)) bad++;
    for (PetscInt k = 0; k < ncols; k++) pinned_column[cols[k]] = 1;
    PetscCall(MatRestoreRow(P, row, &ncols, &cols, &vals));
  }
  PetscCall(PetscMalloc1(ncoarse, &all));
  PetscCallMPI(MPIU_Allreduce(pinned_column, all, ncoarse, MPIU_INT, MPI_MAX, layout.comm));
  for (PetscInt row = rstart; row < rend; row++) {
    if (layout.fixed[row / 3 - layout.rstart]) continue;
    PetscCall(MatGetRow(P, row, &ncols, &cols, &vals));
    for (PetscInt k = 0; k < ncols; k++)
      if (all[cols[k]]) bad++;
    PetscCall(MatRestoreRow(P, row, &ncols, &cols, &vals));
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT, MPI_SUM, layout.comm));
  PetscCallMPI(MPIU_Allreduce(&found, npinned_rows, 1, MPIU_INT, MPI_SUM, layout.comm));
  PetscCheck(bad == 0, layout.comm, PETSC_ERR_PLIB, "%" PetscInt_FMT " entries of the interpolation mix pinned and free particles", bad);
  PetscCall(PetscFree(pinned_column));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene              scene;
  Cloth              cloth;
  ClothGridHierarchy gh;
  PetscInt           ratio = 2, nlevels, n, expected, levels_expected = 1;
  Vec                x, v, f, fsq, c;
  PetscReal          err, rel, relsq;
  PetscBool          pinned = PETSC_FALSE;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-ratio", &ratio, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-pinned", &pinned, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(ClothGridHierarchyCreate(cloth, ratio, CLOTH_GRID_MAX_LEVELS, 1, PETSC_FALSE, &gh));
  PetscCall(ClothGridHierarchyView(gh, PETSC_VIEWER_STDOUT_WORLD));
  PetscCall(ClothGridHierarchyGetLevels(gh, &nlevels));
  while (ExpectedLevelSize(scene, ratio, levels_expected) != ExpectedLevelSize(scene, ratio, levels_expected - 1)) levels_expected++;
  PetscCheck(nlevels == levels_expected, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "%" PetscInt_FMT " levels, expected %" PetscInt_FMT, nlevels, levels_expected);
  for (PetscInt l = 0; l < nlevels; l++) {
    PetscCall(ClothGridHierarchyGetLevelSize(gh, l, &n));
    expected = ExpectedLevelSize(scene, ratio, nlevels - 1 - l);
    PetscCheck(n == expected, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "level %" PetscInt_FMT ": %" PetscInt_FMT " particles, expected %" PetscInt_FMT, l, n, expected);
  }

  if (pinned) {
    Mat      P;
    PetscInt rows;
    PetscCall(ClothGridHierarchyGetInterpolation(gh, nlevels - 1, &P));
    PetscCall(MatConvert(P, MATAIJ, MAT_INITIAL_MATRIX, &P)); /* MatGetRow: of an AIJ copy of the MAIJ */
    PetscCall(CheckPinned(cloth, P, &rows));
    PetscCall(MatDestroy(&P));
    PetscCheck(rows > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "-pinned: the scene has no pinned particles");
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " rows of pinned particles: the coarse space vanishes on them\n", rows / 3));
    PetscCall(ClothGridHierarchyDestroy(&gh));
    PetscCall(ClothDestroy(&cloth));
    PetscCall(SceneDestroy(&scene));
    PetscCall(TestCheckExpectationsUsed());
    PetscCall(PetscFinalize());
    return 0;
  }
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(VecDuplicate(x, &f));
  PetscCall(VecCopy(x, f));
  PetscCall(VecDuplicate(x, &fsq));
  PetscCall(CentredSquares(x, fsq));
  for (PetscInt l = nlevels - 1; l >= 1; l--) {
    Mat       P;
    PetscBool maij;
    PetscCall(ClothGridHierarchyGetInterpolation(gh, l, &P));
    PetscCall(PetscObjectTypeCompareAny((PetscObject)P, &maij, MATSEQMAIJ, MATMPIMAIJ, ""));
    PetscCheck(maij == (l == nlevels - 1), PETSC_COMM_WORLD, PETSC_ERR_PLIB, "P_%" PetscInt_FMT " is %sMAIJ: expected MAIJ for the finest level only", l, maij ? "" : "not ");
    PetscCall(RowSumError(P, &err));
    PetscCall(LeastSquares(P, f, &c, &rel));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "level %" PetscInt_FMT " -> %" PetscInt_FMT ": largest |row sum - 1| %.2e, linear field's relative residual %.2e", l - 1, l, (double)err, (double)rel));
    PetscCheck(err <= 1e-14, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "rows of P_%" PetscInt_FMT " do not sum to 1: %g", l, (double)err);
    PetscCheck(rel <= 1e-10, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "a linear field is not in the range of P_%" PetscInt_FMT ": relative residual %g", l, (double)rel);
    if (l == nlevels - 1) {
      Vec csq;
      PetscCall(LeastSquares(P, fsq, &csq, &relsq));
      PetscCall(VecDestroy(&csq));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, ", quadratic field's %.2e", (double)relsq));
      PetscCheck(relsq >= 1e-3, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "a quadratic field is reproduced by P_%" PetscInt_FMT " (relative residual %g): the linear check cannot fail", l, (double)relsq);
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\n"));
    PetscCall(VecDestroy(&f));
    f = c;
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "pattern-grid hierarchy (ratio %" PetscInt_FMT "): %" PetscInt_FMT " levels as expected, every check passed\n", ratio, nlevels));
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&fsq));
  PetscCall(ClothGridHierarchyDestroy(&gh));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
