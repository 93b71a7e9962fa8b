/* Cloth: forces, implicit system and energies (see cloth.h). One loop over this rank's interactions
   serves them all, so forces and stiffness always come from the same element evaluation. */
#include "cloth_impl.h"
#include "log.h"
#include "block_matrix.h"

/* What one pass over the interactions accumulates (NULL / PETSC_FALSE: not wanted); the contributions' elements
   reach it as a ClothElementSink. */
typedef struct _n_ClothElementSink {
  Cloth              cloth;
  const PetscScalar *x;        /* positions, local form */
  PetscScalar       *force;    /* local form (owned + ghosts), 3 per particle */
  PetscScalar       *kv;       /* K v, local form */
  const PetscScalar *velocity; /* local form, needed for kv */
  Mat                A;        /* receives h^2 K, filtered ... */
  ClothBlockAdder    adder;    /* ... through this */
  PetscReal          h2;
  PetscBool          energy_wanted;
  PetscReal          energy;
  PetscBool          psd;       /* clamp the links' stiffness to its positive semidefinite part */
  const PetscReal   *filter;    /* each local particle's S (9 values), when A is wanted */
  const PetscBool   *filtered;  /* ... and whether it differs from I */
  ClothStiffness     stiffness; /* form of the angle and twist elements' stiffness */
  PetscBool          factored;  /* filter and assemble factored elements from their factors (else expand them first) */
  const PetscScalar *normal;    /* contact normals, local form (NULL: no contacts) */
} ClothEvaluation;

