/* The held body contacts in checkpoints (see collision.h): the hooks of the collision's ClothContribution. A held
   particle's constraint (its normal, or twice it when stuck) is the next step's filter S, so a restart without it
   would not continue bit for bit (the 17 x 17 sphere drape ended 1.3e-3 m off after 80 steps, docs/checkpoint.md). */
#include "collision.h"

PetscErrorCode ClothCollisionCheckpointFields_Private(void *ctx, PetscBool write, ClothCheckpointField fields[], PetscInt *nfields)
{
  Cloth cloth;
  Vec   natural, normals;

  PetscFunctionBeginUser;
  PetscCall(ClothCollisionGetCloth((ClothCollision)ctx, &cloth));
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  if (write) {
    PetscCall(ClothGetContactNormals(cloth, &normals));
    PetscCall(ClothScatterToNatural(cloth, normals, natural, SCATTER_FORWARD));
  }
  fields[0] = (ClothCheckpointField){"contact_normal", natural, PETSC_FALSE, PETSC_FALSE};
  *nfields  = 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The field is optional: a checkpoint without it leaves the contact constraints as set-up left them. */
PetscErrorCode ClothCollisionCheckpointLoad_Private(void *ctx, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  const ClothCheckpointField *field;
  Cloth                       cloth;
  Vec                         normals;

  PetscFunctionBeginUser;
  PetscCall(ClothCheckpointFieldFind(nfields, fields, "contact_normal", &field));
  if (!field || !field->found) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothCollisionGetCloth((ClothCollision)ctx, &cloth));
  PetscCall(ClothGetContactNormals(cloth, &normals));
  PetscCall(ClothScatterToNatural(cloth, normals, field->vec, SCATTER_REVERSE));
  PetscCall(ClothCollisionRestoreHeldContacts((ClothCollision)ctx));
  PetscFunctionReturn(PETSC_SUCCESS);
}
