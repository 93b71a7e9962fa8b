/* Bending and shear hysteresis as a contribution of the cloth (see hysteresis.h, forces.h).

   Each friction element sits beside an elastic spring, of one thread-bending chain (p0, p1, p2) or of one
   cell's shear angle (corners p0..p3), and carries the slider's position as its rest angle (cos0, sin0).
   The sliders move once per (sub-)step, at its start; a checkpoint stores them per particle in natural
   order: for bending, four values per middle particle p1, cos0 and sin0 of the chain along the warp, then
   of the chain along the weft; for shear, two values per cell at its first corner p0 = (i, j), which is
   the first corner of no other cell. Exact copies, so that a restarted run is bit-identical to an
   uninterrupted one. */
#include "hysteresis.h"

#define CLOTH_HYSTERESIS_NAME "hysteresis"

typedef struct {
  MPI_Comm    comm;
  ClothModel  model;
  PetscInt    nglobal;
  PetscInt    n;
  ClothAngle *elements;    /* this rank's friction elements, local particle numbering */
  PetscInt   *state_index; /* where each one's cos0 (then sin0) goes in its family's state Vec */
  PetscReal  *saved[2];    /* cos0, sin0 of each, per save slot */
  PetscBool   is_saved[2]; /* (a rank may have no friction elements: saved[] stays NULL) */
} ClothHysteresis;

static ClothSliderFamily SliderFamily(const ClothAngle *angle)
{
  return angle->kind == CLOTH_ANGLE_CELL ? CLOTH_SLIDERS_SHEAR : CLOTH_SLIDERS_BEND;
}

static PetscInt SliderBlockSize(ClothSliderFamily family)
{
  return family == CLOTH_SLIDERS_BEND ? 4 : 2;
}

static PetscInt SliderCount(ClothModel model, ClothSliderFamily family)
{
  return family == CLOTH_SLIDERS_BEND ? model->nfriction - model->nfriction_shear : model->nfriction_shear;
}

/* Where a friction element (natural particle numbers) puts its cos0 (then sin0) in its family's state Vec.
   Bending: its middle particle's row, slot 0 for the chain along the warp (i), 1 along the weft (j); in a piece's
   natural numbering j nu + i the warp neighbours of a particle are 1 apart, the weft neighbours nu >= 2. Shear:
   the row of the cell's first corner. */
static PetscInt SliderIndex(const ClothAngle *natural)
{
  if (SliderFamily(natural) == CLOTH_SLIDERS_SHEAR) return 2 * natural->p[0];
  return 4 * natural->p[1] + 2 * (natural->p[1] - natural->p[0] == 1 ? 0 : 1);
}

