/* Seam links as a contribution of the cloth (see seam_links.h). */
#include "seam_links.h"

#define CLOTH_SEAM_LINKS_NAME "seam links"

typedef struct {
  PetscInt       n;
  ClothSeamLink *links;       /* local particle numbering; stiffness set by the sewing phases */
  PetscInt      *model_index; /* index of each into the model's seam links */
} ClothSeamLinks;

/* Their Hessians are positive semidefinite as they are, whatever the stiffness form. */
static PetscErrorCode SeamLinksAddElements(void *ctx, ClothElementSink sink)
{
  const ClothSeamLinks *sl = (const ClothSeamLinks *)ctx;
  const PetscScalar    *x;
  PetscBool             want_h;
  ClothElement          e;

  PetscFunctionBeginUser;
  PetscCall(ClothElementSinkGetInput(sink, &x, &want_h, NULL));
  for (PetscInt s = 0; s < sl->n; s++) {
    const ClothSeamLink *link = &sl->links[s];
    const PetscReal     *xs[CLOTH_SEAM_LINK_MAX_PARTICLES];

    e.np       = link->np;
    e.factored = PETSC_FALSE;
    for (PetscInt k = 0; k < link->np; k++) {
      e.p[k] = link->p[k];
      xs[k]  = &x[3 * link->p[k]];
    }
    PetscCall(ClothSeamLinkEvaluate(link, xs, &e.energy, e.force, want_h ? e.H : NULL));
    PetscCall(ClothElementSinkAdd(sink, &e));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamLinksDestroy(void *ctx)
{
  ClothSeamLinks *sl = (ClothSeamLinks *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(sl->links, sl->model_index));
  PetscCall(PetscFree(sl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Keeps the model's seam links this rank evaluates (ClothLocalizeInteraction), in local numbering: counted first,
   so that the arrays hold this rank's share. */
static PetscErrorCode SeamLinksDistribute(Cloth cloth, ClothSeamLinks *sl)
{
  PetscInt   local[CLOTH_SEAM_LINK_MAX_PARTICLES], n = 0;
  PetscBool  here;
  ClothModel m;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(cloth, &m));
  for (PetscInt s = 0; s < m->nseamlinks; s++) {
    PetscCall(ClothLocalizeInteraction(cloth, m->seamlinks[s].np, m->seamlinks[s].p, &here, local));
    n += here;
  }
  PetscCall(PetscMalloc2(n, &sl->links, n, &sl->model_index));
  for (PetscInt s = 0; s < m->nseamlinks; s++) {
    PetscCall(ClothLocalizeInteraction(cloth, m->seamlinks[s].np, m->seamlinks[s].p, &here, local));
    if (!here) continue;
    sl->links[sl->n] = m->seamlinks[s];
    for (PetscInt k = 0; k < m->seamlinks[s].np; k++) sl->links[sl->n].p[k] = local[k];
    sl->model_index[sl->n++] = s;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamLinksRegister(Cloth cloth)
{
  ClothSeamLinks *sl;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&sl));
  PetscCall(SeamLinksDistribute(cloth, sl));
  {
    const ClothContribution contribution = {.name = CLOTH_SEAM_LINKS_NAME, .ctx = sl, .add_elements = SeamLinksAddElements, .destroy = SeamLinksDestroy};

    PetscCall(ClothAddContribution(cloth, &contribution));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSeamLinksGetLocal(Cloth cloth, PetscInt *n, ClothSeamLink **links, const PetscInt **model_index)
{
  ClothSeamLinks *sl;

  PetscFunctionBeginUser;
  PetscCall(ClothGetContribution(cloth, CLOTH_SEAM_LINKS_NAME, (void **)&sl));
  PetscCheck(sl, PETSC_COMM_SELF, PETSC_ERR_ORDER, "The cloth has no seam links' contribution: call ClothSetUp first");
  *n     = sl->n;
  *links = sl->links;
  if (model_index) *model_index = sl->model_index;
  PetscFunctionReturn(PETSC_SUCCESS);
}
