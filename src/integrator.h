/* ClothIntegrator: advances the cloth by one step (docs/model.md section 5).

   Types, chosen by name (-integrator): explicit (forward Euler), symplectic (semi-implicit Euler),
   implicit (linearised backward Euler, Baraff & Witkin 1998, solved with PETSc KSP), bdf2 (linearised second-order
   backward differentiation in velocity form, Choi & Ko 2002: the same system with step 2h/3 and a history term;
   backward Euler on a step without a history of its size). A step that
   fails (Krylov divergence, a non-finite state) is retried as two half steps, recursively, up to
   -integrator_max_halvings times; the step count and time stay those of the nominal step. */
#pragma once
#include <petscksp.h>
#include "cloth.h"
#include "collision.h"

typedef struct _n_ClothIntegrator *ClothIntegrator;

/* Statistics of the last ClothIntegratorStep. */
typedef struct {
  PetscInt  substeps;          /* sub-steps actually taken (1 when no reduction was needed) */
  PetscInt  krylov_iterations; /* summed over the sub-steps */
  PetscReal smallest_dt;       /* the smallest step tried */
} ClothStepStats;

PetscErrorCode ClothIntegratorCreate(Cloth cloth, ClothIntegrator *integ);
PetscErrorCode ClothIntegratorSetType(ClothIntegrator integ, const char type[]);
PetscErrorCode ClothIntegratorGetType(ClothIntegrator integ, const char **type);
/* -integrator, -integrator_max_halvings, and the KSP's own options for the implicit type. */
PetscErrorCode ClothIntegratorSetFromOptions(ClothIntegrator integ);
PetscErrorCode ClothIntegratorSetUp(ClothIntegrator integ);
/* Advances by dt. *ok is false when even the smallest allowed sub-step failed; the state is then
   left as it was before the call (the last good state). Collective. */
PetscErrorCode ClothIntegratorStep(ClothIntegrator integ, PetscReal dt, PetscBool *ok, ClothStepStats *stats);
/* The implicit type's warm start: dv of the last step, the Krylov initial guess of the next one
   (solver numbering, borrowed; after ClothIntegratorSetUp). *dv is NULL for the other types, which
   keep no state between steps. A bit-for-bit restart saves and restores it. */
PetscErrorCode ClothIntegratorGetWarmStart(ClothIntegrator integ, Vec *dv);
/* The bdf2 history (borrowed; solver numbering; after ClothIntegratorSetUp): rate = (x_n - x_{n-1}) / dt and v_{n-1}
   of the last (sub-)step, as its solve left them, and that sub-step's size dt (0: no history; the next step is then
   backward Euler). NULL and 0 for the other types. A bit-for-bit restart saves and restores all three. */
PetscErrorCode ClothIntegratorGetHistory(ClothIntegrator integ, Vec *rate, Vec *velocity, PetscReal *dt);
/* Declares the history Vecs (filled by the caller, e.g. from a checkpoint) as that of a sub-step of dt (0: none). */
PetscErrorCode ClothIntegratorSetHistoryStep(ClothIntegrator integ, PetscReal dt);
/* One line on the implicit system: matrix type, stored blocks and their memory, preconditioner (nothing for
   explicit integrators); for a multilevel preconditioner how often it was rebuilt, refreshed or kept; with
   -integrator_view the whole ClothIntegratorView. */
PetscErrorCode ClothIntegratorViewSystem(ClothIntegrator integ, PetscViewer viewer);
/* The next implicit step rebuilds its preconditioner from scratch and forgets its lagging history, as a run
   restarted at this point would: called
   after every checkpoint, so that a restart continues bit for bit. */
PetscErrorCode ClothIntegratorRequestPreconditionerRebuild(ClothIntegrator integ);
/* Why the last failed sub-step failed (the Krylov and preconditioner reasons, or a non-finite state), for messages. */
PetscErrorCode ClothIntegratorGetFailure(ClothIntegrator integ, const char **why);
/* How many implicit solves were redone by the fallback solver (prefix fallback_) after a preconditioner breakdown. */
PetscErrorCode ClothIntegratorGetPCFallbacks(ClothIntegrator integ, PetscInt *count);
/* Resolves contacts with the scene's bodies after every successful sub-step (collision borrowed; NULL: none). */
PetscErrorCode ClothIntegratorSetCollision(ClothIntegrator integ, ClothCollision collision);
PetscErrorCode ClothIntegratorView(ClothIntegrator integ, PetscViewer viewer);
PetscErrorCode ClothIntegratorDestroy(ClothIntegrator *integ);
