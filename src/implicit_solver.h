/* ClothImplicitSolver: the one owner of the implicit step's linear solve (M + h C + h^2 K) dv = rhs.

   It owns the Krylov solver (CG) and all of its settings: the tolerances and the norm (PETSc's relative 1e-5 on the
   preconditioned norm; a garment on (seam-)block Jacobi: 1e-4 on the natural norm), the iteration limit (-ksp_max_it,
   cut short for a lagged preconditioner), the preconditioner (chosen by size and seams, kept between steps and lagged,
   refreshed or rebuilt: preconditioner.h, a part of this object) and the fallback solver (CG + point-block Jacobi,
   options prefix fallback_) that redoes a solve whose preconditioner broke down. The integrator assembles the system and
   asks it to solve. Every -ksp_, -pc_, -mg_levels_, -fallback_ and -implicit_ option overrides its defaults.

   Life cycle: Create, SetFromOptions (the KSP and the preconditioner; GetMatType then says how to store the matrix),
   SetOperators (the matrix once created), SetUp (the fallback solver), Solve at every step, View, Destroy. */
#pragma once
#include <petscksp.h>
#include "cloth.h"

typedef struct _n_ClothImplicitSolver *ClothImplicitSolver;

/* The solver of the implicit systems of cloth (borrowed, set up). Collective. */
PetscErrorCode ClothImplicitSolverCreate(Cloth cloth, ClothImplicitSolver *solver);
/* The KSP's defaults, then its options (-ksp_*, -pc_*), the preconditioner's (-implicit_pc_*) and, for a garment on
   (seam-)block Jacobi, the garment's tolerance and norm unless -ksp_rtol / -ksp_norm_type are given. Collective. */
PetscErrorCode ClothImplicitSolverSetFromOptions(ClothImplicitSolver solver);
/* The storage of the implicit matrix that suits the preconditioner (after SetFromOptions; -implicit_mat_type
   overrides it in ClothCreateMatrix): SBAIJ or BAIJ (ClothPreconditionerGetMatType). */
PetscErrorCode ClothImplicitSolverGetMatType(ClothImplicitSolver solver, MatType *type);
/* The operator op of the system (ClothCreateImplicitOperator: A, or A and the contacts' couplings) and the assembled
   matrix A, preconditioned from (both borrowed; their pattern never changes). */
PetscErrorCode ClothImplicitSolverSetOperators(ClothImplicitSolver solver, Mat op, Mat A);
/* Creates the fallback solver (at set-up, so that -help lists its -fallback_ options). Collective. */
PetscErrorCode ClothImplicitSolverSetUp(ClothImplicitSolver solver);
/* Solves op dv = rhs from the warm start guess (copied into dv), with A assembled at step size h and particle
   positions x (solver numbering). The preconditioner is lagged, refreshed or rebuilt first; a solve with a lagged one
   that stops at its iteration limit is redone once with it rebuilt, one whose preconditioner broke down by the
   fallback solver. *reason is the last solve's, *its the iterations of all. Collective. */
PetscErrorCode ClothImplicitSolverSolve(ClothImplicitSolver solver, Vec x, PetscReal h, Vec rhs, Vec guess, Vec dv, KSPConvergedReason *reason, PetscInt *its);
/* Why a solve that ended with reason after its iterations failed, for messages: the Krylov reason and the
   preconditioner's reason (the worst over the ranks). Collective. */
PetscErrorCode ClothImplicitSolverDescribeFailure(ClothImplicitSolver solver, KSPConvergedReason reason, PetscInt its, char why[], size_t len);
/* The next solve rebuilds the preconditioner from scratch and forgets its lagging history, as a run restarted at this
   point would (called after every checkpoint, so that a restart continues bit for bit). */
PetscErrorCode ClothImplicitSolverRestart(ClothImplicitSolver solver);
/* How many solves were redone by the fallback solver after a preconditioner breakdown. */
PetscErrorCode ClothImplicitSolverGetFallbacks(ClothImplicitSolver solver, PetscInt *count);
/* One line on the implicit system (matrix type, stored blocks and their memory, preconditioner) and, for a
   multilevel preconditioner, how often it was rebuilt, refreshed or kept. Collective. */
PetscErrorCode ClothImplicitSolverViewSystem(ClothImplicitSolver solver, PetscViewer viewer);
/* The KSP, the solves redone with a rebuilt preconditioner and, when it was used, the fallback solver. */
PetscErrorCode ClothImplicitSolverView(ClothImplicitSolver solver, PetscViewer viewer);
PetscErrorCode ClothImplicitSolverDestroy(ClothImplicitSolver *solver);
