/* ClothPreconditioner: keeps the implicit solve's preconditioner up to date at the least cost. A part of
   ClothImplicitSolver (implicit_solver.h), which owns the KSP, its tolerances and norm, and calls these functions.

   The default preconditioner of large systems is multigrid: on the pattern pieces' own grids (PCMG with the levels of
   gridhierarchy.h) for a scene without seams, smoothed aggregation (PCGAMG) for a garment. Its Krylov iteration count
   does not grow with the sheet's size, as point-block Jacobi's does (docs/performance.md). Its set-up costs several
   solves, so not all of it is redone every step:

   - lag:     the coarse levels of an earlier step are used as they are; the operator and the finest level's smoother
              (its point-block diagonal and Chebyshev bounds) are always the current matrix's;
   - refresh: the coarse operators (Galerkin products), smoothers and point-block diagonals are recomputed from
              the current matrix, the aggregates and interpolation are kept (the pattern grids' interpolation is
              geometric and never changes: for them a rebuild is a refresh);
   - rebuild: everything (with -implicit_pc_rigid_body_modes, the rigid-body modes at the current positions as the
              near-null space; by default the three translations).

   Which one is decided by the iteration count: with -implicit_pc_lag_ratio r > 0 a step refreshes when the last solve
   took more than r times the iterations of the first solve after the last refresh (default 1.2, measured best of
   0 (every step refreshes), 1.15, 1.2, 1.3, 1.6 and 2.5: docs/performance.md), and after at most
   -implicit_pc_lag_max lagged solves in a row (default 2); a refresh is followed by a rebuild when its solve took more than
   -implicit_pc_rebuild_ratio times the iterations after the last rebuild (the sheet has moved so far that the
   aggregates no longer fit). A lagged solve that takes more than -implicit_pc_lag_excess iterations beyond the last
   refreshed one stops lagging for -implicit_pc_lag_pause solves, a pause doubled for each such lag in a row (at most
   -implicit_pc_lag_backoff times). A new matrix (new nonzero pattern) and
   ClothPreconditionerRequestRebuild force a rebuild, a change of the step size (a halved step) a refresh.
   GAMG needs a scalar (AIJ) matrix; when the implicit matrix is BAIJ or SBAIJ, GAMG is built from an AIJ copy made
   only when it is refreshed or rebuilt, while the Krylov method and the finest smoother stream the block matrix
   itself (PCSetUseAmat). The pattern-grid multigrid needs no copy: its finest Galerkin product is taken of the block
   matrix itself (block_ptap.h; -implicit_pc_grid_block_product false goes back to the AIJ copy and MatPtAP).

   Preconditioners without a set-up worth saving (point-block Jacobi, ICC, ...) are set up every step, as before. */
#pragma once
#include <petscksp.h>
#include "util.h"
#include "cloth.h"

typedef struct _n_ClothPreconditioner *ClothPreconditioner;

/* What ClothPreconditionerPrepare did to the preconditioner (in increasing cost). */
typedef enum { CLOTH_PC_LAG, CLOTH_PC_REFRESH, CLOTH_PC_REBUILD } ClothPCUpdate;

/* Manages the preconditioner of ksp (borrowed) for the implicit system of cloth (borrowed, set up). Call before
   KSPSetFromOptions(ksp): it sets the default preconditioner, GAMG for large systems (-implicit_pc_multilevel_min_particles),
   point-block Jacobi for small ones, where a multilevel set-up costs more than it saves. */
PetscErrorCode ClothPreconditionerCreate(KSP ksp, Cloth cloth, ClothPreconditioner *pre);
/* -implicit_pc_lag_ratio; call after KSPSetFromOptions(ksp), when the preconditioner type is known. */
PetscErrorCode ClothPreconditionerSetFromOptions(ClothPreconditioner pre);
/* The storage of the implicit matrix that suits the preconditioner (after SetFromOptions; -implicit_mat_type
   overrides it): SBAIJ for large systems preconditioned by the pattern-grid multigrid or point-block Jacobi, which
   take it as it is; BAIJ otherwise. */
PetscErrorCode ClothPreconditionerGetMatType(ClothPreconditioner pre, MatType *type);
/* Before a solve with the operator op (ClothCreateImplicitOperator: A, or A and the contacts' couplings) of the
   assembled matrix A at step size h and particle positions x (solver numbering, block size 3 layout of A): sets the
   operators of the KSP (op, preconditioned from A) and lags, refreshes or rebuilds its preconditioner. */
PetscErrorCode ClothPreconditionerPrepare(ClothPreconditioner pre, Mat op, Mat A, Vec x, PetscReal h, ClothPCUpdate *update);
/* The iteration limit of the solve after Prepare: max_it, or, for a lagged preconditioner, one more than the iterations of
   the last refreshed solve plus -implicit_pc_lag_excess. Past that count the lag has cost more than a refresh saves
   (the excess rule of ClothPreconditionerSolved), so a hierarchy that no longer fits the matrix is given up there, not
   after max_it iterations; the caller then solves again with it rebuilt. */
PetscErrorCode ClothPreconditionerIterationLimit(ClothPreconditioner pre, PetscInt max_it, PetscInt *limit);
/* After a solve that took its iterations: decides what the next Prepare does. */
PetscErrorCode ClothPreconditionerSolved(ClothPreconditioner pre, PetscInt its);
/* The next Prepare rebuilds everything (after a failed solve; at a checkpoint, so that a restart from it sees the
   same preconditioner as the run that continued, bit for bit). */
PetscErrorCode ClothPreconditionerRequestRebuild(ClothPreconditioner pre);
/* Forgets the lagging history (the pause after costly lags, its backoff) and requests a rebuild: the state of a run
   restarted from a checkpoint written now, so that the run that goes on and the restarted one take the same steps. */
PetscErrorCode ClothPreconditionerRestart(ClothPreconditioner pre);
/* Whether the KSP's preconditioner is point-block Jacobi or its seam-block form (seam_blocks.h): the solver's
   garment defaults apply to those (ClothImplicitSolverSetFromOptions). After SetFromOptions. */
PetscErrorCode ClothPreconditionerIsPointBlockJacobi(ClothPreconditioner pre, PetscBool *is);
/* Whether the preconditioner is kept between steps (a multilevel one) at all. */
PetscErrorCode ClothPreconditionerIsKept(ClothPreconditioner pre, PetscBool *kept);
PetscErrorCode ClothPreconditionerView(ClothPreconditioner pre, PetscViewer viewer);
PetscErrorCode ClothPreconditionerDestroy(ClothPreconditioner *pre);
