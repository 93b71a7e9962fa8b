/* Cloth: the state of bending and shear hysteresis (see cloth.h, forces.h).

   Each friction element sits beside an elastic spring, of one thread-bending chain (p0, p1, p2) or of one
   cell's shear angle (corners p0..p3), and carries the slider's position as its rest angle (cos0, sin0).
   The sliders move once per (sub-)step, at its start; a checkpoint stores them per particle in natural
   order: for bending, four values per middle particle p1, cos0 and sin0 of the chain along the warp, then
   of the chain along the weft; for shear, two values per cell at its first corner p0 = (i, j), which is
   the first corner of no other cell. Exact copies, so that a restarted run is bit-identical to an
   uninterrupted one. */
#include "cloth_impl.h"

static ClothSliderFamily SliderFamily(const ClothAngle *angle)
{
  return angle->kind == CLOTH_ANGLE_CELL ? CLOTH_SLIDERS_SHEAR : CLOTH_SLIDERS_BEND;
}

static PetscInt SliderBlockSize(ClothSliderFamily family)
{
  return family == CLOTH_SLIDERS_BEND ? 4 : 2;
}

static PetscInt SliderCount(Cloth cloth, ClothSliderFamily family)
{
  return family == CLOTH_SLIDERS_BEND ? cloth->model->nfriction - cloth->model->nfriction_shear : cloth->model->nfriction_shear;
}

/* Where a friction element's cos0 (then sin0) goes in its family's state Vec. Bending: its middle particle's
   row, slot 0 for the chain along the warp (i), 1 along the weft (j); in a piece's natural numbering j nu + i
   the warp neighbours of a particle are 1 apart, the weft neighbours nu >= 2. Shear: the row of the cell's
   first corner. */
static PetscInt SliderIndex(Cloth cloth, const ClothAngle *angle)
{
  PetscInt middle, slot;

  if (SliderFamily(angle) == CLOTH_SLIDERS_SHEAR) return 2 * cloth->natural_of_local[angle->p[0]];
  middle = cloth->natural_of_local[angle->p[1]];
  slot   = middle - cloth->natural_of_local[angle->p[0]] == 1 ? 0 : 1;
  return 4 * middle + 2 * slot;
}

PetscErrorCode ClothUpdateHysteresis(Cloth cloth, Vec position)
{
  Vec                xl;
  const PetscScalar *x;

  PetscFunctionBeginUser;
  if (cloth->model->nfriction == 0) PetscFunctionReturn(PETSC_SUCCESS); /* the same on every rank */
  PetscCall(VecGhostUpdateBegin(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(position, &xl));
  PetscCall(VecGetArrayRead(xl, &x));
  for (PetscInt a = 0; a < cloth->nangles; a++) {
    ClothAngle      *angle = &cloth->angles[a];
    const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES];

    if (angle->slip <= 0) continue;
    for (PetscInt k = 0; k < ClothAngleParticleCount(angle->kind); k++) xs[k] = &x[3 * angle->p[k]];
    ClothAngleSlide(angle, xs);
  }
  PetscCall(VecRestoreArrayRead(xl, &x));
  PetscCall(VecGhostRestoreLocalForm(position, &xl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisCreateStateVec(Cloth cloth, ClothSliderFamily family, Vec *state)
{
  const PetscInt bs = SliderBlockSize(family);

  PetscFunctionBeginUser;
  *state = NULL;
  if (SliderCount(cloth, family) == 0) PetscFunctionReturn(PETSC_SUCCESS); /* the same on every rank */
  PetscCall(VecCreate(cloth->comm, state));
  PetscCall(VecSetBlockSize(*state, bs));
  PetscCall(VecSetSizes(*state, PETSC_DECIDE, bs * cloth->nglobal));
  PetscCall(VecSetFromOptions(*state));
  PetscCall(PetscObjectSetName((PetscObject)*state, family == CLOTH_SLIDERS_BEND ? "bend_slider" : "shear_slider"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisGetState(Cloth cloth, ClothSliderFamily family, Vec state)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(state));
  for (PetscInt a = 0; a < cloth->nangles; a++) {
    const ClothAngle *angle = &cloth->angles[a];
    PetscInt          idx[2];
    PetscScalar       val[2];

    if (angle->slip <= 0 || SliderFamily(angle) != family) continue;
    idx[0] = SliderIndex(cloth, angle);
    idx[1] = idx[0] + 1;
    val[0] = angle->cos0;
    val[1] = angle->sin0;
    PetscCall(VecSetValues(state, 2, idx, val, INSERT_VALUES)); /* each entry has one writer: the element's owner */
  }
  PetscCall(VecAssemblyBegin(state));
  PetscCall(VecAssemblyEnd(state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisSetState(Cloth cloth, ClothSliderFamily family, Vec state)
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
  for (PetscInt a = 0; a < cloth->nangles; a++) {
    ClothAngle *angle = &cloth->angles[a];
    PetscInt    row;
    PetscReal   c, sn;

    if (angle->slip <= 0 || SliderFamily(angle) != family) continue;
    row = SliderIndex(cloth, angle);
    c   = PetscRealPart(s[row]);
    sn  = PetscRealPart(s[row + 1]);
    PetscCheck(PetscAbsReal(c * c + sn * sn - 1) < 1e-12, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "Checkpoint %s: particle %" PetscInt_FMT " has no slider angle (cos %g, sin %g)", name, SliderIndex(cloth, angle) / SliderBlockSize(family),
               (double)c, (double)sn);
    angle->cos0 = c;
    angle->sin0 = sn;
  }
  PetscCall(VecRestoreArrayRead(all, &s));
  PetscCall(VecScatterDestroy(&to_all));
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisSave(Cloth cloth, PetscInt slot)
{
  PetscFunctionBeginUser;
  PetscCheck(slot == 0 || slot == 1, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Slider save slot %" PetscInt_FMT ": expected 0 or 1", slot);
  if (cloth->model->nfriction == 0) PetscFunctionReturn(PETSC_SUCCESS);
  if (!cloth->slider_saved[slot]) PetscCall(PetscMalloc1(2 * cloth->nangles, &cloth->slider_saved[slot]));
  for (PetscInt a = 0; a < cloth->nangles; a++) {
    cloth->slider_saved[slot][2 * a]     = cloth->angles[a].cos0;
    cloth->slider_saved[slot][2 * a + 1] = cloth->angles[a].sin0;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothHysteresisRestore(Cloth cloth, PetscInt slot)
{
  PetscFunctionBeginUser;
  if (cloth->model->nfriction == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(cloth->slider_saved[slot], PETSC_COMM_SELF, PETSC_ERR_ORDER, "ClothHysteresisRestore of slot %" PetscInt_FMT " before ClothHysteresisSave", slot);
  for (PetscInt a = 0; a < cloth->nangles; a++) { /* elastic springs never move: restoring them is a no-op */
    cloth->angles[a].cos0 = cloth->slider_saved[slot][2 * a];
    cloth->angles[a].sin0 = cloth->slider_saved[slot][2 * a + 1];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
