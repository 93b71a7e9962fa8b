/* ClothSewing (see sewing.h). */
#include "sewing.h"
#include "seam.h"
#include "seam_links.h"
#include "options.h"

#define SEAM_BAND 2         /* grid rows around a seam where cloth-cloth contact is not applied while it is pulled closed */
#define SEWING_MAX_SEAMS 64 /* seams of a scene: each is one bit of the uint64_t masks near and near_joined */

const char *const ClothSewingPhases[] = {"pull", "settle", "ClothSewingPhase", "CLOTH_SEWING_", NULL};

struct _n_ClothSewing {
  Cloth            cloth;
  MPI_Comm         comm;  /* the cloth's */
  Scene            scene; /* seam names */
  SceneSewing      params;
  ClothSewingPhase phase;
  PetscInt         nlinks;         /* seam links of the whole model */
  PetscInt        *sewn;           /* per model seam link: 1 once sewn; the same on every rank */
  PetscInt        *closed;         /* work: links this rank found closed in the last step */
  uint64_t        *near;           /* per particle (natural): bit s set within SEAM_BAND rows of seam s */
  uint64_t        *near_joined;    /* per particle: near, plus every seam sharing a particle with one of those */
  PetscInt        *partner_offset; /* CSR per particle (natural): the particles a seam link joins it to */
  PetscInt        *partner;
  PetscReal        max_time;
};

