/* The force plug-in interface (cloth.h, ClothContribution), checked against an analytic answer.

   A contribution written here, as a user would write one: every particle tied to its start position by a spring of
   stiffness omega^2 m (m its own mass), with energy, forces, K v and its diagonal stiffness blocks. The free sheet
   (no gravity, no damping) is displaced rigidly by u0 from those anchors and let go: the internal forces of a rigid
   translation vanish, and with stiffness proportional to mass every particle feels the same acceleration
   -omega^2 u, so the sheet stays rigid and its displacement follows backward Euler for one harmonic oscillator
   (linear forces: the linearised step is exact):
     v_{n+1} = (v_n - h omega^2 u_n) / (1 + h^2 omega^2),   u_{n+1} = u_n + h v_{n+1}.
   Checks: (1) the forces of the registered contribution are -omega^2 m u0 (to 1e-9 relative: the fabric's links see the
   translation only through rounding, measured 7e-12) and vanish once it is removed; (2) its
   energy is counted; (3) after the implicit steps every particle's displacement equals the recurrence's to
   -tolerance (default 1e-10 m, with -ksp_rtol 1e-13), while the sheet has moved by a good
   fraction of |u0| (not a test of a sheet standing still).
   With -elements the same springs are one-particle elements handed to the cloth's own pass (add_elements,
   ClothElementSinkAdd: the way seam links and hysteresis plug in) instead of add; the contribution then also counts
   ClothBeginStep's calls through begin_step: (4) one per implicit step (a linear problem: no step is halved). */
#include <petscksp.h>
#include "test_support.h"
#include "integrator.h"

typedef struct {
  Cloth     cloth;
  Vec       anchor;      /* start positions */
  PetscReal omega2;      /* 1/s^2 */
  PetscInt  steps_begun; /* begin_step calls */
} AnchorSprings;

