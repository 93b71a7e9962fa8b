/* ClothPreconditioner (see preconditioner.h). */
#include "preconditioner.h"
#include "gridhierarchy.h"
#include "block_ptap.h"
#include "block_matrix.h"
#include "seam_blocks.h"

/* The default preconditioner (docs/performance.md, "Pattern-grid multigrid"):
   - a scene without seams (sheets, drapes): the pattern-grid multigrid from CLOTH_PC_GRID_MIN_PARTICLES particles on.
     On the hanging sheet, 1 rank: as fast as point-block Jacobi at 33 x 33, 1.2x faster at 49 x 49, 1.4x at 65 x 65
     (2 ranks: 2.3x); 1.3x faster than GAMG at 257 x 257 (1 and 2 ranks) with 8 iterations a step against 10.7.
   - a garment (seams): GAMG from CLOTH_PC_MULTILEVEL_MIN_PARTICLES on. On the dress (2,478 particles) the grid
     multigrid takes 84 iterations a step against point-block Jacobi's 219 but 2.3x its wall time: the pieces are
     small and the stiff seams couple them only on the finest level, so the coarse levels help little.
   - point-block Jacobi below; for a garment its seam-block form (seam_blocks.h, -implicit_pc_seam_blocks), which inverts
     each sewn node with its partner: on the main job 144,250 Krylov iterations against 210,757, 10-16 % less wall time
     (docs/performance.md, "Seam-block Jacobi"). GAMG on the hanging sheet: 1.4x point-block Jacobi's wall time at
     65 x 65, about the same at 129 x 129, 1.8-1.9x less at 257 x 257. */
#define CLOTH_PC_GRID_MIN_PARTICLES 2500
#define CLOTH_PC_MULTILEVEL_MIN_PARTICLES 40000

/* The default -implicit_pc_lag_ratio: a lagged hierarchy is refreshed once a solve takes 20 % more iterations than after
   the last refresh. Measured (docs/performance.md): 8-24 % less wall time than refreshing every step at 257 x 257 and
   129 x 129, for about 10 % more iterations (GAMG, and the pattern-grid multigrid before its coarse levels became block
   products). */
#define CLOTH_PC_DEFAULT_LAG_RATIO 1.2

/* The default -implicit_pc_grid_lag_max_particles: the pattern-grid multigrid is lagged only below this many particles
   and refreshed at every step from it on, where a refresh (block products of every level, the smoothers' bounds, the
   coarse LU) now costs less than the iterations a lagged hierarchy adds. Measured over the full second, 1 rank (wall,
   Krylov iterations a step, lagged against refreshed every step; docs/performance.md): 65 x 65 4.2-4.5 s, 7.9 against
   5.3-5.4 s, 7.4; 129 x 129 23.3-27.5 s, 14.0 against 25.8-29.7 s, 12.6; 257 x 257 138.6-147.9 s, 21.5 against 130.4-137.5
   s, 18.6 (2 ranks: 85.7-96.1 s against 91.6-92.7 s); 513 x 513, 48 steps: 127.8 s, 26.1 against 116.8 s, 23.3. The
   crossover lies between 16,641 and 66,049 particles. */
#define CLOTH_PC_GRID_LAG_MAX_PARTICLES 40000

/* Pattern-grid multigrid (-pc_type mg): coarsened until a level has at most this many particles, whose system is
   then factored directly (PCMG's coarse solve: LU, redundant on every rank). */
#define CLOTH_PC_GRID_COARSE_PARTICLES 1000

/* Pattern-grid multigrid: the default coarsening ratio. Measured on the hanging sheet, 1 rank (iterations a step,
   wall time relative to ratio 2): 129 x 129: ratio 2: 7.4, 1; 3: 8.8, 0.91; 4: 9.4, 0.84; 257 x 257 (ratio 3 = 1):
   3: 6.5, 1; 4: 8.0, 0.89; 5: 9.9, 0.94. A larger ratio makes the coarse levels far smaller (1/16 of the particles
   at ratio 4) for a few more iterations. */
#define CLOTH_PC_GRID_DEFAULT_RATIO 4

/* The default -implicit_pc_lag_max: at most this many lagged solves in a row. The ratio test alone let the pattern-grid
   multigrid run 77 iterations a step on a 65 x 65 sheet pinned along an edge at dt = 1/60 s (2 ranks, 180 steps),
   against 22 when refreshed every step; with at most 1, 2, 3, 5, 10 lagged solves in a row: 22, 22, 31, 58, 61
   iterations a step (3.7, 3.4, 4.3, 7.5, 7.8 s). On the hanging sheet (129 x 129 over 48 steps, 257 x 257 over 24)
   2 costs nothing measurable against no limit, for the grid multigrid and GAMG alike (within 3 %). */
#define CLOTH_PC_DEFAULT_LAG_MAX 2

