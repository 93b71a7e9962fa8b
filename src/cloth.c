/* Cloth: the distributed fabric (see cloth.h). */
#include "cloth_impl.h"
#include "log.h"

PetscErrorCode ClothCreate(MPI_Comm comm, Scene scene, Cloth *cloth)
{
  Cloth c;

  PetscFunctionBeginUser;
  PetscCall(ClothLogRegister());
  PetscCall(PetscNew(&c));
  c->comm           = comm;
  c->scene          = scene;
  c->partition_type = CLOTH_PARTITION_METIS;
  *cloth            = c;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSetFromOptions(Cloth cloth)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(cloth->comm, NULL, "Cloth distribution", "Cloth");
  PetscCall(PetscOptionsEnum("-cloth_partition", "How particles are split across ranks", "ClothSetUp", ClothPartitionTypes, (PetscEnum)cloth->partition_type, (PetscEnum *)&cloth->partition_type, NULL));
  PetscCall(PetscOptionsBool("-cloth_view_partition", "Print the partition quality at start-up", "ClothView", cloth->view_partition, &cloth->view_partition, NULL));
  PetscOptionsEnd();
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

/* Collects the solver indices of particles this rank's interactions touch but does not own. */
static PetscErrorCode ClothFindGhosts(Cloth cloth, PetscMPIInt rank)
{
  const ClothModel m = cloth->model;
  PetscInt         n = 0, cap = 0;

  PetscFunctionBeginUser;
  for (PetscInt l = 0; l < m->nlinks; l++) cap += (InteractionOwner(cloth, m->links[l].p, 2) == rank) ? 2 : 0;
  for (PetscInt a = 0; a < m->nangles; a++) cap += (InteractionOwner(cloth, m->angles[a].p, 3) == rank) ? 3 : 0;
  PetscCall(PetscMalloc1(cap + 1, &cloth->ghosts));
  for (PetscInt l = 0; l < m->nlinks; l++)
    if (InteractionOwner(cloth, m->links[l].p, 2) == rank)
      for (PetscInt k = 0; k < 2; k++)
        if (cloth->part[m->links[l].p[k]] != rank) cloth->ghosts[n++] = cloth->solver_of_natural[m->links[l].p[k]];
  for (PetscInt a = 0; a < m->nangles; a++)
    if (InteractionOwner(cloth, m->angles[a].p, 3) == rank)
      for (PetscInt k = 0; k < 3; k++)
        if (cloth->part[m->angles[a].p[k]] != rank) cloth->ghosts[n++] = cloth->solver_of_natural[m->angles[a].p[k]];
  PetscCall(PetscSortRemoveDupsInt(&n, cloth->ghosts));
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

/* Keeps this rank's interactions, renumbered to local indices. */
static PetscErrorCode ClothDistributeInteractions(Cloth cloth, PetscMPIInt rank)
{
  const ClothModel m = cloth->model;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(m->nlinks, &cloth->links, m->nangles, &cloth->angles));
  for (PetscInt l = 0; l < m->nlinks; l++) {
    if (InteractionOwner(cloth, m->links[l].p, 2) != rank) continue;
    cloth->links[cloth->nlinks] = m->links[l];
    for (PetscInt k = 0; k < 2; k++) PetscCall(ClothLocalIndex(cloth, m->links[l].p[k], &cloth->links[cloth->nlinks].p[k]));
    cloth->nlinks++;
  }
  for (PetscInt a = 0; a < m->nangles; a++) {
    if (InteractionOwner(cloth, m->angles[a].p, 3) != rank) continue;
    cloth->angles[cloth->nangles] = m->angles[a];
    for (PetscInt k = 0; k < 3; k++) PetscCall(ClothLocalIndex(cloth, m->angles[a].p[k], &cloth->angles[cloth->nangles].p[k]));
    cloth->nangles++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Per-particle data of owned particles and ghosts, and the initial state. */
static PetscErrorCode ClothDistributeParticles(Cloth cloth)
{
  const ClothModel m = cloth->model;
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
  PetscCall(VecCreateMPI(cloth->comm, 3 * nnat, 3 * cloth->nglobal, &cloth->natural));
  PetscCall(VecSetBlockSize(cloth->natural, 3));
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
  PetscCall(ClothModelCreate(cloth->scene, &cloth->model));
  cloth->nglobal = cloth->model->nparticles;
  PetscCheck(cloth->nglobal >= size, cloth->comm, PETSC_ERR_ARG_OUTOFRANGE, "%" PetscInt_FMT " particles cannot be shared by %d ranks", cloth->nglobal, size);
  PetscCall(ClothModelGetAdjacency(cloth->model, &cloth->xadj, &cloth->adjncy));
  PetscCall(PetscMalloc1(cloth->nglobal, &cloth->part));
  PetscCall(PetscLogEventBegin(ClothLog.partition, 0, 0, 0, 0));
  PetscCall(ClothPartitionGraph(cloth->comm, cloth->partition_type, cloth->nglobal, cloth->xadj, cloth->adjncy, size, cloth->part));
  PetscCall(PetscLogEventEnd(ClothLog.partition, 0, 0, 0, 0));
  cloth->edge_cut = ClothPartitionEdgeCut(cloth->nglobal, cloth->xadj, cloth->adjncy, cloth->part);
  PetscCall(ClothNumberParticles(cloth));
  PetscCall(ClothFindGhosts(cloth, rank));
  PetscCall(ClothDistributeInteractions(cloth, rank));
  PetscCall(ClothDistributeParticles(cloth));
  PetscCall(ClothSetUpNaturalScatter(cloth));
  cloth->setup = PETSC_TRUE;
  PetscCall(PetscLogEventEnd(ClothLog.setup, 0, 0, 0, 0));
  if (cloth->view_partition) PetscCall(ClothView(cloth, PETSC_VIEWER_STDOUT_(cloth->comm)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothView(Cloth cloth, PetscViewer viewer)
{
  PetscMPIInt size;
  PetscInt    counts[2] = {cloth->nlocal, cloth->nghost}, maxc[2], minc[2];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(cloth->comm, &size));
  PetscCallMPI(MPI_Allreduce(counts, maxc, 2, MPIU_INT, MPI_MAX, cloth->comm));
  PetscCallMPI(MPI_Allreduce(counts, minc, 2, MPIU_INT, MPI_MIN, cloth->comm));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Cloth: %" PetscInt_FMT " particles, %" PetscInt_FMT " links, %" PetscInt_FMT " angle springs on %d rank(s), partition %s\n", cloth->nglobal, cloth->model->nlinks, cloth->model->nangles, size, ClothPartitionTypes[cloth->partition_type]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  edge cut %" PetscInt_FMT "; owned per rank %" PetscInt_FMT "..%" PetscInt_FMT " (imbalance %.3f); ghosts per rank %" PetscInt_FMT "..%" PetscInt_FMT "\n", cloth->edge_cut, minc[0], maxc[0], (double)(maxc[0] * size) / (double)cloth->nglobal, minc[1], maxc[1]));
  PetscCall(PetscViewerASCIIPushSynchronized(viewer));
  PetscCall(PetscViewerASCIISynchronizedPrintf(viewer, "  [%d] owned %" PetscInt_FMT ", ghosts %" PetscInt_FMT ", links %" PetscInt_FMT ", angles %" PetscInt_FMT "\n", PetscGlobalRank, cloth->nlocal, cloth->nghost, cloth->nlinks, cloth->nangles));
  PetscCall(PetscViewerFlush(viewer));
  PetscCall(PetscViewerASCIIPopSynchronized(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothDestroy(Cloth *cloth)
{
  Cloth c = *cloth;

  PetscFunctionBeginUser;
  if (!c) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothModelDestroy(&c->model));
  PetscCall(PetscFree(c->part));
  PetscCall(PetscFree(c->solver_of_natural));
  PetscCall(PetscFree(c->ghosts));
  PetscCall(PetscFree(c->xadj));
  PetscCall(PetscFree(c->adjncy));
  if (c->setup) {
    PetscCall(PetscFree4(c->natural_of_local, c->mass, c->damping, c->fixed));
    PetscCall(PetscFree2(c->links, c->angles));
  }
  PetscCall(VecDestroy(&c->position));
  PetscCall(VecDestroy(&c->velocity));
  PetscCall(VecDestroy(&c->work_force));
  PetscCall(VecDestroy(&c->work_kv));
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

PetscErrorCode ClothGetMasses(Cloth cloth, const PetscReal **mass, const PetscBool **fixed)
{
  PetscFunctionBeginUser;
  if (mass) *mass = cloth->mass;
  if (fixed) *fixed = cloth->fixed;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGetModel(Cloth cloth, ClothModel *model)
{
  PetscFunctionBeginUser;
  *model = cloth->model;
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