/* Marks the particles within SEAM_BAND grid rows (of their own piece) of every particle of every seam link. */
static PetscErrorCode ClothSewingMarkSeamBands(ClothSewing s, Scene scene, ClothModel model)
{
  PetscFunctionBeginUser;
  PetscCheck(scene->nseams <= SEWING_MAX_SEAMS, s->comm, PETSC_ERR_SUP, "At most %d seams are supported, the scene has %" PetscInt_FMT, SEWING_MAX_SEAMS, scene->nseams);
  PetscCall(PetscCalloc1(model->nparticles, &s->near));
  for (PetscInt l = 0; l < model->nseamlinks; l++)
    for (PetscInt k = 0; k < model->seamlinks[l].np; k++) {
      const PetscInt g     = model->seamlinks[l].p[k];
      PetscInt       piece = 0;
      while (model->piece_offset[piece + 1] <= g) piece++;
      {
        const PetscInt nu = scene->pieces[piece].nu, nv = scene->pieces[piece].nv, off = model->piece_offset[piece];
        const PetscInt i = (g - off) % nu, j = (g - off) / nu;
        for (PetscInt dj = -SEAM_BAND; dj <= SEAM_BAND; dj++)
          for (PetscInt di = -SEAM_BAND; di <= SEAM_BAND; di++)
            if (i + di >= 0 && i + di < nu && j + dj >= 0 && j + dj < nv) s->near[off + (j + dj) * nu + i + di] |= (uint64_t)1 << model->seamlinks[l].seam;
      }
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* near_joined: where seams meet (a waist corner joins two side seams and the waist seam), the four corners
   must come together although no one seam holds two diagonal ones, so while pulling a particle near seam s
   does not repel one near a seam that shares a particle with s. */
static PetscErrorCode ClothSewingMarkJoinedBands(ClothSewing s, ClothModel model)
{
  uint64_t *seams_of, joined[SEWING_MAX_SEAMS];

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(model->nparticles, &seams_of));
  for (PetscInt l = 0; l < model->nseamlinks; l++)
    for (PetscInt k = 0; k < model->seamlinks[l].np; k++) seams_of[model->seamlinks[l].p[k]] |= (uint64_t)1 << model->seamlinks[l].seam;
  for (PetscInt b = 0; b < SEWING_MAX_SEAMS; b++) joined[b] = (uint64_t)1 << b;
  for (PetscInt g = 0; g < model->nparticles; g++)
    for (PetscInt b = 0; b < SEWING_MAX_SEAMS; b++)
      if (seams_of[g] >> b & 1) joined[b] |= seams_of[g];
  PetscCall(PetscCalloc1(model->nparticles, &s->near_joined));
  for (PetscInt g = 0; g < model->nparticles; g++)
    for (PetscInt b = 0; b < SEWING_MAX_SEAMS; b++)
      if (s->near[g] >> b & 1) s->near_joined[g] |= joined[b];
  PetscCall(PetscFree(seams_of));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The partners of every particle: the particles of the other side of each seam link it belongs to (the
   node and the one or two nodes of the point it is sewn to), in CSR form. */
static PetscErrorCode ClothSewingBuildPartners(ClothSewing s, ClothModel model)
{
  PetscInt *count;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(model->nparticles + 1, &s->partner_offset));
  PetscCall(PetscCalloc1(model->nparticles, &count));
  for (PetscInt l = 0; l < model->nseamlinks; l++) {
    const ClothSeamLink *link = &model->seamlinks[l];
    s->partner_offset[link->p[0] + 1] += link->np - 1;
    for (PetscInt k = 1; k < link->np; k++) s->partner_offset[link->p[k] + 1]++;
  }
  for (PetscInt g = 0; g < model->nparticles; g++) s->partner_offset[g + 1] += s->partner_offset[g];
  PetscCall(PetscMalloc1(s->partner_offset[model->nparticles] + 1, &s->partner));
  for (PetscInt l = 0; l < model->nseamlinks; l++) {
    const ClothSeamLink *link = &model->seamlinks[l];
    const PetscInt       a    = link->p[0];
    for (PetscInt k = 1; k < link->np; k++) {
      const PetscInt b                              = link->p[k];
      s->partner[s->partner_offset[a] + count[a]++] = b;
      s->partner[s->partner_offset[b] + count[b]++] = a;
    }
  }
  PetscCall(PetscFree(count));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscBool ClothSewingArePartners(ClothSewing s, PetscInt a, PetscInt b)
{
  for (PetscInt k = s->partner_offset[a]; k < s->partner_offset[a + 1]; k++)
    if (s->partner[k] == b) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscErrorCode ClothSewingExcludeContact(void *ctx, PetscInt a, PetscInt b, PetscBool *excluded)
{
  ClothSewing s = (ClothSewing)ctx;

  PetscFunctionBeginUser;
  if (s->phase == CLOTH_SEWING_PULL) {
    *excluded = (s->near[a] & s->near_joined[b]) ? PETSC_TRUE : PETSC_FALSE;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  *excluded = ClothSewingArePartners(s, a, b);
  for (PetscInt k = s->partner_offset[a]; !*excluded && k < s->partner_offset[a + 1]; k++) *excluded = ClothSewingArePartners(s, s->partner[k], b);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The sewn seams as the checkpoint field seams_sewn (ClothSewingGetStateVec): the sewing's ClothContribution, which
   adds no force (the seam links' stiffness is set on seam_links.c's contribution) but owns this state. */
static PetscErrorCode SewingCheckpointFields(void *ctx, PetscBool write, ClothCheckpointField fields[], PetscInt *nfields)
{
  ClothSewing sewing = (ClothSewing)ctx;
  Vec         sewn;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateStrainVec(sewing->cloth, &sewn)); /* one value per particle, natural order */
  if (write) PetscCall(ClothSewingGetStateVec(sewing, sewn));
  fields[0] = (ClothCheckpointField){"seams_sewn", sewn, PETSC_TRUE, PETSC_FALSE};
  *nfields  = 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The phase follows from the sewn seams and the checkpoint's time. */
static PetscErrorCode SewingCheckpointLoad(void *ctx, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[])
{
  const ClothCheckpointField *field;

  PetscFunctionBeginUser;
  PetscCall(ClothCheckpointFieldFind(nfields, fields, "seams_sewn", &field));
  if (field && field->found) PetscCall(ClothSewingSetStateVec((ClothSewing)ctx, field->vec, info->time));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingCreate(Cloth cloth, Scene scene, ClothSewing *sewing)
{
  ClothSewing s;
  ClothModel  model;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&s));
  PetscCall(ClothGetModel(cloth, &model));
  s->cloth = cloth;
  PetscCall(ClothGetComm(cloth, &s->comm));
  s->scene    = scene;
  s->params   = scene->sewing;
  s->phase    = CLOTH_SEWING_PULL;
  s->nlinks   = model->nseamlinks;
  s->max_time = scene->sewing.max_time;
  PetscCall(PetscCalloc2(s->nlinks, &s->sewn, s->nlinks, &s->closed));
  PetscCall(ClothSewingMarkSeamBands(s, scene, model));
  PetscCall(ClothSewingMarkJoinedBands(s, model));
  PetscCall(ClothSewingBuildPartners(s, model));
  {
    const ClothContribution state = {.name = "sewing", .ctx = s, .checkpoint_fields = SewingCheckpointFields, .checkpoint_load = SewingCheckpointLoad};

    PetscCall(ClothAddContribution(cloth, &state)); /* removed by ClothSewingDestroy */
  }
  *sewing = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingSetFromOptions(ClothSewing sewing)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(sewing->comm, NULL, "Sewing (garment assembly)", "ClothSewing");
  PetscCall(PetscOptionsReal("-sewing_max_time", "Seconds of pulling after which gravity comes on even if pairs are still open", "ClothSewingUpdate", sewing->max_time, &sewing->max_time, NULL));
  PetscOptionsEnd();
  PetscCall(ClothOptionsCheckReal(sewing->comm, "-sewing_max_time", sewing->max_time, 0, PETSC_FALSE, PETSC_MAX_REAL, "s"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Seam stiffnesses and gravity for the current phase and sewn set. */
static PetscErrorCode ClothSewingApply(ClothSewing sewing)
{
  ClothModel      model;
  ClothSeamLink  *links;
  const PetscInt *model_index;
  PetscInt        n;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(sewing->cloth, &model));
  PetscCall(ClothSeamLinksGetLocal(sewing->cloth, &n, &links, &model_index));
  for (PetscInt l = 0; l < n; l++) {
    const ClothSeamLink *global = &model->seamlinks[model_index[l]];
    PetscReal            mass   = 0;
    for (PetscInt k = 0; k < global->np; k++) mass += 0.5 * PetscAbsReal(global->c[k]) * model->mass[global->p[k]];
    if (sewing->sewn[model_index[l]]) {
      links[l].pull_force = 0;
      links[l].k          = sewing->params.sewn_stiffness;
    } else {
      links[l].pull_force = sewing->params.pull_acceleration * mass;
      links[l].k          = links[l].pull_force / sewing->params.pull_radius;
    }
  }
  PetscCall(ClothSetGravityScale(sewing->cloth, sewing->phase == CLOTH_SEWING_PULL ? 0.0 : 1.0));
  PetscCall(ClothSetFrictionScale(sewing->cloth, sewing->phase == CLOTH_SEWING_PULL ? sewing->params.pull_friction : 1.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingSetUp(ClothSewing sewing)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSewingApply(sewing));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gap of every local seam link at the current positions; the largest in *max_gap, and the links
   under the tolerance flagged in sewing->closed (model numbering). */
static PetscErrorCode ClothSewingMeasure(ClothSewing sewing, PetscReal *max_gap)
{
  ClothSeamLink     *links;
  const PetscInt    *model_index;
  const PetscScalar *x;
  PetscInt           n;

  PetscFunctionBeginUser;
  *max_gap = 0;
  PetscCall(PetscArrayzero(sewing->closed, sewing->nlinks));
  PetscCall(ClothSeamLinksGetLocal(sewing->cloth, &n, &links, &model_index));
  PetscCall(ClothGetLocalPositionArray(sewing->cloth, &x));
  for (PetscInt l = 0; l < n; l++) {
    const PetscReal *xs[CLOTH_SEAM_LINK_MAX_PARTICLES];
    PetscReal        gap;
    for (PetscInt k = 0; k < links[l].np; k++) xs[k] = &x[3 * links[l].p[k]];
    gap      = ClothSeamLinkGap(&links[l], xs);
    *max_gap = PetscMax(*max_gap, gap);
    if (gap <= sewing->params.tolerance) sewing->closed[model_index[l]] = 1;
  }
  PetscCall(ClothRestoreLocalPositionArray(sewing->cloth, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingUpdate(ClothSewing sewing, PetscReal time)
{
  PetscReal local_gap, max_gap;
  PetscInt  nsewn = 0;

  PetscFunctionBeginUser;
  if (sewing->nlinks == 0 || sewing->phase == CLOTH_SEWING_SETTLE) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothSewingMeasure(sewing, &local_gap));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sewing->closed, (PetscMPIInt)sewing->nlinks, MPIU_INT, MPI_MAX, sewing->comm));
  PetscCallMPI(MPI_Allreduce(&local_gap, &max_gap, 1, MPIU_REAL, MPIU_MAX, sewing->comm));
  for (PetscInt l = 0; l < sewing->nlinks; l++) {
    sewing->sewn[l] = PetscMax(sewing->sewn[l], sewing->closed[l]);
    nsewn += sewing->sewn[l];
  }
  if (nsewn == sewing->nlinks) {
    sewing->phase = CLOTH_SEWING_SETTLE;
    PetscCall(PetscPrintf(sewing->comm, "Sewing: all %" PetscInt_FMT " seam pairs sewn at t = %.4f s; gravity on\n", sewing->nlinks, (double)time));
  } else if (time >= sewing->max_time) {
    sewing->phase = CLOTH_SEWING_SETTLE;
    PetscCall(PetscPrintf(sewing->comm, "WARNING: sewing time %.3f s reached with %" PetscInt_FMT " of %" PetscInt_FMT " seam pairs open (widest gap %.4f m); gravity on, the open pairs keep pulling\n", (double)time, sewing->nlinks - nsewn,
                          sewing->nlinks, (double)max_gap));
  }
  PetscCall(ClothSewingApply(sewing));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingGetStatus(ClothSewing sewing, ClothSewingPhase *phase, PetscInt *sewn, PetscInt *total, PetscReal *max_gap)
{
  PetscReal local_gap;
  PetscInt  count = 0;

  PetscFunctionBeginUser;
  PetscCall(ClothSewingMeasure(sewing, &local_gap));
  if (max_gap) PetscCallMPI(MPI_Allreduce(&local_gap, max_gap, 1, MPIU_REAL, MPIU_MAX, sewing->comm));
  for (PetscInt l = 0; l < sewing->nlinks; l++) count += sewing->sewn[l];
  if (phase) *phase = sewing->phase;
  if (sewn) *sewn = count;
  if (total) *total = sewing->nlinks;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingViewWidest(ClothSewing sewing, PetscInt n)
{
  ClothModel         model;
  ClothSeamLink     *links;
  const PetscInt    *model_index;
  const PetscScalar *x;
  PetscReal         *gap;
  PetscInt           nlocal;

  PetscFunctionBeginUser;
  if (n <= 0 || sewing->nlinks == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothGetModel(sewing->cloth, &model));
  PetscCall(PetscCalloc1(sewing->nlinks, &gap));
  PetscCall(ClothSeamLinksGetLocal(sewing->cloth, &nlocal, &links, &model_index));
  PetscCall(ClothGetLocalPositionArray(sewing->cloth, &x));
  for (PetscInt l = 0; l < nlocal; l++) {
    const PetscReal *xs[CLOTH_SEAM_LINK_MAX_PARTICLES];
    for (PetscInt k = 0; k < links[l].np; k++) xs[k] = &x[3 * links[l].p[k]];
    gap[model_index[l]] = ClothSeamLinkGap(&links[l], xs);
  }
  PetscCall(ClothRestoreLocalPositionArray(sewing->cloth, &x));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, gap, (PetscMPIInt)sewing->nlinks, MPIU_REAL, MPIU_MAX, sewing->comm));
  PetscCall(PetscPrintf(sewing->comm, "Widest seam pairs (seam: node - the point it is sewn to, between nodes with weights):\n"));
  for (PetscInt r = 0; r < PetscMin(n, sewing->nlinks); r++) {
    const ClothSeamLink *link;
    PetscInt             widest = 0;
    char                 name[3][2 * CLOTH_NAME_LEN];

    for (PetscInt l = 1; l < sewing->nlinks; l++)
      if (gap[l] > gap[widest]) widest = l;
    link = &model->seamlinks[widest];
    for (PetscInt k = 0; k < link->np; k++) PetscCall(ClothGetParticleName(sewing->cloth, link->p[k], name[k], sizeof(name[k])));
    if (link->np == 2)
      PetscCall(PetscPrintf(sewing->comm, "  %6.2f mm  %s: %s - %s\n", (double)(1e3 * gap[widest]), sewing->scene->seams[link->seam].name, name[0], name[1]));
    else
      PetscCall(PetscPrintf(sewing->comm, "  %6.2f mm  %s: %s - %.2f %s + %.2f %s\n", (double)(1e3 * gap[widest]), sewing->scene->seams[link->seam].name, name[0], (double)-link->c[1], name[1], (double)-link->c[2], name[2]));
    gap[widest] = -1;
  }
  PetscCall(PetscFree(gap));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingGetStateVec(ClothSewing sewing, Vec sewn)
{
  ClothModel   model;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(sewing->cloth, &model));
  PetscCheck(model->nseamlinks == 0 || sewing->nlinks == model->nseamlinks, sewing->comm, PETSC_ERR_PLIB, "Sewing state and model disagree");
  PetscCall(VecZeroEntries(sewn));
  PetscCall(VecGetOwnershipRange(sewn, &lo, &hi));
  PetscCall(VecGetArray(sewn, &a));
  PetscCheck(sewing->scene->nseams <= SCENE_MAX_SEAMS, sewing->comm, PETSC_ERR_SUP, "A checkpoint stores at most %d seams exactly, the scene has %" PetscInt_FMT, SCENE_MAX_SEAMS, sewing->scene->nseams);
  for (PetscInt l = 0; l < sewing->nlinks; l++) { /* a sum of distinct 2^s, s < SCENE_MAX_SEAMS: exact in a double */
    const PetscInt node = model->seamlinks[l].p[0];
    if (sewing->sewn[l] && node >= lo && node < hi) a[node - lo] += PetscPowReal(2.0, (PetscReal)model->seamlinks[l].seam);
  }
  PetscCall(VecRestoreArray(sewn, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingSetStateVec(ClothSewing sewing, Vec sewn, PetscReal time)
{
  ClothModel         model;
  VecScatter         to_all;
  Vec                all;
  const PetscScalar *a;
  PetscInt           nsewn = 0;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(sewing->cloth, &model));
  PetscCall(VecScatterCreateToAll(sewn, &to_all, &all));
  PetscCall(VecScatterBegin(to_all, sewn, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_all, sewn, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(all, &a));
  for (PetscInt l = 0; l < sewing->nlinks; l++) {
    const PetscInt64 bits = (PetscInt64)PetscRealPart(a[model->seamlinks[l].p[0]]);
    sewing->sewn[l]       = (PetscInt)((bits >> model->seamlinks[l].seam) & 1);
    nsewn += sewing->sewn[l];
  }
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscCall(VecScatterDestroy(&to_all));
  PetscCall(VecDestroy(&all));
  sewing->phase = (nsewn == sewing->nlinks || time >= sewing->max_time) ? CLOTH_SEWING_SETTLE : CLOTH_SEWING_PULL;
  PetscCall(ClothSewingApply(sewing));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSewingDestroy(ClothSewing *sewing)
{
  PetscFunctionBeginUser;
  if (!*sewing) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothRemoveContribution((*sewing)->cloth, *sewing));
  PetscCall(PetscFree2((*sewing)->sewn, (*sewing)->closed));
  PetscCall(PetscFree((*sewing)->near));
  PetscCall(PetscFree((*sewing)->near_joined));
  PetscCall(PetscFree((*sewing)->partner_offset));
  PetscCall(PetscFree((*sewing)->partner));
  PetscCall(PetscFree(*sewing));
  PetscFunctionReturn(PETSC_SUCCESS);
}