/* The default -implicit_pc_lag_excess and -implicit_pc_lag_pause: a refresh of the 257 x 257 sheet's pattern-grid
   multigrid (then with an AIJ copy; Galerkin products, coarse smoothers' bounds, coarse factorisation) costs about 9 of its
   V-cycles (docs/performance.md), so a lagged solve that needs more than 10 extra iterations lost more than it saved;
   then the next 8 solves refresh. Measured on 513 x 513 over 24 steps (2 ranks): without it, lagged solves took 43-52
   iterations against 15-19 refreshed ones in the last steps. */
#define CLOTH_PC_DEFAULT_LAG_EXCESS 10
#define CLOTH_PC_DEFAULT_LAG_PAUSE 8

/* The default -implicit_pc_lag_backoff: each lag in a row that costs more than -implicit_pc_lag_excess doubles the
   pause, up to this many times (8, 16, ..., 128 solves). Where lags never pay (1025 x 1025 mid-run, 2 ranks: a lagged
   solve needs more than 70 iterations against 55-60 refreshed, so it is stopped and redone) a fixed pause of 8 kept
   losing one in nine steps to a failed lag: 176.7 s for 10 steps against 160.0 s refreshing every step. */
#define CLOTH_PC_DEFAULT_LAG_BACKOFF 4

/* The implicit matrix is stored as SBAIJ (the upper triangle of blocks) from this many particles on, where the
   preconditioner takes it as it is (pattern-grid multigrid, point-block Jacobi). Every Krylov iteration streams the
   matrix a few times and SBAIJ streams half the bytes. Measured on the hanging sheet with the multigrid (the same
   iterations, docs/performance.md): 129 x 129 and 257 x 257 1.2-1.3x faster on 1 and 2 ranks and 470 bytes per
   particle less; 65 x 65 (4,225 particles) the same; the dress (2,478 particles, point-block Jacobi, 2 ranks), whose
   matrix fits in the caches, 3 % slower (MPISBAIJ's product has an extra exchange). GAMG keeps BAIJ (its AIJ copy
   of an SBAIJ matrix took 4x the iterations until the copy's refresh was mended, UpdatePreconditioningMatrix; since
   then 4.35 s against 3.79 s at 129 x 129, 24 steps, 1 rank, as each refresh converts SBAIJ afresh). */
#define CLOTH_SBAIJ_MIN_PARTICLES 10000

/* A solve this many iterations or fewer never triggers a refresh: at such counts a ratio is noise. */
#define CLOTH_PC_MIN_ITERATIONS 4

struct _n_ClothPreconditioner {
  KSP                ksp;           /* borrowed */
  Cloth              cloth;         /* borrowed */
  ClothGridHierarchy grid;          /* the pattern-grid levels of -pc_type mg, else NULL */
  Mat               *coarse;        /* their operators, coarse[l] of level l < nlevels - 1 */
  PetscBool          block_product; /* the Galerkin products are taken of the block matrices themselves (block_ptap.h) */
  ClothBlockPtAP    *block_ptap;    /* those products, block_ptap[l] making level l - 1's, while A's nonzero pattern lasts */
  PetscBool          kept;          /* the preconditioner is kept between steps (multilevel types) */
  PetscBool          copy_aij;      /* it is built from an AIJ copy P of the (block) matrix */
  PetscReal          lag_ratio, rebuild_ratio;
  PetscBool          rigid_body; /* near-null space: the six rigid-body modes (else the three translations) */
  Mat                A;          /* the matrix of the last Prepare (borrowed: a new one means a new pattern) */
  Mat                P;          /* the AIJ copy (copy_aij) */
  Vec                coords;     /* positions in the layout of A, for the rigid-body modes */
  PetscReal          h;          /* step size of the last refresh or rebuild */
  ClothPCUpdate      pending, last;
  PetscInt           its_rebuilt, its_refreshed; /* iterations of the first solve after the last rebuild / refresh */
  PetscInt           lag_max, lagged;            /* at most lag_max lagged solves in a row; lagged since the last refresh */
  PetscInt           lag_excess, lag_pause;      /* a lag that cost more extra iterations stops lagging for lag_pause solves */
  PetscInt           paused;                     /* solves left without lagging */
  PetscInt           lag_backoff, failed_lags;   /* the pause doubles for each costly lag in a row, at most lag_backoff times */
  PetscInt           count[3];                   /* solves per ClothPCUpdate */
};

/* Puts name=value in the options database unless the user gave name: defaults of objects that PCGAMG creates during
   its set-up (the level smoothers), which cannot be set through an API before they exist. */
