/* ClothSelfContact (see selfcontact.h): cloth-cloth proximity search across ranks, repulsion with
   its stiffness for the implicit system, and the inelastic velocity filter.

   The closest points come from geometry.h, the cell grids from cellgrid.h; the response follows R. Bridson, R. Fedkiw,
   J. Anderson, "Robust treatment of collisions, contact and friction for cloth animation",
   SIGGRAPH 2002 (repulsion within the thickness, inelastic impulses along the normal weighted by the
   barycentric weights and inverse masses, iterated Gauss-Seidel sweeps). */
#include "selfcontact.h"
#include "cellgrid.h"
#include "geometry.h"
#include "log.h"
#include "vec3.h"

#define SELF_CONTACT_NP 4 /* particles of a contact element */

struct _n_ClothSelfContact {
  Cloth                     cloth; /* borrowed; read through its public accessors only */
  Scene                     scene;
  ClothLayout               layout;             /* the cloth's particle distribution (after set-up) */
  Vec                       position, velocity; /* the cloth's state (borrowed) */
  MPI_Comm                  comm;
  PetscMPIInt               size, rank;
  PetscBool                 enabled, view, setup;
  PetscReal                 thickness, stiffness, min_gap;
  PetscInt                  exclude_ring, impulse_iterations;
  PetscBool                 same_piece;
  ClothSelfContactExcludeFn exclude;
  void                     *exclude_ctx;

  /* static topology, natural numbering */
  PetscInt  ntri, *tri;                 /* 3 per triangle */
  PetscInt  nedge, *edge;               /* 2 per edge, lower particle first */
  PetscInt *tri_start, *tri_of;         /* particle -> incident triangles (CSR) */
  PetscInt *edge_start, *edge_of;       /* particle -> incident edges (CSR) */
  PetscInt *piece_of, *grid_i, *grid_j; /* per particle: its piece and grid position in it */

  /* the last search: "contact-local" particles are the owned ones (0 .. nlocal-1, solver order)
     followed by the remote ones received from other ranks */
  PetscInt      nremote, *remote_natural;
  PetscInt      nremote_prev;         /* remote particles listed in natural_of */
  PetscInt     *tri_mark, *edge_mark; /* per primitive: the search (or query) that last visited it */
  PetscInt      visit;
  PetscInt     *natural_of;                                   /* contact-local -> natural */
  PetscInt     *contact_index;                                /* natural -> contact-local, -1 when not present (size N) */
  PetscReal    *x, *dx;                                       /* contact-local positions at the search, displacements over the step */
  Vec           xremote, vremote, fremote, kvremote, bremote; /* bremote: body-contact normals */
  VecScatter    remote_scatter;                               /* cloth state -> remote particles */
  CellGrid      triangle_grid, edge_grid;                     /* the cell grids of the last search */
  PetscInt      ncontacts, maxcontacts;
  ClothContact *contacts; /* natural numbering */
  PetscInt     *local;    /* 4 contact-local indices per contact */

  /* blocks of the implicit matrix beyond the static pattern, for owned rows: keys row * N + col (solver) */
  PetscInt    nextra;
  PetscInt64 *extra;
  PetscInt    rebuilds;                           /* how often the matrix pattern had to grow */
  PetscInt    searches, contacts_found, impulses; /* statistics for the view (summed over ranks where relevant) */
};

/* ------------------------------------------------------------------------------------------------ */
/* Geometry                                                                                         */

/* r = sum_k a[k] x[k] */
static void Separation(const PetscReal *const xs[SELF_CONTACT_NP], const PetscReal a[SELF_CONTACT_NP], PetscReal r[3])
{
  for (PetscInt c = 0; c < 3; c++) {
    r[c] = 0;
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) r[c] += a[k] * xs[k][c];
  }
}

/* Is the contact closer than radius plus the relative travel of its closest points over the step
   (ds: the particles' displacements over the step; NULL: none)? */
static PetscBool Within(const ClothContact *contact, const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius)
{
  PetscReal travel[3] = {0, 0, 0};

  if (ds) Separation(ds, contact->a, travel);
  return contact->distance < radius + PetscSqrtReal(Dot3(travel, travel)) ? PETSC_TRUE : PETSC_FALSE;
}

/* The contact of particle xs[0] with triangle xs[1..3], if within radius (see Within). */
static void TestPointTriangle(const PetscReal *const xs[SELF_CONTACT_NP], const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius, ClothContact *contact, PetscBool *hit)
{
  PetscReal w[3], r[3];

  GeometryClosestPointTriangle(xs[0], xs[1], xs[2], xs[3], w);
  contact->kind = CLOTH_CONTACT_POINT_TRIANGLE;
  contact->a[0] = 1, contact->a[1] = -w[0], contact->a[2] = -w[1], contact->a[3] = -w[2];
  Separation(xs, contact->a, r);
  contact->distance = PetscSqrtReal(Dot3(r, r));
  *hit              = Within(contact, ds, radius);
}

/* The contact of edge xs[0] xs[1] with edge xs[2] xs[3], if within radius (see Within). */
static void TestEdgeEdge(const PetscReal *const xs[SELF_CONTACT_NP], const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius, ClothContact *contact, PetscBool *hit)
{
  PetscReal s, t, r[3];

  GeometryClosestPointsSegments(xs[0], xs[1], xs[2], xs[3], &s, &t);
  contact->kind = CLOTH_CONTACT_EDGE_EDGE;
  contact->a[0] = 1 - s, contact->a[1] = s, contact->a[2] = -(1 - t), contact->a[3] = -t;
  Separation(xs, contact->a, r);
  contact->distance = PetscSqrtReal(Dot3(r, r));
  *hit              = Within(contact, ds, radius);
}

/* The box of n points xs at the start and xs + ds at the end of the step, inflated by inflate. */
static void SweptBoxOf(const PetscReal *const xs[], const PetscReal *const ds[], PetscInt n, PetscReal inflate, PetscReal box[6])
{
  for (PetscInt c = 0; c < 3; c++) {
    box[c] = box[3 + c] = xs[0][c];
    for (PetscInt k = 0; k < n; k++) {
      box[c]     = PetscMin(box[c], PetscMin(xs[k][c], xs[k][c] + ds[k][c]));
      box[3 + c] = PetscMax(box[3 + c], PetscMax(xs[k][c], xs[k][c] + ds[k][c]));
    }
    box[c] -= inflate;
    box[3 + c] += inflate;
  }
}

/* Do the boxes a and b (6 reals: low corner, high corner) overlap? */
static inline PetscBool Boxes6Overlap(const PetscReal a[6], const PetscReal b[6])
{
  return GeometryBoxesOverlap(a, a + 3, b, b + 3);
}

/* ------------------------------------------------------------------------------------------------ */
/* Static topology                                                                                  */

static int CompareEdges(const void *a, const void *b)
{
  const PetscInt *x = (const PetscInt *)a, *y = (const PetscInt *)b;

  if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
  if (x[1] != y[1]) return x[1] < y[1] ? -1 : 1;
  return 0;
}

static int CompareInt64(const void *a, const void *b)
{
  const PetscInt64 x = *(const PetscInt64 *)a, y = *(const PetscInt64 *)b;

  return x < y ? -1 : (x > y ? 1 : 0);
}