/* ClothContribution.add of the anchor springs. */
static PetscErrorCode AnchorSpringsAdd(void *ctx, const ClothContributionArgs *args)
{
  AnchorSprings     *a = (AnchorSprings *)ctx;
  const PetscReal   *mass;
  const PetscScalar *x, *x0, *v = NULL;
  PetscScalar       *f, *kv = NULL;
  ClothLayout        layout;

  PetscFunctionBeginUser;
  PetscCall(ClothGetLayout(a->cloth, &layout));
  PetscCall(ClothGetMasses(a->cloth, &mass, NULL));
  PetscCall(VecGetArrayRead(args->position, &x));
  PetscCall(VecGetArrayRead(a->anchor, &x0));
  PetscCall(VecGetArray(args->force, &f));
  if (args->kv) {
    PetscCall(VecGetArrayRead(args->velocity, &v));
    PetscCall(VecGetArray(args->kv, &kv));
  }
  for (PetscInt i = 0; i < layout.nlocal; i++) {
    const PetscReal k = a->omega2 * mass[i];
    for (PetscInt c = 0; c < 3; c++) {
      const PetscReal u = PetscRealPart(x[3 * i + c] - x0[3 * i + c]);
      f[3 * i + c] -= k * u;
      if (kv) kv[3 * i + c] += k * v[3 * i + c];
      if (args->energy) *args->energy += 0.5 * k * u * u;
    }
    if (args->A) { /* no pins or contacts here: the constraint filter is the identity */
      const PetscInt    row      = layout.rstart + i;
      const PetscScalar block[9] = {args->h2 * k, 0, 0, 0, args->h2 * k, 0, 0, 0, args->h2 * k};
      PetscCall(MatSetValuesBlocked(args->A, 1, &row, 1, &row, block, ADD_VALUES));
    }
  }
  if (args->kv) {
    PetscCall(VecRestoreArray(args->kv, &kv));
    PetscCall(VecRestoreArrayRead(args->velocity, &v));
  }
  PetscCall(VecRestoreArray(args->force, &f));
  PetscCall(VecRestoreArrayRead(a->anchor, &x0));
  PetscCall(VecRestoreArrayRead(args->position, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ClothContribution.add_elements of the same springs: one element per owned particle, in the cloth's pass. */
static PetscErrorCode AnchorSpringsAddElements(void *ctx, ClothElementSink sink)
{
  AnchorSprings     *a = (AnchorSprings *)ctx;
  const PetscReal   *mass;
  const PetscScalar *x, *x0;
  PetscBool          want_h;
  PetscInt           nlocal;
  ClothElement       e;

  PetscFunctionBeginUser;
  PetscCall(ClothElementSinkGetInput(sink, &x, &want_h, NULL));
  PetscCall(ClothGetMasses(a->cloth, &mass, NULL));
  PetscCall(ClothGetSizes(a->cloth, &nlocal, NULL));
  PetscCall(VecGetArrayRead(a->anchor, &x0));
  for (PetscInt i = 0; i < nlocal; i++) {
    const PetscReal k = a->omega2 * mass[i];

    e.np       = 1;
    e.p[0]     = i;
    e.energy   = 0;
    e.factored = PETSC_FALSE;
    for (PetscInt c = 0; c < 3; c++) {
      const PetscReal u = PetscRealPart(x[3 * i + c] - x0[3 * i + c]);

      e.force[c] = -k * u;
      e.energy += 0.5 * k * u * u;
    }
    if (want_h)
      for (PetscInt r = 0; r < 9; r++) e.H[r] = r % 4 == 0 ? k : 0;
    PetscCall(ClothElementSinkAdd(sink, &e));
  }
  PetscCall(VecRestoreArrayRead(a->anchor, &x0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode AnchorSpringsBeginStep(void *ctx, Vec position)
{
  PetscFunctionBeginUser;
  (void)position;
  ((AnchorSprings *)ctx)->steps_begun++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Moves every owned particle by u (a rigid translation). */
static PetscErrorCode Translate(Cloth cloth, const PetscReal u[3])
{
  Vec          x;
  PetscScalar *a;
  PetscInt     nlocal;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, NULL));
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(VecGetArray(x, &a));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) a[3 * i + c] += u[c];
  PetscCall(VecRestoreArray(x, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest |force + omega^2 m u| over the particles (expected 0 with the springs) and the largest |force| (expected
   0 without them). */
static PetscErrorCode ForceErrors(Cloth cloth, PetscReal omega2, const PetscReal u[3], PetscReal *spring_error, PetscReal *largest)
{
  Vec                x, v, f;
  const PetscScalar *a;
  const PetscReal   *mass;
  PetscInt           nlocal;
  PetscReal          err = 0, big = 0;
  MPI_Comm           comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(cloth, &comm));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothCreateStateVec(cloth, &f));
  PetscCall(ClothComputeForces(cloth, x, v, f));
  PetscCall(ClothGetMasses(cloth, &mass, NULL));
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(VecGetArrayRead(f, &a));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) {
      err = PetscMax(err, PetscAbsReal(PetscRealPart(a[3 * i + c]) + omega2 * mass[i] * u[c]));
      big = PetscMax(big, PetscAbsReal(PetscRealPart(a[3 * i + c])));
    }
  PetscCall(VecRestoreArrayRead(f, &a));
  PetscCall(VecDestroy(&f));
  PetscCallMPI(MPI_Allreduce(&err, spring_error, 1, MPIU_REAL, MPI_MAX, comm));
  PetscCallMPI(MPI_Allreduce(&big, largest, 1, MPIU_REAL, MPI_MAX, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest distance of a particle's displacement from the anchor to u. */
static PetscErrorCode DisplacementError(AnchorSprings *a, const PetscReal u[3], PetscReal *error)
{
  Vec                x;
  const PetscScalar *p, *p0;
  PetscInt           nlocal;
  PetscReal          err = 0;
  MPI_Comm           comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(a->cloth, &comm));
  PetscCall(ClothGetState(a->cloth, &x, NULL));
  PetscCall(ClothGetSizes(a->cloth, &nlocal, NULL));
  PetscCall(VecGetArrayRead(x, &p));
  PetscCall(VecGetArrayRead(a->anchor, &p0));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) err = PetscMax(err, PetscAbsReal(PetscRealPart(p[3 * i + c] - p0[3 * i + c]) - u[c]));
  PetscCall(VecRestoreArrayRead(a->anchor, &p0));
  PetscCall(VecRestoreArrayRead(x, &p));
  PetscCallMPI(MPI_Allreduce(&err, error, 1, MPIU_REAL, MPI_MAX, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  const PetscReal   u0[3] = {0.01, -0.02, 0.03}, h = 0.01;
  const PetscInt    steps     = 40;
  PetscReal         tolerance = 1e-10, omega2 = 400, u[3], w[3] = {0, 0, 0}, err, big, moved = 0;
  Scene             scene;
  Cloth             cloth;
  ClothIntegrator   integ;
  ClothContribution springs = {0};
  AnchorSprings     ctx;
  ClothEnergy       e;
  Vec               x, v;
  PetscBool         ok, elements = PETSC_FALSE;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-tolerance", &tolerance, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-elements", &elements, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(VecDuplicate(x, &ctx.anchor));
  PetscCall(VecCopy(x, ctx.anchor));
  ctx.cloth                = cloth;
  ctx.omega2               = omega2;
  ctx.steps_begun          = 0;
  springs.name             = "anchor springs";
  springs.ctx              = &ctx;
  springs.add              = elements ? NULL : AnchorSpringsAdd;
  springs.add_elements     = elements ? AnchorSpringsAddElements : NULL;
  springs.begin_step       = elements ? AnchorSpringsBeginStep : NULL;
  springs.count_row_blocks = NULL; /* diagonal blocks only: already in the pattern */
  PetscCall(ClothAddContribution(cloth, &springs));

  /* (1), (2): forces and energy of the displaced sheet, with and without the contribution */
  PetscCall(Translate(cloth, u0));
  PetscCall(ForceErrors(cloth, omega2, u0, &err, &big));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "with the springs: largest |f + omega^2 m u0| %.3e N (largest |f| %.3e N)\n", (double)err, (double)big));
  PetscCheck(err <= 1e-9 * big && big > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the contribution's forces are not -omega^2 m u0: error %g N of %g N", (double)err, (double)big);
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  {
    const PetscReal *mass;
    PetscInt         nlocal;
    PetscReal        m = 0, total, expected;

    PetscCall(ClothGetMasses(cloth, &mass, NULL));
    PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
    for (PetscInt i = 0; i < nlocal; i++) m += mass[i];
    PetscCallMPI(MPI_Allreduce(&m, &total, 1, MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD));
    expected = 0.5 * omega2 * total * (u0[0] * u0[0] + u0[1] * u0[1] + u0[2] * u0[2]);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "elastic energy with the springs %.6e J (0.5 omega^2 M |u0|^2 = %.6e J)\n", (double)e.elastic, (double)expected));
    PetscCheck(PetscAbsReal(e.elastic - expected) <= 1e-9 * expected, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the contribution's energy is not counted: elastic energy %g J, expected %g J", (double)e.elastic, (double)expected);
  }
  PetscCall(ClothRemoveContribution(cloth, &ctx));
  PetscCall(ForceErrors(cloth, omega2, u0, &err, &big));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "without them: largest |f| %.3e N\n", (double)big));
  PetscCheck(big <= 1e-9, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "a rigid translation without the springs has forces up to %g N", (double)big);
  PetscCall(ClothAddContribution(cloth, &springs));

  /* (3): implicit steps against the oscillator's backward Euler recurrence */
  PetscCall(ClothIntegratorCreate(cloth, &integ));
  PetscCall(ClothIntegratorSetType(integ, "implicit"));
  PetscCall(ClothIntegratorSetFromOptions(integ));
  PetscCall(ClothIntegratorSetUp(integ));
  for (PetscInt c = 0; c < 3; c++) u[c] = u0[c];
  for (PetscInt n = 0; n < steps; n++) {
    PetscCall(ClothIntegratorStep(integ, h, &ok, NULL));
    PetscCheck(ok, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "implicit step %" PetscInt_FMT " failed", n);
    for (PetscInt c = 0; c < 3; c++) {
      w[c] = (w[c] - h * omega2 * u[c]) / (1 + h * h * omega2);
      u[c] += h * w[c];
    }
    moved = PetscMax(moved, PetscAbsReal(u[2] - u0[2]) / PetscAbsReal(u0[2]));
  }
  PetscCall(DisplacementError(&ctx, u, &err));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "after %" PetscInt_FMT " implicit steps: displacement (%.6e, %.6e, %.6e) m, largest particle error %.3e m (tolerance %.1e m); largest excursion %.2f |u0|\n", steps, (double)u[0], (double)u[1], (double)u[2],
                        (double)err, (double)tolerance, (double)moved));
  PetscCheck(moved > 0.5, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the sheet hardly moved (%g of |u0|): the check would be vacuous", (double)moved);
  PetscCheck(err <= tolerance, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "particles deviate from the backward Euler oscillator by %g m > %g m", (double)err, (double)tolerance);
  if (elements) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "begin_step called %" PetscInt_FMT " times in %" PetscInt_FMT " steps\n", ctx.steps_begun, steps));
    PetscCheck(ctx.steps_begun == steps, PETSC_COMM_SELF, PETSC_ERR_PLIB, "begin_step was called %" PetscInt_FMT " times in %" PetscInt_FMT " steps", ctx.steps_begun, steps);
  }
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(ClothIntegratorDestroy(&integ));
  PetscCall(VecDestroy(&ctx.anchor));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
