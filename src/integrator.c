/* ClothIntegrator (see integrator.h). */
#include "integrator.h"
#include "implicit_solver.h"
#include "options.h"
#include "selfcontact.h"

typedef PetscErrorCode (*ClothStepFunction)(ClothIntegrator, PetscReal, PetscBool *, PetscInt *);

struct _n_ClothIntegrator {
  MPI_Comm          comm; /* the cloth's */
  Cloth             cloth;
  char              type[CLOTH_NAME_LEN];
  ClothStepFunction step;
  PetscFunctionList steps;
  PetscInt          max_halvings;
  PetscBool         view; /* -integrator_view: ClothIntegratorView at the end of the run */
  PetscBool         setup;
  Vec               force, start_position, start_velocity; /* start_*: the state at the step's start */
  /* the state at the start of a half step (created at the first halving: a run that never halves does not touch
     them; a whole step's attempt saves into start_*) */
  Vec            saved_position, saved_velocity;
  PetscInt       depth;     /* halvings of the attempt under way (0: the whole step) */
  ClothCollision collision; /* borrowed; NULL: no bodies */
  /* implicit only */
  Mat                 A, op;             /* the assembled matrix; the operator of the system (A and the contacts' couplings, ClothCreateImplicitOperator) */
  ClothImplicitSolver solver;            /* the linear solve: KSP, tolerances, preconditioner, fallback (implicit_solver.h) */
  Vec                 rhs, dv, start_dv; /* start_dv: dv at the step's start, put back when it fails */
  Vec                 dv_guess;          /* a half step's warm start, kept for a solve redone (created at the first halving) */
  char                failure[256];      /* why the last failed (sub-)step failed */
  /* bdf2 only (StepBDF2): the last (sub-)step's history. rate = (x_n - x_{n-1}) / h and v_{n-1}, both as the solve left
     them, before the contact responses: those moved x_n and v_n by jumps that the history takes over, so that an
     impact neither bounces back nor pushes on. history_dt: the (sub-)step they belong to; 0: none. */
  Vec       history_rate, history_velocity;
  PetscReal history_dt;
  PetscBool history_pending;                            /* the sub-step just taken left history_velocity at v_n - v_{n+1} */
  Vec       start_history_rate, start_history_velocity; /* the history at the step's start, put back when it fails */
  PetscReal start_history_dt;
  Vec       extrapolated, work; /* x_n + h/3 S rate, where BDF2 linearises; the extra right-hand side, then w */
  PetscInt  order_steps[2];     /* sub-steps taken as BDF1 (no history of their size) and as BDF2 */
};

