/* ClothPreconditioner (see preconditioner.h). */
#include "preconditioner.h"

/* The default preconditioner is GAMG from this many particles on, point-block Jacobi below. Measured on the hanging
   sheet (docs/performance.md): GAMG takes 1.4x the wall time of point-block Jacobi at 65 x 65 (its set-up costs
   about as much as the 147 Jacobi iterations it saves), about the same at 129 x 129 (0.88x on 1 rank, 1.17x on 2),
   1.8-1.9x less at 257 x 257. */
#define CLOTH_PC_MULTILEVEL_MIN_PARTICLES 40000

/* The default -implicit_pc_lag_ratio: a lagged hierarchy is refreshed once a solve takes 20 % more iterations than after
   the last refresh. Measured (docs/performance.md): 8-24 % less wall time than refreshing every step at 257 x 257 and
   129 x 129, for about 10 % more iterations. */
#define CLOTH_PC_DEFAULT_LAG_RATIO 1.2

/* A solve this many iterations or fewer never triggers a refresh: at such counts a ratio is noise. */
#define CLOTH_PC_MIN_ITERATIONS 4

struct _n_ClothPreconditioner {
  KSP           ksp;      /* borrowed */
  PetscBool     kept;     /* the preconditioner is kept between steps (multilevel types) */
  PetscBool     copy_aij; /* it is built from an AIJ copy P of the (block) matrix */
  PetscReal     lag_ratio, rebuild_ratio;
  PetscBool     rigid_body; /* near-null space: the six rigid-body modes (else the three translations) */
  Mat           A;          /* the matrix of the last Prepare (borrowed: a new one means a new pattern) */
  Mat           P;          /* the AIJ copy (copy_aij) */
  Vec           coords;     /* positions in the layout of A, for the rigid-body modes */
  PetscReal     h;          /* step size of the last refresh or rebuild */
  ClothPCUpdate pending, last;
  PetscInt      its_rebuilt, its_refreshed; /* iterations of the first solve after the last rebuild / refresh */
  PetscInt      count[3];                   /* solves per ClothPCUpdate */
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
   Jacobi (a particle's 3x3 block at once), its eigenvalue bounds those of the smoothed prolongator, widened by
   10 %. SOR smooths better per sweep but costs two MatMults on AIJ. The threshold drops weak couplings (bending
   against stretch) from the aggregation graph. */
static PetscErrorCode SetGAMGDefaults(KSP ksp)
{
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  PetscCall(SetDefaultOption(prefix, "mg_levels_ksp_type", "chebyshev"));
  PetscCall(SetDefaultOption(prefix, "mg_levels_pc_type", "pbjacobi"));
  PetscCall(SetDefaultOption(prefix, "mg_levels_ksp_chebyshev_esteig", "0,0.1,0,1.1"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerCreate(KSP ksp, PetscInt nparticles, ClothPreconditioner *pre)
{
  ClothPreconditioner p;
  PC                  pc;
  PetscReal           threshold     = 0.01;
  PetscInt            min_particles = CLOTH_PC_MULTILEVEL_MIN_PARTICLES;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&p));
  p->ksp           = ksp;
  p->lag_ratio     = CLOTH_PC_DEFAULT_LAG_RATIO;
  p->rebuild_ratio = 1.5;
  p->pending       = CLOTH_PC_REBUILD;
  p->h             = -1;
  PetscOptionsBegin(PetscObjectComm((PetscObject)ksp), NULL, "Implicit solve: default preconditioner", "ClothPreconditioner");
  PetscCall(PetscOptionsInt("-implicit_pc_multilevel_min_particles", "Default preconditioner: GAMG from this many particles on, point-block Jacobi below (-pc_type overrides)", "ClothPreconditionerCreate", min_particles, &min_particles, NULL));
  PetscOptionsEnd();
  PetscCall(KSPGetPC(ksp, &pc));
  if (nparticles >= min_particles) {
    PetscCall(PCSetType(pc, PCGAMG));
    PetscCall(PCGAMGSetThreshold(pc, &threshold, 1));
    PetscCall(PCGAMGSetReuseInterpolation(pc, PETSC_TRUE));
  } else
    PetscCall(PCSetType(pc, PCPBJACOBI));
  *pre = p;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerSetFromOptions(ClothPreconditioner pre)
{
  PC          pc;
  PetscBool   multilevel, use_amat_set;
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(pre->ksp, &pc));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &multilevel, PCGAMG, PCML, PCHYPRE, ""));
  pre->kept     = multilevel;
  pre->copy_aij = multilevel;
  if (multilevel) {
    PetscBool gamg;
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCGAMG, &gamg));
    if (gamg) PetscCall(SetGAMGDefaults(pre->ksp));
  }
  PetscOptionsBegin(PetscObjectComm((PetscObject)pre->ksp), NULL, "Implicit solve: multilevel preconditioner", "ClothPreconditioner");
  PetscCall(PetscOptionsReal("-implicit_pc_lag_ratio", "Keep a multilevel preconditioner over steps until a solve takes more than this times the iterations after its last refresh (0: refresh every step)", "ClothPreconditionerSolved", pre->lag_ratio,
                             &pre->lag_ratio, NULL));
  PetscCall(PetscOptionsReal("-implicit_pc_rebuild_ratio", "Rebuild the aggregates and interpolation when a refreshed preconditioner takes more than this times the iterations after the last rebuild", "ClothPreconditionerSolved", pre->rebuild_ratio,
                             &pre->rebuild_ratio, NULL));
  PetscCall(PetscOptionsBool("-implicit_pc_rigid_body_modes", "Near-null space of the multilevel preconditioner: the six rigid-body modes at the current positions (false: the three translations)", "ClothPreconditionerPrepare", pre->rigid_body,
                             &pre->rigid_body, NULL));
  PetscOptionsEnd();
  PetscCheck(pre->lag_ratio == 0 || (pre->lag_ratio >= 1 && PetscIsNormalReal(pre->lag_ratio)), PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_lag_ratio %g: expected 0 (refresh every step) or a finite number >= 1",
             (double)pre->lag_ratio);
  PetscCheck(pre->rebuild_ratio >= 1 && PetscIsNormalReal(pre->rebuild_ratio), PetscObjectComm((PetscObject)pre->ksp), PETSC_ERR_USER_INPUT, "-implicit_pc_rebuild_ratio %g: expected a finite number >= 1", (double)pre->rebuild_ratio);
  /* The finest level is smoothed with the block matrix itself (faster MatMult than its AIJ copy). */
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-pc_use_amat", &use_amat_set));
  if (!use_amat_set) PetscCall(PCSetUseAmat(pc, PETSC_TRUE));
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
   reuse flag; other multilevel types are reset for a rebuild. */
