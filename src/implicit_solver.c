/* ClothImplicitSolver (see implicit_solver.h). */
#include "implicit_solver.h"
#include "preconditioner.h"
#include "log.h"

/* The Krylov solver's defaults, chosen by measurement (docs/performance.md). CG: the system is symmetric positive
   definite. Relative tolerance: PETSc's default 1e-5 on the preconditioned norm (as the Taichi peer); a garment on
   (seam-)block Jacobi stops on the natural norm at CLOTH_GARMENT_RTOL (SetGarmentDefaults). No absolute tolerance (1e-50):
   the relative decrease alone decides. Iteration caps: the default
   preconditioners need tens of iterations (hundreds without a multilevel one); the fallback, point-block Jacobi CG, up
   to a few thousand on the largest sheets. */
#define CLOTH_KRYLOV_ABSTOL 1e-50
#define CLOTH_KRYLOV_MAX_IT 2000
#define CLOTH_FALLBACK_KRYLOV_MAX_IT 10000

/* A garment solved with point-block Jacobi (its default below -implicit_pc_multilevel_min_particles, preconditioner.h)
   stops CG on its natural norm (r^T B r)^(1/2) instead of PETSc's default preconditioned norm |B r|, at a relative
   decrease of CLOTH_GARMENT_RTOL instead of PETSc's 1e-5. -ksp_norm_type and -ksp_rtol override.
   - The natural norm: one reduction less per iteration, and fewer iterations. Measured on the main job (the fitted
     dress, 2 ranks, 1,250 steps, 2026-11-26): 298,090 against 340,828 iterations, 30.1-32.1 s against 32.8-37.5 s
     (three runs each, in turns), the same quality. The hanging sheet with point-block Jacobi took 10 % more
     iterations with it (65 x 65, the full second), so sheets keep the default.
   - The tolerance: a garment's drape is chaotic (folds settle one way or another). On the main job, solved to 1e-7,
     1e-5 and 1e-4, the runs at 1e-5 and 1e-4 are as far from the 1e-7 one at every time (RMS 1.6 and 2.0 mm at
     t = 0.1 s, 19 and 18 mm at 5 s) as the same run on 1 rank is from 2 ranks (1.6 mm, 20 mm), with the same seam
     gaps, strain and settling; the main job takes 210,757 iterations instead of 298,090 and 21.3-22.2 s instead of
     26.7-27.3 s, the 12 mm dress 82.6 s instead of 93.5-97.0 s (docs/performance.md, 2026-11-26). 1e-3 opened the
     seams to 0.63 mm. */
#define CLOTH_GARMENT_RTOL 1e-4

struct _n_ClothImplicitSolver {
  MPI_Comm            comm;
  Cloth               cloth;        /* borrowed */
  KSP                 ksp;          /* CG with the preconditioner pre keeps */
  KSP                 fallback_ksp; /* redoes the solves whose preconditioner breaks down */
  ClothPreconditioner pre;          /* keeps ksp's preconditioner between steps */
  Mat                 op, A;        /* borrowed: the system's operator and the assembled matrix */
  PetscInt            max_it;       /* the Krylov solve's iteration limit (-ksp_max_it) */
  PetscInt            retries;      /* solves redone after a rebuild of a preconditioner kept from earlier steps */
  PetscInt            fallbacks;    /* solves redone with fallback_ksp */
};

PetscErrorCode ClothImplicitSolverCreate(Cloth cloth, ClothImplicitSolver *solver)
{
  ClothImplicitSolver s;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&s));
  s->cloth = cloth;
  PetscCall(ClothGetComm(cloth, &s->comm));
  PetscCall(KSPCreate(s->comm, &s->ksp));
  *solver = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A garment (a scene with seams) on (seam-)block Jacobi: the natural norm and CLOTH_GARMENT_RTOL, unless given as
   options. Decided after KSPSetFromOptions, when the preconditioner is known (-pc_type may have changed it); an option
   given keeps the value KSPSetFromOptions took from it. */
