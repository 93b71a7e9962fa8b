/* Cloth: the distributed fabric (see cloth.h). */
#include <stddef.h>
#include "cloth_impl.h"
#include "log.h"
#include "options.h"

PetscErrorCode ClothCreate(MPI_Comm comm, Scene scene, Cloth *cloth)
{
  Cloth c;

  PetscFunctionBeginUser;
  PetscCall(ClothLogRegister());
  PetscCall(PetscNew(&c));
  c->comm              = comm;
  c->scene             = scene;
  c->partition_type    = CLOTH_PARTITION_METIS;
  c->gravity_scale     = 1.0;
  c->friction_scale    = 1.0;
  c->perturbation_seed = 1;
  c->stiffness         = CLOTH_STIFFNESS_GAUSS_NEWTON;
  c->factored          = PETSC_TRUE;
  *cloth               = c;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetFromOptions(Cloth cloth)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(cloth->comm, NULL, "Cloth distribution", "Cloth");
  PetscCall(PetscOptionsEnum("-cloth_partition", "How particles are split across ranks: metis (METIS on rank 0), block (natural order), ptscotch or parmetis (PETSc MatPartitioning on all ranks; parmetis if PETSc has it)", "ClothSetUp",
                             ClothPartitionTypes, (PetscEnum)cloth->partition_type, (PetscEnum *)&cloth->partition_type, NULL));
  PetscCall(PetscOptionsBool("-cloth_view_partition", "Print the partition quality at start-up, with one line per rank", "ClothView", cloth->view_partition, &cloth->view_partition, NULL));
  PetscCall(PetscOptionsBool("-cloth_view_partition_summary", "Print a one-line partition summary at start-up on more than one rank", "ClothSetViewPartitionSummary", cloth->view_partition_summary, &cloth->view_partition_summary, NULL));
  PetscCall(PetscOptionsReal("-cloth_perturbation", "Amplitude, m, of a seeded random displacement of the free particles along the fabric's normal at the start (a real specimen's imperfections; 0: none)", "ClothModelPerturbPositions",
                             cloth->perturbation, &cloth->perturbation, NULL));
  PetscCall(PetscOptionsInt("-cloth_perturbation_seed", "Seed of -cloth_perturbation (one trial of a test per seed)", "ClothModelPerturbPositions", cloth->perturbation_seed, &cloth->perturbation_seed, NULL));
  PetscCall(PetscOptionsReal("-cloth_perturbation_wavelength", "Shortest wavelength, m, of a smooth -cloth_perturbation field, the same at any resolution (0: independent per particle)", "ClothModelPerturbPositions", cloth->perturbation_wavelength,
                             &cloth->perturbation_wavelength, NULL));
  PetscCall(PetscOptionsEnum(
      "-cloth_stiffness",
      "Stiffness of the angle and twist elements in the implicit system: gauss_newton (closed form, positive semidefinite; the default), projected (the exact Hessian projected by a LAPACK eigen-decomposition per element, 7.9x the assembly), "
      "exact (indefinite: tests only)",
      "ClothAssembleImplicitSystem", ClothStiffnessTypes, (PetscEnum)cloth->stiffness, (PetscEnum *)&cloth->stiffness, NULL));
  PetscCall(PetscOptionsBool("-cloth_stiffness_factored", "With gauss_newton: filter and assemble each angle and twist element from its rank-1 to 3 factors (false: from its expanded matrix; the same system up to rounding)",
                             "ClothAssembleImplicitSystem", cloth->factored, &cloth->factored, NULL));
  PetscOptionsEnd();
  PetscCall(ClothOptionsCheckReal(cloth->comm, "-cloth_perturbation", cloth->perturbation, 0, PETSC_FALSE, PETSC_MAX_REAL, "m"));
  PetscCall(ClothOptionsCheckReal(cloth->comm, "-cloth_perturbation_wavelength", cloth->perturbation_wavelength, 0, PETSC_FALSE, PETSC_MAX_REAL, "m"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetViewPartitionSummary(Cloth cloth, PetscBool flg)
{
  PetscFunctionBeginUser;
  cloth->view_partition_summary = flg;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Solver numbering: ranks' parts one after another, natural order within a part. */
static PetscErrorCode ClothNumberParticles(Cloth cloth)
{
  PetscMPIInt size, rank;
  PetscInt   *offset;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(cloth->comm, &size));
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  PetscCall(PetscCalloc1(size + 1, &offset));
  for (PetscInt g = 0; g < cloth->nglobal; g++) offset[cloth->part[g] + 1]++;
  for (PetscMPIInt r = 0; r < size; r++) offset[r + 1] += offset[r];
  cloth->rstart = offset[rank];
  cloth->nlocal = offset[rank + 1] - offset[rank];
  PetscCall(PetscMalloc1(cloth->nglobal, &cloth->solver_of_natural));
  for (PetscInt g = 0; g < cloth->nglobal; g++) cloth->solver_of_natural[g] = offset[cloth->part[g]]++;
  PetscCall(PetscFree(offset));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The rank that evaluates an interaction: the owner of its lowest-numbered particle. */
static PetscInt InteractionOwner(Cloth cloth, const PetscInt p[], PetscInt np)
{
  PetscInt lowest = cloth->solver_of_natural[p[0]], natural = p[0];

  for (PetscInt k = 1; k < np; k++)
    if (cloth->solver_of_natural[p[k]] < lowest) {
      lowest  = cloth->solver_of_natural[p[k]];
      natural = p[k];
    }
  return cloth->part[natural];
}

/* How many links, angle elements (of them elastic) and seam links this rank evaluates, so that arrays are sized by
   its own share and not by the model's totals. */
static void ClothCountOwnInteractions(Cloth cloth, PetscMPIInt rank, PetscInt *nlinks, PetscInt *nangles, PetscInt *nelastic, PetscInt *nseam)
{
  const ClothModel m = cloth->model;

  *nlinks = *nangles = *nelastic = *nseam = 0;
  for (PetscInt s = 0; s < m->nseamlinks; s++)
    if (InteractionOwner(cloth, m->seamlinks[s].p, m->seamlinks[s].np) == rank) (*nseam)++;
  for (PetscInt l = 0; l < m->nlinks; l++)
    if (InteractionOwner(cloth, m->links[l].p, 2) == rank) (*nlinks)++;
  for (PetscInt a = 0; a < m->nangles; a++)
    if (InteractionOwner(cloth, m->angles[a].p, ClothAngleParticleCount(m->angles[a].kind)) == rank) {
      (*nangles)++;
      if (m->angles[a].slip <= 0) (*nelastic)++;
    }
}

/* Collects the solver indices of particles this rank's interactions touch but does not own. */
static PetscErrorCode ClothFindGhosts(Cloth cloth, PetscMPIInt rank)
{
  const ClothModel m = cloth->model;
  PetscInt         n = 0, nlinks, nangles, nelastic, nseam, *touched;

  PetscFunctionBeginUser;
  ClothCountOwnInteractions(cloth, rank, &nlinks, &nangles, &nelastic, &nseam);
  PetscCall(PetscMalloc1(2 * nlinks + CLOTH_ANGLE_MAX_PARTICLES * nangles + CLOTH_SEAM_LINK_MAX_PARTICLES * nseam + 1, &cloth->ghosts));
  for (PetscInt s = 0; s < m->nseamlinks; s++)
    if (InteractionOwner(cloth, m->seamlinks[s].p, m->seamlinks[s].np) == rank)
      for (PetscInt k = 0; k < m->seamlinks[s].np; k++)
        if (cloth->part[m->seamlinks[s].p[k]] != rank) cloth->ghosts[n++] = cloth->solver_of_natural[m->seamlinks[s].p[k]];
  for (PetscInt l = 0; l < m->nlinks; l++)
    if (InteractionOwner(cloth, m->links[l].p, 2) == rank)
      for (PetscInt k = 0; k < 2; k++)
        if (cloth->part[m->links[l].p[k]] != rank) cloth->ghosts[n++] = cloth->solver_of_natural[m->links[l].p[k]];
  for (PetscInt a = 0; a < m->nangles; a++)
    if (InteractionOwner(cloth, m->angles[a].p, ClothAngleParticleCount(m->angles[a].kind)) == rank)
      for (PetscInt k = 0; k < ClothAngleParticleCount(m->angles[a].kind); k++)
        if (cloth->part[m->angles[a].p[k]] != rank) cloth->ghosts[n++] = cloth->solver_of_natural[m->angles[a].p[k]];
  PetscCall(PetscSortRemoveDupsInt(&n, cloth->ghosts));
  /* the array above has room for every particle of every interaction (48 bytes per particle of the hanging sheet,
     kept for the whole run): keep the ghosts alone */
  touched = cloth->ghosts;
  PetscCall(PetscMalloc1(n + 1, &cloth->ghosts));
  PetscCall(PetscArraycpy(cloth->ghosts, touched, n));
  PetscCall(PetscFree(touched));
  cloth->nghost = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothLocalIndex(Cloth cloth, PetscInt natural, PetscInt *local)
{
  const PetscInt s = cloth->solver_of_natural[natural];

  PetscFunctionBeginUser;
  if (s >= cloth->rstart && s < cloth->rstart + cloth->nlocal) {
    *local = s - cloth->rstart;
  } else {
    PetscInt g;
    PetscCall(PetscFindInt(s, cloth->nghost, cloth->ghosts, &g));
    PetscCheck(g >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Particle %" PetscInt_FMT " is neither owned nor a ghost", natural);
    *local = cloth->nlocal + g;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothLocalizeInteraction(Cloth cloth, PetscInt np, const PetscInt natural[], PetscBool *here, PetscInt local[])
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  *here = InteractionOwner(cloth, natural, np) == rank ? PETSC_TRUE : PETSC_FALSE;
  if (*here)
    for (PetscInt k = 0; k < np; k++) PetscCall(ClothLocalIndex(cloth, natural[k], &local[k]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Orders this rank's links (indices into cloth->links, whose param is still the model's link) by their parameters,
   everything of a ClothLink but p, byte for byte: equal parameters compare equal. */
static int CompareLinkParametersOf(const void *a, const void *b, void *ctx)
{
  const Cloth      cloth = (Cloth)ctx;
  const ClothLink *la = &cloth->model->links[cloth->links[*(const PetscInt *)a].param], *lb = &cloth->model->links[cloth->links[*(const PetscInt *)b].param];
  return memcmp(&la->k, &lb->k, sizeof(ClothLink) - offsetof(ClothLink, k));
}

/* Replaces each link's model index (in param) by the index of its parameters in link_params, one entry per
   distinct set: sorted by parameters, equal neighbours share an entry. */
static PetscErrorCode ClothShareLinkParameters(Cloth cloth)
{
  PetscInt *order, *param, n = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(cloth->nlinks, &order, cloth->nlinks, &param));
  for (PetscInt l = 0; l < cloth->nlinks; l++) order[l] = l;
  PetscCall(PetscTimSort(cloth->nlinks, order, sizeof(PetscInt), CompareLinkParametersOf, cloth));
  for (PetscInt r = 0; r < cloth->nlinks; r++) {
    if (r == 0 || CompareLinkParametersOf(&order[r - 1], &order[r], cloth) != 0) n++;
    param[order[r]] = n;
  }
  cloth->nlink_params = n + 1;
  PetscCall(PetscMalloc1(PetscMax(cloth->nlink_params, 1), &cloth->link_params));
  for (PetscInt l = 0; l < cloth->nlinks; l++) {
    cloth->link_params[param[l]] = cloth->model->links[cloth->links[l].param];
    cloth->links[l].param        = param[l];
  }
  PetscCall(PetscFree2(order, param));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Keeps this rank's links and elastic angle springs, renumbered to local indices (the other interactions of the
   model: their contributions, ClothModelContributions in cloth_regis.c). */
static PetscErrorCode ClothDistributeInteractions(Cloth cloth, PetscMPIInt rank)
{
  const ClothModel m = cloth->model;
  PetscInt         nlinks, nseam, local[CLOTH_ANGLE_MAX_PARTICLES];
  PetscBool        here;

  PetscFunctionBeginUser;
  ClothCountOwnInteractions(cloth, rank, &nlinks, &cloth->nangles_evaluated, &cloth->nangles, &nseam);
  PetscCall(PetscMalloc2(nlinks, &cloth->links, cloth->nangles, &cloth->angles));
  cloth->nangles = 0;
  for (PetscInt l = 0; l < m->nlinks; l++) {
    PetscCall(ClothLocalizeInteraction(cloth, 2, m->links[l].p, &here, local));
    if (!here) continue;
    for (PetscInt k = 0; k < 2; k++) cloth->links[cloth->nlinks].p[k] = local[k];
    cloth->links[cloth->nlinks].param = l; /* the model's link, until ClothShareLinkParameters */
    cloth->nlinks++;
  }
  PetscCall(ClothShareLinkParameters(cloth));
  for (PetscInt a = 0; a < m->nangles; a++) {
    const PetscInt np = ClothAngleParticleCount(m->angles[a].kind);

    if (m->angles[a].slip > 0) continue;
    PetscCall(ClothLocalizeInteraction(cloth, np, m->angles[a].p, &here, local));
    if (!here) continue;
    cloth->angles[cloth->nangles] = m->angles[a];
    for (PetscInt k = 0; k < np; k++) cloth->angles[cloth->nangles].p[k] = local[k];
    cloth->nangles++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Per-particle data of owned particles and ghosts, and the initial state. */
static PetscErrorCode ClothDistributeParticles(Cloth cloth)
{
  const ClothModel m  = cloth->model;
  const PetscInt   nl = cloth->nlocal + cloth->nghost;
  PetscInt        *ghost_natural;
  PetscScalar     *x;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(nl, &cloth->natural_of_local, cloth->nlocal, &cloth->mass, cloth->nlocal, &cloth->damping, nl, &cloth->fixed));
  PetscCall(PetscMalloc1(cloth->nglobal, &ghost_natural));
  for (PetscInt g = 0; g < cloth->nglobal; g++) {
    const PetscInt s = cloth->solver_of_natural[g];
    if (s >= cloth->rstart && s < cloth->rstart + cloth->nlocal) cloth->natural_of_local[s - cloth->rstart] = g;
    ghost_natural[s] = g; /* inverse permutation, used for the ghosts */
  }
  for (PetscInt k = 0; k < cloth->nghost; k++) cloth->natural_of_local[cloth->nlocal + k] = ghost_natural[cloth->ghosts[k]];
  PetscCall(PetscFree(ghost_natural));
  for (PetscInt i = 0; i < nl; i++) {
    const PetscInt g = cloth->natural_of_local[i];
    cloth->fixed[i]  = m->pinned[g];
    if (i < cloth->nlocal) {
      cloth->mass[i]    = m->mass[g];
      cloth->damping[i] = m->damping[g];
    }
  }
  PetscCall(VecCreateGhostBlock(cloth->comm, 3, 3 * cloth->nlocal, 3 * cloth->nglobal, cloth->nghost, cloth->ghosts, &cloth->position));
  PetscCall(PetscObjectSetName((PetscObject)cloth->position, "position"));
  PetscCall(VecDuplicate(cloth->position, &cloth->velocity));
  PetscCall(PetscObjectSetName((PetscObject)cloth->velocity, "velocity"));
  PetscCall(VecDuplicate(cloth->position, &cloth->work_force));
  PetscCall(VecDuplicate(cloth->position, &cloth->work_kv));
  PetscCall(VecZeroEntries(cloth->velocity));
  PetscCall(VecGetArray(cloth->position, &x));
  for (PetscInt i = 0; i < cloth->nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) x[3 * i + c] = m->position[3 * cloth->natural_of_local[i] + c];
  PetscCall(VecRestoreArray(cloth->position, &x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothSetUpNaturalScatter(Cloth cloth)
{
  PetscMPIInt size, rank;
  PetscInt    nnat, *from, *to;
  IS          isfrom, isto;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(cloth->comm, &size));
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  nnat = cloth->nglobal / size + (rank < cloth->nglobal % size ? 1 : 0);
  /* a layout only, without values (24 bytes per particle): ClothCreateNaturalVec duplicates it, the scatter reads its layout */
  PetscCall(VecCreateMPIWithArray(cloth->comm, 3, 3 * nnat, 3 * cloth->nglobal, NULL, &cloth->natural));
  PetscCall(PetscMalloc2(cloth->nlocal, &from, cloth->nlocal, &to));
  for (PetscInt i = 0; i < cloth->nlocal; i++) {
    from[i] = cloth->rstart + i;
    to[i]   = cloth->natural_of_local[i];
  }
  PetscCall(ISCreateBlock(cloth->comm, 3, cloth->nlocal, from, PETSC_COPY_VALUES, &isfrom));
  PetscCall(ISCreateBlock(cloth->comm, 3, cloth->nlocal, to, PETSC_COPY_VALUES, &isto));
  PetscCall(VecScatterCreate(cloth->position, isfrom, cloth->natural, isto, &cloth->to_natural));
  PetscCall(ISDestroy(&isfrom));
  PetscCall(ISDestroy(&isto));
  PetscCall(PetscFree2(from, to));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetUp(Cloth cloth)
{
  PetscMPIInt size, rank;

  PetscFunctionBeginUser;
  if (cloth->setup) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscLogEventBegin(ClothLog.setup, 0, 0, 0, 0));
  PetscCallMPI(MPI_Comm_size(cloth->comm, &size));
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_MESHING));
  PetscCall(ClothModelCreate(cloth->scene, &cloth->model));
  PetscCall(ClothModelPerturbPositions(cloth->model, cloth->perturbation, cloth->perturbation_wavelength, cloth->perturbation_seed));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_MESHING));
  if (cloth->perturbation > 0 && cloth->perturbation_wavelength > 0)
    PetscCall(PetscPrintf(cloth->comm, "Start imperfections: free particles moved along the fabric's normal by up to %g m, a smooth field of wavelengths %g-%g m (seed %" PetscInt_FMT ")\n", (double)cloth->perturbation,
                          (double)cloth->perturbation_wavelength, (double)(3 * cloth->perturbation_wavelength), cloth->perturbation_seed));
  else if (cloth->perturbation > 0)
    PetscCall(PetscPrintf(cloth->comm, "Start imperfections: free particles moved along the fabric's normal by up to %g m (seed %" PetscInt_FMT ")\n", (double)cloth->perturbation, cloth->perturbation_seed));
  cloth->nglobal = cloth->model->nparticles;
  PetscCheck(cloth->nglobal >= size, cloth->comm, PETSC_ERR_USER_INPUT, "%" PetscInt_FMT " particles cannot be shared by %d ranks: expected at most %" PetscInt_FMT " ranks (mpiexec -n) or a finer grid", cloth->nglobal, size, cloth->nglobal);
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_GRAPH));
  PetscCall(ClothModelGetAdjacency(cloth->model, &cloth->xadj, &cloth->adjncy));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_GRAPH));
  PetscCall(PetscMalloc1(cloth->nglobal, &cloth->part));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_PARTITION));
  PetscCall(PetscLogEventBegin(ClothLog.partition, 0, 0, 0, 0));
  PetscCall(ClothPartitionGraph(cloth->comm, cloth->partition_type, cloth->nglobal, cloth->xadj, cloth->adjncy, size, cloth->part));
  PetscCall(PetscLogEventEnd(ClothLog.partition, 0, 0, 0, 0));
  cloth->edge_cut = ClothPartitionEdgeCut(cloth->nglobal, cloth->xadj, cloth->adjncy, cloth->part);
  cloth->nedges   = cloth->xadj[cloth->nglobal] / 2;
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_PARTITION));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_DISTRIBUTE));
  PetscCall(ClothNumberParticles(cloth));
  PetscCall(ClothFindGhosts(cloth, rank));
  PetscCall(ClothDistributeInteractions(cloth, rank));
  PetscCall(ClothDistributeParticles(cloth));
  PetscCall(ClothSetUpNaturalScatter(cloth));
  cloth->setup = PETSC_TRUE;
  PetscCall(ClothComputeRestMeasures(cloth));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_DISTRIBUTE));
  PetscCall(ClothRegisterModelContributions_Private(cloth)); /* the model's own forces (cloth_regis.c) */
  PetscCall(PetscLogEventEnd(ClothLog.setup, 0, 0, 0, 0));
  if (cloth->view_partition)
    PetscCall(ClothView(cloth, PETSC_VIEWER_STDOUT_(cloth->comm)));
  else if (cloth->view_partition_summary && size > 1) {
    PetscViewer viewer = PETSC_VIEWER_STDOUT_(cloth->comm);
    PetscCall(PetscViewerPushFormat(viewer, PETSC_VIEWER_ASCII_INFO));
    PetscCall(ClothView(cloth, viewer));
    PetscCall(PetscViewerPopFormat(viewer));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Number of other ranks that own this rank's ghosts (its partners in a ghost update). Ghosts are
   sorted by solver index, and each rank's particles are contiguous there, so owners come in runs. */
static PetscInt ClothCountGhostOwners(Cloth cloth)
{
  PetscInt owners = 0, last = -1;

  for (PetscInt k = 0; k < cloth->nghost; k++) {
    const PetscInt owner = cloth->part[cloth->natural_of_local[cloth->nlocal + k]];
    if (owner != last) owners++;
    last = owner;
  }
  return owners;
}

/* The one-line summary: edge cut, and min..max over ranks of owned particles, ghosts and evaluated
   interactions, with imbalance = max / mean (1 is perfect; the slowest rank sets the pace). */
static PetscErrorCode ClothViewPartitionSummary(Cloth cloth, PetscViewer viewer)
{
  enum { OWNED, GHOSTS, INTERACTIONS, NCOUNTS };
  const PetscInt local[NCOUNTS] = {cloth->nlocal, cloth->nghost, cloth->nlinks + cloth->nangles_evaluated};
  const PetscInt edges          = cloth->nedges;
  PetscInt       minc[NCOUNTS], maxc[NCOUNTS], sum[NCOUNTS];
  PetscMPIInt    size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(cloth->comm, &size));
  PetscCallMPI(MPI_Allreduce(local, minc, NCOUNTS, MPIU_INT, MPI_MIN, cloth->comm));
  PetscCallMPI(MPI_Allreduce(local, maxc, NCOUNTS, MPIU_INT, MPI_MAX, cloth->comm));
  PetscCallMPI(MPI_Allreduce(local, sum, NCOUNTS, MPIU_INT, MPI_SUM, cloth->comm));
  PetscCall(PetscViewerASCIIPrintf(viewer,
                                   "Partition (%s, %d rank(s)): edge cut %" PetscInt_FMT " of %" PetscInt_FMT " graph edges (%.2f%%); owned particles %" PetscInt_FMT "..%" PetscInt_FMT " (imbalance %.3f); ghosts %" PetscInt_FMT "..%" PetscInt_FMT
                                   " (total %" PetscInt_FMT "); interactions evaluated %" PetscInt_FMT "..%" PetscInt_FMT " (imbalance %.3f)\n",
                                   ClothPartitionTypes[cloth->partition_type], size, cloth->edge_cut, edges, edges ? 100.0 * (double)cloth->edge_cut / (double)edges : 0.0, minc[OWNED], maxc[OWNED], (double)maxc[OWNED] * size / (double)sum[OWNED],
                                   minc[GHOSTS], maxc[GHOSTS], sum[GHOSTS], minc[INTERACTIONS], maxc[INTERACTIONS], sum[INTERACTIONS] ? (double)maxc[INTERACTIONS] * size / (double)sum[INTERACTIONS] : 1.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothView(Cloth cloth, PetscViewer viewer)
{
  PetscMPIInt       rank;
  PetscBool         ascii;
  PetscViewerFormat format;

  PetscFunctionBeginUser;
  PetscCheck(cloth->setup, cloth->comm, PETSC_ERR_ORDER, "Call ClothSetUp before ClothView");
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscViewerGetFormat(viewer, &format));
  if (format == PETSC_VIEWER_ASCII_INFO) {
    PetscCall(ClothViewPartitionSummary(cloth, viewer));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Cloth: %" PetscInt_FMT " particles, %" PetscInt_FMT " links, %" PetscInt_FMT " angle springs\n", cloth->nglobal, cloth->model->nlinks, cloth->model->nangles));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(ClothViewPartitionSummary(cloth, viewer));
  PetscCall(PetscViewerASCIIPushSynchronized(viewer));
  PetscCall(PetscViewerASCIISynchronizedPrintf(viewer, "[%d] owned %" PetscInt_FMT " (solver numbers %" PetscInt_FMT "..%" PetscInt_FMT "), ghosts %" PetscInt_FMT " from %" PetscInt_FMT " rank(s), links %" PetscInt_FMT ", angles %" PetscInt_FMT "\n",
                                               rank, cloth->nlocal, cloth->rstart, cloth->rstart + cloth->nlocal - 1, cloth->nghost, ClothCountGhostOwners(cloth), cloth->nlinks, cloth->nangles_evaluated));
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerASCIIPopSynchronized(viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothDestroy(Cloth *cloth)
{
  Cloth c = *cloth;

  PetscFunctionBeginUser;
  if (!c) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothModelDestroy(&c->model));
  PetscCall(PetscFree(c->part));
  for (PetscInt k = 0; k < c->ncontributions; k++)
    if (c->contributions[k].destroy) PetscCall(c->contributions[k].destroy(c->contributions[k].ctx));
  PetscCall(PetscFree(c->solver_of_natural));
  PetscCall(PetscFree(c->ghosts));
  PetscCall(PetscFree(c->xadj));
  PetscCall(PetscFree(c->adjncy));
  if (c->setup) {
    PetscCall(PetscFree4(c->natural_of_local, c->mass, c->damping, c->fixed));
    PetscCall(PetscFree2(c->links, c->angles));
    PetscCall(PetscFree(c->link_params));
    PetscCall(PetscFree2(c->thread_width, c->area));
  }
  PetscCall(VecDestroy(&c->position));
  PetscCall(VecDestroy(&c->velocity));
  PetscCall(VecDestroy(&c->work_force));
  PetscCall(VecDestroy(&c->work_kv));
  PetscCall(PetscFree2(c->filter, c->filtered));
  PetscCall(VecDestroy(&c->contact_normal));
  PetscCall(VecDestroy(&c->natural));
  PetscCall(VecScatterDestroy(&c->to_natural));
  PetscCall(PetscFree(*cloth));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetState(Cloth cloth, Vec *position, Vec *velocity)
{
  PetscFunctionBeginUser;
  if (position) *position = cloth->position;
  if (velocity) *velocity = cloth->velocity;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateStateVec(Cloth cloth, Vec *v)
{
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(cloth->position, v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetSizes(Cloth cloth, PetscInt *nlocal, PetscInt *nglobal)
{
  PetscFunctionBeginUser;
  if (nlocal) *nlocal = cloth->nlocal;
  if (nglobal) *nglobal = cloth->nglobal;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetLayout(Cloth cloth, ClothLayout *layout)
{
  PetscFunctionBeginUser;
  PetscCheck(cloth->setup, cloth->comm, PETSC_ERR_ORDER, "Set the cloth up (ClothSetUp) before asking for its layout");
  layout->comm              = cloth->comm;
  layout->nglobal           = cloth->nglobal;
  layout->nlocal            = cloth->nlocal;
  layout->nghost            = cloth->nghost;
  layout->rstart            = cloth->rstart;
  layout->part              = cloth->part;
  layout->solver_of_natural = cloth->solver_of_natural;
  layout->natural_of_local  = cloth->natural_of_local;
  layout->xadj              = cloth->xadj;
  layout->adjncy            = cloth->adjncy;
  layout->nlinks            = cloth->nlinks;
  layout->links             = cloth->links;
  layout->link_params       = cloth->link_params;
  layout->fixed             = cloth->fixed;
  layout->model             = cloth->model;
  layout->scene             = cloth->scene;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothIsSetUp(Cloth cloth, PetscBool *setup)
{
  PetscFunctionBeginUser;
  *setup = cloth->setup;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothPeekContactNormals(Cloth cloth, Vec *normals)
{
  PetscFunctionBeginUser;
  *normals = cloth->contact_normal;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetInteractionCounts(Cloth cloth, PetscInt *nlinks, PetscInt *nangles)
{
  PetscFunctionBeginUser;
  PetscCheck(cloth->setup, PETSC_COMM_SELF, PETSC_ERR_ORDER, "Call ClothSetUp before ClothGetInteractionCounts");
  if (nlinks) *nlinks = cloth->nlinks;
  if (nangles) *nangles = cloth->nangles_evaluated;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetMasses(Cloth cloth, const PetscReal **mass, const PetscBool **fixed)
{
  PetscFunctionBeginUser;
  if (mass) *mass = cloth->mass;
  if (fixed) *fixed = cloth->fixed;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetGravityScale(Cloth cloth, PetscReal scale)
{
  PetscFunctionBeginUser;
  cloth->gravity_scale = scale;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetFrictionScale(Cloth cloth, PetscReal scale)
{
  PetscFunctionBeginUser;
  cloth->friction_scale = scale;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetFrictionScale(Cloth cloth, PetscReal *scale)
{
  PetscFunctionBeginUser;
  *scale = cloth->friction_scale;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A ghosted Vec stores its ghost values right after the owned ones, so its array is the local form's. */
PetscErrorCode ClothGetLocalPositionArray(Cloth cloth, const PetscScalar **x)
{
  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(cloth->position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(cloth->position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(cloth->position, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRestoreLocalPositionArray(Cloth cloth, const PetscScalar **x)
{
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArrayRead(cloth->position, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetModel(Cloth cloth, ClothModel *model)
{
  PetscFunctionBeginUser;
  *model = cloth->model;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetComm(Cloth cloth, MPI_Comm *comm)
{
  PetscFunctionBeginUser;
  *comm = cloth->comm;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetScene(Cloth cloth, Scene *scene)
{
  PetscFunctionBeginUser;
  *scene = cloth->scene;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetParticleName(Cloth cloth, PetscInt g, char name[], size_t len)
{
  const ClothModel m     = cloth->model;
  PetscInt         piece = 0, nu;

  PetscFunctionBeginUser;
  PetscCheck(g >= 0 && g < m->nparticles, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Particle %" PetscInt_FMT " is not in 0..%" PetscInt_FMT, g, m->nparticles - 1);
  while (m->piece_offset[piece + 1] <= g) piece++;
  nu = cloth->scene->pieces[piece].nu;
  PetscCall(PetscSNPrintf(name, len, "%s (%" PetscInt_FMT ", %" PetscInt_FMT ")", cloth->scene->pieces[piece].name, (g - m->piece_offset[piece]) % nu, (g - m->piece_offset[piece]) / nu));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateNaturalVec(Cloth cloth, Vec *natural)
{
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(cloth->natural, natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothScatterToNatural(Cloth cloth, Vec solver, Vec natural, ScatterMode mode)
{
  PetscFunctionBeginUser;
  if (mode == SCATTER_FORWARD) {
    PetscCall(VecScatterBegin(cloth->to_natural, solver, natural, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(cloth->to_natural, solver, natural, INSERT_VALUES, SCATTER_FORWARD));
  } else {
    PetscCall(VecScatterBegin(cloth->to_natural, natural, solver, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(cloth->to_natural, natural, solver, INSERT_VALUES, SCATTER_REVERSE));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothScatterParticleValuesToNatural(Cloth cloth, Vec solver, Vec values)
{
  Vec natural;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(ClothScatterToNatural(cloth, solver, natural, SCATTER_FORWARD));
  PetscCall(VecStrideGather(natural, 0, values, INSERT_VALUES));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}
