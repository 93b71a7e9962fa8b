/* ClothSelfContact, the search side (see selfcontact_impl.h): static topology of triangles and edges, the exchange of
   particles near other ranks, the proximity search on cell grids (point-triangle and edge-edge, geometry.h,
   cellgrid.h) and its brute-force reference for tests. */
#include "selfcontact_impl.h"
#include "geometry.h"
#include "log.h"
#include "vec3.h"

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

/* Does the contact come within radius of closing during the step: the smallest distance |r + t dr|, t in [0, 1], of its
   separation r (closest points at the step's start, weights frozen) moving by the relative travel dr of those points
   over the step (ds: the particles' displacements over the step; NULL: none, then |r| alone)? A pair that the step
   moves as one (a sheet falling as a whole, a layer sliding in its own plane) has dr = 0, however fast it moves. */
static PetscBool Within(const ClothContact *contact, const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius)
{
  PetscReal dr[3] = {0, 0, 0}, r[3], t = 0, dd;

  if (ds) Separation(ds, contact->a, dr);
  dd = Dot3(dr, dr);
  for (PetscInt c = 0; c < 3; c++) r[c] = contact->r[c];
  if (dd > 0) t = PetscMin(1.0, PetscMax(0.0, -Dot3(r, dr) / dd));
  for (PetscInt c = 0; c < 3; c++) r[c] += t * dr[c];
  return Dot3(r, r) < radius * radius ? PETSC_TRUE : PETSC_FALSE;
}

/* The contact of particle xs[0] with triangle xs[1..3], if within radius (see Within). */
static void TestPointTriangle(const PetscReal *const xs[SELF_CONTACT_NP], const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius, ClothContact *contact, PetscBool *hit)
{
  PetscReal w[3], r[3];

  GeometryClosestPointTriangle(xs[0], xs[1], xs[2], xs[3], w);
  contact->kind  = CLOTH_CONTACT_POINT_TRIANGLE;
  contact->scale = 1;
  contact->a[0] = 1, contact->a[1] = -w[0], contact->a[2] = -w[1], contact->a[3] = -w[2];
  Separation(xs, contact->a, r);
  for (PetscInt c = 0; c < 3; c++) contact->r[c] = r[c];
  contact->distance = PetscSqrtReal(Dot3(r, r));
  *hit              = Within(contact, ds, radius);
}

/* The share of an edge-edge contact's repulsion: 1 where its closest points lie well inside both edges, falling to 0
   as either reaches an end of its edge (within SELF_CONTACT_EDGE_RAMP of it). At an end it is a particle that comes
   near the other edge, which its point-triangle contact (NearestOnFabric) holds; the ramp lets the edge pair's force
   fade in and out continuously instead of doubling it, so that only edges that cross (in the projection along their
   separation) repel: a few per edge of a facing layer, however fine its grid. */
#define SELF_CONTACT_EDGE_RAMP 0.1
static PetscReal EdgePairScale(const ClothContact *contact)
{
  const PetscReal s = contact->a[1], t = -contact->a[3];

  return PetscMax(0.0, PetscMin(1.0, PetscMin(PetscMin(s, 1 - s), PetscMin(t, 1 - t)) / SELF_CONTACT_EDGE_RAMP));
}