static PetscErrorCode EvaluateLink(const ClothLink *link, const PetscScalar *x, PetscBool want_h, PetscBool psd, ClothElement *e)
{
  PetscReal f1[3], K[9];

  PetscFunctionBeginUser;
  e->np       = 2;
  e->factored = PETSC_FALSE;
  e->p[0]     = link->p[0];
  e->p[1]     = link->p[1];
  PetscCall(ClothLinkEvaluate(link, &x[3 * link->p[0]], &x[3 * link->p[1]], psd, &e->energy, f1, want_h ? K : NULL));
  for (PetscInt c = 0; c < 3; c++) {
    e->force[c]     = -f1[c];
    e->force[3 + c] = f1[c];
  }
  if (want_h)
    for (PetscInt r = 0; r < 3; r++)
      for (PetscInt c = 0; c < 3; c++) {
        const PetscReal k         = K[3 * r + c];
        e->H[6 * r + c]           = k;
        e->H[6 * r + 3 + c]       = -k;
        e->H[6 * (3 + r) + c]     = -k;
        e->H[6 * (3 + r) + 3 + c] = k;
      }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothElementFromAngle(const ClothAngle *angle, const PetscScalar *x, PetscBool want_h, ClothStiffness form, ClothElement *e)
{
  const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES];

  PetscFunctionBeginUser;
  e->np       = ClothAngleParticleCount(angle->kind);
  e->factored = (want_h && form == CLOTH_STIFFNESS_GAUSS_NEWTON) ? PETSC_TRUE : PETSC_FALSE;
  for (PetscInt k = 0; k < e->np; k++) {
    e->p[k] = angle->p[k];
    xs[k]   = &x[3 * angle->p[k]];
  }
  if (e->factored)
    PetscCall(ClothAngleEvaluateFactored(angle, xs, &e->energy, e->force, &e->K));
  else
    PetscCall(ClothAngleEvaluate(angle, xs, form, &e->energy, e->force, want_h ? e->H : NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The constraint filter of a particle (Baraff & Witkin 1998): S = 0 when pinned or stuck (|c| =
   CLOTH_CONTACT_STUCK), I - c c^T when held against a body with unit normal c, I when free. */
PetscBool ClothContactFilter(const PetscScalar *c, PetscBool pinned, PetscReal S[9])
{
  const PetscReal scale = c ? ClothContactScale(c) : 0.0;

  for (PetscInt r = 0; r < 3; r++)
    for (PetscInt k = 0; k < 3; k++) S[3 * r + k] = (pinned || scale == CLOTH_CONTACT_STUCK) ? 0.0 : (r == k ? 1.0 : 0.0) - (scale > 0 ? PetscRealPart(c[r] * c[k]) : 0.0);
  return (pinned || scale > 0) ? PETSC_TRUE : PETSC_FALSE;
}

/* The filter of local particle i (owned or ghost); returns whether S differs from I. */
static PetscBool ConstraintFilter(Cloth cloth, const PetscScalar *normal, PetscInt i, PetscReal S[9])
{
  return ClothContactFilter(normal ? &normal[3 * i] : NULL, cloth->fixed[i], S);
}

/* Every local particle's filter S and whether it differs from I, once per assembly: each particle is in a dozen
   elements, whose filtering reads them. */
static PetscErrorCode ComputeFilters(Cloth cloth, const PetscScalar *normal)
{
  const PetscInt n = cloth->nlocal + cloth->nghost;

  PetscFunctionBeginUser;
  if (n > cloth->nfilter) {
    PetscCall(PetscFree2(cloth->filter, cloth->filtered));
    PetscCall(PetscMalloc2(9 * n, &cloth->filter, n, &cloth->filtered));
    cloth->nfilter = n;
  }
  for (PetscInt i = 0; i < n; i++) cloth->filtered[i] = ConstraintFilter(cloth, normal, i, &cloth->filter[9 * i]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* H (n x n, row-major, 3x3 blocks) <- h2 S_a H_ab S_b for every block: the filtered element stiffness. Written
   on both sides so that the filtered system stays symmetric and CG applies. */
static void FilterElementStiffness(const ClothEvaluation *ev, ClothElement *e)
{
  const PetscInt   n  = 3 * e->np;
  const PetscReal  h2 = ev->h2;
  const PetscReal *S[CLOTH_ELEMENT_MAX_PARTICLES];
  PetscReal        B[9], T[9];
  PetscBool        constrained = PETSC_FALSE;

  for (PetscInt a = 0; a < e->np; a++) {
    S[a]        = &ev->filter[9 * e->p[a]];
    constrained = ev->filtered[e->p[a]] ? PETSC_TRUE : constrained;
  }
  if (!constrained) {
    for (PetscInt k = 0; k < n * n; k++) e->H[k] *= h2;
    return;
  }
  for (PetscInt a = 0; a < e->np; a++)
    for (PetscInt b = 0; b < e->np; b++) {
      for (PetscInt r = 0; r < 3; r++)
        for (PetscInt c = 0; c < 3; c++) B[3 * r + c] = e->H[n * (3 * a + r) + 3 * b + c];
      for (PetscInt r = 0; r < 3; r++) /* T = B S_b */
        for (PetscInt c = 0; c < 3; c++) T[3 * r + c] = B[3 * r] * S[b][c] + B[3 * r + 1] * S[b][3 + c] + B[3 * r + 2] * S[b][6 + c];
      for (PetscInt r = 0; r < 3; r++) /* S_a T */
        for (PetscInt c = 0; c < 3; c++) e->H[n * (3 * a + r) + 3 * b + c] = h2 * (S[a][3 * r] * T[c] + S[a][3 * r + 1] * T[3 + c] + S[a][3 * r + 2] * T[6 + c]);
    }
}

PetscErrorCode ClothElementSinkGetInput(ClothElementSink ev, const PetscScalar **x, PetscBool *want_hessian, ClothStiffness *form)
{
  PetscFunctionBeginUser;
  if (x) *x = ev->x;
  if (want_hessian) *want_hessian = (ev->kv || ev->A) ? PETSC_TRUE : PETSC_FALSE;
  if (form) *form = ev->stiffness;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An element's K v, with its velocities gathered once and its K v scattered once. */
static void AddElementKv(const ClothEvaluation *ev, const ClothElement *e)
{
  const PetscInt n = 3 * e->np;
  PetscReal      ve[3 * CLOTH_ELEMENT_MAX_PARTICLES], kve[3 * CLOTH_ELEMENT_MAX_PARTICLES];

  for (PetscInt k = 0; k < e->np; k++)
    for (PetscInt c = 0; c < 3; c++) ve[3 * k + c] = ev->velocity[3 * e->p[k] + c];
  if (e->factored) { /* sum_r lambda_r q_r (q_r . v) */
    for (PetscInt q = 0; q < n; q++) kve[q] = 0;
    for (PetscInt m = 0; m < e->K.rank; m++) {
      PetscReal dot = 0;
      for (PetscInt q = 0; q < n; q++) dot += e->K.q[m][q] * ve[q];
      dot *= e->K.lambda[m];
      for (PetscInt q = 0; q < n; q++) kve[q] += dot * e->K.q[m][q];
    }
  } else
    for (PetscInt r = 0; r < n; r++) {
      const PetscReal *row = &e->H[n * r];
      kve[r]               = 0;
      for (PetscInt q = 0; q < n; q++) kve[r] += row[q] * ve[q];
    }
  for (PetscInt k = 0; k < e->np; k++)
    for (PetscInt c = 0; c < 3; c++) ev->kv[3 * e->p[k] + c] += kve[3 * k + c];
}

/* A factored element's h^2 S K S into H: S_a q_r (the filter acts on each particle's part of the factors), then the
   product, so the filter costs O(rank n) instead of two 3x3 products per block. */
static void FilterFactoredStiffness(const ClothEvaluation *ev, ClothElement *e)
{
  for (PetscInt a = 0; a < e->np; a++) {
    const PetscReal *S = &ev->filter[9 * e->p[a]];

    if (!ev->filtered[e->p[a]]) continue;
    for (PetscInt m = 0; m < e->K.rank; m++) {
      PetscReal *qa = &e->K.q[m][3 * a], w[3];
      for (PetscInt r = 0; r < 3; r++) w[r] = S[3 * r] * qa[0] + S[3 * r + 1] * qa[1] + S[3 * r + 2] * qa[2];
      for (PetscInt r = 0; r < 3; r++) qa[r] = w[r];
    }
  }
  ClothFactoredStiffnessExpand(&e->K, 3 * e->np, ev->h2, e->H);
}

/* Adds one element's contributions to what the evaluation wants. */
PetscErrorCode ClothElementSinkAdd(ClothElementSink ev, ClothElement *e)
{
  PetscFunctionBeginUser;
  if (ev->energy_wanted) ev->energy += e->energy;
  if (ev->force)
    for (PetscInt k = 0; k < e->np; k++)
      for (PetscInt c = 0; c < 3; c++) ev->force[3 * e->p[k] + c] += e->force[3 * k + c];
  if (e->factored && !ev->factored) { /* the reference path: the expanded matrix, filtered block by block */
    ClothFactoredStiffnessExpand(&e->K, 3 * e->np, 1.0, e->H);
    e->factored = PETSC_FALSE;
  }
  if (ev->kv) AddElementKv(ev, e);
  if (ev->A) {
    /* Filter: constrained directions drop out (I - S goes on the diagonal, AddDiagonalBlocks). */
    if (e->factored)
      FilterFactoredStiffness(ev, e);
    else
      FilterElementStiffness(ev, e);
    PetscCall(ClothBlockAdderAdd(&ev->adder, e->np, e->p, e->H));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One pass over this rank's interactions at local positions x: the cloth's own, then the contributions' elements. */
static PetscErrorCode ClothEvaluateInteractions(Cloth cloth, const PetscScalar *x, ClothEvaluation *ev)
{
  const PetscBool want_h = (ev->kv || ev->A) ? PETSC_TRUE : PETSC_FALSE;
  ClothElement    e;

  PetscFunctionBeginUser;
  ev->cloth = cloth;
  ev->x     = x;
  for (PetscInt l = 0; l < cloth->nlinks; l++) {
    const ClothLink link = ClothLinkExpand(cloth->link_params, cloth->links[l]);
    PetscCall(EvaluateLink(&link, x, want_h, ev->psd, &e));
    PetscCall(ClothElementSinkAdd(ev, &e));
  }
  for (PetscInt a = 0; a < cloth->nangles; a++) {
    PetscCall(ClothElementFromAngle(&cloth->angles[a], x, want_h, ev->stiffness, &e));
    PetscCall(ClothElementSinkAdd(ev, &e));
  }
  PetscCall(PetscLogFlops(60.0 * cloth->nlinks + 400.0 * cloth->nangles));
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].add_elements) PetscCall(cloth->contributions[c].add_elements(cloth->contributions[c].ctx, ev));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode GhostRefresh(Vec v)
{
  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(v, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(v, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode GhostSumBack(Vec v)
{
  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(v, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecGhostUpdateEnd(v, ADD_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gravity and damping on owned particles, added to the internal forces. */
static PetscErrorCode AddBodyForces(Cloth cloth, const PetscScalar *v, PetscScalar *f)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < cloth->nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) f[3 * i + c] += cloth->mass[i] * cloth->gravity_scale * cloth->scene->gravity[c] - cloth->damping[i] * v[3 * i + c];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Evaluates the interactions with ghosts refreshed before and force (and kv) summed back after;
   then adds the body forces. */
/* Asks every plugged-in contribution (cloth.h) for its share of what the evaluation wants. */
static PetscErrorCode AddContributions(Cloth cloth, Vec position, Vec velocity, Vec force, Vec kv, ClothEvaluation *ev)
{
  ClothContributionArgs args = {position, velocity, force, kv, ev->A, ev->h2, ev->psd, ev->energy_wanted ? &ev->energy : NULL};

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].add) PetscCall(cloth->contributions[c].add(cloth->contributions[c].ctx, &args));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothEvaluate(Cloth cloth, Vec position, Vec velocity, Vec force, Vec kv, ClothEvaluation *ev)
{
  Vec                xl, vl, fl, kvl = NULL;
  const PetscScalar *x, *v;
  PetscScalar       *f, *k = NULL;

  PetscFunctionBeginUser;
  PetscCall(GhostRefresh(position));
  PetscCall(GhostRefresh(velocity));
  PetscCall(VecGhostGetLocalForm(position, &xl));
  PetscCall(VecGhostGetLocalForm(velocity, &vl));
  PetscCall(VecGhostGetLocalForm(force, &fl));
  PetscCheck(fl, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "The force vector must be ghosted: create it with ClothCreateStateVec");
  PetscCall(VecZeroEntries(fl));
  PetscCall(VecGetArrayRead(xl, &x));
  PetscCall(VecGetArrayRead(vl, &v));
  PetscCall(VecGetArray(fl, &f));
  if (kv) {
    PetscCall(VecGhostGetLocalForm(kv, &kvl));
    PetscCall(VecZeroEntries(kvl));
    PetscCall(VecGetArray(kvl, &k));
  }
  ev->force    = f;
  ev->kv       = k;
  ev->velocity = v;
  PetscCall(ClothEvaluateInteractions(cloth, x, ev));
  if (kv) {
    PetscCall(VecRestoreArray(kvl, &k));
    PetscCall(VecGhostRestoreLocalForm(kv, &kvl));
  }
  PetscCall(VecRestoreArray(fl, &f));
  PetscCall(VecRestoreArrayRead(vl, &v));
  PetscCall(VecRestoreArrayRead(xl, &x));
  PetscCall(VecGhostRestoreLocalForm(force, &fl));
  PetscCall(VecGhostRestoreLocalForm(velocity, &vl));
  PetscCall(VecGhostRestoreLocalForm(position, &xl));
  PetscCall(GhostSumBack(force));
  if (kv) PetscCall(GhostSumBack(kv));
  /* plugged-in forces (cloth-cloth repulsion: its elements reach particles of other ranks that are not ghosts) */
  PetscCall(AddContributions(cloth, position, velocity, force, kv, ev));
  PetscCall(VecGetArrayRead(velocity, &v));
  PetscCall(VecGetArray(force, &f));
  PetscCall(AddBodyForces(cloth, v, f));
  PetscCall(VecRestoreArray(force, &f));
  PetscCall(VecRestoreArrayRead(velocity, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeForces(Cloth cloth, Vec position, Vec velocity, Vec force)
{
  ClothEvaluation ev = {0};

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.forces, 0, 0, 0, 0));
  PetscCall(ClothEvaluate(cloth, position, velocity, force, NULL, &ev));
  PetscCall(PetscLogEventEnd(ClothLog.forces, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Diagonal blocks: S (m + h c) I S + (I - S) = (m + h c) S + (I - S) (S is a projector) for every owned particle, with
   the filters of this assembly (ComputeFilters). */
static PetscErrorCode AddDiagonalBlocks(Cloth cloth, PetscReal h, ClothBlockAdder *adder)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < cloth->nlocal; i++) {
    const PetscReal  d = cloth->mass[i] + h * cloth->damping[i];
    const PetscReal *S = &cloth->filter[9 * i]; /* ComputeFilters' of this assembly */
    PetscReal        block[9];

    for (PetscInt k = 0; k < 9; k++) block[k] = d * S[k] + ((k % 4 == 0) ? 1.0 : 0.0) - S[k];
    PetscCall(ClothBlockAdderAdd(adder, 1, &i, block));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The contact normals in local form with fresh ghosts (NULL when there are no contacts), and their release. */
static PetscErrorCode GetContactNormalsLocal(Cloth cloth, Vec *local, const PetscScalar **normal)
{
  PetscFunctionBeginUser;
  *local  = NULL;
  *normal = NULL;
  if (!cloth->contact_normal) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(GhostRefresh(cloth->contact_normal));
  PetscCall(VecGhostGetLocalForm(cloth->contact_normal, local));
  PetscCall(VecGetArrayRead(*local, normal));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode RestoreContactNormalsLocal(Cloth cloth, Vec *local, const PetscScalar **normal)
{
  PetscFunctionBeginUser;
  if (!*local) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecRestoreArrayRead(*local, normal));
  PetscCall(VecGhostRestoreLocalForm(cloth->contact_normal, local));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetContactNormals(Cloth cloth, Vec *normals)
{
  PetscFunctionBeginUser;
  if (!cloth->contact_normal) {
    PetscCall(ClothCreateStateVec(cloth, &cloth->contact_normal));
    PetscCall(VecZeroEntries(cloth->contact_normal));
  }
  *normals = cloth->contact_normal;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothAssembleImplicitSystem(Cloth cloth, PetscReal h, Vec position, Vec velocity, Mat A, Vec rhs)
{
  ClothEvaluation ev = {0};
  Vec             normal_local;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.jacobian, 0, 0, 0, 0));
  PetscCall(MatZeroEntries(A));
  ev.A         = A;
  ev.h2        = h * h;
  ev.stiffness = cloth->stiffness;
  ev.factored  = cloth->factored;
  ev.psd       = cloth->stiffness == CLOTH_STIFFNESS_EXACT ? PETSC_FALSE : PETSC_TRUE;
  PetscCall(GetContactNormalsLocal(cloth, &normal_local, &ev.normal));
  PetscCall(ComputeFilters(cloth, ev.normal));
  ev.filter   = cloth->filter;
  ev.filtered = cloth->filtered;
  PetscCall(ClothBlockAdderBegin(A, cloth->nlocal, &ev.adder));
  PetscCall(ClothEvaluate(cloth, position, velocity, cloth->work_force, cloth->work_kv, &ev));
  PetscCall(AddDiagonalBlocks(cloth, h, &ev.adder));
  PetscCall(ClothBlockAdderEnd(&ev.adder));
  for (PetscInt c = 0; c < cloth->ncontributions; c++) /* forces that depend on the whole force (body friction) */
    if (cloth->contributions[c].add_to_implicit_step) PetscCall(cloth->contributions[c].add_to_implicit_step(cloth->contributions[c].ctx, h, velocity, cloth->work_force, A));
  PetscCall(RestoreContactNormalsLocal(cloth, &normal_local, &ev.normal));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  /* rhs = h (F - h K v), filtered, while the matrix assembly communicates */
  PetscCall(VecAXPBYPCZ(rhs, h, -h * h, 0.0, cloth->work_force, cloth->work_kv));
  PetscCall(ClothApplyConstraints(cloth, rhs));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscCall(PetscLogEventEnd(ClothLog.jacobian, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothApplyConstraints(Cloth cloth, Vec v)
{
  PetscScalar       *a;
  const PetscScalar *normal = NULL;
  PetscReal          S[9], w[3];

  PetscFunctionBeginUser;
  if (cloth->contact_normal) PetscCall(VecGetArrayRead(cloth->contact_normal, &normal));
  PetscCall(VecGetArray(v, &a));
  for (PetscInt i = 0; i < cloth->nlocal; i++) {
    if (!ConstraintFilter(cloth, normal, i, S)) continue;
    for (PetscInt r = 0; r < 3; r++) w[r] = S[3 * r] * a[3 * i] + S[3 * r + 1] * a[3 * i + 1] + S[3 * r + 2] * a[3 * i + 2];
    for (PetscInt r = 0; r < 3; r++) a[3 * i + r] = w[r];
  }
  PetscCall(VecRestoreArray(v, &a));
  if (normal) PetscCall(VecRestoreArrayRead(cloth->contact_normal, &normal));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeEnergy(Cloth cloth, Vec position, Vec velocity, ClothEnergy *energy)
{
  ClothEvaluation    ev = {0};
  const PetscScalar *x, *v;
  PetscReal          local[3] = {0, 0, 0}, global[3];

  PetscFunctionBeginUser;
  ev.energy_wanted = PETSC_TRUE;
  PetscCall(ClothEvaluate(cloth, position, velocity, cloth->work_force, NULL, &ev));
  local[2] = ev.energy;
  PetscCall(VecGetArrayRead(position, &x));
  PetscCall(VecGetArrayRead(velocity, &v));
  for (PetscInt i = 0; i < cloth->nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) {
      local[0] += 0.5 * cloth->mass[i] * v[3 * i + c] * v[3 * i + c];
      local[1] -= cloth->mass[i] * cloth->gravity_scale * cloth->scene->gravity[c] * x[3 * i + c];
    }
  PetscCall(VecRestoreArrayRead(velocity, &v));
  PetscCall(VecRestoreArrayRead(position, &x));
  PetscCallMPI(MPI_Allreduce(local, global, 3, MPIU_REAL, MPIU_SUM, cloth->comm));
  energy->kinetic = global[0];
  energy->gravity = global[1];
  energy->elastic = global[2];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Block nonzeros per owned row: the particle itself and its neighbours, split into the diagonal
   (owned) and off-diagonal parts, and the same for the upper triangle (for SBAIJ). */
static PetscErrorCode CountRowBlocks(Cloth cloth, PetscInt dnnz[], PetscInt onnz[], PetscInt dnnzu[], PetscInt onnzu[])
{
  const PetscInt rend = cloth->rstart + cloth->nlocal;

  PetscFunctionBeginUser;
  PetscCheck(cloth->xadj, cloth->comm, PETSC_ERR_ORDER, "ClothCreateMatrix after ClothReleaseGraph: the interaction graph is gone");
  for (PetscInt i = 0; i < cloth->nlocal; i++) {
    const PetscInt g = cloth->natural_of_local[i], row = cloth->rstart + i;
    dnnz[i] = dnnzu[i] = 1;
    onnz[i] = onnzu[i] = 0;
    for (PetscInt k = cloth->xadj[g]; k < cloth->xadj[g + 1]; k++) ClothCountRowBlock(cloth->rstart, rend, row, cloth->solver_of_natural[cloth->adjncy[k]], dnnz, onnz, dnnzu, onnzu);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothReleaseGraph(Cloth cloth)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(cloth->xadj));
  PetscCall(PetscFree(cloth->adjncy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateMatrix(Cloth cloth, MatType type, Mat *A)
{
  PetscInt              *dnnz, *onnz, *dnnzu, *onnzu;
  ISLocalToGlobalMapping l2g;
  PetscBool              sbaij;

  PetscFunctionBeginUser;
  PetscCall(MatCreate(cloth->comm, A));
  PetscCall(MatSetSizes(*A, 3 * cloth->nlocal, 3 * cloth->nlocal, 3 * cloth->nglobal, 3 * cloth->nglobal));
  PetscCall(MatSetBlockSize(*A, 3));
  PetscCall(MatSetType(*A, type));
  PetscCall(MatSetOptionsPrefix(*A, "implicit_"));
  PetscCall(MatSetFromOptions(*A));
  PetscCall(PetscMalloc4(cloth->nlocal, &dnnz, cloth->nlocal, &onnz, cloth->nlocal, &dnnzu, cloth->nlocal, &onnzu));
  PetscCall(CountRowBlocks(cloth, dnnz, onnz, dnnzu, onnzu));
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].count_row_blocks) PetscCall(cloth->contributions[c].count_row_blocks(cloth->contributions[c].ctx, dnnz, onnz, dnnzu, onnzu));
  PetscCall(MatXAIJSetPreallocation(*A, 3, dnnz, onnz, dnnzu, onnzu));
  PetscCall(PetscFree4(dnnz, onnz, dnnzu, onnzu));
  PetscCall(VecGetLocalToGlobalMapping(cloth->position, &l2g));
  PetscCall(MatSetLocalToGlobalMapping(*A, l2g, l2g));
  PetscCall(MatSetOption(*A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(ClothBlockMatrixIsUpper(*A, &sbaij));
  PetscCall(ClothBlockMatrixSetUpOperations(*A));
  if (sbaij)
    PetscCall(MatSetOption(*A, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE));
  else {
    PetscCall(MatSetOption(*A, MAT_SYMMETRIC, PETSC_TRUE));
    PetscCall(MatSetOption(*A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetExactStiffness(Cloth cloth, PetscBool exact)
{
  PetscFunctionBeginUser;
  cloth->stiffness = exact ? CLOTH_STIFFNESS_EXACT : CLOTH_STIFFNESS_PROJECTED;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetFactoredStiffness(Cloth cloth, PetscBool factored)
{
  PetscFunctionBeginUser;
  cloth->factored = factored;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetSelfContact(Cloth cloth, ClothSelfContact sc)
{
  PetscFunctionBeginUser;
  cloth->self_contact = sc;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothBeginStep(Cloth cloth, Vec position)
{
  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].begin_step) PetscCall(cloth->contributions[c].begin_step(cloth->contributions[c].ctx, position));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Calls every contribution's save (or restore) with slot 0 or 1. */
static PetscErrorCode CallSlotHooks(Cloth cloth, PetscInt slot, PetscBool save)
{
  PetscFunctionBeginUser;
  PetscCheck(slot == 0 || slot == 1, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "%s slot %" PetscInt_FMT ": expected 0 or 1", save ? "Save" : "Restore", slot);
  for (PetscInt c = 0; c < cloth->ncontributions; c++) {
    PetscErrorCode (*hook)(void *, PetscInt) = save ? cloth->contributions[c].save : cloth->contributions[c].restore;

    if (hook) PetscCall(hook(cloth->contributions[c].ctx, slot));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSaveState(Cloth cloth, PetscInt slot)
{
  PetscFunctionBeginUser;
  PetscCall(CallSlotHooks(cloth, slot, PETSC_TRUE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRestoreState(Cloth cloth, PetscInt slot)
{
  PetscFunctionBeginUser;
  PetscCall(CallSlotHooks(cloth, slot, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetSelfContact(Cloth cloth, ClothSelfContact *sc)
{
  PetscFunctionBeginUser;
  *sc = cloth->self_contact;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The shell of ClothCreateImplicitOperator. */
typedef struct {
  Cloth cloth;
  Mat   A;
} ClothImplicitOperator;

static PetscErrorCode ImplicitOperatorMult(Mat op, Vec x, Vec y)
{
  ClothImplicitOperator *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(op, &ctx));
  PetscCall(MatMult(ctx->A, x, y));
  for (PetscInt c = 0; c < ctx->cloth->ncontributions; c++)
    if (ctx->cloth->contributions[c].mult_coupling) PetscCall(ctx->cloth->contributions[c].mult_coupling(ctx->cloth->contributions[c].ctx, x, y));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ImplicitOperatorDestroy(Mat op)
{
  ClothImplicitOperator *ctx;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(op, &ctx));
  PetscCall(MatDestroy(&ctx->A));
  PetscCall(PetscFree(ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateImplicitOperator(Cloth cloth, Mat A, Mat *op)
{
  PetscBool              coupled = PETSC_FALSE;
  ClothImplicitOperator *ctx;
  PetscInt               m, n, M, N;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].mult_coupling) coupled = PETSC_TRUE;
  if (!coupled) {
    PetscCall(PetscObjectReference((PetscObject)A));
    *op = A;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscNew(&ctx));
  ctx->cloth = cloth;
  ctx->A     = A;
  PetscCall(PetscObjectReference((PetscObject)A));
  PetscCall(MatGetLocalSize(A, &m, &n));
  PetscCall(MatGetSize(A, &M, &N));
  PetscCall(MatCreateShell(cloth->comm, m, n, M, N, ctx, op));
  PetscCall(MatShellSetOperation(*op, MATOP_MULT, (void (*)(void))ImplicitOperatorMult));
  PetscCall(MatShellSetOperation(*op, MATOP_DESTROY, (void (*)(void))ImplicitOperatorDestroy));
  PetscCall(MatSetBlockSize(*op, 3));
  PetscCall(MatSetOption(*op, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(*op, MAT_SPD, PETSC_TRUE));
  PetscFunctionReturn(PETSC_SUCCESS);
}
