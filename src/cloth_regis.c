/* The cloth's registry of contributions (cloth.h, docs/architecture.md "Adding a force"): the table of the model's
   own contributions, registering, finding and removing one, and their checkpoint fields. */
#include "cloth_impl.h"
#include "hysteresis.h"
#include "seam_links.h"

/* The model's forces that plug in as contributions: each registers itself at set-up, also when the model has none of
   its elements (then it adds nothing). Hysteresis first: its friction elements were summed with the angle springs,
   before the seam links. */
static PetscErrorCode (*const ClothModelContributions[])(Cloth) = {ClothHysteresisRegister, ClothSeamLinksRegister};

PetscErrorCode ClothRegisterModelContributions_Private(Cloth cloth)
{
  PetscFunctionBeginUser;
  for (size_t c = 0; c < PETSC_STATIC_ARRAY_LENGTH(ClothModelContributions); c++) PetscCall(ClothModelContributions[c](cloth));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothAddContribution(Cloth cloth, const ClothContribution *contribution)
{
  const PetscBool forces = contribution->add || contribution->add_to_implicit_step || contribution->add_elements ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCheck(forces || contribution->checkpoint_fields, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Contribution '%s' adds nothing (no add, add_elements, add_to_implicit_step or checkpoint_fields)", contribution->name);
  PetscCheck(!contribution->checkpoint_fields == !contribution->checkpoint_load, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "Contribution '%s': give both checkpoint_fields and checkpoint_load, or neither", contribution->name);
  PetscCheck(cloth->ncontributions < CLOTH_MAX_CONTRIBUTIONS, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Contribution '%s': the cloth takes at most %d", contribution->name, CLOTH_MAX_CONTRIBUTIONS);
  cloth->contributions[cloth->ncontributions++] = *contribution;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRemoveContribution(Cloth cloth, void *ctx)
{
  PetscInt kept = 0;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < cloth->ncontributions; c++) {
    if (cloth->contributions[c].ctx != ctx)
      cloth->contributions[kept++] = cloth->contributions[c];
    else if (cloth->contributions[c].destroy)
      PetscCall(cloth->contributions[c].destroy(ctx));
  }
  cloth->ncontributions = kept;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetContribution(Cloth cloth, const char *name, void **ctx)
{
  PetscBool same;

  PetscFunctionBeginUser;
  *ctx = NULL;
  for (PetscInt c = 0; c < cloth->ncontributions && !*ctx; c++) {
    PetscCall(PetscStrcmp(cloth->contributions[c].name, name, &same));
    if (same) *ctx = cloth->contributions[c].ctx;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetCheckpointFields(Cloth cloth, PetscBool write, PetscInt max, ClothCheckpointField fields[], PetscInt *nfields)
{
  PetscFunctionBeginUser;
  *nfields = 0;
  for (PetscInt c = 0; c < cloth->ncontributions; c++) {
    const ClothContribution *contribution = &cloth->contributions[c];
    PetscInt                 n            = 0;

    if (!contribution->checkpoint_fields) continue;
    PetscCheck(*nfields + CLOTH_CONTRIBUTION_MAX_FIELDS <= max, cloth->comm, PETSC_ERR_ARG_SIZ, "Contribution '%s': no room for its checkpoint fields (%" PetscInt_FMT " taken of %" PetscInt_FMT ")", contribution->name, *nfields, max);
    PetscCall(contribution->checkpoint_fields(contribution->ctx, write, &fields[*nfields], &n));
    PetscCheck(n >= 0 && n <= CLOTH_CONTRIBUTION_MAX_FIELDS, cloth->comm, PETSC_ERR_PLIB, "Contribution '%s' declared %" PetscInt_FMT " checkpoint fields: expected at most %d", contribution->name, n, CLOTH_CONTRIBUTION_MAX_FIELDS);
    *nfields += n;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothLoadCheckpointFields(Cloth cloth, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < cloth->ncontributions; c++)
    if (cloth->contributions[c].checkpoint_load) PetscCall(cloth->contributions[c].checkpoint_load(cloth->contributions[c].ctx, info, nfields, fields));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRestoreCheckpointFields(Cloth cloth, PetscInt nfields, ClothCheckpointField fields[])
{
  PetscFunctionBeginUser;
  for (PetscInt f = 0; f < nfields; f++) PetscCall(VecDestroy(&fields[f].vec));
  PetscFunctionReturn(PETSC_SUCCESS);
}