static PetscErrorCode SetReuseInterpolation(ClothPreconditioner pre, PetscBool reuse)
{
  PC        pc;
  PetscBool gamg;

  PetscFunctionBeginUser;
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

/* The matrix the preconditioner is built from: A itself, or its AIJ copy brought up to date. */
static PetscErrorCode UpdatePreconditioningMatrix(ClothPreconditioner pre, Mat A, PetscBool new_pattern, Mat *P)
{
  PetscBool aij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)A, &aij, MATAIJ, MATSEQAIJ, MATMPIAIJ, ""));
  if (!pre->copy_aij || aij) {
    *P = A;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (new_pattern) PetscCall(MatDestroy(&pre->P));
  PetscCall(MatConvert(A, MATAIJ, pre->P ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &pre->P));
  *P = pre->P;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerPrepare(ClothPreconditioner pre, Mat A, Vec x, PetscReal h, ClothPCUpdate *update)
{
  ClothPCUpdate u = pre->pending;
  Mat           P;

  PetscFunctionBeginUser;
  if (!pre->kept) { /* set up every step from A itself */
    PetscCall(KSPSetOperators(pre->ksp, A, A));
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
  PetscCall(KSPSetOperators(pre->ksp, A, P));
  PetscCall(KSPSetReusePreconditioner(pre->ksp, u == CLOTH_PC_LAG ? PETSC_TRUE : PETSC_FALSE));
  /* PCGAMG's refresh takes the finest operator of its Galerkin products from the finest smoother: give it P again */
  PetscCall(SmoothFinestLevelWith(pre, A, u == CLOTH_PC_LAG ? A : P));
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

PetscErrorCode ClothPreconditionerSolved(ClothPreconditioner pre, PetscInt its)
{
  PetscFunctionBeginUser;
  if (!pre->kept) PetscFunctionReturn(PETSC_SUCCESS);
  switch (pre->last) {
  case CLOTH_PC_REBUILD:
    pre->its_rebuilt = pre->its_refreshed = its;
    PetscCall(SetReuseInterpolation(pre, PETSC_TRUE)); /* the rebuild is done: later refreshes keep it */
    break;
  case CLOTH_PC_REFRESH: /* new coarse operators did not help enough: the interpolation itself is out of date */
    pre->its_refreshed = its;
    if (SlowerThan(its, pre->rebuild_ratio, pre->its_rebuilt)) pre->pending = CLOTH_PC_REBUILD;
    break;
  case CLOTH_PC_LAG:
    if (SlowerThan(its, pre->lag_ratio, pre->its_refreshed)) pre->pending = CLOTH_PC_REFRESH;
    break;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerRequestRebuild(ClothPreconditioner pre)
{
  PetscFunctionBeginUser;
  pre->pending = CLOTH_PC_REBUILD;
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
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPreconditionerDestroy(ClothPreconditioner *pre)
{
  PetscFunctionBeginUser;
  if (!*pre) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(MatDestroy(&(*pre)->P));
  PetscCall(VecDestroy(&(*pre)->coords));
  PetscCall(PetscFree(*pre));
  PetscFunctionReturn(PETSC_SUCCESS);
}