/* Triangles (a b c), (a c d) of every quad, and the unique edges: the quad sides and that diagonal. */
static PetscErrorCode BuildPrimitives(ClothSelfContact sc, ClothModel m)
{
  const PetscInt side[5][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}};
  PetscInt       n          = 0;

  PetscFunctionBeginUser;
  sc->ntri = 2 * m->nquads;
  PetscCall(PetscMalloc1(3 * sc->ntri + 1, &sc->tri));
  PetscCall(PetscMalloc1(10 * m->nquads + 2, &sc->edge));
  for (PetscInt q = 0; q < m->nquads; q++) {
    const PetscInt *c  = &m->quads[4 * q];
    sc->tri[6 * q + 0] = c[0], sc->tri[6 * q + 1] = c[1], sc->tri[6 * q + 2] = c[2];
    sc->tri[6 * q + 3] = c[0], sc->tri[6 * q + 4] = c[2], sc->tri[6 * q + 5] = c[3];
    for (PetscInt e = 0; e < 5; e++) {
      sc->edge[2 * n]     = PetscMin(c[side[e][0]], c[side[e][1]]);
      sc->edge[2 * n + 1] = PetscMax(c[side[e][0]], c[side[e][1]]);
      n++;
    }
  }
  if (n) qsort(sc->edge, (size_t)n, 2 * sizeof(PetscInt), CompareEdges);
  sc->nedge = 0;
  for (PetscInt e = 0; e < n; e++)
    if (sc->nedge == 0 || CompareEdges(&sc->edge[2 * e], &sc->edge[2 * (sc->nedge - 1)]) != 0) {
      sc->edge[2 * sc->nedge]     = sc->edge[2 * e];
      sc->edge[2 * sc->nedge + 1] = sc->edge[2 * e + 1];
      sc->nedge++;
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* particle -> primitives with nv vertices each (CSR) */
static PetscErrorCode BuildIncidence(PetscInt nparticles, PetscInt nprim, PetscInt nv, const PetscInt prim[], PetscInt **start, PetscInt **of)
{
  PetscInt *fill;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nparticles + 1, start));
  PetscCall(PetscCalloc1(nparticles, &fill));
  for (PetscInt t = 0; t < nprim * nv; t++) (*start)[prim[t] + 1]++;
  for (PetscInt i = 0; i < nparticles; i++) (*start)[i + 1] += (*start)[i];
  PetscCall(PetscMalloc1((*start)[nparticles] + 1, of));
  for (PetscInt t = 0; t < nprim * nv; t++) (*of)[(*start)[prim[t]] + fill[prim[t]]++] = t / nv;
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each particle's piece and (i, j) grid position, for the ring exclusion. */
static PetscErrorCode BuildGridPositions(ClothSelfContact sc, Scene scene, ClothModel m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(m->nparticles, &sc->piece_of, m->nparticles, &sc->grid_i, m->nparticles, &sc->grid_j));
  for (PetscInt k = 0; k < m->npieces; k++)
    for (PetscInt g = m->piece_offset[k]; g < m->piece_offset[k + 1]; g++) {
      const PetscInt local = g - m->piece_offset[k];
      sc->piece_of[g]      = k;
      sc->grid_i[g]        = local % scene->pieces[k].nu;
      sc->grid_j[g]        = local / scene->pieces[k].nu;
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Must the primitives with particles pa[0..na) and pb[0..nb) (natural) never be in contact? */
static PetscErrorCode Excluded(ClothSelfContact sc, const PetscInt pa[], PetscInt na, const PetscInt pb[], PetscInt nb, PetscBool *excluded)
{
  PetscFunctionBeginUser;
  *excluded = PETSC_FALSE;
  for (PetscInt i = 0; i < na; i++)
    for (PetscInt j = 0; j < nb; j++) {
      const PetscInt a = pa[i], b = pb[j];
      if (sc->piece_of[a] == sc->piece_of[b]) {
        const PetscInt ring = PetscMax(PetscAbsInt(sc->grid_i[a] - sc->grid_i[b]), PetscAbsInt(sc->grid_j[a] - sc->grid_j[b]));
        if (!sc->same_piece || ring <= sc->exclude_ring) *excluded = PETSC_TRUE;
      }
      if (!*excluded && sc->exclude) PetscCall(sc->exclude(sc->exclude_ctx, a, b, excluded));
      if (*excluded) PetscFunctionReturn(PETSC_SUCCESS);
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Exchange of particles near other ranks                                                           */

/* The bounding box of the owned particles (empty: inverted). */
static void OwnedBox(ClothSelfContact sc, const PetscScalar x[], PetscReal box[6])
{
  for (PetscInt c = 0; c < 3; c++) box[c] = PETSC_MAX_REAL, box[3 + c] = -PETSC_MAX_REAL;
  for (PetscInt i = 0; i < sc->layout.nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) {
      box[c]     = PetscMin(box[c], PetscRealPart(x[3 * i + c]));
      box[3 + c] = PetscMax(box[3 + c], PetscRealPart(x[3 * i + c]));
    }
}

/* Sends every owned particle inside another rank's box inflated by margin to that rank; returns the
   natural indices received, grouped by sender (MPI_Allgather of boxes, MPI_Alltoallv of indices). */
static PetscErrorCode ExchangeNearParticles(ClothSelfContact sc, const PetscScalar x[], PetscReal margin, PetscInt *nrecv, PetscInt **recv)
{
  const ClothLayout *layout = &sc->layout;
  PetscReal          mybox[6], *boxes;
  PetscMPIInt       *scount, *rcount, *sdispl, *rdispl;
  PetscInt          *send, nsend = 0;

  PetscFunctionBeginUser;
  OwnedBox(sc, x, mybox);
  PetscCall(PetscMalloc1(6 * sc->size, &boxes));
  PetscCallMPI(MPI_Allgather(mybox, 6, MPIU_REAL, boxes, 6, MPIU_REAL, sc->comm));
  PetscCall(PetscCalloc4(sc->size, &scount, sc->size, &rcount, sc->size + 1, &sdispl, sc->size + 1, &rdispl));
  PetscCall(PetscMalloc1(layout->nlocal * (sc->size - 1) + 1, &send));
  for (PetscMPIInt r = 0; r < sc->size; r++) {
    sdispl[r] = (PetscMPIInt)nsend;
    if (r == sc->rank) continue;
    for (PetscInt i = 0; i < layout->nlocal; i++) {
      PetscBool inside = PETSC_TRUE;
      for (PetscInt c = 0; c < 3 && inside; c++) {
        const PetscReal v = PetscRealPart(x[3 * i + c]);
        if (v < boxes[6 * r + c] - margin || v > boxes[6 * r + 3 + c] + margin) inside = PETSC_FALSE;
      }
      if (inside) send[nsend++] = layout->natural_of_local[i];
    }
    scount[r] = (PetscMPIInt)(nsend - sdispl[r]);
  }
  PetscCallMPI(MPI_Alltoall(scount, 1, MPI_INT, rcount, 1, MPI_INT, sc->comm));
  for (PetscMPIInt r = 0; r < sc->size; r++) rdispl[r + 1] = rdispl[r] + rcount[r];
  *nrecv = rdispl[sc->size];
  PetscCall(PetscMalloc1(*nrecv + 1, recv));
  PetscCallMPI(MPI_Alltoallv(send, scount, sdispl, MPIU_INT, *recv, rcount, rdispl, MPIU_INT, sc->comm));
  PetscCall(PetscFree(send));
  PetscCall(PetscFree4(scount, rcount, sdispl, rdispl));
  PetscCall(PetscFree(boxes));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The scatter from the cloth's state to the remote particles, rebuilt when the set changes. */
static PetscErrorCode SetRemoteParticles(ClothSelfContact sc, PetscInt nrecv, PetscInt *recv)
{
  const ClothLayout *layout = &sc->layout;
  PetscBool          same   = (sc->remote_scatter && nrecv == sc->nremote) ? PETSC_TRUE : PETSC_FALSE, all_same;
  PetscInt          *solver;
  IS                 from;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; same && k < nrecv; k++)
    if (recv[k] != sc->remote_natural[k]) same = PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(&same, &all_same, 1, MPIU_BOOL, MPI_LAND, sc->comm));
  if (all_same) {
    PetscCall(PetscFree(recv));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscFree(sc->remote_natural));
  sc->remote_natural = recv;
  sc->nremote        = nrecv;
  PetscCall(VecScatterDestroy(&sc->remote_scatter));
  PetscCall(VecDestroy(&sc->xremote));
  PetscCall(VecDestroy(&sc->vremote));
  PetscCall(VecDestroy(&sc->fremote));
  PetscCall(VecDestroy(&sc->kvremote));
  PetscCall(VecDestroy(&sc->bremote));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3 * nrecv, &sc->xremote));
  PetscCall(VecSetBlockSize(sc->xremote, 3));
  PetscCall(VecDuplicate(sc->xremote, &sc->vremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->fremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->kvremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->bremote));
  PetscCall(PetscMalloc1(nrecv + 1, &solver));
  for (PetscInt k = 0; k < nrecv; k++) solver[k] = layout->solver_of_natural[recv[k]];
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, 3, nrecv, solver, PETSC_OWN_POINTER, &from));
  PetscCall(VecScatterCreate(sc->position, from, sc->xremote, NULL, &sc->remote_scatter));
  PetscCall(ISDestroy(&from));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode RefreshRemote(ClothSelfContact sc, Vec global, Vec remote)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(sc->remote_scatter, global, remote, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc->remote_scatter, global, remote, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SumRemoteInto(ClothSelfContact sc, Vec remote, Vec global)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(sc->remote_scatter, remote, global, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sc->remote_scatter, remote, global, ADD_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Contact-local numbering and positions: owned particles, then the remote ones. */
/* Contact-local numbering, positions and displacements over the step (h velocity; zero without velocity):
   owned particles, then the remote ones. */
static PetscErrorCode GatherContactLocal(ClothSelfContact sc, const PetscScalar x[], Vec velocity, PetscReal h)
{
  const ClothLayout *layout = &sc->layout;
  const PetscInt     n      = layout->nlocal + sc->nremote;
  const PetscScalar *xr, *v = NULL, *vr = NULL;

  PetscFunctionBeginUser;
  if (sc->natural_of)
    for (PetscInt k = 0; k < layout->nlocal + sc->nremote_prev; k++) sc->contact_index[sc->natural_of[k]] = -1;
  PetscCall(PetscFree(sc->natural_of));
  PetscCall(PetscFree2(sc->x, sc->dx));
  PetscCall(PetscMalloc1(n + 1, &sc->natural_of));
  PetscCall(PetscCalloc2(3 * n + 1, &sc->x, 3 * n + 1, &sc->dx));
  if (velocity) {
    PetscCall(RefreshRemote(sc, velocity, sc->vremote));
    PetscCall(VecGetArrayRead(velocity, &v));
    PetscCall(VecGetArrayRead(sc->vremote, &vr));
  }
  PetscCall(RefreshRemote(sc, sc->position, sc->xremote));
  PetscCall(VecGetArrayRead(sc->xremote, &xr));
  for (PetscInt k = 0; k < n; k++) {
    const PetscBool owned = k < layout->nlocal ? PETSC_TRUE : PETSC_FALSE;
    sc->natural_of[k]     = owned ? layout->natural_of_local[k] : sc->remote_natural[k - layout->nlocal];
    for (PetscInt c = 0; c < 3; c++) sc->x[3 * k + c] = PetscRealPart(owned ? x[3 * k + c] : xr[3 * (k - layout->nlocal) + c]);
    if (v)
      for (PetscInt c = 0; c < 3; c++) sc->dx[3 * k + c] = h * PetscRealPart(owned ? v[3 * k + c] : vr[3 * (k - layout->nlocal) + c]);
    sc->contact_index[sc->natural_of[k]] = k;
  }
  sc->nremote_prev = sc->nremote;
  PetscCall(VecRestoreArrayRead(sc->xremote, &xr));
  if (velocity) {
    PetscCall(VecRestoreArrayRead(sc->vremote, &vr));
    PetscCall(VecRestoreArrayRead(velocity, &v));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Search                                                                                           */

static PetscErrorCode AppendContact(ClothSelfContact sc, const ClothContact *contact)
{
  PetscFunctionBeginUser;
  if (sc->ncontacts == sc->maxcontacts) {
    ClothContact *contacts;
    PetscInt     *local;

    sc->maxcontacts = 2 * sc->maxcontacts + 64;
    PetscCall(PetscMalloc2(sc->maxcontacts, &contacts, SELF_CONTACT_NP * sc->maxcontacts, &local));
    PetscCall(PetscArraycpy(contacts, sc->contacts, sc->ncontacts));
    PetscCall(PetscArraycpy(local, sc->local, SELF_CONTACT_NP * sc->ncontacts));
    PetscCall(PetscFree2(sc->contacts, sc->local));
    sc->contacts = contacts;
    sc->local    = local;
  }
  sc->contacts[sc->ncontacts] = *contact;
  for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) sc->local[SELF_CONTACT_NP * sc->ncontacts + k] = sc->contact_index[contact->p[k]];
  sc->ncontacts++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Primitives (nv vertices each) whose vertices are all present here, with their boxes inflated by
   inflate; also the longest edge among them. */
static PetscErrorCode CollectPrimitives(ClothSelfContact sc, PetscInt nv, const PetscInt prim[], const PetscInt start[], const PetscInt of[], PetscInt mark[], PetscReal inflate, PetscInt *n, PetscInt **list, PetscReal **boxes, PetscReal *longest)
{
  const PetscInt nparticles = sc->layout.nlocal + sc->nremote;

  PetscFunctionBeginUser;
  *n = 0;
  sc->visit++;
  PetscCall(PetscMalloc1(start[sc->layout.nglobal] + 1, list));
  for (PetscInt k = 0; k < nparticles; k++) {
    const PetscInt g = sc->natural_of[k];
    for (PetscInt q = start[g]; q < start[g + 1]; q++) {
      const PetscInt t       = of[q];
      PetscBool      present = PETSC_TRUE;
      if (mark[t] == sc->visit) continue;
      mark[t] = sc->visit;
      for (PetscInt v = 0; v < nv; v++)
        if (sc->contact_index[prim[nv * t + v]] < 0) present = PETSC_FALSE;
      if (present) (*list)[(*n)++] = t;
    }
  }
  PetscCall(PetscMalloc1(6 * *n + 1, boxes));
  for (PetscInt k = 0; k < *n; k++) {
    const PetscReal *xs[3], *ds[3];
    for (PetscInt v = 0; v < nv; v++) {
      xs[v] = &sc->x[3 * sc->contact_index[prim[nv * (*list)[k] + v]]];
      ds[v] = &sc->dx[3 * sc->contact_index[prim[nv * (*list)[k] + v]]];
    }
    SweptBoxOf(xs, ds, nv, inflate, &(*boxes)[6 * k]);
    for (PetscInt v = 0; v < nv; v++) {
      const PetscReal *b    = xs[(v + 1) % nv];
      PetscReal        d[3] = {b[0] - xs[v][0], b[1] - xs[v][1], b[2] - xs[v][2]};
      *longest              = PetscMax(*longest, PetscSqrtReal(Dot3(d, d)));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The box of every particle present here, at the start and the end of the step, inflated by inflate:
   the region the cell grids cover. */
static void ContactRegion(ClothSelfContact sc, PetscReal inflate, PetscReal region[6])
{
  const PetscInt n = sc->layout.nlocal + sc->nremote;

  for (PetscInt c = 0; c < 3; c++) region[c] = PETSC_MAX_REAL, region[3 + c] = -PETSC_MAX_REAL;
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt c = 0; c < 3; c++) {
      region[c]     = PetscMin(region[c], PetscMin(sc->x[3 * k + c], sc->x[3 * k + c] + sc->dx[3 * k + c]) - inflate);
      region[3 + c] = PetscMax(region[3 + c], PetscMax(sc->x[3 * k + c], sc->x[3 * k + c] + sc->dx[3 * k + c]) + inflate);
    }
  if (n == 0)
    for (PetscInt c = 0; c < 3; c++) region[c] = region[3 + c] = 0;
}

/* The cap on the cells of a search grid: a few per particle present, so that memory follows the particles
   whatever the spread of the region (cells grow instead). */
static PetscInt SelfContactMaxCells(ClothSelfContact sc)
{
  return 8 * (sc->layout.nlocal + sc->nremote) + 64;
}

/* Is the state the search sees finite? Collective. *nonfinite: the lowest natural index of a particle
   present on some rank whose position or displacement over the step is not finite (-1: none);
   *farthest: when every value is finite but the region the grids would cover is not (it overflows), the
   lowest natural index of a particle reaching farthest from the origin, *reach (-1: the region is finite). */
static PetscErrorCode CheckSearchFinite(ClothSelfContact sc, const PetscReal region[6], PetscInt *nonfinite, PetscInt *farthest, PetscReal *reach)
{
  const PetscInt n        = sc->layout.nlocal + sc->nremote;
  PetscInt       local[2] = {PETSC_MAX_INT, 1}, global[2], candidate = PETSC_MAX_INT; /* {lowest non-finite particle, region finite} */
  PetscReal      far = 0;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < 3; c++)
    if (PetscIsInfOrNanReal(region[c]) || PetscIsInfOrNanReal(region[3 + c]) || PetscIsInfOrNanReal(region[3 + c] - region[c])) local[1] = 0;
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt c = 0; c < 3; c++) {
      const PetscReal start = sc->x[3 * k + c], end = start + sc->dx[3 * k + c];
      if (PetscIsInfOrNanReal(start) || PetscIsInfOrNanReal(end))
        local[0] = PetscMin(local[0], sc->natural_of[k]);
      else
        far = PetscMax(far, PetscMax(PetscAbsReal(start), PetscAbsReal(end)));
    }
  PetscCallMPI(MPI_Allreduce(local, global, 2, MPIU_INT, MPI_MIN, sc->comm)); /* the only reduction of a finite state */
  *nonfinite = global[0] < PETSC_MAX_INT ? global[0] : -1;
  *farthest  = -1;
  *reach     = far;
  if (*nonfinite >= 0 || global[1]) PetscFunctionReturn(PETSC_SUCCESS);
  /* finite values, overflowing region: name the particle reaching farthest */
  PetscCallMPI(MPI_Allreduce(&far, reach, 1, MPIU_REAL, MPIU_MAX, sc->comm));
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt c = 0; c < 3; c++) {
      const PetscReal start = sc->x[3 * k + c], end = start + sc->dx[3 * k + c];
      if (PetscAbsReal(start) == *reach || PetscAbsReal(end) == *reach) candidate = PetscMin(candidate, sc->natural_of[k]);
    }
  PetscCallMPI(MPI_Allreduce(&candidate, farthest, 1, MPIU_INT, MPI_MIN, sc->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every owned particle against the triangles of the cells its path over the step touches. */
static PetscErrorCode FindPointTriangle(ClothSelfContact sc, PetscReal radius, const PetscReal region[6], PetscReal cell, PetscInt ntri, const PetscInt tris[], const PetscReal boxes[])
{
  CellGrid        g = sc->triangle_grid;
  PetscInt        n[3];
  const PetscInt *start, *item;

  PetscFunctionBeginUser;
  PetscCall(CellGridBuild(g, region, region + 3, cell, SelfContactMaxCells(sc), ntri, boxes, boxes + 3, 6));
  CellGridGetCells(g, n, &start, &item);
  for (PetscInt k = 0; k < sc->layout.nlocal; k++) {
    const PetscReal *p = &sc->x[3 * k], *dp = &sc->dx[3 * k];
    PetscReal        pbox[6];
    PetscInt         lo[3], hi[3];

    SweptBoxOf(&p, &dp, 1, 0.0, pbox);
    CellGridGetCellRange(g, pbox, pbox + 3, lo, hi);
    sc->visit++;
    for (PetscInt i = lo[0]; i <= hi[0]; i++)
      for (PetscInt j = lo[1]; j <= hi[1]; j++)
        for (PetscInt l = lo[2]; l <= hi[2]; l++) {
          const PetscInt c = CellGridCellIndex(n, i, j, l);
          for (PetscInt q = start[c]; q < start[c + 1]; q++) {
            const PetscInt   tid = tris[item[q]], *t = &sc->tri[3 * tid], point = sc->natural_of[k];
            const PetscReal *xs[SELF_CONTACT_NP], *ds[SELF_CONTACT_NP];
            ClothContact     contact;
            PetscBool        excluded, hit;

            if (sc->tri_mark[tid] == sc->visit) continue;
            sc->tri_mark[tid] = sc->visit;
            if (!Boxes6Overlap(pbox, &boxes[6 * item[q]])) continue;
            PetscCall(Excluded(sc, &point, 1, t, 3, &excluded));
            if (excluded) continue;
            xs[0] = p, ds[0] = dp;
            for (PetscInt v = 0; v < 3; v++) xs[1 + v] = &sc->x[3 * sc->contact_index[t[v]]], ds[1 + v] = &sc->dx[3 * sc->contact_index[t[v]]];
            TestPointTriangle(xs, ds, radius, &contact, &hit);
            if (!hit) continue;
            contact.p[0] = point;
            for (PetscInt v = 0; v < 3; v++) contact.p[1 + v] = t[v];
            PetscCall(AppendContact(sc, &contact));
          }
        }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Two overlapping boxes (items a and b) share several cells; the pair is examined only in the one
   holding the low corner of their intersection (whose cell is the larger of their low cells, per
   axis), so that it is met once without marking. */
static PetscBool CellOwnsPair(const PetscInt low_cell[], PetscInt a, PetscInt b, PetscInt i, PetscInt j, PetscInt l)
{
  const PetscInt *ca = &low_cell[3 * a], *cb = &low_cell[3 * b];

  return (PetscMax(ca[0], cb[0]) == i && PetscMax(ca[1], cb[1]) == j && PetscMax(ca[2], cb[2]) == l) ? PETSC_TRUE : PETSC_FALSE;
}

static PetscBool EdgeHasOwned(ClothSelfContact sc, PetscInt e)
{
  return (sc->contact_index[sc->edge[2 * e]] < sc->layout.nlocal || sc->contact_index[sc->edge[2 * e + 1]] < sc->layout.nlocal) ? PETSC_TRUE : PETSC_FALSE;
}

/* Is this rank the one that handles the edge-edge contact of edges e1 and e2 (particles p)? Any owner
   of one of its particles has all four (the exchange margin covers two edges and the radius), so the
   owner of particle (e1 + e2) mod 4 is chosen: a rule that spreads contacts between two pieces owned
   by two ranks over both, where "the lowest particle" would give them all to one. */
static PetscBool HandlesEdgePair(ClothSelfContact sc, PetscInt e1, PetscInt e2, const PetscInt p[4])
{
  return sc->layout.part[p[(e1 + e2) % 4]] == sc->rank ? PETSC_TRUE : PETSC_FALSE;
}

/* Every edge with an owned particle against the edges in the cells its box touches. */
static PetscErrorCode FindEdgeEdge(ClothSelfContact sc, PetscReal radius, const PetscReal region[6], PetscReal cell, PetscInt nedge, const PetscInt edges[], const PetscReal boxes[])
{
  CellGrid        g = sc->edge_grid;
  PetscInt        lo[3], hi[3], n[3];
  const PetscInt *start, *item, *low_cell;

  PetscFunctionBeginUser;
  PetscCall(CellGridBuild(g, region, region + 3, cell, SelfContactMaxCells(sc), nedge, boxes, boxes + 3, 6));
  CellGridGetCells(g, n, &start, &item);
  CellGridGetItemLowCells(g, &low_cell);
  for (PetscInt k1 = 0; k1 < nedge; k1++) {
    const PetscInt e1 = edges[k1];
    if (!EdgeHasOwned(sc, e1)) continue;
    CellGridGetCellRange(g, &boxes[6 * k1], &boxes[6 * k1 + 3], lo, hi);
    for (PetscInt i = lo[0]; i <= hi[0]; i++)
      for (PetscInt j = lo[1]; j <= hi[1]; j++)
        for (PetscInt l = lo[2]; l <= hi[2]; l++) {
          const PetscInt c = CellGridCellIndex(n, i, j, l);
          for (PetscInt q = start[c]; q < start[c + 1]; q++) {
            const PetscInt   k2 = item[q], e2 = edges[k2], first = PetscMin(e1, e2), second = PetscMax(e1, e2);
            const PetscReal *xs[SELF_CONTACT_NP], *ds[SELF_CONTACT_NP];
            ClothContact     contact;
            PetscBool        excluded, hit;

            if (e2 <= e1 && (e2 == e1 || EdgeHasOwned(sc, e2))) continue; /* itself, or found from e2 */
            if (!CellOwnsPair(low_cell, k1, k2, i, j, l)) continue;       /* met in another cell */
            if (!Boxes6Overlap(&boxes[6 * k1], &boxes[6 * k2])) continue;
            contact.p[0] = sc->edge[2 * first], contact.p[1] = sc->edge[2 * first + 1];
            contact.p[2] = sc->edge[2 * second], contact.p[3] = sc->edge[2 * second + 1];
            if (!HandlesEdgePair(sc, e1, e2, contact.p)) continue;
            PetscCall(Excluded(sc, contact.p, 2, &contact.p[2], 2, &excluded));
            if (excluded) continue;
            for (PetscInt v = 0; v < 4; v++) xs[v] = &sc->x[3 * sc->contact_index[contact.p[v]]], ds[v] = &sc->dx[3 * sc->contact_index[contact.p[v]]];
            TestEdgeEdge(xs, ds, radius, &contact, &hit);
            if (hit) PetscCall(AppendContact(sc, &contact));
          }
        }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The longest link between grid neighbours (cell sides and, with the link shear model, diagonals) at
   the current positions (ghosts refreshed): every triangle edge is at most twice as long (a cell
   diagonal is at most two sides). Collective. */
static PetscErrorCode LongestLink(ClothSelfContact sc, PetscReal *longest)
{
  const ClothLayout *layout = &sc->layout;
  Vec                xl;
  const PetscScalar *x;
  PetscReal          local = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGhostUpdateBegin(sc->position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(sc->position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostGetLocalForm(sc->position, &xl));
  PetscCall(VecGetArrayRead(xl, &x));
  for (PetscInt l = 0; l < layout->nlinks; l++) {
    const PetscInt     g0 = layout->natural_of_local[layout->links[l].p[0]], g1 = layout->natural_of_local[layout->links[l].p[1]];
    const PetscScalar *a = &x[3 * layout->links[l].p[0]], *b = &x[3 * layout->links[l].p[1]];
    PetscReal          d2 = 0;
    if (sc->piece_of[g0] != sc->piece_of[g1] || PetscMax(PetscAbsInt(sc->grid_i[g0] - sc->grid_i[g1]), PetscAbsInt(sc->grid_j[g0] - sc->grid_j[g1])) != 1) continue; /* bending links, seams */
    for (PetscInt c = 0; c < 3; c++) d2 += PetscSqr(PetscRealPart(a[c] - b[c]));
    local = PetscMax(local, d2);
  }
  PetscCall(VecRestoreArrayRead(xl, &x));
  PetscCall(VecGhostRestoreLocalForm(sc->position, &xl));
  PetscCallMPI(MPI_Allreduce(&local, longest, 1, MPIU_REAL, MPIU_MAX, sc->comm));
  *longest = PetscSqrtReal(*longest);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest particle speed. Collective. */
static PetscErrorCode MaxSpeed(ClothSelfContact sc, Vec velocity, PetscReal *vmax)
{
  const PetscScalar *v;
  PetscReal          local = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(velocity, &v));
  for (PetscInt i = 0; i < sc->layout.nlocal; i++) local = PetscMax(local, PetscRealPart(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]));
  PetscCall(VecRestoreArrayRead(velocity, &v));
  PetscCallMPI(MPI_Allreduce(&local, vmax, 1, MPIU_REAL, MPIU_MAX, sc->comm));
  *vmax = PetscSqrtReal(*vmax);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* All contacts within radius, plus the relative travel of their closest points over a step of h at
   velocity (NULL: no travel), at the cloth's current positions. Collective. */
static PetscErrorCode Search(ClothSelfContact sc, PetscReal radius, Vec velocity, PetscReal h)
{
  const PetscScalar *x;
  PetscReal          link, longest = 0, region[6], vmax = 0, reach;
  PetscInt           nrecv, *recv, ntri, nedge, *tris, *edges, nonfinite, farthest;
  PetscReal         *tboxes, *eboxes;

  PetscFunctionBeginUser;
  PetscCall(LongestLink(sc, &link));
  if (velocity) PetscCall(MaxSpeed(sc, velocity, &vmax));
  PetscCall(VecGetArrayRead(sc->position, &x));
  /* a contact's handler owns one of its particles; the others lie within radius + 2 triangle edges
     + the travel of two particles */
  PetscCall(ExchangeNearParticles(sc, x, radius + 4 * link + 2 * h * vmax, &nrecv, &recv));
  PetscCall(SetRemoteParticles(sc, nrecv, recv));
  PetscCall(GatherContactLocal(sc, x, velocity, h));
  PetscCall(VecRestoreArrayRead(sc->position, &x));
  sc->ncontacts = 0;
  ContactRegion(sc, radius, region);
  PetscCall(CheckSearchFinite(sc, region, &nonfinite, &farthest, &reach));
  if (nonfinite >= 0) {
    /* a diverged state has no meaningful contacts; the integrator's test of the state at the end of the
       step fails that step, which is halved and, failing at every size, ends the run at its last good
       state, as it does without self-collision */
    PetscCall(PetscInfo(NULL, "Self-collision search skipped: particle %" PetscInt_FMT " (natural numbering) has a non-finite position or velocity\n", nonfinite));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCheck(farthest < 0, sc->comm, PETSC_ERR_FP,
             "Self-collision: the region that the particles sweep over a step of %g s, widened by the contact radius %g m, is too large for a cell grid: particle %" PetscInt_FMT
             " (natural numbering) reaches %g m from the origin. The state has diverged, or the self-collision thickness is far too large",
             (double)h, (double)radius, farthest, (double)reach);
  PetscCall(CollectPrimitives(sc, 3, sc->tri, sc->tri_start, sc->tri_of, sc->tri_mark, radius, &ntri, &tris, &tboxes, &longest));
  PetscCall(CollectPrimitives(sc, 2, sc->edge, sc->edge_start, sc->edge_of, sc->edge_mark, 0.5 * radius, &nedge, &edges, &eboxes, &longest));
  PetscCall(FindPointTriangle(sc, radius, region, PetscMax(radius, longest), ntri, tris, tboxes));
  PetscCall(FindEdgeEdge(sc, radius, region, PetscMax(radius, longest), nedge, edges, eboxes));
  PetscCall(PetscFree(tris));
  PetscCall(PetscFree(tboxes));
  PetscCall(PetscFree(edges));
  PetscCall(PetscFree(eboxes));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Matrix pattern                                                                                   */

static PetscBool StaticallyCoupled(const ClothLayout *layout, PetscInt a, PetscInt b)
{
  PetscInt loc;

  if (PetscFindInt(b, layout->xadj[a + 1] - layout->xadj[a], &layout->adjncy[layout->xadj[a]], &loc)) return PETSC_FALSE;
  return loc >= 0 ? PETSC_TRUE : PETSC_FALSE;
}

/* The blocks (row, col in solver numbering, as keys row * N + col) that the contacts couple beyond the
   static pattern, sent to the owners of the rows; sorted, without duplicates. Collective. */
static PetscErrorCode ContactBlocks(ClothSelfContact sc, PetscInt *nkeys, PetscInt64 **keys)
{
  const ClothLayout *layout = &sc->layout;
  const PetscInt64   N      = layout->nglobal;
  PetscMPIInt       *scount, *rcount, *sdispl, *rdispl;
  PetscInt64        *send, *recv;
  PetscInt           nsend = 0, n = 0, *dest;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc4(sc->size, &scount, sc->size, &rcount, sc->size + 1, &sdispl, sc->size + 1, &rdispl));
  PetscCall(PetscMalloc2(12 * sc->ncontacts + 1, &send, 12 * sc->ncontacts + 1, &dest));
  for (PetscInt c = 0; c < sc->ncontacts; c++)
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) {
        const PetscInt a = sc->contacts[c].p[j], b = sc->contacts[c].p[k];
        if (j == k || StaticallyCoupled(layout, a, b)) continue;
        send[nsend]   = layout->solver_of_natural[a] * N + layout->solver_of_natural[b];
        dest[nsend++] = layout->part[a];
        scount[layout->part[a]]++;
      }
  for (PetscMPIInt r = 0; r < sc->size; r++) sdispl[r + 1] = sdispl[r] + scount[r];
  {
    PetscInt64  *sorted;
    PetscMPIInt *fill;
    PetscCall(PetscMalloc1(nsend + 1, &sorted));
    PetscCall(PetscCalloc1(sc->size, &fill));
    for (PetscInt k = 0; k < nsend; k++) sorted[sdispl[dest[k]] + fill[dest[k]]++] = send[k];
    PetscCall(PetscFree(fill));
    PetscCall(PetscFree2(send, dest));
    send = sorted;
  }
  PetscCallMPI(MPI_Alltoall(scount, 1, MPI_INT, rcount, 1, MPI_INT, sc->comm));
  for (PetscMPIInt r = 0; r < sc->size; r++) rdispl[r + 1] = rdispl[r] + rcount[r];
  PetscCall(PetscMalloc1(rdispl[sc->size] + 1, &recv));
  PetscCallMPI(MPI_Alltoallv(send, scount, sdispl, MPIU_INT64, recv, rcount, rdispl, MPIU_INT64, sc->comm));
  PetscCall(PetscSortInt64(rdispl[sc->size], recv));
  for (PetscInt k = 0; k < rdispl[sc->size]; k++)
    if (n == 0 || recv[k] != recv[n - 1]) recv[n++] = recv[k];
  *nkeys = n;
  *keys  = recv;
  PetscCall(PetscFree(send));
  PetscCall(PetscFree4(scount, rcount, sdispl, rdispl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* When blocks are needed that the pattern lacks, the new pattern is the union of the needed and the
   present ones (contacts come and go as layers slide: keeping recent blocks saves rebuilds), or only
   the needed ones once the union has grown beyond twice their number. Collective. */
static PetscErrorCode UpdatePattern(ClothSelfContact sc, PetscBool *changed)
{
  PetscInt    n = 0, nunion = 0;
  PetscInt64 *keys    = NULL, *both;
  PetscBool   missing = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(ContactBlocks(sc, &n, &keys));
  for (PetscInt k = 0; k < n && !missing; k++)
    if (!bsearch(&keys[k], sc->extra, (size_t)sc->nextra, sizeof(PetscInt64), CompareInt64)) missing = PETSC_TRUE;
  PetscCallMPI(MPI_Allreduce(&missing, changed, 1, MPIU_BOOL, MPI_LOR, sc->comm));
  if (!*changed) {
    PetscCall(PetscFree(keys));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscMalloc1(n + sc->nextra + 1, &both));
  PetscCall(PetscArraycpy(both, keys, n));
  PetscCall(PetscArraycpy(both + n, sc->extra, sc->nextra));
  PetscCall(PetscSortInt64(n + sc->nextra, both));
  for (PetscInt k = 0; k < n + sc->nextra; k++)
    if (nunion == 0 || both[k] != both[nunion - 1]) both[nunion++] = both[k];
  PetscCall(PetscFree(sc->extra));
  if (nunion <= 2 * n + 64) {
    sc->extra  = both;
    sc->nextra = nunion;
    PetscCall(PetscFree(keys));
  } else {
    sc->extra  = keys;
    sc->nextra = n;
    PetscCall(PetscFree(both));
  }
  sc->rebuilds++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The contribution's count_row_blocks (cloth.h): the blocks the contacts couple beyond the static pattern. */
static PetscErrorCode CountRowBlocks(void *ctx, PetscInt dnnz[], PetscInt onnz[], PetscInt dnnzu[], PetscInt onnzu[])
{
  const ClothSelfContact sc     = (ClothSelfContact)ctx;
  const ClothLayout     *layout = &sc->layout;
  const PetscInt64       N      = layout->nglobal;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < sc->nextra; k++) {
    const PetscInt row = (PetscInt)(sc->extra[k] / N), col = (PetscInt)(sc->extra[k] % N), i = row - layout->rstart;
    PetscCheck(i >= 0 && i < layout->nlocal, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Contact block row %" PetscInt_FMT " is not owned", row);
    ClothCountRowBlock(layout->rstart, layout->rstart + layout->nlocal, row, col, dnnz, onnz, dnnzu, onnzu);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Repulsion                                                                                        */

/* Contact-local particle k's 3-vector in the owned array or the remote one. */
static inline PetscScalar *At(ClothSelfContact sc, PetscScalar *owned, PetscScalar *remote, PetscInt k)
{
  return k < sc->layout.nlocal ? &owned[3 * k] : &remote[3 * (k - sc->layout.nlocal)];
}

/* Energy, force on the separation r (as on the particle side) and its 3x3 stiffness, from the link
   kernel with its repulsion term only: 0.5 k (thickness - |r|)^2 for |r| < thickness. */
static PetscErrorCode RepulsionEvaluate(ClothSelfContact sc, const PetscReal r[3], PetscBool psd, PetscReal *energy, PetscReal force[3], PetscReal K[9])
{
  const PetscReal zero[3] = {0, 0, 0};
  ClothLink       link;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&link, sizeof(link))); /* no stretch, no rest length: only the repulsion */
  link.p[0] = link.p[1] = -1;
  link.repel_length     = sc->thickness;
  link.repel_k          = sc->stiffness;
  PetscCall(ClothLinkEvaluate(&link, zero, r, psd, energy, force, K));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The constraint filter of a particle, as in the rest of the implicit system (ClothContactFilter, from its
   body contact constraint b; NULL: free). */
static void ParticleFilter(ClothSelfContact sc, PetscInt natural, const PetscScalar *b, PetscReal S[9])
{
  (void)ClothContactFilter(b, sc->layout.model->pinned[natural], S);
}

/* The body-contact normals of this evaluation: owned part and remote copies (NULL when no body). */
typedef struct {
  Vec                normals; /* the cloth's (borrowed) */
  const PetscScalar *owned, *remote;
} BodyNormals;

static PetscErrorCode BodyNormalsGet(ClothSelfContact sc, BodyNormals *bn)
{
  PetscFunctionBeginUser;
  bn->owned = bn->remote = NULL;
  PetscCall(ClothPeekContactNormals(sc->cloth, &bn->normals));
  if (!bn->normals) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(RefreshRemote(sc, bn->normals, sc->bremote));
  PetscCall(VecGetArrayRead(bn->normals, &bn->owned));
  PetscCall(VecGetArrayRead(sc->bremote, &bn->remote));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BodyNormalsRestore(ClothSelfContact sc, BodyNormals *bn)
{
  PetscFunctionBeginUser;
  if (!bn->owned) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecRestoreArrayRead(sc->bremote, &bn->remote));
  PetscCall(VecRestoreArrayRead(bn->normals, &bn->owned));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static void ContactFilters(ClothSelfContact sc, const BodyNormals *bn, PetscInt c, PetscReal S[SELF_CONTACT_NP][9])
{
  for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
    const PetscInt k = sc->local[SELF_CONTACT_NP * c + j];
    ParticleFilter(sc, sc->contacts[c].p[j], bn->owned ? (k < sc->layout.nlocal ? &bn->owned[3 * k] : &bn->remote[3 * (k - sc->layout.nlocal)]) : NULL, S[j]);
  }
}

/* h2 S_j (a_j a_k K) S_k into A at the contact's rows and columns: the filtered contact stiffness. */
static PetscErrorCode AddContactStiffness(ClothSelfContact sc, const BodyNormals *bn, PetscInt c, const PetscReal K[9], PetscReal h2, Mat A)
{
  const ClothContact *contact = &sc->contacts[c];
  const PetscInt      n       = 3 * SELF_CONTACT_NP;
  PetscInt            rows[SELF_CONTACT_NP];
  PetscReal           S[SELF_CONTACT_NP][9], KS[9];
  PetscScalar         H[9 * SELF_CONTACT_NP * SELF_CONTACT_NP];

  PetscFunctionBeginUser;
  ContactFilters(sc, bn, c, S);
  for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) rows[j] = sc->layout.solver_of_natural[contact->p[j]];
  for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) {
    for (PetscInt r = 0; r < 3; r++) /* KS = K S_k */
      for (PetscInt q = 0; q < 3; q++) KS[3 * r + q] = K[3 * r] * S[k][q] + K[3 * r + 1] * S[k][3 + q] + K[3 * r + 2] * S[k][6 + q];
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt r = 0; r < 3; r++)
        for (PetscInt q = 0; q < 3; q++) H[n * (3 * j + r) + 3 * k + q] = h2 * contact->a[j] * contact->a[k] * (S[j][3 * r] * KS[q] + S[j][3 * r + 1] * KS[3 + q] + S[j][3 * r + 2] * KS[6 + q]);
  }
  PetscCall(MatSetValuesBlocked(A, SELF_CONTACT_NP, rows, SELF_CONTACT_NP, rows, H, ADD_VALUES));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Zero blocks at every preallocated contact block of the owned rows: PETSc compresses a matrix to the
   blocks set in its first assembly, so every assembly sets them all, whichever contacts are active. */
static PetscErrorCode AddPatternZeros(ClothSelfContact sc, Mat A)
{
  const PetscInt64  N       = sc->layout.nglobal;
  const PetscScalar zero[9] = {0};

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < sc->nextra; k++) {
    const PetscInt row = (PetscInt)(sc->extra[k] / N), col = (PetscInt)(sc->extra[k] % N);
    PetscCall(MatSetValuesBlocked(A, 1, &row, 1, &col, zero, ADD_VALUES));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Adds the repulsion of the current contacts at (position, velocity) to force, to kv (K v; may be NULL), h2 K to A (may
   be NULL; filtered like the rest of the system) and to *energy (may be NULL). Collective. */
static PetscErrorCode AddRepulsion(ClothSelfContact sc, Vec position, Vec velocity, Vec force, Vec kv, Mat A, PetscReal h2, PetscBool psd, PetscReal *energy)
{
  PetscScalar *x, *xr, *v = NULL, *vr = NULL, *f, *fr, *k = NULL, *kr = NULL;
  BodyNormals  bn = {NULL, NULL, NULL};

  PetscFunctionBeginUser;
  if (!sc->remote_scatter) PetscFunctionReturn(PETSC_SUCCESS); /* no search yet (on every rank alike) */
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  PetscCall(RefreshRemote(sc, position, sc->xremote));
  if (kv) PetscCall(RefreshRemote(sc, velocity, sc->vremote));
  PetscCall(VecZeroEntries(sc->fremote));
  PetscCall(VecZeroEntries(sc->kvremote));
  if (A) PetscCall(BodyNormalsGet(sc, &bn));
  PetscCall(VecGetArray(position, &x));
  PetscCall(VecGetArray(sc->xremote, &xr));
  PetscCall(VecGetArray(force, &f));
  PetscCall(VecGetArray(sc->fremote, &fr));
  if (kv) {
    PetscCall(VecGetArray(velocity, &v));
    PetscCall(VecGetArray(sc->vremote, &vr));
    PetscCall(VecGetArray(kv, &k));
    PetscCall(VecGetArray(sc->kvremote, &kr));
  }
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           r[3] = {0, 0, 0}, e, fr3[3], K[9], kvr[3] = {0, 0, 0}, vrel[3] = {0, 0, 0}, d;

    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) r[q] += contact->a[j] * PetscRealPart(At(sc, x, xr, loc[j])[q]);
    d = PetscSqrtReal(Dot3(r, r));
    if (!(d < sc->thickness) || d <= 0) continue; /* outside the repulsion zone (or no direction) */
    PetscCall(RepulsionEvaluate(sc, r, psd, &e, fr3, (kv || A) ? K : NULL));
    if (energy) *energy += e;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) At(sc, f, fr, loc[j])[q] += contact->a[j] * fr3[q];
    if (kv) {
      for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
        for (PetscInt q = 0; q < 3; q++) vrel[q] += contact->a[j] * PetscRealPart(At(sc, v, vr, loc[j])[q]);
      for (PetscInt q = 0; q < 3; q++)
        for (PetscInt s = 0; s < 3; s++) kvr[q] += K[3 * q + s] * vrel[s];
      for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
        for (PetscInt q = 0; q < 3; q++) At(sc, k, kr, loc[j])[q] += contact->a[j] * kvr[q];
    }
    if (A) PetscCall(AddContactStiffness(sc, &bn, c, K, h2, A));
  }
  PetscCall(PetscLogFlops(200.0 * sc->ncontacts));
  PetscCall(BodyNormalsRestore(sc, &bn));
  if (A) PetscCall(AddPatternZeros(sc, A));
  if (kv) {
    PetscCall(VecRestoreArray(sc->kvremote, &kr));
    PetscCall(VecRestoreArray(kv, &k));
    PetscCall(VecRestoreArray(sc->vremote, &vr));
    PetscCall(VecRestoreArray(velocity, &v));
  }
  PetscCall(VecRestoreArray(sc->fremote, &fr));
  PetscCall(VecRestoreArray(force, &f));
  PetscCall(VecRestoreArray(sc->xremote, &xr));
  PetscCall(VecRestoreArray(position, &x));
  PetscCall(SumRemoteInto(sc, sc->fremote, force));
  if (kv) PetscCall(SumRemoteInto(sc, sc->kvremote, kv));
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Velocity filter                                                                                  */

static PetscReal InverseMass(ClothSelfContact sc, PetscInt natural)
{
  const ClothModel m = sc->layout.model;

  return (m->pinned[natural] || m->mass[natural] <= 0) ? 0.0 : 1.0 / m->mass[natural];
}

/* One Gauss-Seidel sweep over this rank's contacts: each contact whose gap would fall below the
   target during the step gets the inelastic impulse along its normal that brings it to the target,
   applied at once to the velocities v (owned) and vr (remote) that the next contacts see. Returns the
   number of contacts that needed one. */
static PetscErrorCode ImpulseSweep(ClothSelfContact sc, const BodyNormals *bn, PetscReal h, PetscScalar v[], PetscScalar vr[], PetscInt *active)
{
  const PetscReal target = sc->min_gap * sc->thickness;

  PetscFunctionBeginUser;
  *active = 0;
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           r[3] = {0, 0, 0}, n[3], Sn[SELF_CONTACT_NP][3], S[SELF_CONTACT_NP][9], vn = 0, wsum = 0, impulse;

    if (contact->distance <= 0) continue;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) r[q] += contact->a[j] * sc->x[3 * loc[j] + q];
    for (PetscInt q = 0; q < 3; q++) n[q] = r[q] / contact->distance;
    /* a particle that a body holds (or a pin) does not move along the constrained directions: its
       share of the impulse is filtered, S n, as in the implicit system */
    ContactFilters(sc, bn, c, S);
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      const PetscScalar *vj = At(sc, v, vr, loc[j]);
      for (PetscInt q = 0; q < 3; q++) Sn[j][q] = S[j][3 * q] * n[0] + S[j][3 * q + 1] * n[1] + S[j][3 * q + 2] * n[2];
      vn += contact->a[j] * PetscRealPart(n[0] * vj[0] + n[1] * vj[1] + n[2] * vj[2]);
      wsum += contact->a[j] * contact->a[j] * InverseMass(sc, contact->p[j]) * Dot3(n, Sn[j]);
    }
    /* the gap after the step, to first order along the normal at the start of the step */
    if (contact->distance + h * vn >= target * (1 - 1e-6) || wsum <= 0) continue;
    impulse = ((target - contact->distance) / h - vn) / wsum;
    (*active)++;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      const PetscReal scale = contact->a[j] * InverseMass(sc, contact->p[j]) * impulse;
      PetscScalar    *vj    = At(sc, v, vr, loc[j]);
      for (PetscInt q = 0; q < 3; q++) vj[q] += scale * Sn[j][q];
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactFilterVelocity(ClothSelfContact sc, PetscReal h, Vec velocity)
{
  PetscInt    it, active = 0, total = 0;
  BodyNormals bn;

  PetscFunctionBeginUser;
  PetscCheck(sc->remote_scatter, sc->comm, PETSC_ERR_ORDER, "Call ClothSelfContactUpdate before ClothSelfContactFilterVelocity");
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  /* the contacts the step will meet: those within the thickness plus their travel at the new velocities */
  PetscCall(Search(sc, sc->thickness, velocity, h));
  PetscCall(BodyNormalsGet(sc, &bn));
  for (it = 0; it < sc->impulse_iterations; it++) {
    PetscScalar *v, *vr;

    /* remote particles: their velocity changes go back to their owners (fremote = new - old) */
    PetscCall(RefreshRemote(sc, velocity, sc->vremote));
    PetscCall(VecCopy(sc->vremote, sc->fremote));
    PetscCall(VecGetArray(velocity, &v));
    PetscCall(VecGetArray(sc->vremote, &vr));
    PetscCall(ImpulseSweep(sc, &bn, h, v, vr, &active));
    PetscCall(VecRestoreArray(sc->vremote, &vr));
    PetscCall(VecRestoreArray(velocity, &v));
    PetscCall(VecAYPX(sc->fremote, -1.0, sc->vremote));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &active, 1, MPIU_INT, MPI_SUM, sc->comm));
    if (!active) break;
    total += active;
    PetscCall(SumRemoteInto(sc, sc->fremote, velocity));
  }
  PetscCall(BodyNormalsRestore(sc, &bn));
  if (active) PetscCall(PetscInfo(NULL, "Self-collision impulses: %" PetscInt_FMT " contacts still closing after %" PetscInt_FMT " iterations\n", active, it));
  sc->impulses += total;
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Brute force (the reference for tests)                                                            */

PetscErrorCode ClothSelfContactFindBruteForce(ClothSelfContact sc, const PetscReal x[], PetscReal radius, PetscInt *n, ClothContact **contacts)
{
  const PetscInt nparticles = sc->layout.nglobal;
  PetscInt       cap        = 64;

  PetscFunctionBeginUser;
  *n = 0;
  PetscCall(PetscMalloc1(cap, contacts));
  for (PetscInt pass = 0; pass < 2; pass++) {
    const PetscInt na = pass == 0 ? nparticles : sc->nedge, nb = pass == 0 ? sc->ntri : sc->nedge;
    for (PetscInt a = 0; a < na; a++)
      for (PetscInt b = pass == 0 ? 0 : a + 1; b < nb; b++) {
        ClothContact     contact;
        const PetscReal *xs[SELF_CONTACT_NP];
        PetscBool        excluded, hit;

        if (pass == 0) {
          contact.p[0] = a;
          for (PetscInt v = 0; v < 3; v++) contact.p[1 + v] = sc->tri[3 * b + v];
          PetscCall(Excluded(sc, contact.p, 1, &contact.p[1], 3, &excluded));
        } else {
          contact.p[0] = sc->edge[2 * a], contact.p[1] = sc->edge[2 * a + 1];
          contact.p[2] = sc->edge[2 * b], contact.p[3] = sc->edge[2 * b + 1];
          PetscCall(Excluded(sc, contact.p, 2, &contact.p[2], 2, &excluded));
        }
        if (excluded) continue;
        for (PetscInt v = 0; v < SELF_CONTACT_NP; v++) xs[v] = &x[3 * contact.p[v]];
        if (pass == 0)
          TestPointTriangle(xs, NULL, radius, &contact, &hit);
        else
          TestEdgeEdge(xs, NULL, radius, &contact, &hit);
        if (!hit) continue;
        if (*n == cap) {
          ClothContact *more;
          cap *= 2;
          PetscCall(PetscMalloc1(cap, &more));
          PetscCall(PetscArraycpy(more, *contacts, *n));
          PetscCall(PetscFree(*contacts));
          *contacts = more;
        }
        (*contacts)[(*n)++] = contact;
      }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Object                                                                                           */

PetscErrorCode ClothSelfContactCreate(Cloth cloth, ClothSelfContact *sc)
{
  ClothSelfContact          s;
  Scene                     full;
  const SceneSelfCollision *scene;

  PetscFunctionBeginUser;
  PetscCall(ClothLogRegister());
  PetscCall(PetscNew(&s));
  PetscCall(ClothGetScene(cloth, &full));
  scene    = &full->self_collision;
  s->cloth = cloth;
  s->scene = full;
  PetscCall(ClothGetComm(cloth, &s->comm));
  s->enabled            = scene->enabled;
  s->thickness          = scene->thickness;
  s->stiffness          = scene->stiffness;
  s->exclude_ring       = scene->given ? scene->exclude_ring : 1;
  s->same_piece         = scene->given ? scene->same_piece : PETSC_TRUE;
  s->min_gap            = 0.25;
  s->impulse_iterations = 100;
  PetscCallMPI(MPI_Comm_size(s->comm, &s->size));
  PetscCallMPI(MPI_Comm_rank(s->comm, &s->rank));
  *sc = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactSetFromOptions(ClothSelfContact sc)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(sc->comm, NULL, "Cloth-cloth collisions (defaults from the scene's self_collision: block)", "ClothSelfContact");
  PetscCall(PetscOptionsBool("-self_collision", "Collide the fabric with itself and with other pieces", "ClothSelfContactSetUp", sc->enabled, &sc->enabled, NULL));
  PetscCall(PetscOptionsReal("-self_collision_thickness", "Distance kept between layers, m", "ClothSelfContactUpdate", sc->thickness, &sc->thickness, NULL));
  PetscCall(PetscOptionsReal("-self_collision_stiffness", "Repulsion stiffness within the thickness, N/m", "ClothSelfContactUpdate", sc->stiffness, &sc->stiffness, NULL));
  PetscCall(PetscOptionsInt("-self_collision_exclude_ring", "Particles of one piece this many grid rings apart or closer never collide", "ClothSelfContactUpdate", sc->exclude_ring, &sc->exclude_ring, NULL));
  PetscCall(PetscOptionsReal("-self_collision_min_gap", "Impulses keep every gap above this fraction of the thickness", "ClothSelfContactFilterVelocity", sc->min_gap, &sc->min_gap, NULL));
  PetscCall(PetscOptionsInt("-self_collision_impulse_iterations", "Largest number of Gauss-Seidel sweeps of the impulse filter per step", "ClothSelfContactFilterVelocity", sc->impulse_iterations, &sc->impulse_iterations, NULL));
  PetscCall(PetscOptionsBool("-self_collision_view", "Print the self-collision settings and statistics at the end", "ClothSelfContactView", sc->view, &sc->view, NULL));
  PetscOptionsEnd();
  if (sc->enabled) {
    PetscReal spacing;

    /* finite and bounded before the cell grid, whose size follows the thickness, is built */
    PetscCall(SceneGetLargestSpacing(sc->scene, &spacing));
    PetscCheck(sc->thickness > 0 && sc->thickness <= SCENE_SELF_COLLISION_MAX_SPACINGS * spacing, sc->comm, PETSC_ERR_USER_INPUT,
               "Self-collision thickness (scene self_collision: thickness, or -self_collision_thickness) %g m: expected a positive number of at most %d particle spacings, %g m", (double)sc->thickness, SCENE_SELF_COLLISION_MAX_SPACINGS,
               (double)(SCENE_SELF_COLLISION_MAX_SPACINGS * spacing));
    PetscCheck(sc->stiffness > 0 && !PetscIsInfOrNanReal(sc->stiffness), sc->comm, PETSC_ERR_USER_INPUT, "Self-collision needs a positive, finite stiffness (scene self_collision: stiffness, or -self_collision_stiffness), got %g N/m",
               (double)sc->stiffness);
    PetscCheck(sc->exclude_ring >= 0, sc->comm, PETSC_ERR_USER_INPUT, "-self_collision_exclude_ring must not be negative, got %" PetscInt_FMT, sc->exclude_ring);
    PetscCheck(sc->min_gap > 0 && sc->min_gap < 1, sc->comm, PETSC_ERR_USER_INPUT, "-self_collision_min_gap must lie in (0, 1), got %g", (double)sc->min_gap);
    PetscCheck(sc->impulse_iterations >= 1, sc->comm, PETSC_ERR_USER_INPUT, "-self_collision_impulse_iterations must be at least 1, got %" PetscInt_FMT, sc->impulse_iterations);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactSetUp(ClothSelfContact sc)
{
  const ClothLayout *layout = &sc->layout;
  PetscBool          cloth_setup;

  PetscFunctionBeginUser;
  if (sc->setup) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothIsSetUp(sc->cloth, &cloth_setup));
  PetscCheck(cloth_setup, sc->comm, PETSC_ERR_ORDER, "Set the cloth up (ClothSetUp) before its self-contact");
  PetscCall(ClothGetLayout(sc->cloth, &sc->layout));
  PetscCall(ClothGetState(sc->cloth, &sc->position, &sc->velocity));
  PetscCall(BuildPrimitives(sc, layout->model));
  PetscCall(BuildIncidence(layout->nglobal, sc->ntri, 3, sc->tri, &sc->tri_start, &sc->tri_of));
  PetscCall(BuildIncidence(layout->nglobal, sc->nedge, 2, sc->edge, &sc->edge_start, &sc->edge_of));
  PetscCall(BuildGridPositions(sc, layout->scene, layout->model));
  PetscCall(PetscMalloc1(layout->nglobal, &sc->contact_index));
  for (PetscInt g = 0; g < layout->nglobal; g++) sc->contact_index[g] = -1;
  PetscCall(PetscCalloc2(sc->ntri + 1, &sc->tri_mark, sc->nedge + 1, &sc->edge_mark));
  PetscCall(CellGridCreate(&sc->triangle_grid));
  PetscCall(CellGridCreate(&sc->edge_grid));
  sc->setup = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The contribution's add (cloth.h). */
static PetscErrorCode AddContribution(void *ctx, const ClothContributionArgs *args)
{
  PetscFunctionBeginUser;
  PetscCall(AddRepulsion((ClothSelfContact)ctx, args->position, args->velocity, args->force, args->kv, args->A, args->h2, args->psd, args->energy));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactGetContribution(ClothSelfContact sc, ClothContribution *contribution)
{
  PetscFunctionBeginUser;
  contribution->name             = "self-contact";
  contribution->ctx              = sc;
  contribution->add              = AddContribution;
  contribution->count_row_blocks = CountRowBlocks;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactGetEnabled(ClothSelfContact sc, PetscBool *enabled)
{
  PetscFunctionBeginUser;
  *enabled = sc->enabled;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactSetExclusion(ClothSelfContact sc, ClothSelfContactExcludeFn exclude, void *ctx)
{
  PetscFunctionBeginUser;
  sc->exclude     = exclude;
  sc->exclude_ctx = ctx;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactUpdate(ClothSelfContact sc, PetscReal h, PetscBool *pattern_changed)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSelfContactSetUp(sc));
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  /* at the velocities of the start of the step; the velocity filter searches again at the new ones */
  PetscCall(Search(sc, sc->thickness, sc->velocity, h));
  if (pattern_changed) PetscCall(UpdatePattern(sc, pattern_changed));
  sc->searches++;
  sc->contacts_found += sc->ncontacts;
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactFind(ClothSelfContact sc, PetscReal radius)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSelfContactSetUp(sc));
  PetscCall(Search(sc, radius, NULL, 0.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactGetContacts(ClothSelfContact sc, PetscInt *n, const ClothContact **contacts)
{
  PetscFunctionBeginUser;
  *n        = sc->ncontacts;
  *contacts = sc->contacts;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactGetContactField(ClothSelfContact sc, Vec field, PetscInt *ncontacts, PetscInt *nparticles)
{
  const PetscScalar *f;
  PetscInt           n, counts[2] = {sc->ncontacts, 0};

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(field));
  for (PetscInt c = 0; c < sc->ncontacts; c++)
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) PetscCall(VecSetValue(field, sc->contacts[c].p[k], 1.0, ADD_VALUES));
  PetscCall(VecAssemblyBegin(field));
  PetscCall(VecAssemblyEnd(field));
  PetscCall(VecGetLocalSize(field, &n));
  PetscCall(VecGetArrayRead(field, &f));
  for (PetscInt i = 0; i < n; i++) counts[1] += PetscRealPart(f[i]) > 0;
  PetscCall(VecRestoreArrayRead(field, &f));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPIU_INT, MPI_SUM, sc->comm));
  *ncontacts  = counts[0];
  *nparticles = counts[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactView(ClothSelfContact sc, PetscViewer viewer)
{
  PetscInt local[3] = {sc->contacts_found, sc->impulses, sc->nremote}, sum[3];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(local, sum, 3, MPIU_INT, MPI_SUM, sc->comm));
  if (!sc->enabled) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Self-collision: off\n"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "Self-collision: thickness %g m, stiffness %g N/m, particles within %" PetscInt_FMT " ring(s) excluded%s, impulses keep gaps above %g x thickness\n", (double)sc->thickness, (double)sc->stiffness,
                                   sc->exclude_ring, sc->same_piece ? "" : ", one piece never collides with itself", (double)sc->min_gap));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  %" PetscInt_FMT " searches, %.1f contacts per search, %" PetscInt_FMT " impulses, %" PetscInt_FMT " matrix pattern rebuilds, %" PetscInt_FMT " remote particles at the last search\n", sc->searches,
                                   sc->searches ? (double)sum[0] / (double)sc->searches : 0.0, sum[1], sc->rebuilds, sum[2]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactDestroy(ClothSelfContact *sc)
{
  ClothSelfContact s = *sc;

  PetscFunctionBeginUser;
  if (!s) PetscFunctionReturn(PETSC_SUCCESS);
  if (s->view) PetscCall(ClothSelfContactView(s, PETSC_VIEWER_STDOUT_(s->comm)));
  PetscCall(PetscFree(s->tri));
  PetscCall(PetscFree(s->edge));
  PetscCall(PetscFree(s->tri_start));
  PetscCall(PetscFree(s->tri_of));
  PetscCall(PetscFree(s->edge_start));
  PetscCall(PetscFree(s->edge_of));
  PetscCall(PetscFree3(s->piece_of, s->grid_i, s->grid_j));
  PetscCall(PetscFree(s->remote_natural));
  PetscCall(PetscFree(s->natural_of));
  PetscCall(PetscFree(s->contact_index));
  PetscCall(PetscFree2(s->x, s->dx));
  PetscCall(PetscFree2(s->tri_mark, s->edge_mark));
  PetscCall(CellGridDestroy(&s->triangle_grid));
  PetscCall(CellGridDestroy(&s->edge_grid));
  PetscCall(PetscFree2(s->contacts, s->local));
  PetscCall(PetscFree(s->extra));
  PetscCall(VecDestroy(&s->xremote));
  PetscCall(VecDestroy(&s->vremote));
  PetscCall(VecDestroy(&s->fremote));
  PetscCall(VecDestroy(&s->kvremote));
  PetscCall(VecDestroy(&s->bremote));
  PetscCall(VecScatterDestroy(&s->remote_scatter));
  PetscCall(PetscFree(*sc));
  PetscFunctionReturn(PETSC_SUCCESS);
}