static PetscErrorCode SetGarmentDefaults(ClothImplicitSolver solver)
{
  PetscBool   pbjacobi, norm_set, rtol_set;
  ClothLayout layout;
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCall(ClothPreconditionerIsPointBlockJacobi(solver->pre, &pbjacobi));
  PetscCall(ClothGetLayout(solver->cloth, &layout));
  if (!pbjacobi || layout.model->nseamlinks == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(KSPGetOptionsPrefix(solver->ksp, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-ksp_norm_type", &norm_set));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-ksp_rtol", &rtol_set));
  if (!norm_set) PetscCall(KSPSetNormType(solver->ksp, KSP_NORM_NATURAL));
  if (!rtol_set) PetscCall(KSPSetTolerances(solver->ksp, CLOTH_GARMENT_RTOL, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The defaults of every scene, then the options, then the garments' defaults. The preconditioner object chooses the
   default preconditioner before KSPSetFromOptions (so that -pc_type overrides it) and sets up the chosen one after. */
PetscErrorCode ClothImplicitSolverSetFromOptions(ClothImplicitSolver solver)
{
  PetscFunctionBeginUser;
  PetscCall(KSPSetType(solver->ksp, KSPCG));
  PetscCall(ClothPreconditionerCreate(solver->ksp, solver->cloth, &solver->pre));
  PetscCall(KSPSetTolerances(solver->ksp, PETSC_DEFAULT, CLOTH_KRYLOV_ABSTOL, PETSC_DEFAULT, CLOTH_KRYLOV_MAX_IT));
  PetscCall(KSPSetInitialGuessNonzero(solver->ksp, PETSC_TRUE)); /* dv of the last step: a good guess */
  PetscCall(KSPSetFromOptions(solver->ksp));
  PetscCall(KSPGetTolerances(solver->ksp, NULL, NULL, NULL, &solver->max_it));
  PetscCall(ClothPreconditionerSetFromOptions(solver->pre));
  PetscCall(SetGarmentDefaults(solver));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverGetMatType(ClothImplicitSolver solver, MatType *type)
{
  PetscFunctionBeginUser;
  PetscCheck(solver->pre, solver->comm, PETSC_ERR_ORDER, "Call ClothImplicitSolverSetFromOptions before ClothImplicitSolverGetMatType");
  PetscCall(ClothPreconditionerGetMatType(solver->pre, type));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverSetOperators(ClothImplicitSolver solver, Mat op, Mat A)
{
  PetscFunctionBeginUser;
  solver->op = op;
  solver->A  = A;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The robust solver of the steps whose preconditioner breaks down, options prefix fallback_: CG + point-block
   Jacobi (for SBAIJ through block_matrix.h). */
PetscErrorCode ClothImplicitSolverSetUp(ClothImplicitSolver solver)
{
  PC pc;

  PetscFunctionBeginUser;
  if (solver->fallback_ksp) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(KSPCreate(solver->comm, &solver->fallback_ksp));
  PetscCall(KSPSetOptionsPrefix(solver->fallback_ksp, "fallback_"));
  PetscCall(KSPSetType(solver->fallback_ksp, KSPCG));
  PetscCall(KSPGetPC(solver->fallback_ksp, &pc));
  PetscCall(PCSetType(pc, PCPBJACOBI));
  PetscCall(KSPSetTolerances(solver->fallback_ksp, PETSC_DEFAULT, CLOTH_KRYLOV_ABSTOL, PETSC_DEFAULT, CLOTH_FALLBACK_KRYLOV_MAX_IT));
  PetscCall(KSPSetInitialGuessNonzero(solver->fallback_ksp, PETSC_TRUE));
  PetscCall(KSPSetFromOptions(solver->fallback_ksp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* KSPSolve from the warm start in guess; its iterations are added to *its. */
static PetscErrorCode SolveFromGuess(KSP ksp, Vec rhs, Vec guess, Vec dv, KSPConvergedReason *reason, PetscInt *its)
{
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(guess, dv));
  PetscCall(KSPSolve(ksp, rhs, dv));
  PetscCall(KSPGetConvergedReason(ksp, reason));
  PetscCall(KSPGetIterationNumber(ksp, &n));
  *its += n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A preconditioner lagged from earlier steps may not fit a matrix that changed abruptly (a contact, a halved step, a
   sheet folding): its solve is stopped once the lag has cost more than a refresh saves (ClothPreconditionerIterationLimit;
   limited by -ksp_max_it alone, a step of a 1025 x 1025 sheet was still solving after 20 minutes) and redone once with
   the preconditioner rebuilt. An incomplete factorisation can break down (a non-positive pivot: DIVERGED_INDEFINITE_PC)
   on a matrix that is itself positive definite; then the step is solved again by the fallback solver rather than
   halved. */
PetscErrorCode ClothImplicitSolverSolve(ClothImplicitSolver solver, Vec x, PetscReal h, Vec rhs, Vec guess, Vec dv, KSPConvergedReason *reason, PetscInt *its)
{
  ClothPCUpdate update;
  PetscBool     kept;
  PetscInt      last_its = 0, limit;

  PetscFunctionBeginUser;
  PetscCheck(solver->A && solver->fallback_ksp, solver->comm, PETSC_ERR_ORDER, "Call ClothImplicitSolverSetOperators and ClothImplicitSolverSetUp before ClothImplicitSolverSolve");
  PetscCall(PetscLogEventBegin(ClothLog.solve, 0, 0, 0, 0));
  *its = 0;
  PetscCall(ClothPreconditionerPrepare(solver->pre, solver->op, solver->A, x, h, &update));
  PetscCall(ClothPreconditionerIterationLimit(solver->pre, solver->max_it, &limit));
  PetscCall(KSPSetTolerances(solver->ksp, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, limit));
  PetscCall(SolveFromGuess(solver->ksp, rhs, guess, dv, reason, &last_its));
  PetscCall(ClothPreconditionerIsKept(solver->pre, &kept));
  if (*reason < 0 && kept && update != CLOTH_PC_REBUILD) {
    PetscCall(PetscInfo(NULL, "Solve with a preconditioner of earlier steps failed (%s after %" PetscInt_FMT " iterations); rebuilding it\n", KSPConvergedReasons[*reason], last_its));
    PetscCall(ClothPreconditionerSolved(solver->pre, last_its)); /* a lag cut short by its limit pauses lagging */
    *its     = last_its;
    last_its = 0;
    PetscCall(ClothPreconditionerRequestRebuild(solver->pre));
    PetscCall(ClothPreconditionerPrepare(solver->pre, solver->op, solver->A, x, h, NULL));
    PetscCall(KSPSetTolerances(solver->ksp, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, solver->max_it));
    PetscCall(SolveFromGuess(solver->ksp, rhs, guess, dv, reason, &last_its));
    solver->retries++;
  }
  *its += last_its;
  PetscCall(ClothPreconditionerSolved(solver->pre, last_its));
  if (*reason == KSP_DIVERGED_INDEFINITE_PC || *reason == KSP_DIVERGED_PC_FAILED) {
    PetscCall(PetscInfo(NULL, "Preconditioner broke down (%s); solving again with the fallback solver\n", KSPConvergedReasons[*reason]));
    PetscCall(ClothPreconditionerRequestRebuild(solver->pre));
    PetscCall(KSPSetOperators(solver->fallback_ksp, solver->op, solver->A));
    PetscCall(SolveFromGuess(solver->fallback_ksp, rhs, guess, dv, reason, its));
    solver->fallbacks++;
  }
  PetscCall(PetscLogEventEnd(ClothLog.solve, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The preconditioner's reason is the worst over the ranks: a zero pivot of one rank's factor fails the solve on all. */
PetscErrorCode ClothImplicitSolverDescribeFailure(ClothImplicitSolver solver, KSPConvergedReason reason, PetscInt its, char why[], size_t len)
{
  PC             pc;
  PCType         type;
  PCFailedReason local, worst;
  int            l, w;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(solver->ksp, &pc));
  PetscCall(PCGetType(pc, &type));
  PetscCall(PCGetFailedReasonRank(pc, &local));
  l = (int)local;
  PetscCallMPI(MPI_Allreduce(&l, &w, 1, MPI_INT, MPI_MAX, solver->comm));
  worst = (PCFailedReason)w;
  if (worst != PC_NOERROR)
    PetscCall(PetscSNPrintf(why, len, "the Krylov solve stopped with %s after %" PetscInt_FMT " iterations: preconditioner %s failed with %s", KSPConvergedReasons[reason], its, type, PCFailedReasons[worst]));
  else
    PetscCall(PetscSNPrintf(why, len, "the Krylov solve stopped with %s after %" PetscInt_FMT " iterations (preconditioner %s)", KSPConvergedReasons[reason], its, type));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverRestart(ClothImplicitSolver solver)
{
  PetscFunctionBeginUser;
  if (solver->pre) PetscCall(ClothPreconditionerRestart(solver->pre));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverGetFallbacks(ClothImplicitSolver solver, PetscInt *count)
{
  PetscFunctionBeginUser;
  *count = solver->fallbacks;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverViewSystem(ClothImplicitSolver solver, PetscViewer viewer)
{
  MatInfo     info;
  MatType     mtype;
  PCType      pctype;
  PC          pc;
  PetscInt    bs;
  PetscBool   shell;
  const char *name = NULL;

  PetscFunctionBeginUser;
  if (!solver->A) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(MatGetInfo(solver->A, MAT_GLOBAL_SUM, &info));
  PetscCall(MatGetType(solver->A, &mtype));
  PetscCall(MatGetBlockSize(solver->A, &bs));
  PetscCall(KSPGetPC(solver->ksp, &pc));
  PetscCall(PCGetType(pc, &pctype));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCSHELL, &shell));
  if (shell) PetscCall(PCShellGetName(pc, &name));
  if (name) pctype = name; /* seam-block Jacobi */
  /* nz_used counts stored scalars (one triangle for SBAIJ): what every matrix pass streams */
  PetscCall(PetscViewerASCIIPrintf(viewer, "Implicit system: %s, %" PetscInt_FMT " stored %" PetscInt_FMT "x%" PetscInt_FMT " blocks (%.1f MiB of values), preconditioner %s\n", mtype, (PetscInt)(info.nz_used / (bs * bs)), bs, bs,
                                   info.nz_used * sizeof(PetscScalar) / 1048576.0, pctype));
  if (solver->pre) PetscCall(ClothPreconditionerView(solver->pre, viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverView(ClothImplicitSolver solver, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(KSPView(solver->ksp, viewer));
  if (solver->retries) PetscCall(PetscViewerASCIIPrintf(viewer, "Solves redone with a rebuilt preconditioner after one kept from earlier steps failed: %" PetscInt_FMT "\n", solver->retries));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  if (solver->fallbacks) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Solves redone by the fallback solver after a preconditioner breakdown: %" PetscInt_FMT "\n", solver->fallbacks));
    PetscCall(PetscViewerASCIIPushTab(viewer));
    PetscCall(KSPView(solver->fallback_ksp, viewer));
    PetscCall(PetscViewerASCIIPopTab(viewer));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothImplicitSolverDestroy(ClothImplicitSolver *solver)
{
  PetscFunctionBeginUser;
  if (!*solver) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(KSPDestroy(&(*solver)->ksp));
  PetscCall(KSPDestroy(&(*solver)->fallback_ksp));
  PetscCall(ClothPreconditionerDestroy(&(*solver)->pre));
  PetscCall(PetscFree(*solver));
  PetscFunctionReturn(PETSC_SUCCESS);
}