/* The contact of edge xs[0] xs[1] with edge xs[2] xs[3], if within radius (see Within). */
static void TestEdgeEdge(const PetscReal *const xs[SELF_CONTACT_NP], const PetscReal *const ds[SELF_CONTACT_NP], PetscReal radius, ClothContact *contact, PetscBool *hit)
{
  PetscReal s, t, r[3];

  GeometryClosestPointsSegments(xs[0], xs[1], xs[2], xs[3], &s, &t);
  contact->kind = CLOTH_CONTACT_EDGE_EDGE;
  contact->a[0] = 1 - s, contact->a[1] = s, contact->a[2] = -(1 - t), contact->a[3] = -t;
  contact->scale = EdgePairScale(contact);
  Separation(xs, contact->a, r);
  for (PetscInt c = 0; c < 3; c++) contact->r[c] = r[c];
  contact->distance = PetscSqrtReal(Dot3(r, r));
  *hit              = Within(contact, ds, radius);
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

int SelfContactCompareInt64(const void *a, const void *b)
{
  const PetscInt64 x = *(const PetscInt64 *)a, y = *(const PetscInt64 *)b;

  return x < y ? -1 : (x > y ? 1 : 0);
}

/* Triangles (a b c), (a c d) of every quad, and the unique edges: the quad sides and that diagonal. */
PetscErrorCode SelfContactBuildPrimitives(ClothSelfContact sc, ClothModel m)
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
PetscErrorCode SelfContactBuildIncidence(PetscInt nparticles, PetscInt nprim, PetscInt nv, const PetscInt prim[], PetscInt **start, PetscInt **of)
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
PetscErrorCode SelfContactBuildGridPositions(ClothSelfContact sc, Scene scene, ClothModel m)
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

PetscErrorCode SelfContactSetExclusionRings(ClothSelfContact sc)
{
  const ClothLayout *layout  = &sc->layout;
  const PetscInt     npieces = layout->model->npieces;
  PetscReal         *spacing;

  PetscFunctionBeginUser;
  /* each piece's shortest link between grid neighbours at rest (a rank evaluates some links of a piece, or none) */
  PetscCall(PetscMalloc1(npieces, &spacing));
  PetscCall(PetscMalloc1(npieces, &sc->ring));
  for (PetscInt k = 0; k < npieces; k++) spacing[k] = PETSC_MAX_REAL;
  for (PetscInt l = 0; l < layout->nlinks; l++) {
    const PetscInt g0 = layout->natural_of_local[layout->links[l].p[0]], g1 = layout->natural_of_local[layout->links[l].p[1]];
    if (sc->piece_of[g0] != sc->piece_of[g1] || PetscAbsInt(sc->grid_i[g0] - sc->grid_i[g1]) + PetscAbsInt(sc->grid_j[g0] - sc->grid_j[g1]) != 1) continue; /* not a thread link */
    spacing[sc->piece_of[g0]] = PetscMin(spacing[sc->piece_of[g0]], layout->link_params[layout->links[l].param].rest);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, spacing, (PetscMPIInt)npieces, MPIU_REAL, MPIU_MIN, sc->comm));
  /* particles (R + 1) rings apart lie at least (R + 1) spacings apart in the pattern */
  for (PetscInt k = 0; k < npieces; k++) {
    const PetscReal rings = spacing[k] < PETSC_MAX_REAL ? sc->exclude_thicknesses * sc->thickness / spacing[k] : 0;
    sc->ring[k]           = PetscMax(sc->exclude_ring, (PetscInt)PetscCeilReal(rings) - 1);
  }
  PetscCall(PetscFree(spacing));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Are the primitives with particles pa[0..na) and pb[0..nb) (natural) too close in one piece to collide (within the
   piece's exclusion ring, SelfContactSetExclusionRings, or same_piece off)? These exclusions never change: the
   search leaves such pairs out before any geometry. */
PetscBool SelfContactRingExcluded(ClothSelfContact sc, const PetscInt pa[], PetscInt na, const PetscInt pb[], PetscInt nb)
{
  for (PetscInt i = 0; i < na; i++)
    for (PetscInt j = 0; j < nb; j++) {
      const PetscInt a = pa[i], b = pb[j], piece = sc->piece_of[a];
      if (piece == sc->piece_of[b]) {
        const PetscInt ring = PetscMax(PetscAbsInt(sc->grid_i[a] - sc->grid_i[b]), PetscAbsInt(sc->grid_j[a] - sc->grid_j[b]));
        if (!sc->same_piece || ring <= sc->ring[piece]) return PETSC_TRUE;
      }
    }
  return PETSC_FALSE;
}

/* Does the exclusion callback exclude the primitives with particles pa[0..na) and pb[0..nb)? It changes as seams
   close, so it is asked at every search, about the pairs within reach only. */
static PetscErrorCode CallbackExcluded(ClothSelfContact sc, const PetscInt pa[], PetscInt na, const PetscInt pb[], PetscInt nb, PetscBool *excluded)
{
  PetscFunctionBeginUser;
  *excluded = PETSC_FALSE;
  if (!sc->exclude) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < na && !*excluded; i++)
    for (PetscInt j = 0; j < nb && !*excluded; j++) PetscCall(sc->exclude(sc->exclude_ctx, pa[i], pb[j], excluded));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Must the primitives with particles pa[0..na) and pb[0..nb) (natural) never be in contact? */
static PetscErrorCode Excluded(ClothSelfContact sc, const PetscInt pa[], PetscInt na, const PetscInt pb[], PetscInt nb, PetscBool *excluded)
{
  PetscFunctionBeginUser;
  *excluded = SelfContactRingExcluded(sc, pa, na, pb, nb);
  if (!*excluded) PetscCall(CallbackExcluded(sc, pa, na, pb, nb, excluded));
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

PetscErrorCode SelfContactSameParticles(ClothSelfContact sc, PetscBool have, PetscInt n, const PetscInt list[], PetscInt nold, const PetscInt old[], PetscBool *all_same)
{
  PetscBool same = (have && n == nold) ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; same && k < n; k++)
    if (list[k] != old[k]) same = PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(&same, all_same, 1, MPIU_BOOL, MPI_LAND, sc->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactCreateScatter(ClothSelfContact sc, PetscInt n, const PetscInt natural[], Vec target, VecScatter *scatter)
{
  PetscInt *solver;
  IS        from;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &solver));
  for (PetscInt k = 0; k < n; k++) solver[k] = sc->layout.solver_of_natural[natural[k]];
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, 3, n, solver, PETSC_OWN_POINTER, &from));
  PetscCall(VecScatterCreate(sc->position, from, target, NULL, scatter));
  PetscCall(ISDestroy(&from));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The scatter from the cloth's state to the remote particles, rebuilt when the set changes. */
static PetscErrorCode SetRemoteParticles(ClothSelfContact sc, PetscInt nrecv, PetscInt *recv)
{
  PetscBool all_same;

  PetscFunctionBeginUser;
  PetscCall(SelfContactSameParticles(sc, sc->remote_scatter ? PETSC_TRUE : PETSC_FALSE, nrecv, recv, sc->nremote, sc->remote_natural, &all_same));
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
  PetscCall(VecDestroy(&sc->wremote));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3 * nrecv, &sc->xremote));
  PetscCall(VecSetBlockSize(sc->xremote, 3));
  PetscCall(VecDuplicate(sc->xremote, &sc->vremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->fremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->kvremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->bremote));
  PetscCall(VecDuplicate(sc->xremote, &sc->wremote));
  PetscCall(SelfContactCreateScatter(sc, nrecv, recv, sc->xremote, &sc->remote_scatter));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactRefreshRemote(ClothSelfContact sc, Vec global, Vec remote)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(sc->remote_scatter, global, remote, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc->remote_scatter, global, remote, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactSumRemoteInto(ClothSelfContact sc, Vec remote, Vec global)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(sc->remote_scatter, remote, global, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sc->remote_scatter, remote, global, ADD_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Contact-local numbering of a new list: owned particles (solver order), then the remote ones. */
static PetscErrorCode SetContactLocalNumbering(ClothSelfContact sc)
{
  const ClothLayout *layout = &sc->layout;
  const PetscInt     n      = layout->nlocal + sc->nremote;

  PetscFunctionBeginUser;
  if (sc->natural_of)
    for (PetscInt k = 0; k < layout->nlocal + sc->nremote_prev; k++) sc->contact_index[sc->natural_of[k]] = -1;
  if (n > sc->nalloc) {
    PetscCall(PetscFree(sc->natural_of));
    PetscCall(PetscFree3(sc->x, sc->dx, sc->x0));
    sc->nalloc = n + n / 4;
    PetscCall(PetscMalloc1(sc->nalloc + 1, &sc->natural_of));
    PetscCall(PetscMalloc3(3 * sc->nalloc + 1, &sc->x, 3 * sc->nalloc + 1, &sc->dx, 3 * sc->nalloc + 1, &sc->x0));
  }
  for (PetscInt k = 0; k < n; k++) {
    sc->natural_of[k]                    = k < layout->nlocal ? layout->natural_of_local[k] : sc->remote_natural[k - layout->nlocal];
    sc->contact_index[sc->natural_of[k]] = k;
  }
  sc->nremote_prev = sc->nremote;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Contact-local positions and displacements over the step (h velocity; zero without velocity). Collective. */
static PetscErrorCode LoadContactLocalState(ClothSelfContact sc, Vec velocity, PetscReal h)
{
  const ClothLayout *layout = &sc->layout;
  const PetscInt     n      = layout->nlocal + sc->nremote;
  const PetscScalar *x, *xr, *v = NULL, *vr = NULL;

  PetscFunctionBeginUser;
  if (velocity) {
    PetscCall(SelfContactRefreshRemote(sc, velocity, sc->vremote));
    PetscCall(VecGetArrayRead(velocity, &v));
    PetscCall(VecGetArrayRead(sc->vremote, &vr));
  }
  PetscCall(SelfContactRefreshRemote(sc, sc->position, sc->xremote));
  PetscCall(VecGetArrayRead(sc->position, &x));
  PetscCall(VecGetArrayRead(sc->xremote, &xr));
  for (PetscInt k = 0; k < n; k++) {
    const PetscBool owned = k < layout->nlocal ? PETSC_TRUE : PETSC_FALSE;
    for (PetscInt c = 0; c < 3; c++) sc->x[3 * k + c] = PetscRealPart(owned ? x[3 * k + c] : xr[3 * (k - layout->nlocal) + c]);
    for (PetscInt c = 0; c < 3; c++) sc->dx[3 * k + c] = v ? h * PetscRealPart(owned ? v[3 * k + c] : vr[3 * (k - layout->nlocal) + c]) : 0.0;
  }
  PetscCall(VecRestoreArrayRead(sc->xremote, &xr));
  PetscCall(VecRestoreArrayRead(sc->position, &x));
  if (velocity) {
    PetscCall(VecRestoreArrayRead(sc->vremote, &vr));
    PetscCall(VecRestoreArrayRead(velocity, &v));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactGrowArray(size_t size, PetscInt n, PetscInt *max, PetscInt extra, void *array)
{
  void **old = (void **)array, *more;

  PetscFunctionBeginUser;
  *max = 2 * *max + extra;
  PetscCall(PetscMalloc(size * (size_t)*max, &more));
  if (n > 0) PetscCall(PetscMemcpy(more, *old, size * (size_t)n));
  PetscCall(PetscFree(*old));
  *old = more;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Candidate list                                                                                   */

static PetscErrorCode AppendCandidate(ClothSelfContact sc, ClothContactKind kind, const PetscInt p[SELF_CONTACT_NP])
{
  SelfContactCandidate *cand;

  PetscFunctionBeginUser;
  if (sc->ncandidates == sc->maxcandidates) PetscCall(SelfContactGrowArray(sizeof(SelfContactCandidate), sc->ncandidates, &sc->maxcandidates, 256, &sc->candidates));
  cand       = &sc->candidates[sc->ncandidates++];
  cand->kind = kind;
  for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) {
    cand->p[k]     = p[k];
    cand->local[k] = sc->contact_index[p[k]];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A contact with its particles' local indices, as FilterCandidates returns them. */
typedef struct {
  ClothContact contact;
  PetscInt     local[SELF_CONTACT_NP];
} SelfContactEntry;

static int CompareContactEntries(const void *pa, const void *pb)
{
  const ClothContact *a = &((const SelfContactEntry *)pa)->contact, *b = &((const SelfContactEntry *)pb)->contact;

  if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
  for (PetscInt k = 0; k < SELF_CONTACT_NP; k++)
    if (a->p[k] != b->p[k]) return a->p[k] < b->p[k] ? -1 : 1;
  return 0;
}

/* The contacts in a canonical order (kind, then particles' natural numbers), whatever the order of the candidate list
   they came from: a list built at another step (after a restart) or on other ranks gives the same sums. Sorting the
   few contacts, not the many candidates (the 12 mm dress: 150,000 candidates a build on each rank, 0.4-30 contacts),
   costs nothing. */
static PetscErrorCode SortContacts(ClothSelfContact sc)
{
  SelfContactEntry *entry;

  PetscFunctionBeginUser;
  if (sc->ncontacts < 2) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscMalloc1(sc->ncontacts, &entry));
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    entry[c].contact = sc->contacts[c];
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) entry[c].local[k] = sc->local[SELF_CONTACT_NP * c + k];
  }
  qsort(entry, (size_t)sc->ncontacts, sizeof(SelfContactEntry), CompareContactEntries);
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    sc->contacts[c] = entry[c].contact;
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) sc->local[SELF_CONTACT_NP * c + k] = entry[c].local[k];
  }
  PetscCall(PetscFree(entry));
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

/* ------------------------------------------------------------------------------------------------ */
/* Search                                                                                           */

static PetscErrorCode AppendContact(ClothSelfContact sc, const ClothContact *contact, const PetscInt local[SELF_CONTACT_NP])
{
  PetscFunctionBeginUser;
  if (sc->ncontacts == sc->maxcontacts) {
    ClothContact *contacts;
    PetscInt     *more;

    sc->maxcontacts = 2 * sc->maxcontacts + 64;
    PetscCall(PetscMalloc2(sc->maxcontacts, &contacts, SELF_CONTACT_NP * sc->maxcontacts, &more));
    PetscCall(PetscArraycpy(contacts, sc->contacts, sc->ncontacts));
    PetscCall(PetscArraycpy(more, sc->local, SELF_CONTACT_NP * sc->ncontacts));
    PetscCall(PetscFree2(sc->contacts, sc->local));
    sc->contacts = contacts;
    sc->local    = more;
  }
  sc->contacts[sc->ncontacts] = *contact;
  for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) sc->local[SELF_CONTACT_NP * sc->ncontacts + k] = local[k];
  sc->ncontacts++;
  PetscFunctionReturn(PETSC_SUCCESS);
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

/* Positions of natural particles: x[3 index[g]] (index NULL: x[3 g], the whole fabric in natural order); a particle
   with index[g] < 0 is not present. */
typedef struct {
  const PetscReal *x;
  const PetscInt  *index;
} SelfContactPositions;

static inline const PetscReal *PositionOf(const SelfContactPositions *P, PetscInt g)
{
  return &P->x[3 * (P->index ? P->index[g] : g)];
}

/* Squared distance from p to triangle t, computed alike wherever it is asked. */
static PetscReal TriangleDistance2(ClothSelfContact sc, const SelfContactPositions *P, const PetscReal p[3], PetscInt t)
{
  const PetscInt  *v = &sc->tri[3 * t];
  const PetscReal *a = PositionOf(P, v[0]), *b = PositionOf(P, v[1]), *c = PositionOf(P, v[2]);
  PetscReal        w[3], r[3];

  GeometryClosestPointTriangle(p, a, b, c, w);
  for (PetscInt k = 0; k < 3; k++) r[k] = p[k] - w[0] * a[k] - w[1] * b[k] - w[2] * c[k];
  return Dot3(r, r);
}

/* Are triangle t's particles all present? */
static PetscBool TrianglePresent(ClothSelfContact sc, const SelfContactPositions *P, PetscInt t)
{
  for (PetscInt k = 0; k < 3 && P->index; k++)
    if (P->index[sc->tri[3 * t + k]] < 0) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* Is triangle t the nearest to particle me (at p) among the triangles that share a particle with it and are not
   excluded from contact with me (a tie goes to the lower triangle number)? Where the distance from me to the fabric,
   taken without me's excluded neighbourhood, has a local minimum, exactly one triangle around it is: a particle facing
   a layer meets one triangle of it, the one under it, however fine the layer's grid, rather than every triangle within
   the thickness. As the particle moves the nearest passes to a neighbour where the two are equally near, at a point
   they share, so the force does not jump (nor between runs on different ranks, whose rounding may pick the other of
   two equal triangles). Near me's own neighbourhood the minimum lies at the edge of the exclusion, which holds a tight
   fold apart and lies farther than the thickness in a flat layer (SelfContactSetExclusionRings). The search brings
   every particle within two links of a candidate's, so the triangles compared are present wherever the pair is
   examined. */
static PetscBool NearestOnFabric(ClothSelfContact sc, const SelfContactPositions *P, PetscInt me, const PetscReal p[3], PetscInt t)
{
  const PetscReal d2 = TriangleDistance2(sc, P, p, t);

  for (PetscInt k = 0; k < 3; k++) {
    const PetscInt v = sc->tri[3 * t + k];
    for (PetscInt q = sc->tri_start[v]; q < sc->tri_start[v + 1]; q++) {
      const PetscInt o = sc->tri_of[q];
      PetscReal      d2o;

      if (o == t || !TrianglePresent(sc, P, o) || SelfContactRingExcluded(sc, &me, 1, &sc->tri[3 * o], 3)) continue;
      d2o = TriangleDistance2(sc, P, p, o);
      if (d2o < d2 || (d2o == d2 && o < t)) return PETSC_FALSE;
    }
  }
  return PETSC_TRUE;
}

/* Is this rank the one that handles the edge-edge contact of edges e1 and e2 (particles p)? Any owner
   of one of its particles has all four (the exchange margin covers two edges and the radius), so the
   owner of particle (e1 + e2) mod 4 is chosen: a rule that spreads contacts between two pieces owned
   by two ranks over both, where "the lowest particle" would give them all to one. */
PetscBool SelfContactHandlesEdgePair(ClothSelfContact sc, PetscInt e1, PetscInt e2, const PetscInt p[4])
{
  return sc->layout.part[p[(e1 + e2) % 4]] == sc->rank ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode SelfContactTestPair(ClothSelfContact sc, ClothContactKind kind, PetscInt a, PetscInt b, PetscReal rho)
{
  const SelfContactPositions here = {sc->x, sc->contact_index};
  const PetscReal           *xs[SELF_CONTACT_NP], *ds[SELF_CONTACT_NP];
  ClothContact               contact;
  PetscBool                  hit;

  PetscFunctionBeginUser;
  sc->primitive_pairs_total++;
  if (kind == CLOTH_CONTACT_POINT_TRIANGLE) {
    contact.p[0] = a;
    for (PetscInt v = 0; v < 3; v++) contact.p[1 + v] = sc->tri[3 * b + v];
  } else {
    contact.p[0] = sc->edge[2 * a], contact.p[1] = sc->edge[2 * a + 1];
    contact.p[2] = sc->edge[2 * b], contact.p[3] = sc->edge[2 * b + 1];
  }
  for (PetscInt v = 0; v < SELF_CONTACT_NP; v++) xs[v] = &sc->x[3 * sc->contact_index[contact.p[v]]], ds[v] = &sc->dx[3 * sc->contact_index[contact.p[v]]];
  if (kind == CLOTH_CONTACT_POINT_TRIANGLE) {
    TestPointTriangle(xs, ds, rho, &contact, &hit);
    if (hit) hit = NearestOnFabric(sc, &here, a, xs[0], b);
  } else {
    TestEdgeEdge(xs, ds, rho, &contact, &hit);
    if (hit) hit = contact.scale > 0 ? PETSC_TRUE : PETSC_FALSE;
  }
  if (hit) PetscCall(AppendCandidate(sc, kind, contact.p));
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

/* change[0]: the largest displacement of an owned particle since the candidates were found (infinite when there are
   none); change[1]: the largest change of an owned particle's displacement over the step, h v, since then; both over
   all ranks, infinite when a value is not finite (the search then checks the state). One reduction: the only one of
   a search that keeps the candidates. Collective. */
static PetscErrorCode CandidateChange(ClothSelfContact sc, Vec velocity, PetscReal h, PetscReal change[2])
{
  const PetscInt     n        = sc->layout.nlocal;
  PetscReal          local[2] = {0, 0};
  const PetscScalar *x, *v = NULL;

  PetscFunctionBeginUser;
  if (!sc->list_valid) local[0] = local[1] = PETSC_INFINITY;
  PetscCall(VecGetArrayRead(sc->position, &x));
  if (velocity) PetscCall(VecGetArrayRead(velocity, &v));
  for (PetscInt i = 0; i < n && sc->list_valid; i++) {
    PetscReal dxx = 0, dvv = 0;
    for (PetscInt c = 0; c < 3; c++) {
      dxx += PetscSqr(PetscRealPart(x[3 * i + c]) - sc->x0[3 * i + c]);
      dvv += PetscSqr((v ? h * PetscRealPart(v[3 * i + c]) : 0.0) - sc->dx0[3 * i + c]);
    }
    local[0] = PetscIsInfOrNanReal(dxx) ? PETSC_INFINITY : PetscMax(local[0], dxx); /* PetscMax would drop a NaN */
    local[1] = PetscIsInfOrNanReal(dvv) ? PETSC_INFINITY : PetscMax(local[1], dvv);
  }
  if (velocity) PetscCall(VecRestoreArrayRead(velocity, &v));
  PetscCall(VecRestoreArrayRead(sc->position, &x));
  local[0] = PetscSqrtReal(local[0]);
  local[1] = PetscSqrtReal(local[1]);
  PetscCallMPI(MPI_Allreduce(local, change, 2, MPIU_REAL, MPIU_MAX, sc->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest travel h |v| of a particle over the step, over all ranks (infinite when not finite). Collective. */
static PetscErrorCode LargestTravel(ClothSelfContact sc, Vec velocity, PetscReal h, PetscReal *travel)
{
  const PetscScalar *v;
  PetscReal          local = 0;

  PetscFunctionBeginUser;
  *travel = 0;
  if (!velocity) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecGetArrayRead(velocity, &v));
  for (PetscInt i = 0; i < sc->layout.nlocal; i++) {
    const PetscReal vv = PetscRealPart(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    local              = PetscIsInfOrNanReal(vv) ? PETSC_INFINITY : PetscMax(local, vv);
  }
  PetscCall(VecRestoreArrayRead(velocity, &v));
  local = h * PetscSqrtReal(local);
  PetscCallMPI(MPI_Allreduce(&local, travel, 1, MPIU_REAL, MPIU_MAX, sc->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Finds the candidates of searches within radius at the current positions, for displacements over the step that
   differ from h velocity by at most the margin (velocity_margin x radius) per particle: the pairs that come within
   rho = radius + 2 margin during the step, each found from the boxes its primitives sweep over the step, so that the
   particles' common motion adds nothing; with the exchange of the particles near other ranks and the cell grids.
   *ok false: the state is not finite (no candidates). Collective. */
static PetscErrorCode BuildCandidates(ClothSelfContact sc, PetscReal radius, Vec velocity, PetscReal h, PetscBool *ok)
{
  const PetscReal    margin = sc->velocity_margin * radius, rho = radius + 2 * margin;
  const PetscScalar *x;
  PetscReal          link, travel, region[6], far;
  PetscInt           nrecv = 0, *recv = NULL, nonfinite, farthest;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.self_build, 0, 0, 0, 0));
  sc->list_valid     = PETSC_FALSE;
  sc->any_candidates = PETSC_FALSE;
  sc->ncandidates    = 0;
  *ok                = PETSC_FALSE;
  PetscCall(LongestLink(sc, &link));
  PetscCall(LargestTravel(sc, velocity, h, &travel));
  PetscCall(VecGetArrayRead(sc->position, &x));
  /* a pair's handler owns one of its particles; the others lie within rho, both primitives' travels and two triangle
     edges (four links), and the triangles that NearestOnFabric compares two links further */
  PetscCall(ExchangeNearParticles(sc, x, rho + 2 * travel + 6 * link, &nrecv, &recv));
  PetscCall(VecRestoreArrayRead(sc->position, &x));
  PetscCall(SetRemoteParticles(sc, nrecv, recv));
  PetscCall(SetContactLocalNumbering(sc));
  PetscCall(LoadContactLocalState(sc, velocity, h));
  ContactRegion(sc, rho, region);
  PetscCall(CheckSearchFinite(sc, region, &nonfinite, &farthest, &far));
  if (nonfinite >= 0) {
    /* a diverged state has no meaningful contacts; the integrator's test of the state at the end of the
       step fails that step, which is halved and, failing at every size, ends the run at its last good
       state, as it does without self-collision */
    PetscCall(PetscInfo(NULL, "Self-collision search skipped: particle %" PetscInt_FMT " (natural numbering) has a non-finite position or velocity\n", nonfinite));
    PetscCall(PetscLogEventEnd(ClothLog.self_build, 0, 0, 0, 0));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCheck(farthest < 0, sc->comm, PETSC_ERR_FP,
             "Self-collision: the region that the particles sweep over a step of %g s, widened by the contact radius %g m, is too large for a cell grid: particle %" PetscInt_FMT
             " (natural numbering) reaches %g m from the origin. The state has diverged, or the self-collision thickness is far too large",
             (double)h, (double)radius, farthest, (double)far);
  PetscCall(SelfContactPairPrimitives(sc, region, rho));
  sc->any_candidates = sc->ncandidates > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &sc->any_candidates, 1, MPIU_BOOL, MPI_LOR, sc->comm));
  PetscCall(PetscArraycpy(sc->x0, sc->x, 3 * sc->layout.nlocal));
  PetscCall(PetscArraycpy(sc->dx0, sc->dx, 3 * sc->layout.nlocal));
  sc->list_valid  = PETSC_TRUE;
  sc->list_radius = radius;
  sc->list_margin = margin;
  sc->builds++;
  sc->candidates_built += sc->ncandidates;
  sc->candidates_max = PetscMax(sc->candidates_max, sc->ncandidates);
  *ok                = PETSC_TRUE;
  PetscCall(PetscLogEventEnd(ClothLog.self_build, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The contacts: the candidates that come within radius during the step (see Within) and that the exclusion callback
   allows. */
static PetscErrorCode FilterCandidates(ClothSelfContact sc, PetscReal radius)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.self_filter, 0, 0, 0, 0));
  sc->ncontacts = 0;
  for (PetscInt c = 0; c < sc->ncandidates; c++) {
    const SelfContactCandidate *cand = &sc->candidates[c];
    const PetscReal            *xs[SELF_CONTACT_NP], *ds[SELF_CONTACT_NP];
    ClothContact                contact;
    PetscBool                   hit, excluded;

    for (PetscInt v = 0; v < SELF_CONTACT_NP; v++) xs[v] = &sc->x[3 * cand->local[v]], ds[v] = &sc->dx[3 * cand->local[v]];
    if (cand->kind == CLOTH_CONTACT_POINT_TRIANGLE)
      TestPointTriangle(xs, ds, radius, &contact, &hit);
    else
      TestEdgeEdge(xs, ds, radius, &contact, &hit);
    if (!hit) continue;
    if (cand->kind == CLOTH_CONTACT_POINT_TRIANGLE)
      PetscCall(CallbackExcluded(sc, cand->p, 1, &cand->p[1], 3, &excluded));
    else
      PetscCall(CallbackExcluded(sc, cand->p, 2, &cand->p[2], 2, &excluded));
    if (excluded) continue;
    contact.kind = cand->kind;
    for (PetscInt v = 0; v < SELF_CONTACT_NP; v++) contact.p[v] = cand->p[v];
    PetscCall(AppendContact(sc, &contact, cand->local));
  }
  PetscCall(SortContacts(sc));
  PetscCall(PetscLogEventEnd(ClothLog.self_filter, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* All contacts within radius during a step of h at velocity (NULL: at the current positions), at the cloth's current
   positions. The candidates found at these positions serve again while no particle's displacement over the step
   differs from theirs by more than their margin (the velocity filter's search after the solve, at the same
   positions); otherwise they are found anew. Collective. */
PetscErrorCode SelfContactSearch(ClothSelfContact sc, PetscReal radius, Vec velocity, PetscReal h)
{
  PetscReal change[2];
  PetscBool ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(CandidateChange(sc, velocity, h, change));
  sc->ncontacts = 0;
  if (sc->list_valid && radius == sc->list_radius && change[0] == 0 && change[1] <= sc->list_margin) {
    if (!sc->any_candidates) PetscFunctionReturn(PETSC_SUCCESS); /* no contact possible anywhere */
    PetscCall(LoadContactLocalState(sc, velocity, h));
  } else
    PetscCall(BuildCandidates(sc, radius, velocity, h, &ok));
  if (ok) PetscCall(FilterCandidates(sc, radius));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Brute force (the reference for tests)                                                            */

PetscErrorCode ClothSelfContactFindBruteForce(ClothSelfContact sc, const PetscReal x[], const PetscReal dx[], PetscReal radius, PetscInt *n, ClothContact **contacts)
{
  const SelfContactPositions all        = {x, NULL};
  const PetscInt             nparticles = sc->layout.nglobal;
  PetscInt                   cap        = 64;

  PetscFunctionBeginUser;
  *n = 0;
  PetscCall(PetscMalloc1(cap, contacts));
  for (PetscInt pass = 0; pass < 2; pass++) {
    const PetscInt na = pass == 0 ? nparticles : sc->nedge, nb = pass == 0 ? sc->ntri : sc->nedge;
    for (PetscInt a = 0; a < na; a++)
      for (PetscInt b = pass == 0 ? 0 : a + 1; b < nb; b++) {
        ClothContact     contact;
        const PetscReal *xs[SELF_CONTACT_NP], *ds[SELF_CONTACT_NP];
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
        for (PetscInt v = 0; v < SELF_CONTACT_NP; v++) xs[v] = &x[3 * contact.p[v]], ds[v] = dx ? &dx[3 * contact.p[v]] : NULL;
        if (pass == 0) {
          TestPointTriangle(xs, dx ? ds : NULL, radius, &contact, &hit);
          if (hit) hit = NearestOnFabric(sc, &all, a, xs[0], b);
        } else {
          TestEdgeEdge(xs, dx ? ds : NULL, radius, &contact, &hit);
          if (hit) hit = contact.scale > 0 ? PETSC_TRUE : PETSC_FALSE;
        }
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