static PetscErrorCode SetDefaultOption(const char prefix[], const char name[], const char value[])
{
  char      full[256];
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(full, sizeof(full), "-%s%s", prefix ? prefix : "", name));
  PetscCall(PetscOptionsHasName(NULL, NULL, full, &set));
  if (!set) PetscCall(PetscOptionsSetValue(NULL, full, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The smoother chosen by measurement (docs/performance.md): Chebyshev (symmetric, so CG applies) on point-block
   Jacobi (a particle's 3x3 block at once), on the upper 90 % of its estimated spectrum, widened by 10 %. SOR smooths
   better per sweep but costs two MatMults on AIJ. The same for GAMG and the pattern-grid multigrid. */
/* GAMG's defaults, unless given as options: a threshold that drops weak couplings (bending against stretch) from the
   aggregation graph, and aggregates kept over steps (ClothPreconditionerPrepare decides when to rebuild them). */
static PetscErrorCode SetGAMGDefaults(PC pc)
{
  const char *prefix;
  PetscBool   set;
  PetscReal   threshold = 0.01;

  PetscFunctionBeginUser;
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-pc_gamg_threshold", &set));
  if (!set) PetscCall(PCGAMGSetThreshold(pc, &threshold, 1));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-pc_gamg_reuse_interpolation", &set));
  if (!set) PetscCall(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Chebyshev smoothing with the point-block (3x3) Jacobi blocks, or point Jacobi (smoother_pc) where the coarse blocks are
   6x6 (GAMG with the rigid-body modes: a one-particle aggregate's rotations make them singular, measured zero pivots). */
static PetscErrorCode SetMultigridSmootherDefaults(KSP ksp, PCType smoother_pc)
{
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  PetscCall(SetDefaultOption(prefix, "mg_levels_ksp_type", "chebyshev"));
  PetscCall(SetDefaultOption(prefix, "mg_levels_pc_type", smoother_pc));
  PetscCall(SetDefaultOption(prefix, "mg_levels_ksp_chebyshev_esteig", "0,0.1,0,1.1"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The system is symmetric positive definite (CG solves it), so Lanczos (CG) estimates the grid levels' spectra in place
   of PETSc's GMRES default: the same iterations, 45 % less smoother memory, the same wall time (docs/performance.md).
   Not for GAMG: there the restarts were then no longer bit for bit (3.9e-8 m after 12 + 12 steps, cause not found). */
static PetscErrorCode SetGridMultigridDefaults(KSP ksp)
{
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  PetscCall(SetDefaultOption(prefix, "mg_levels_esteig_ksp_type", "cg"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerCreate(KSP ksp, Cloth cloth, ClothPreconditioner *pre)
{
  ClothPreconditioner p;
  PC                  pc;
  PetscInt            min_particles = CLOTH_PC_MULTILEVEL_MIN_PARTICLES, grid_min_particles = CLOTH_PC_GRID_MIN_PARTICLES, nparticles;
  ClothLayout         layout;
  PetscBool           seam_blocks = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSizes(cloth, NULL, &nparticles));
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCall(PetscNew(&p));
  p->ksp           = ksp;
  p->cloth         = cloth;
  p->lag_ratio     = CLOTH_PC_DEFAULT_LAG_RATIO;
  p->rebuild_ratio = 1.5;
  p->lag_max       = CLOTH_PC_DEFAULT_LAG_MAX;
  p->lag_excess    = CLOTH_PC_DEFAULT_LAG_EXCESS;
  p->lag_pause     = CLOTH_PC_DEFAULT_LAG_PAUSE;
  p->lag_backoff   = CLOTH_PC_DEFAULT_LAG_BACKOFF;
  p->pending       = CLOTH_PC_REBUILD;
  p->h             = -1;
  p->block_product = PETSC_TRUE;
  PetscOptionsBegin(PetscObjectComm((PetscObject)ksp), NULL, "Implicit solve: default preconditioner", "ClothPreconditioner");
  PetscCall(PetscOptionsInt("-implicit_pc_grid_min_particles", "Default preconditioner of a scene without seams: the pattern-grid multigrid (mg) from this many particles on, point-block Jacobi below (-pc_type overrides)", "ClothPreconditionerCreate",
                            grid_min_particles, &grid_min_particles, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_multilevel_min_particles", "Default preconditioner of a garment (a scene with seams): GAMG from this many particles on, seam-block Jacobi below (-pc_type overrides)", "ClothPreconditionerCreate",
                            min_particles, &min_particles, NULL));
  PetscCall(PetscOptionsBool("-implicit_pc_seam_blocks", "Default preconditioner of a garment below -implicit_pc_multilevel_min_particles: point-block Jacobi with each sewn node and its partner in one block (false: every particle its own block)",
                             "ClothSeamBlocksCreate", seam_blocks, &seam_blocks, NULL));
  PetscOptionsEnd();
  PetscCall(KSPGetPC(ksp, &pc));
  if (layout.model->nseamlinks == 0 && nparticles >= grid_min_particles)
    PetscCall(PCSetType(pc, PCMG));
  else if (nparticles >= min_particles)
    PetscCall(PCSetType(pc, PCGAMG));
  else if (seam_blocks && layout.model->nseamlinks > 0) {
    ClothSeamBlocks sb;
    PetscCall(ClothSeamBlocksCreate(cloth, &sb));
    PetscCall(ClothSeamBlocksSetPC(sb, pc));
  } else
    PetscCall(PCSetType(pc, PCPBJACOBI));
  *pre = p;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* -pc_type mg: the levels of the pattern grids (gridhierarchy.h), coarse operators by Galerkin products. */
static PetscErrorCode SetUpGridMultigrid(ClothPreconditioner pre, PC pc)
{
  PetscInt max_levels = CLOTH_GRID_MAX_LEVELS, coarse_particles = CLOTH_PC_GRID_COARSE_PARTICLES, ratio = CLOTH_PC_GRID_DEFAULT_RATIO, nlevels;
  KSP      smoother;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PetscObjectComm((PetscObject)pc), NULL, "Implicit solve: pattern-grid multigrid (-pc_type mg)", "ClothPreconditioner");
  PetscCall(PetscOptionsInt("-implicit_pc_grid_ratio", "Pattern-grid multigrid: keep every ratio-th row and column of each piece on the next coarser level", "ClothGridHierarchyCreate", ratio, &ratio, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_grid_levels", "Pattern-grid multigrid: at most this many levels, the cloth included", "ClothGridHierarchyCreate", max_levels, &max_levels, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_grid_coarse_particles", "Pattern-grid multigrid: coarsen until a level has at most this many particles (solved directly)", "ClothGridHierarchyCreate", coarse_particles, &coarse_particles, NULL));
  PetscCall(PetscOptionsBool("-implicit_pc_grid_block_product", "Pattern-grid multigrid: take the Galerkin products of the block (BAIJ or SBAIJ) matrix itself, the coarse levels stored alike (false: of an AIJ copy, by MatPtAP)",
                             "ClothBlockPtAPCreate", pre->block_product, &pre->block_product, NULL));
  PetscOptionsEnd();
  PetscCheck(max_levels >= 1 && max_levels <= CLOTH_GRID_MAX_LEVELS, PetscObjectComm((PetscObject)pc), PETSC_ERR_USER_INPUT, "-implicit_pc_grid_levels %" PetscInt_FMT ": expected 1 to %d", max_levels, CLOTH_GRID_MAX_LEVELS);
  PetscCheck(coarse_particles >= 1, PetscObjectComm((PetscObject)pc), PETSC_ERR_USER_INPUT, "-implicit_pc_grid_coarse_particles %" PetscInt_FMT ": expected a positive count", coarse_particles);
  PetscCheck(ratio >= 2, PetscObjectComm((PetscObject)pc), PETSC_ERR_USER_INPUT, "-implicit_pc_grid_ratio %" PetscInt_FMT ": expected 2 or more", ratio);
  PetscCall(ClothGridHierarchyCreate(pre->cloth, ratio, max_levels, coarse_particles, pre->block_product, &pre->grid));
  PetscCall(ClothGridHierarchyGetLevels(pre->grid, &nlevels));
  PetscCall(PCMGSetLevels(pc, nlevels, NULL));
  for (PetscInt l = 1; l < nlevels; l++) {
    Mat P;
    PetscCall(ClothGridHierarchyGetInterpolation(pre->grid, l, &P));
    PetscCall(PCMGSetInterpolation(pc, l, P));
  }
  /* The coarse operators are Galerkin products made here (RefreshGridOperators): of the block matrices themselves
     (ClothBlockPtAP), which MatPtAP does not support, or of AIJ copies by MatPtAP. */
  PetscCall(PCMGSetGalerkin(pc, PC_MG_GALERKIN_NONE));
  PetscCall(PetscCalloc2(nlevels, &pre->coarse, nlevels, &pre->block_ptap));
  /* the levels' solvers exist only now: they read their -mg_levels_ and -mg_coarse_ options here */
  for (PetscInt l = 0; l < nlevels; l++) {
    PetscCall(PCMGGetSmoother(pc, l, &smoother));
    PetscCall(KSPSetFromOptions(smoother));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Point-block Jacobi, or its seam-block form (seam_blocks.h). */
static PetscErrorCode IsPointBlockJacobi(PC pc, PetscBool *is)
{
  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCPBJACOBI, is));
  if (!*is) PetscCall(ClothSeamBlocksIsPC(pc, is));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerIsPointBlockJacobi(ClothPreconditioner pre, PetscBool *is)
{
  PC pc;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(IsPointBlockJacobi(pc, is));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerSetFromOptions(ClothPreconditioner pre)
{
  PC          pc;
  PetscBool   multilevel, mg, use_amat_set;
  PetscInt    lag_max_particles = CLOTH_PC_GRID_LAG_MAX_PARTICLES, nparticles;
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &multilevel, PCGAMG, PCML, PCHYPRE, PCMG, ""));
  pre->kept     = multilevel;
  pre->copy_aij = multilevel;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCMG, &mg));
  PetscCall(ClothGetSizes(pre->cloth, NULL, &nparticles));
  PetscOptionsBegin(PetscObjectComm((PetscObject)pre->ksp), NULL, "Implicit solve: multilevel preconditioner", "ClothPreconditioner");
  PetscCall(PetscOptionsInt("-implicit_pc_grid_lag_max_particles", "Pattern-grid multigrid: keep it over steps (lag) only below this many particles, refresh it every step from it on (there the default -implicit_pc_lag_ratio is 0)",
                            "ClothPreconditionerSetFromOptions", lag_max_particles, &lag_max_particles, NULL));
  PetscCheck(lag_max_particles >= 0, PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_grid_lag_max_particles %" PetscInt_FMT ": expected a count >= 0", lag_max_particles);
  if (mg && nparticles >= lag_max_particles) pre->lag_ratio = 0;
  PetscCall(PetscOptionsReal("-implicit_pc_lag_ratio", "Keep a multilevel preconditioner over steps until a solve takes more than this times the iterations after its last refresh (0: refresh every step)", "ClothPreconditionerSolved", pre->lag_ratio,
                             &pre->lag_ratio, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_lag_max", "Refresh a multilevel preconditioner after at most this many lagged solves in a row", "ClothPreconditionerSolved", pre->lag_max, &pre->lag_max, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_lag_excess", "A lagged solve that takes more than this many iterations beyond the last refreshed one stops lagging for -implicit_pc_lag_pause solves", "ClothPreconditionerSolved", pre->lag_excess,
                            &pre->lag_excess, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_lag_pause", "Solves refreshed in a row after a lag that cost more than -implicit_pc_lag_excess iterations", "ClothPreconditionerSolved", pre->lag_pause, &pre->lag_pause, NULL));
  PetscCall(PetscOptionsInt("-implicit_pc_lag_backoff", "Each such lag in a row doubles -implicit_pc_lag_pause, at most this many times (0: a fixed pause)", "ClothPreconditionerSolved", pre->lag_backoff, &pre->lag_backoff, NULL));
  PetscCall(PetscOptionsReal("-implicit_pc_rebuild_ratio", "Rebuild the aggregates and interpolation when a refreshed preconditioner takes more than this times the iterations after the last rebuild", "ClothPreconditionerSolved", pre->rebuild_ratio,
                             &pre->rebuild_ratio, NULL));
  PetscCall(PetscOptionsBool("-implicit_pc_rigid_body_modes",
                             "Near-null space of the multilevel preconditioner: the six rigid-body modes at the current positions (false: the three translations; smoothing then defaults to point Jacobi, -mg_levels_pc_type)",
                             "ClothPreconditionerPrepare", pre->rigid_body, &pre->rigid_body, NULL));
  PetscOptionsEnd();
  if (multilevel) {
    PetscBool gamg;
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
    if (gamg || mg) PetscCall(SetMultigridSmootherDefaults(pre->ksp, gamg && pre->rigid_body ? PCJACOBI : PCPBJACOBI));
    if (gamg) PetscCall(SetGAMGDefaults(pc));
    if (mg) PetscCall(SetGridMultigridDefaults(pre->ksp));
    if (mg) PetscCall(SetUpGridMultigrid(pre, pc));
  }
  PetscCheck(pre->lag_ratio == 0 || (pre->lag_ratio >= 1 && PetscIsNormalReal(pre->lag_ratio)), PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_lag_ratio %g: expected 0 (refresh every step) or a finite number >= 1",
             (double)pre->lag_ratio);
  PetscCheck(pre->lag_max >= 1, PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_lag_max %" PetscInt_FMT ": expected a positive count", pre->lag_max);
  PetscCheck(pre->lag_backoff >= 0 && pre->lag_backoff <= 20, PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_lag_backoff %" PetscInt_FMT ": expected 0 to 20 doublings", pre->lag_backoff);
  PetscCheck(pre->lag_excess >= 0 && pre->lag_pause >= 0, PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_lag_excess %" PetscInt_FMT ", -implicit_pc_lag_pause %" PetscInt_FMT ": expected counts >= 0", pre->lag_excess,
             pre->lag_pause);
  PetscCheck(pre->rebuild_ratio >= 1 && PetscIsNormalReal(pre->rebuild_ratio), PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_rebuild_ratio %g: expected a finite number >= 1", (double)pre->rebuild_ratio);
  /* The finest level is smoothed with the block matrix itself (faster MatMult than its AIJ copy). */
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-pc_use_amat", &use_amat_set));
  if (!use_amat_set) PetscCall(PCSetUseAmat(pc, PETSC_TRUE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerGetMatType(ClothPreconditioner pre, MatType *type)
{
  PC        pc;
  PetscBool takes_block;
  PetscInt  nparticles;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCMG, &takes_block));
  if (!takes_block) PetscCall(IsPointBlockJacobi(pc, &takes_block));
  PetscCall(ClothGetSizes(pre->cloth, NULL, &nparticles));
  *type = takes_block && nparticles >= CLOTH_SBAIJ_MIN_PARTICLES ? MATSBAIJ : MATBAIJ;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The rigid-body modes (3 translations, 3 rotations) at the positions x: the near-null space of the stiffness,
   which smoothed aggregation builds its interpolation to reproduce. */
static PetscErrorCode SetRigidBodyModes(ClothPreconditioner pre, Mat P, Vec x)
{
  MatNullSpace rigid;

  PetscFunctionBeginUser;
  if (!pre->rigid_body) PetscFunctionReturn(PETSC_SUCCESS); /* PCGAMG's default: the constants of each of the 3 components */
  if (!pre->coords) PetscCall(MatCreateVecs(P, &pre->coords, NULL));
  PetscCall(VecCopy(x, pre->coords));
  PetscCall(MatNullSpaceCreateRigidBody(pre->coords, &rigid));
  PetscCall(MatSetNearNullSpace(P, rigid));
  PetscCall(MatNullSpaceDestroy(&rigid));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether the next set-up keeps the aggregates and interpolation of the last one. PCGAMG decides that itself from its
   reuse flag; the pattern grids' interpolation never changes (a rebuild is a refresh); other multilevel types are reset
   for a rebuild. */
static PetscErrorCode SetReuseInterpolation(ClothPreconditioner pre, PetscBool reuse)
{
  PC        pc;
  PetscBool gamg;

  PetscFunctionBeginUser;
  if (pre->grid) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
  if (gamg)
    PetscCall(PCGAMGSetReuseInterpolation(pc, reuse));
  else if (!reuse)
    PetscCall(PCReset(pc));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A multigrid hierarchy kept from an earlier step (lagged) keeps its coarse operators, but its finest smoother works
   on the current matrix A alone: point-block Jacobi from A's blocks, Chebyshev bounds estimated again (KSPChebyshev
   does so when its operator changed). A V-cycle with a convergent symmetric smoother and any positive definite
   coarse operators is positive definite, so CG stays valid; with the finest smoother's blocks and bounds from the
   older matrix it is not (measured: DIVERGED_INDEFINITE_PC within 5 steps). Sets the finest smoother's operators to
   (A, P). No-op before the first set-up. */
static PetscErrorCode SmoothFinestLevelWith(ClothPreconditioner pre, Mat A, Mat P)
{
  PC        pc;
  PetscBool mg;
  PetscInt  nlevels = 0;
  KSP       smoother;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &mg, PCGAMG, PCML, PCMG, ""));
  if (mg) PetscCall(PCMGGetLevels(pc, &nlevels));
  if (nlevels < 2) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PCMGGetSmoother(pc, nlevels - 1, &smoother));
  PetscCall(KSPSetOperators(smoother, A, P));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Level l - 1's operator P^T A P of the block matrix A itself (ClothBlockPtAP), into pre->coarse[l - 1], stored as
   ctype. */
static PetscErrorCode BlockGalerkinProduct(ClothPreconditioner pre, PetscInt l, Mat A, Mat interpolation, MatType ctype, PetscBool new_pattern)
{
  PetscFunctionBeginUser;
  if (new_pattern || !pre->block_ptap[l]) {
    PetscCall(ClothBlockPtAPDestroy(&pre->block_ptap[l]));
    PetscCall(MatDestroy(&pre->coarse[l - 1]));
    PetscCall(ClothBlockPtAPCreate(A, interpolation, ctype, &pre->block_ptap[l]));
    PetscCall(ClothBlockPtAPGetProduct(pre->block_ptap[l], &pre->coarse[l - 1]));
    PetscCall(PetscObjectReference((PetscObject)pre->coarse[l - 1]));
  }
  PetscCall(ClothBlockPtAPCompute(pre->block_ptap[l], A));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The pattern-grid levels' operators, from the finest level's matrix P down: P_l^T B_l P_l, the storage of the
   products kept (their symbolic part is done once per nonzero pattern of A). When P is a block matrix
   (-implicit_pc_grid_block_product) every product is ClothBlockPtAP's and each coarse level keeps P's storage (BAIJ,
   or SBAIJ: the upper triangle), but the coarsest, which PCMG factors (LU of AIJ); else MatPtAP of P (AIJ) at every
   level. The finest level's residual is the system operator op's (the matrix and the contacts' couplings, which the
   coarse levels and the point-block smoother do not see). */
static PetscErrorCode RefreshGridOperators(ClothPreconditioner pre, PC pc, Mat op, Mat P, PetscBool new_pattern)
{
  PetscInt  nlevels;
  Mat       fine = P, interpolation;
  KSP       smoother;
  PetscBool block, sbaij;
  MatType   block_type;

  PetscFunctionBeginUser;
  PetscCall(ClothGridHierarchyGetLevels(pre->grid, &nlevels));
  PetscCall(ClothBlockMatrixIsBlock(P, &block));
  PetscCall(ClothBlockMatrixIsUpper(P, &sbaij)); /* not MatGetType's name, which ClothBlockRowsGet renames for a moment */
  block_type = sbaij ? MATSBAIJ : MATBAIJ;
  for (PetscInt l = nlevels - 1; l > 0; l--) {
    PetscCall(ClothGridHierarchyGetInterpolation(pre->grid, l, &interpolation));
    if (block)
      PetscCall(BlockGalerkinProduct(pre, l, fine, interpolation, l == 1 ? MATAIJ : block_type, new_pattern));
    else {
      if (new_pattern) PetscCall(MatDestroy(&pre->coarse[l - 1]));
      PetscCall(MatPtAP(fine, interpolation, pre->coarse[l - 1] ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, PETSC_DEFAULT, &pre->coarse[l - 1]));
    }
    PetscCall(PCMGGetSmoother(pc, l - 1, &smoother));
    PetscCall(KSPSetOperators(smoother, pre->coarse[l - 1], pre->coarse[l - 1]));
    /* PCSetUp_MG takes a level's residual operator from its smoother only once: a product created anew (a new
       pattern of A, from contacts) must be given to it too, or the residual is taken with the level's old operator */
    if (l > 1) PetscCall(PCMGSetResidual(pc, l - 1, PCMGResidualDefault, pre->coarse[l - 1]));
    fine = pre->coarse[l - 1];
  }
  if (nlevels > 1) PetscCall(PCMGSetResidual(pc, nlevels - 1, PCMGResidualDefault, op));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The matrix the preconditioner is built from: A itself, or its AIJ copy brought up to date. The pattern-grid
   multigrid takes a block matrix (BAIJ, SBAIJ) as it is (its finest Galerkin product is ClothBlockPtAP's); GAMG
   gets the copy. */
static PetscErrorCode UpdatePreconditioningMatrix(ClothPreconditioner pre, Mat A, PetscBool new_pattern, Mat *P)
{
  PetscBool aij, block, sbaij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &aij, MATAIJ, MATSEQAIJ, MATMPIAIJ, ""));
  PetscCall(ClothBlockMatrixIsBlock(A, &block));
  if (!pre->copy_aij || aij || (block && pre->grid && pre->block_product)) {
    *P = A;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (new_pattern) PetscCall(MatDestroy(&pre->P));
  PetscCall(ClothBlockMatrixIsUpper(A, &sbaij));
  if (sbaij && pre->P) {
    /* PETSc 3.18's MatConvert of SEQSBAIJ with MAT_REUSE_MATRIX writes block-row offsets into the AIJ matrix's point
       rows (src/mat/impls/sbaij/seq/aijsbaij.c; GAMG's next product then overran the heap, seen with valgrind):
       convert afresh and copy the values into the copy the preconditioner holds, entry by entry: the held copy's value
       array does not line up with a fresh conversion's (the same number of entries, not the same layout), so the array
       copy of SAME_NONZERO_PATTERN put values in the wrong places (GAMG on SBAIJ took 897 Krylov iterations against
       BAIJ's 208 at 129 x 129, 24 steps; now 209) */
    Mat fresh;
    PetscCall(MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, &fresh));
    PetscCall(MatCopy(fresh, pre->P, DIFFERENT_NONZERO_PATTERN));
    PetscCall(MatDestroy(&fresh));
  } else
    PetscCall(MatConvert(A, MATAIJ, pre->P ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &pre->P));
  *P = pre->P;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerPrepare(ClothPreconditioner pre, Mat op, Mat A, Vec x, PetscReal h, ClothPCUpdate *update)
{
  ClothPCUpdate u = pre->pending;
  Mat           P;

  PetscFunctionBeginUser;
  if (!pre->kept) { /* set up every step from A itself */
    PetscCall(KSPSetOperators(pre->ksp, op, A));
    pre->last = CLOTH_PC_REFRESH;
    pre->count[CLOTH_PC_REFRESH]++;
    if (update) *update = CLOTH_PC_REFRESH;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (pre->lag_ratio == 0 && u == CLOTH_PC_LAG) u = CLOTH_PC_REFRESH;
  if (A != pre->A) u = CLOTH_PC_REBUILD;
  if (h != pre->h && u == CLOTH_PC_LAG) u = CLOTH_PC_REFRESH;
  if (u != CLOTH_PC_LAG)
    PetscCall(UpdatePreconditioningMatrix(pre, A, A != pre->A ? PETSC_TRUE : PETSC_FALSE, &P));
  else
    PetscCall(KSPGetOperators(pre->ksp, NULL, &P));
  if (u == CLOTH_PC_REBUILD) {
    PetscCall(SetReuseInterpolation(pre, PETSC_FALSE)); /* new aggregates and interpolation, not only coarse operators */
    PetscCall(SetRigidBodyModes(pre, P, x));
  }
  if (pre->grid && u != CLOTH_PC_LAG) {
    PC pc;
    PetscCall(KSPGetPC(pre->ksp, &pc));
    PetscCall(RefreshGridOperators(pre, pc, op, P, A != pre->A ? PETSC_TRUE : PETSC_FALSE));
  }
  PetscCall(KSPSetOperators(pre->ksp, op, P));
  PetscCall(KSPSetReusePreconditioner(pre->ksp, u == CLOTH_PC_LAG ? PETSC_TRUE : PETSC_FALSE));
  /* PCGAMG's refresh takes the finest operator of its Galerkin products from the finest smoother: give it P again */
  PetscCall(SmoothFinestLevelWith(pre, op, u == CLOTH_PC_LAG ? A : P));
  if (u != CLOTH_PC_LAG) pre->h = h;
  pre->A       = A;
  pre->last    = u;
  pre->pending = CLOTH_PC_LAG;
  pre->count[u]++;
  if (update) *update = u;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Does a solve of its iterations exceed the ratio over a reference count? */
static PetscBool SlowerThan(PetscInt its, PetscReal ratio, PetscInt reference)
{
  return its > CLOTH_PC_MIN_ITERATIONS && its > ratio * PetscMax(reference, 1) ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode ClothPreconditionerIterationLimit(ClothPreconditioner pre, PetscInt max_it, PetscInt *limit)
{
  PetscFunctionBeginUser;
  *limit = max_it;
  if (pre->kept && pre->last == CLOTH_PC_LAG) *limit = PetscMin(max_it, PetscMax(pre->its_refreshed, CLOTH_PC_MIN_ITERATIONS) + pre->lag_excess + 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerSolved(ClothPreconditioner pre, PetscInt its)
{
  PetscFunctionBeginUser;
  if (!pre->kept) PetscFunctionReturn(PETSC_SUCCESS);
  switch (pre->last) {
  case CLOTH_PC_REBUILD:
    pre->its_rebuilt = pre->its_refreshed = its;
    pre->lagged                           = 0;
    PetscCall(SetReuseInterpolation(pre, PETSC_TRUE)); /* the rebuild is done: later refreshes keep it */
    break;
  case CLOTH_PC_REFRESH: /* new coarse operators did not help enough: the interpolation itself is out of date */
    pre->its_refreshed = its;
    pre->lagged        = 0;
    if (SlowerThan(its, pre->rebuild_ratio, pre->its_rebuilt)) pre->pending = CLOTH_PC_REBUILD;
    break;
  case CLOTH_PC_LAG:
    if (SlowerThan(its, pre->lag_ratio, pre->its_refreshed) || ++pre->lagged >= pre->lag_max) pre->pending = CLOTH_PC_REFRESH;
    if (its - pre->its_refreshed > pre->lag_excess) {
      pre->paused = pre->lag_pause << PetscMin(pre->failed_lags, pre->lag_backoff);
      pre->failed_lags++;
    } else
      pre->failed_lags = 0;
    break;
  }
  if (pre->paused > 0 && pre->pending == CLOTH_PC_LAG) {
    pre->pending = CLOTH_PC_REFRESH;
    pre->paused--;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerRequestRebuild(ClothPreconditioner pre)
{
  PetscFunctionBeginUser;
  pre->pending = CLOTH_PC_REBUILD;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerRestart(ClothPreconditioner pre)
{
  PetscFunctionBeginUser;
  PetscCall(ClothPreconditionerRequestRebuild(pre));
  pre->paused      = 0;
  pre->failed_lags = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerIsKept(ClothPreconditioner pre, PetscBool *kept)
{
  PetscFunctionBeginUser;
  *kept = pre->kept;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerView(ClothPreconditioner pre, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  if (!pre->kept) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscViewerASCIIPrintf(viewer, "Preconditioner kept between solves (lag ratio %g, rebuild ratio %g): %" PetscInt_FMT " rebuilt, %" PetscInt_FMT " refreshed, %" PetscInt_FMT " lagged\n", (double)pre->lag_ratio, (double)pre->rebuild_ratio,
                                   pre->count[CLOTH_PC_REBUILD], pre->count[CLOTH_PC_REFRESH], pre->count[CLOTH_PC_LAG]));
  if (pre->grid) PetscCall(ClothGridHierarchyView(pre->grid, viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerDestroy(ClothPreconditioner *pre)
{
  PetscFunctionBeginUser;
  if (!*pre) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(MatDestroy(&(*pre)->P));
  PetscCall(VecDestroy(&(*pre)->coords));
  if ((*pre)->grid) {
    PetscInt nlevels;
    PetscCall(ClothGridHierarchyGetLevels((*pre)->grid, &nlevels));
    for (PetscInt l = 0; l < nlevels; l++) {
      PetscCall(MatDestroy(&(*pre)->coarse[l]));
      PetscCall(ClothBlockPtAPDestroy(&(*pre)->block_ptap[l]));
    }
    PetscCall(PetscFree2((*pre)->coarse, (*pre)->block_ptap));
  }
  PetscCall(ClothGridHierarchyDestroy(&(*pre)->grid));
  PetscCall(PetscFree(*pre));
  PetscFunctionReturn(PETSC_SUCCESS);
}
