/* Cloth: per-particle strain for visualisation (see cloth.h).

   The strain of a particle is the largest relative elongation (l - l0) / l0 of its stretch links
   (the links to its grid neighbours along warp and weft): what ParaView colours to show where the
   fabric is pulled. Each link is evaluated on the rank that evaluates its forces; a particle owned
   elsewhere gets the value through a MAX reduction of the ghosts. */
#include "cloth_impl.h"

/* Is the link between natural particles a and b a stretch link, i.e. do they sit at (i, j) and
   (i +- 1, j) or (i, j +- 1) of one piece? Bending links skip a node, shear links are diagonal and
   links between two pieces are seams, so none of those is a stretch link. */
static PetscErrorCode ClothIsStretchLink(Cloth cloth, PetscInt a, PetscInt b, PetscBool *stretch)
{
  const ClothModel m     = cloth->model;
  PetscInt         piece = 0, nu, la, lb, di, dj;

  PetscFunctionBeginUser;
  while (piece + 1 < m->npieces && a >= m->piece_offset[piece + 1]) piece++;
  *stretch = PETSC_FALSE;
  if (b < m->piece_offset[piece] || b >= m->piece_offset[piece + 1]) PetscFunctionReturn(PETSC_SUCCESS);
  nu       = cloth->scene->pieces[piece].nu;
  la       = a - m->piece_offset[piece];
  lb       = b - m->piece_offset[piece];
  di       = PetscAbsInt(la % nu - lb % nu);
  dj       = PetscAbsInt(la / nu - lb / nu);
  *stretch = (PetscBool)(di + dj == 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Per local particle (owned and ghosts), 3 entries each: the largest strain of this rank's stretch
   links at it, in all three entries; -PETSC_MAX_REAL where this rank has none. */
static PetscErrorCode ClothStrainLocal(Cloth cloth, const PetscScalar x[], PetscScalar s[])
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < 3 * (cloth->nlocal + cloth->nghost); i++) s[i] = -PETSC_MAX_REAL;
  for (PetscInt l = 0; l < cloth->nlinks; l++) {
    const ClothLink *link = &cloth->links[l];
    const PetscInt   a = link->p[0], b = link->p[1];
    PetscBool        stretch;
    PetscReal        d2 = 0, strain;

    PetscCall(ClothIsStretchLink(cloth, cloth->natural_of_local[a], cloth->natural_of_local[b], &stretch));
    if (!stretch) continue;
    for (PetscInt c = 0; c < 3; c++) d2 += PetscSqr(PetscRealPart(x[3 * b + c] - x[3 * a + c]));
    strain = (PetscSqrtReal(d2) - link->rest) / link->rest;
    for (PetscInt c = 0; c < 3; c++) {
      s[3 * a + c] = PetscMax(PetscRealPart(s[3 * a + c]), strain);
      s[3 * b + c] = PetscMax(PetscRealPart(s[3 * b + c]), strain);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateStrainVec(Cloth cloth, Vec *strain)
{
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCheck(cloth->setup, cloth->comm, PETSC_ERR_ORDER, "Call ClothSetUp before ClothCreateStrainVec");
  PetscCall(VecGetLocalSize(cloth->natural, &n));
  PetscCall(VecCreateMPI(cloth->comm, n / 3, cloth->nglobal, strain));
  PetscCall(PetscObjectSetName((PetscObject)*strain, "strain"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeStrain(Cloth cloth, Vec position, Vec strain)
{
  Vec                work, work_local;
  const PetscScalar *x;
  PetscScalar       *s;
  Vec                position_local;

  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(ClothCreateStateVec(cloth, &work));
  PetscCall(VecGhostGetLocalForm(position, &position_local));
  PetscCall(VecGhostGetLocalForm(work, &work_local));
  PetscCall(VecGetArrayRead(position_local, &x));
  PetscCall(VecGetArrayWrite(work_local, &s));
  PetscCall(ClothStrainLocal(cloth, x, s));
  PetscCall(VecRestoreArrayWrite(work_local, &s));
  PetscCall(VecRestoreArrayRead(position_local, &x));
  PetscCall(VecGhostRestoreLocalForm(work, &work_local));
  PetscCall(VecGhostRestoreLocalForm(position, &position_local));
  PetscCall(VecGhostUpdateBegin(work, MAX_VALUES, SCATTER_REVERSE));
  PetscCall(VecGhostUpdateEnd(work, MAX_VALUES, SCATTER_REVERSE));
  /* a particle without stretch links (a piece of one node) is unstrained */
  PetscCall(VecGetArray(work, &s));
  for (PetscInt i = 0; i < 3 * cloth->nlocal; i++)
    if (PetscRealPart(s[i]) == -PETSC_MAX_REAL) s[i] = 0;
  PetscCall(VecRestoreArray(work, &s));
  PetscCall(ClothScatterParticleValuesToNatural(cloth, work, strain));
  PetscCall(VecDestroy(&work));
  PetscFunctionReturn(PETSC_SUCCESS);
}