/* Is every entry of v finite? Collective. */
static PetscErrorCode VecIsFinite(Vec v, PetscBool *finite)
{
  PetscReal norm;

  PetscFunctionBeginUser;
  PetscCall(VecNorm(v, NORM_INFINITY, &norm));
  *finite = (PetscIsInfOrNanReal(norm) ? PETSC_FALSE : PETSC_TRUE);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* a = S F / m for every owned particle: the constrained acceleration, in place of F. */
static PetscErrorCode ForceToAcceleration(Cloth cloth, Vec force)
{
  const PetscReal *mass;
  PetscScalar     *f;
  PetscInt         nlocal;

  PetscFunctionBeginUser;
  PetscCall(ClothApplyConstraints(cloth, force));
  PetscCall(ClothGetMasses(cloth, &mass, NULL));
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(VecGetArray(force, &f));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) f[3 * i + c] /= mass[i];
  PetscCall(VecRestoreArray(force, &f));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Forward Euler: x += h v_n; v += h a(x_n, v_n). */
static PetscErrorCode StepExplicit(ClothIntegrator integ, PetscReal h, PetscBool *ok, PetscInt *its)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  PetscCall(ClothComputeForces(integ->cloth, x, v, integ->force));
  PetscCall(ForceToAcceleration(integ->cloth, integ->force));
  PetscCall(VecAXPY(x, h, v));
  PetscCall(VecAXPY(v, h, integ->force));
  PetscCall(VecIsFinite(x, ok));
  *its = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Cloth-cloth contacts (selfcontact.h) at the start of a (sub-)step. */
static PetscErrorCode UpdateSelfContact(ClothIntegrator integ, PetscReal h)
{
  ClothSelfContact sc;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSelfContact(integ->cloth, &sc));
  if (sc) PetscCall(ClothSelfContactUpdate(sc, h));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Impulses on v_{n+1} before x moves by h v_{n+1}, so that no layer passes through another. */
static PetscErrorCode FilterSelfContact(ClothIntegrator integ, PetscReal h, Vec v)
{
  ClothSelfContact sc;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSelfContact(integ->cloth, &sc));
  if (sc) PetscCall(ClothSelfContactFilterVelocity(sc, h, v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Symplectic Euler: v += h a(x_n, v_n); x += h v_{n+1}. */
static PetscErrorCode StepSymplectic(ClothIntegrator integ, PetscReal h, PetscBool *ok, PetscInt *its)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  PetscCall(ClothComputeForces(integ->cloth, x, v, integ->force));
  PetscCall(ForceToAcceleration(integ->cloth, integ->force));
  PetscCall(VecAXPY(v, h, integ->force));
  PetscCall(FilterSelfContact(integ, h, v));
  PetscCall(VecAXPY(x, h, v));
  PetscCall(VecIsFinite(x, ok));
  *its = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Solves A dv = rhs (ClothImplicitSolverSolve) from the warm start: the whole step's attempt from the step's dv, a half
   step from the dv that the attempt before it left. */
static PetscErrorCode SolveImplicitSystem(ClothIntegrator integ, Vec x, PetscReal h, KSPConvergedReason *reason, PetscInt *its)
{
  Vec guess = integ->start_dv;

  PetscFunctionBeginUser;
  if (integ->depth > 0) {
    if (!integ->dv_guess) PetscCall(VecDuplicate(integ->dv, &integ->dv_guess));
    PetscCall(VecCopy(integ->dv, integ->dv_guess));
    guess = integ->dv_guess;
  }
  PetscCall(ClothImplicitSolverSolve(integ->solver, x, h, integ->rhs, guess, integ->dv, reason, its));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Assembles the linearised system of step size h at (x, v) (plus extra, already filtered, on its right-hand side when
   given) and solves it for integ->dv; *ok is false when the solve failed or dv is not finite. */
static PetscErrorCode AssembleAndSolve(ClothIntegrator integ, PetscReal h, Vec x, Vec v, Vec extra, PetscBool *ok, PetscInt *its)
{
  KSPConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(ClothAssembleImplicitSystem(integ->cloth, h, x, v, integ->A, integ->rhs));
  if (extra) PetscCall(VecAXPY(integ->rhs, 1.0, extra));
  PetscCall(SolveImplicitSystem(integ, x, h, &reason, its));
  *ok = reason > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (!*ok) PetscCall(ClothImplicitSolverDescribeFailure(integ->solver, reason, *its, integ->failure, sizeof(integ->failure)));
  if (*ok) PetscCall(VecIsFinite(integ->dv, ok));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Linearised backward Euler: (M + h C + h^2 K) dv = h (F - h K v), filtered; v += dv; x += h v. */
static PetscErrorCode StepImplicit(ClothIntegrator integ, PetscReal h, PetscBool *ok, PetscInt *its)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  PetscCall(AssembleAndSolve(integ, h, x, v, NULL, ok, its));
  if (!*ok) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecAXPY(v, 1.0, integ->dv));
  PetscCall(FilterSelfContact(integ, h, v));
  PetscCall(VecAXPY(x, h, v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* BDF2's two history terms at the step's start (docs/model.md section 5): x~ = x_n + h/3 S rate into integ->extrapolated
   (the constraints filter the extrapolation as they filter every motion) and S M (v_n - v_{n-1}) / 3 into integ->work. */
static PetscErrorCode BDF2HistoryTerms(ClothIntegrator integ, PetscReal h, Vec x, Vec v)
{
  const PetscReal *mass;
  PetscInt         nlocal;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(integ->history_rate, integ->work));
  PetscCall(ClothApplyConstraints(integ->cloth, integ->work));
  PetscCall(VecWAXPY(integ->extrapolated, h / 3, integ->work, x));
  PetscCall(VecWAXPY(integ->work, -1.0, integ->history_velocity, v));
  PetscCall(ClothGetMasses(integ->cloth, &mass, NULL));
  PetscCall(ClothGetSizes(integ->cloth, &nlocal, NULL));
  {
    PetscScalar *a;
    PetscCall(VecGetArray(integ->work, &a));
    for (PetscInt i = 0; i < nlocal; i++)
      for (PetscInt c = 0; c < 3; c++) a[3 * i + c] *= mass[i] / 3;
    PetscCall(VecRestoreArray(integ->work, &a));
  }
  PetscCall(ClothApplyConstraints(integ->cloth, integ->work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Second-order backward differentiation (BDF2) in velocity form, linearised at x~ = x_n + h/3 S rate (docs/model.md
   section 5): with b = 2h/3 the backward-Euler system of step b at (x~, v_n),
     (M + b C + b^2 K) dv = b (F(x~, v_n) - b K v_n) + M (v_n - v_{n-1}) / 3,  v_{n+1} = v_n + dv,  x_{n+1} = x~ + b v_{n+1},
   the same assembly, preconditioner and contact handling as StepImplicit. Without a history of this very step size (the
   first step, a halved step's first half, the step after it, a restart without one) it is backward Euler (BDF1):
   x~ = x_n, b = h, no history term. The cloth-cloth impulses act on w = (x_{n+1} - x_n) / h, the velocity over the
   step that their gap check assumes, and change v_{n+1} by as much. */
static PetscErrorCode StepBDF2(ClothIntegrator integ, PetscReal h, PetscBool *ok, PetscInt *its)
{
  const PetscBool  second = integ->history_dt == h ? PETSC_TRUE : PETSC_FALSE;
  const PetscReal  b      = second ? 2 * h / 3 : h;
  ClothSelfContact sc;
  Vec              x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  if (second)
    PetscCall(BDF2HistoryTerms(integ, h, x, v));
  else
    PetscCall(VecCopy(x, integ->extrapolated));
  PetscCall(AssembleAndSolve(integ, b, integ->extrapolated, v, second ? integ->work : NULL, ok, its));
  if (!*ok) PetscFunctionReturn(PETSC_SUCCESS);
  integ->order_steps[second ? 1 : 0]++;
  /* the new history, as the solve leaves it: rate = (x_pre - x_n) / h, and v_n - v_pre (v_{n+1} added after the responses) */
  PetscCall(VecAXPY(integ->extrapolated, b, v));
  PetscCall(VecAXPY(integ->extrapolated, b, integ->dv)); /* x_pre = x~ + b (v_n + dv) */
  PetscCall(VecWAXPY(integ->history_rate, -1.0, x, integ->extrapolated));
  PetscCall(VecScale(integ->history_rate, 1.0 / h));
  PetscCall(VecCopy(integ->dv, integ->history_velocity));
  PetscCall(VecScale(integ->history_velocity, -1.0));
  integ->history_pending = PETSC_TRUE;
  PetscCall(VecAXPY(v, 1.0, integ->dv));
  PetscCall(ClothGetSelfContact(integ->cloth, &sc));
  if (!sc) {
    PetscCall(VecCopy(integ->extrapolated, x));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecCopy(integ->history_rate, integ->work)); /* w, filtered by the impulses; v_{n+1} changes as w does */
  PetscCall(VecAXPY(v, -1.0, integ->work));
  PetscCall(FilterSelfContact(integ, h, integ->work));
  PetscCall(VecAXPY(v, 1.0, integ->work));
  PetscCall(VecAXPY(x, h, integ->work));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After a successful bdf2 sub-step and its contact responses: the history's velocity becomes v_n moved by the jump the
   responses gave v_{n+1}, v_n + (v_{n+1} - v_pre) = v_{n+1} - dv, so that the next step sees no velocity change of
   theirs. */
static PetscErrorCode FinishHistory(ClothIntegrator integ, PetscReal h)
{
  Vec v;

  PetscFunctionBeginUser;
  if (!integ->history_pending) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothGetState(integ->cloth, NULL, &v));
  PetscCall(VecAXPY(integ->history_velocity, 1.0, v));
  integ->history_dt      = h;
  integ->history_pending = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorCreate(Cloth cloth, ClothIntegrator *integ)
{
  ClothIntegrator it;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&it));
  it->cloth = cloth;
  PetscCall(ClothGetComm(cloth, &it->comm));
  it->max_halvings = 6;
  PetscCall(PetscFunctionListAdd(&it->steps, "explicit", StepExplicit));
  PetscCall(PetscFunctionListAdd(&it->steps, "symplectic", StepSymplectic));
  PetscCall(PetscFunctionListAdd(&it->steps, "implicit", StepImplicit));
  PetscCall(PetscFunctionListAdd(&it->steps, "bdf2", StepBDF2));
  PetscCall(ClothIntegratorSetType(it, "implicit"));
  *integ = it;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorSetType(ClothIntegrator integ, const char type[])
{
  ClothStepFunction step;

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListFind(integ->steps, type, &step));
  PetscCheck(step, integ->comm, PETSC_ERR_USER_INPUT, "Unknown integrator '%s': expected explicit, symplectic, implicit or bdf2", type);
  PetscCheck(!integ->setup, integ->comm, PETSC_ERR_ORDER, "Set the integrator type before ClothIntegratorSetUp");
  integ->step = step;
  PetscCall(PetscStrncpy(integ->type, type, sizeof(integ->type)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorGetType(ClothIntegrator integ, const char **type)
{
  PetscFunctionBeginUser;
  *type = integ->type;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorSetFromOptions(ClothIntegrator integ)
{
  char      type[CLOTH_NAME_LEN];
  PetscBool set;

  PetscFunctionBeginUser;
  PetscOptionsBegin(integ->comm, NULL, "Time integration", "ClothIntegrator");
  PetscCall(PetscOptionsFList("-integrator", "Time integrator", "ClothIntegratorSetType", integ->steps, integ->type, type, sizeof(type), &set));
  if (set) PetscCall(ClothIntegratorSetType(integ, type));
  PetscCall(PetscOptionsBool("-integrator_view", "At the end of the run, print the integrator, its KSP and how often a multilevel preconditioner was rebuilt", "ClothIntegratorView", integ->view, &integ->view, NULL));
  PetscCall(PetscOptionsInt("-integrator_max_halvings", "How many times a failing step may be halved before the run stops", "ClothIntegratorStep", integ->max_halvings, &integ->max_halvings, NULL));
  PetscOptionsEnd();
  /* each halving nests one recursion of StepOrHalve: 30 already means steps of dt / 1e9 */
  PetscCall(ClothOptionsCheckInt(integ->comm, "-integrator_max_halvings", integ->max_halvings, 0, 30));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The implicit system's matrix, in the storage its solver's preconditioner suits, and the solver
   (implicit_solver.h: the KSP, its tolerances and norm, the preconditioner, the fallback). */
static PetscErrorCode ClothIntegratorSetUpImplicit(ClothIntegrator integ)
{
  MatType mat_type;

  PetscFunctionBeginUser;
  PetscCall(ClothImplicitSolverCreate(integ->cloth, &integ->solver));
  PetscCall(ClothImplicitSolverSetFromOptions(integ->solver));
  PetscCall(ClothImplicitSolverGetMatType(integ->solver, &mat_type));
  PetscCall(ClothCreateMatrix(integ->cloth, mat_type, &integ->A));
  PetscCall(ClothCreateImplicitOperator(integ->cloth, integ->A, &integ->op));
  PetscCall(MatCreateVecs(integ->A, &integ->dv, NULL));
  PetscCall(VecDuplicate(integ->dv, &integ->start_dv));
  PetscCall(ClothCreateStateVec(integ->cloth, &integ->rhs));
  PetscCall(ClothImplicitSolverSetOperators(integ->solver, integ->op, integ->A));
  PetscCall(ClothImplicitSolverSetUp(integ->solver));
  PetscCall(VecZeroEntries(integ->dv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorSetUp(ClothIntegrator integ)
{
  PetscFunctionBeginUser;
  if (integ->setup) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothCreateStateVec(integ->cloth, &integ->force));
  PetscCall(ClothCreateStateVec(integ->cloth, &integ->start_position));
  PetscCall(ClothCreateStateVec(integ->cloth, &integ->start_velocity));
  if (integ->step == StepImplicit || integ->step == StepBDF2) PetscCall(ClothIntegratorSetUpImplicit(integ));
  if (integ->step == StepBDF2) {
    Vec *vecs[] = {&integ->history_rate, &integ->history_velocity, &integ->start_history_rate, &integ->start_history_velocity, &integ->extrapolated, &integ->work};
    for (size_t k = 0; k < PETSC_STATIC_ARRAY_LENGTH(vecs); k++) PetscCall(ClothCreateStateVec(integ->cloth, vecs[k]));
  }
  integ->setup = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The state a step changes besides x and v, saved in slot 0 at a step's start and slot 1 at each attempt's start:
   the hysteresis sliders and the contacts with bodies. (Self-contacts are found anew from x at every sub-step.) */
#define CLOTH_SLOT_STEP 0
#define CLOTH_SLOT_ATTEMPT 1

static PetscErrorCode SaveInternalState(ClothIntegrator integ, PetscInt slot)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSaveState(integ->cloth, slot));
  if (integ->collision) PetscCall(ClothCollisionSave(integ->collision, slot));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode RestoreInternalState(ClothIntegrator integ, PetscInt slot)
{
  PetscFunctionBeginUser;
  PetscCall(ClothRestoreState(integ->cloth, slot));
  if (integ->collision) PetscCall(ClothCollisionRestore(integ->collision, slot));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Takes one step of h; on failure restores the state and takes two steps of h/2 instead. */
static PetscErrorCode StepOrHalve(ClothIntegrator integ, PetscReal h, PetscInt depth, PetscBool *ok, ClothStepStats *stats)
{
  Vec      x, v, saved_x = integ->start_position, saved_v = integ->start_velocity; /* depth 0: the step's start */
  PetscInt its = 0;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  if (depth > 0) {
    if (!integ->saved_position) PetscCall(ClothCreateStateVec(integ->cloth, &integ->saved_position));
    if (!integ->saved_velocity) PetscCall(ClothCreateStateVec(integ->cloth, &integ->saved_velocity));
    saved_x = integ->saved_position;
    saved_v = integ->saved_velocity;
    PetscCall(VecCopy(x, saved_x));
    PetscCall(VecCopy(v, saved_v));
  }
  PetscCall(SaveInternalState(integ, CLOTH_SLOT_ATTEMPT));
  integ->depth = depth;
  PetscCall(UpdateSelfContact(integ, h));
  PetscCall(ClothBeginStep(integ->cloth, x)); /* the contributions' state at the (sub-)step's start: hysteresis sliders */
  integ->failure[0] = 0;
  PetscCall(integ->step(integ, h, ok, &its));
  if (!*ok && !integ->failure[0]) PetscCall(PetscSNPrintf(integ->failure, sizeof(integ->failure), "the state became non-finite (NaN or Inf)"));
  stats->krylov_iterations += its;
  stats->smallest_dt = PetscMin(stats->smallest_dt, h);
  if (*ok) {
    stats->substeps++;
    if (integ->collision) PetscCall(ClothCollisionApply(integ->collision, saved_x, h)); /* contacts of this sub-step */
    PetscCall(FinishHistory(integ, h));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(VecCopy(saved_x, x));
  PetscCall(VecCopy(saved_v, v));
  PetscCall(RestoreInternalState(integ, CLOTH_SLOT_ATTEMPT));
  if (integ->dv) PetscCall(VecZeroEntries(integ->dv));
  integ->history_pending = PETSC_FALSE; /* an attempt that failed leaves the history alone */
  if (depth >= integ->max_halvings) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscInfo(NULL, "Step of %g s failed; retrying as two steps of %g s\n", (double)h, (double)(h / 2)));
  for (PetscInt half = 0; half < 2; half++) {
    PetscCall(StepOrHalve(integ, h / 2, depth + 1, ok, stats));
    if (!*ok) break;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The bdf2 history saved at a step's start (save) or put back after the step failed (!save); nothing for other types. */
static PetscErrorCode CopyHistory(ClothIntegrator integ, PetscBool save)
{
  PetscFunctionBeginUser;
  if (!integ->history_rate) PetscFunctionReturn(PETSC_SUCCESS);
  if (save) {
    PetscCall(VecCopy(integ->history_rate, integ->start_history_rate));
    PetscCall(VecCopy(integ->history_velocity, integ->start_history_velocity));
    integ->start_history_dt = integ->history_dt;
  } else {
    PetscCall(VecCopy(integ->start_history_rate, integ->history_rate));
    PetscCall(VecCopy(integ->start_history_velocity, integ->history_velocity));
    integ->history_dt = integ->start_history_dt;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorStep(ClothIntegrator integ, PetscReal dt, PetscBool *ok, ClothStepStats *stats)
{
  ClothStepStats s = {0, 0, dt};
  Vec            x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothIntegratorSetUp(integ));
  PetscCall(ClothGetState(integ->cloth, &x, &v));
  PetscCall(VecCopy(x, integ->start_position));
  PetscCall(VecCopy(v, integ->start_velocity));
  PetscCall(SaveInternalState(integ, CLOTH_SLOT_STEP));
  if (integ->dv) PetscCall(VecCopy(integ->dv, integ->start_dv));
  PetscCall(CopyHistory(integ, PETSC_TRUE));
  PetscCall(StepOrHalve(integ, dt, 0, ok, &s));
  if (!*ok) { /* a failed half-step sequence may have advanced part of the way: go back to the start, all of it */
    PetscCall(VecCopy(integ->start_position, x));
    PetscCall(VecCopy(integ->start_velocity, v));
    PetscCall(RestoreInternalState(integ, CLOTH_SLOT_STEP));
    if (integ->dv) PetscCall(VecCopy(integ->start_dv, integ->dv)); /* the warm start too: a checkpoint now is step n's */
    PetscCall(CopyHistory(integ, PETSC_FALSE));
  }
  if (stats) *stats = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorGetWarmStart(ClothIntegrator integ, Vec *dv)
{
  PetscFunctionBeginUser;
  PetscCheck(integ->setup, integ->comm, PETSC_ERR_ORDER, "Call ClothIntegratorSetUp before ClothIntegratorGetWarmStart");
  *dv = integ->dv;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorGetHistory(ClothIntegrator integ, Vec *rate, Vec *velocity, PetscReal *dt)
{
  PetscFunctionBeginUser;
  PetscCheck(integ->setup, integ->comm, PETSC_ERR_ORDER, "Call ClothIntegratorSetUp before ClothIntegratorGetHistory");
  if (rate) *rate = integ->history_rate;
  if (velocity) *velocity = integ->history_velocity;
  if (dt) *dt = integ->history_dt;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorSetHistoryStep(ClothIntegrator integ, PetscReal dt)
{
  PetscFunctionBeginUser;
  PetscCheck(integ->history_rate || dt == 0, integ->comm, PETSC_ERR_ORDER, "Integrator %s keeps no history: set it up as bdf2 first", integ->type);
  PetscCheck(dt >= 0 && PetscIsNormalReal(dt + 1), integ->comm, PETSC_ERR_ARG_OUTOFRANGE, "History step %g: expected 0 (none) or a step size", (double)dt);
  integ->history_dt = dt;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorViewSystem(ClothIntegrator integ, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  if (!integ->solver) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothImplicitSolverViewSystem(integ->solver, viewer));
  if (integ->view) PetscCall(ClothIntegratorView(integ, viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorRequestPreconditionerRebuild(ClothIntegrator integ)
{
  PetscFunctionBeginUser;
  if (integ->solver) PetscCall(ClothImplicitSolverRestart(integ->solver));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorGetFailure(ClothIntegrator integ, const char **why)
{
  PetscFunctionBeginUser;
  *why = integ->failure[0] ? integ->failure : "no step has failed";
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorGetPCFallbacks(ClothIntegrator integ, PetscInt *count)
{
  PetscFunctionBeginUser;
  *count = 0;
  if (integ->solver) PetscCall(ClothImplicitSolverGetFallbacks(integ->solver, count));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorSetCollision(ClothIntegrator integ, ClothCollision collision)
{
  PetscFunctionBeginUser;
  integ->collision = collision;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorView(ClothIntegrator integ, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Integrator: %s (a failing step is halved up to %" PetscInt_FMT " times)\n", integ->type, integ->max_halvings));
  if (integ->step == StepBDF2) PetscCall(PetscViewerASCIIPrintf(viewer, "Sub-steps taken as BDF2: %" PetscInt_FMT ", as backward Euler (no history of their size): %" PetscInt_FMT "\n", integ->order_steps[1], integ->order_steps[0]));
  if (integ->solver) PetscCall(ClothImplicitSolverView(integ->solver, viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIntegratorDestroy(ClothIntegrator *integ)
{
  ClothIntegrator it = *integ;

  PetscFunctionBeginUser;
  if (!it) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFunctionListDestroy(&it->steps));
  PetscCall(VecDestroy(&it->force));
  PetscCall(VecDestroy(&it->saved_position));
  PetscCall(VecDestroy(&it->saved_velocity));
  PetscCall(VecDestroy(&it->start_position));
  PetscCall(VecDestroy(&it->start_velocity));
  PetscCall(MatDestroy(&it->op));
  PetscCall(MatDestroy(&it->A));
  PetscCall(ClothImplicitSolverDestroy(&it->solver));
  PetscCall(VecDestroy(&it->dv_guess));
  PetscCall(VecDestroy(&it->start_dv));
  PetscCall(VecDestroy(&it->rhs));
  PetscCall(VecDestroy(&it->dv));
  PetscCall(VecDestroy(&it->history_rate));
  PetscCall(VecDestroy(&it->history_velocity));
  PetscCall(VecDestroy(&it->start_history_rate));
  PetscCall(VecDestroy(&it->start_history_velocity));
  PetscCall(VecDestroy(&it->extrapolated));
  PetscCall(VecDestroy(&it->work));
  PetscCall(PetscFree(*integ));
  PetscFunctionReturn(PETSC_SUCCESS);
}