static PetscErrorCode HysteresisAddElements(void *ctx, ClothElementSink sink)
{
  const ClothHysteresis *hy = (const ClothHysteresis *)ctx;
  const PetscScalar     *x;
  PetscBool              want_h;
  ClothStiffness         form;
  ClothElement           e;

  PetscFunctionBeginUser;
  PetscCall(ClothElementSinkGetInput(sink, &x, &want_h, &form));
  for (PetscInt a = 0; a < hy->n; a++) {
    PetscCall(ClothElementFromAngle(&hy->elements[a], x, want_h, form, &e));
    PetscCall(ClothElementSinkAdd(sink, &e));
  }
  PetscCall(PetscLogFlops(400.0 * hy->n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The sliders at the (sub-)step's start. */
static PetscErrorCode HysteresisBeginStep(void *ctx, Vec position)
{
  ClothHysteresis   *hy = (ClothHysteresis *)ctx;
  Vec                xl;
  const PetscScalar *x;

  PetscFunctionBeginUser;
  if (hy->model->nfriction == 0) PetscFunctionReturn(PETSC_SUCCESS); /* the same on every rank: no ghost update */
  PetscCall(VecGhostUpdateBegin(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(position, &xl));
  PetscCall(VecGetArrayRead(xl, &x));
  for (PetscInt a = 0; a < hy->n; a++) {
    ClothAngle      *angle = &hy->elements[a];
    const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES];

    for (PetscInt k = 0; k < ClothAngleParticleCount(angle->kind); k++) xs[k] = &x[3 * angle->p[k]];
    ClothAngleSlide(angle, xs);
  }
  PetscCall(VecRestoreArrayRead(xl, &x));
  PetscCall(VecGhostRestoreLocalForm(position, &xl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisSave(void *ctx, PetscInt slot)
{
  ClothHysteresis *hy = (ClothHysteresis *)ctx;

  PetscFunctionBeginUser;
  if (!hy->is_saved[slot]) PetscCall(PetscMalloc1(2 * hy->n, &hy->saved[slot]));
  hy->is_saved[slot] = PETSC_TRUE;
  for (PetscInt a = 0; a < hy->n; a++) {
    hy->saved[slot][2 * a]     = hy->elements[a].cos0;
    hy->saved[slot][2 * a + 1] = hy->elements[a].sin0;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisRestore(void *ctx, PetscInt slot)
{
  ClothHysteresis *hy = (ClothHysteresis *)ctx;

  PetscFunctionBeginUser;
  PetscCheck(hy->is_saved[slot], PETSC_COMM_SELF, PETSC_ERR_ORDER, "Restoring the hysteresis sliders of slot %" PetscInt_FMT " before saving them (ClothSaveState)", slot);
  for (PetscInt a = 0; a < hy->n; a++) {
    hy->elements[a].cos0 = hy->saved[slot][2 * a];
    hy->elements[a].sin0 = hy->saved[slot][2 * a + 1];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisDestroy(void *ctx)
{
  ClothHysteresis *hy = (ClothHysteresis *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(hy->elements, hy->state_index));
  PetscCall(PetscFree(hy->saved[0]));
  PetscCall(PetscFree(hy->saved[1]));
  PetscCall(PetscFree(hy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Keeps the model's friction elements this rank evaluates (ClothLocalizeInteraction), in local numbering, with
   their places in the checkpoint fields: counted first, so that the arrays hold this rank's share. */
static PetscErrorCode HysteresisDistribute(Cloth cloth, ClothHysteresis *hy)
{
  const ClothModel m = hy->model;
  PetscInt         local[CLOTH_ANGLE_MAX_PARTICLES], n = 0;
  PetscBool        here;

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < m->nangles; a++) {
    if (m->angles[a].slip <= 0) continue;
    PetscCall(ClothLocalizeInteraction(cloth, ClothAngleParticleCount(m->angles[a].kind), m->angles[a].p, &here, local));
    n += here;
  }
  PetscCall(PetscMalloc2(n, &hy->elements, n, &hy->state_index));
  for (PetscInt a = 0; a < m->nangles; a++) {
    if (m->angles[a].slip <= 0) continue;
    PetscCall(ClothLocalizeInteraction(cloth, ClothAngleParticleCount(m->angles[a].kind), m->angles[a].p, &here, local));
    if (!here) continue;
    hy->elements[hy->n] = m->angles[a];
    for (PetscInt k = 0; k < ClothAngleParticleCount(m->angles[a].kind); k++) hy->elements[hy->n].p[k] = local[k];
    hy->state_index[hy->n++] = SliderIndex(&m->angles[a]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisCreateStateVec(ClothHysteresis *hy, ClothSliderFamily family, Vec *state)
{
  const PetscInt bs = SliderBlockSize(family);

  PetscFunctionBeginUser;
  *state = NULL;
  if (SliderCount(hy->model, family) == 0) PetscFunctionReturn(PETSC_SUCCESS); /* the same on every rank */
  PetscCall(VecCreate(hy->comm, state));
  PetscCall(VecSetBlockSize(*state, bs));
  PetscCall(VecSetSizes(*state, PETSC_DECIDE, bs * hy->nglobal));
  PetscCall(VecSetFromOptions(*state));
  PetscCall(PetscObjectSetName((PetscObject)*state, family == CLOTH_SLIDERS_BEND ? "bend_slider" : "shear_slider"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisGetState(ClothHysteresis *hy, ClothSliderFamily family, Vec state)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(state));
  for (PetscInt a = 0; a < hy->n; a++) {
    const ClothAngle *angle  = &hy->elements[a];
    const PetscInt    idx[2] = {hy->state_index[a], hy->state_index[a] + 1};
    const PetscScalar val[2] = {angle->cos0, angle->sin0};

    if (SliderFamily(angle) != family) continue;
    PetscCall(VecSetValues(state, 2, idx, val, INSERT_VALUES)); /* each entry has one writer: the element's owner */
  }
  PetscCall(VecAssemblyBegin(state));
  PetscCall(VecAssemblyEnd(state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisSetState(ClothHysteresis *hy, ClothSliderFamily family, Vec state)
{
  VecScatter         to_all;
  Vec                all;
  const PetscScalar *s;
  const char        *name;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetName((PetscObject)state, &name));
  PetscCall(VecScatterCreateToAll(state, &to_all, &all));
  PetscCall(VecScatterBegin(to_all, state, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_all, state, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(all, &s));
  for (PetscInt a = 0; a < hy->n; a++) {
    ClothAngle     *angle = &hy->elements[a];
    const PetscInt  row   = hy->state_index[a];
    const PetscReal c = PetscRealPart(s[row]), sn = PetscRealPart(s[row + 1]);

    if (SliderFamily(angle) != family) continue;
    PetscCheck(PetscAbsReal(c * c + sn * sn - 1) < 1e-12, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint %s: particle %" PetscInt_FMT " has no slider angle (cos %g, sin %g)", name, row / SliderBlockSize(family), (double)c, (double)sn);
    angle->cos0 = c;
    angle->sin0 = sn;
  }
  PetscCall(VecRestoreArrayRead(all, &s));
  PetscCall(VecScatterDestroy(&to_all));
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The checkpoint fields bend_slider and shear_slider: one per family of sliders the fabric has. */
static PetscErrorCode HysteresisCheckpointFields(void *ctx, PetscBool write, ClothCheckpointField fields[], PetscInt *nfields)
{
  ClothHysteresis *hy = (ClothHysteresis *)ctx;

  PetscFunctionBeginUser;
  *nfields = 0;
  for (PetscInt f = 0; f < CLOTH_SLIDER_FAMILIES; f++) {
    Vec         state;
    const char *name;

    PetscCall(HysteresisCreateStateVec(hy, (ClothSliderFamily)f, &state));
    if (!state) continue;
    if (write) PetscCall(HysteresisGetState(hy, (ClothSliderFamily)f, state));
    PetscCall(PetscObjectGetName((PetscObject)state, &name));
    fields[(*nfields)++] = (ClothCheckpointField){name, state, PETSC_TRUE, PETSC_FALSE};
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode HysteresisCheckpointLoad(void *ctx, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  ClothHysteresis *hy = (ClothHysteresis *)ctx;

  PetscFunctionBeginUser;
  for (PetscInt f = 0; f < CLOTH_SLIDER_FAMILIES; f++) {
    const ClothCheckpointField *field;

    PetscCall(ClothCheckpointFieldFind(nfields, fields, f == CLOTH_SLIDERS_BEND ? "bend_slider" : "shear_slider", &field));
    if (field && field->found) PetscCall(HysteresisSetState(hy, (ClothSliderFamily)f, field->vec));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisRegister(Cloth cloth)
{
  ClothHysteresis *hy;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&hy));
  PetscCall(ClothGetModel(cloth, &hy->model));
  PetscCall(ClothGetComm(cloth, &hy->comm));
  PetscCall(ClothGetSizes(cloth, NULL, &hy->nglobal));
  PetscCall(HysteresisDistribute(cloth, hy));
  {
    const ClothContribution contribution = {.name              = CLOTH_HYSTERESIS_NAME,
                                            .ctx               = hy,
                                            .add_elements      = HysteresisAddElements,
                                            .begin_step        = HysteresisBeginStep,
                                            .save              = HysteresisSave,
                                            .restore           = HysteresisRestore,
                                            .checkpoint_fields = HysteresisCheckpointFields,
                                            .checkpoint_load   = HysteresisCheckpointLoad,
                                            .destroy           = HysteresisDestroy};

    PetscCall(ClothAddContribution(cloth, &contribution));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
