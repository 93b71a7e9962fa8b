/* ClothSelfContact (see selfcontact.h), the response side: the matrix pattern of contacts, repulsion with its
   stiffness for the implicit system, the inelastic velocity filter, and the object; the search is in
   selfcontact_search.c.

   The closest points come from geometry.h, the cell grids from cellgrid.h; the response follows R. Bridson, R. Fedkiw,
   J. Anderson, "Robust treatment of collisions, contact and friction for cloth animation",
   SIGGRAPH 2002 (repulsion within the thickness, inelastic impulses along the normal weighted by the
   barycentric weights and inverse masses, iterated Gauss-Seidel sweeps). */
#include "selfcontact_impl.h"
#include "geometry.h"
#include "log.h"
#include "options.h"
#include "friction.h"
#include "vec3.h"

/* ------------------------------------------------------------------------------------------------ */
/* Repulsion                                                                                        */

/* Contact-local particle k's 3-vector in the owned array or the remote one. */
static inline PetscScalar *At(ClothSelfContact sc, PetscScalar *owned, PetscScalar *remote, PetscInt k)
{
  return k < sc->layout.nlocal ? &owned[3 * k] : &remote[3 * (k - sc->layout.nlocal)];
}

/* A contact-local particle's 3-vector in an owned array or the remote one (read only). */
static inline const PetscScalar *AtRead(ClothSelfContact sc, const PetscScalar *owned, const PetscScalar *remote, PetscInt k)
{
  return k < sc->layout.nlocal ? &owned[3 * k] : &remote[3 * (k - sc->layout.nlocal)];
}

/* Energy, force on the separation r (as on the particle side) and its 3x3 stiffness, from the link
   kernel with its repulsion term only: 0.5 k (thickness - |r|)^2 for |r| < thickness. */
static PetscErrorCode RepulsionEvaluate(ClothSelfContact sc, const ClothContact *contact, const PetscReal r[3], PetscBool psd, PetscReal *energy, PetscReal force[3], PetscReal K[9])
{
  const PetscReal zero[3] = {0, 0, 0};
  ClothLink       link;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&link, sizeof(link))); /* no stretch, no rest length: only the repulsion */
  link.p[0] = link.p[1] = -1;
  link.repel_length     = sc->thickness;
  link.repel_k          = sc->stiffness * contact->scale;
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
  PetscCall(SelfContactRefreshRemote(sc, bn->normals, sc->bremote));
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

/* A contact's share of the implicit system, h2 S_j (a_j a_k K) S_k for its particles j, k (K: its stiffness; or, with
   h2 = h and K = D, its friction's velocity Jacobian): the diagonal blocks j = k go into A, where every particle has its
   block; the couplings j != k, between particles that no interaction of the model joins, are kept in the contact's
   record and applied by the implicit operator (MultCoupling), so that A's pattern never changes as contacts come and
   go. */
static PetscErrorCode AddContactStiffness(ClothSelfContact sc, const BodyNormals *bn, PetscInt c, const PetscReal K[9], PetscReal h2, Mat A)
{
  const ClothContact  *contact = &sc->contacts[c];
  SelfContactCoupling *rec;

  PetscFunctionBeginUser;
  if (sc->coupling_of[c] < 0) { /* the contact's first share in this assembly: its record */
    if (sc->ncouplings == sc->maxcouplings) PetscCall(SelfContactGrowArray(sizeof(SelfContactCoupling), sc->ncouplings, &sc->maxcouplings, 64, &sc->couplings));
    sc->coupling_of[c] = sc->ncouplings;
    rec                = &sc->couplings[sc->ncouplings++];
    ContactFilters(sc, bn, c, rec->S);
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) rec->a[j] = contact->a[j], rec->local[j] = sc->local[SELF_CONTACT_NP * c + j];
    for (PetscInt k = 0; k < 9; k++) rec->M[k] = 0;
  }
  rec = &sc->couplings[sc->coupling_of[c]];
  for (PetscInt k = 0; k < 9; k++) rec->M[k] += h2 * K[k];
  for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
    const PetscInt row = sc->layout.solver_of_natural[contact->p[j]];
    PetscReal      KS[9];
    PetscScalar    H[9];

    for (PetscInt r = 0; r < 3; r++) /* KS = K S_j */
      for (PetscInt q = 0; q < 3; q++) KS[3 * r + q] = K[3 * r] * rec->S[j][q] + K[3 * r + 1] * rec->S[j][3 + q] + K[3 * r + 2] * rec->S[j][6 + q];
    for (PetscInt r = 0; r < 3; r++)
      for (PetscInt q = 0; q < 3; q++) H[3 * r + q] = h2 * contact->a[j] * contact->a[j] * (rec->S[j][3 * r] * KS[q] + rec->S[j][3 * r + 1] * KS[3 + q] + rec->S[j][3 * r + 2] * KS[6 + q]);
    PetscCall(MatSetValuesBlocked(A, 1, &row, 1, &row, H, ADD_VALUES));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The contribution's mult_coupling (cloth.h): y += sum over the contacts of h2 a_j a_k S_j M S_k x_k, j != k, their
   couplings of the last assembly (AddContactStiffness), with a_j S_j M (z - q_j), q_k = a_k S_k x_k, z their sum.
   Collective. */
static PetscErrorCode MultCoupling(void *ctx, Vec x, Vec y)
{
  ClothSelfContact   sc     = (ClothSelfContact)ctx;
  const PetscInt     nlocal = sc->layout.nlocal;
  const PetscScalar *xo, *xr;
  PetscScalar       *yo, *yr;

  PetscFunctionBeginUser;
  if (!sc->any_coupling) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscLogEventBegin(ClothLog.self_coupling, 0, 0, 0, 0));
  PetscCall(VecScatterBegin(sc->coupling_scatter, x, sc->xcoupling, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc->coupling_scatter, x, sc->xcoupling, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecZeroEntries(sc->ycoupling));
  PetscCall(VecGetArrayRead(x, &xo));
  PetscCall(VecGetArrayRead(sc->xcoupling, &xr));
  PetscCall(VecGetArray(y, &yo));
  PetscCall(VecGetArray(sc->ycoupling, &yr));
  for (PetscInt c = 0; c < sc->ncouplings; c++) {
    const SelfContactCoupling *rec = &sc->couplings[c];
    PetscReal                  q[SELF_CONTACT_NP][3], z[3] = {0, 0, 0};

    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) {
      const PetscScalar *xk = rec->local_c[k] < nlocal ? &xo[3 * rec->local_c[k]] : &xr[3 * (rec->local_c[k] - nlocal)];
      for (PetscInt r = 0; r < 3; r++) q[k][r] = rec->a[k] * (rec->S[k][3 * r] * PetscRealPart(xk[0]) + rec->S[k][3 * r + 1] * PetscRealPart(xk[1]) + rec->S[k][3 * r + 2] * PetscRealPart(xk[2]));
      for (PetscInt r = 0; r < 3; r++) z[r] += q[k][r];
    }
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      PetscScalar *yj = rec->local_c[j] < nlocal ? &yo[3 * rec->local_c[j]] : &yr[3 * (rec->local_c[j] - nlocal)];
      PetscReal    w[3], Mw[3];
      for (PetscInt r = 0; r < 3; r++) w[r] = z[r] - q[j][r];
      for (PetscInt r = 0; r < 3; r++) Mw[r] = rec->M[3 * r] * w[0] + rec->M[3 * r + 1] * w[1] + rec->M[3 * r + 2] * w[2];
      for (PetscInt r = 0; r < 3; r++) yj[r] += rec->a[j] * (rec->S[j][3 * r] * Mw[0] + rec->S[j][3 * r + 1] * Mw[1] + rec->S[j][3 * r + 2] * Mw[2]);
    }
  }
  PetscCall(PetscLogFlops(200.0 * sc->ncouplings));
  PetscCall(VecRestoreArray(sc->ycoupling, &yr));
  PetscCall(VecRestoreArray(y, &yo));
  PetscCall(VecRestoreArrayRead(sc->xcoupling, &xr));
  PetscCall(VecRestoreArrayRead(x, &xo));
  PetscCall(VecScatterBegin(sc->coupling_scatter, sc->ycoupling, y, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sc->coupling_scatter, sc->ycoupling, y, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(PetscLogEventEnd(ClothLog.self_coupling, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Starts the couplings of an assembly: no contact has a record yet. */
static PetscErrorCode BeginCouplings(ClothSelfContact sc)
{
  PetscFunctionBeginUser;
  if (sc->ncontacts > sc->maxcoupling_of) {
    PetscCall(PetscFree(sc->coupling_of));
    sc->maxcoupling_of = sc->ncontacts + sc->ncontacts / 4;
    PetscCall(PetscMalloc1(sc->maxcoupling_of, &sc->coupling_of));
  }
  for (PetscInt c = 0; c < sc->ncontacts; c++) sc->coupling_of[c] = -1;
  sc->ncouplings = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The remote particles of the couplings (coupling_remote, sorted natural indices; each record's particles numbered
   owned, then by their place there in local_c) and the scatter that brings a product's input to them and its output
   back: only the few particles in contact move at every product, not every particle near another rank. Rebuilt when
   the set changes. Collective. */
static PetscErrorCode SetCouplingScatter(ClothSelfContact sc)
{
  const PetscInt nlocal = sc->layout.nlocal;
  PetscInt       n      = 0, *list;
  PetscBool      all_same;

  PetscFunctionBeginUser;
  sc->any_coupling = sc->ncouplings > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &sc->any_coupling, 1, MPIU_BOOL, MPI_LOR, sc->comm));
  if (!sc->any_coupling) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscMalloc1(SELF_CONTACT_NP * sc->ncouplings + 1, &list));
  for (PetscInt c = 0; c < sc->ncouplings; c++)
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++)
      if (sc->couplings[c].local[k] >= nlocal) list[n++] = sc->natural_of[sc->couplings[c].local[k]];
  PetscCall(PetscSortRemoveDupsInt(&n, list));
  for (PetscInt c = 0; c < sc->ncouplings; c++)
    for (PetscInt k = 0; k < SELF_CONTACT_NP; k++) {
      const PetscInt l = sc->couplings[c].local[k];
      PetscInt       at;
      if (l < nlocal) {
        sc->couplings[c].local_c[k] = l;
        continue;
      }
      PetscCall(PetscFindInt(sc->natural_of[l], n, list, &at));
      sc->couplings[c].local_c[k] = nlocal + at;
    }
  PetscCall(SelfContactSameParticles(sc, sc->coupling_scatter ? PETSC_TRUE : PETSC_FALSE, n, list, sc->ncoupling_remote, sc->coupling_remote, &all_same));
  if (all_same) {
    PetscCall(PetscFree(list));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscFree(sc->coupling_remote));
  sc->coupling_remote  = list;
  sc->ncoupling_remote = n;
  PetscCall(VecScatterDestroy(&sc->coupling_scatter));
  PetscCall(VecDestroy(&sc->xcoupling));
  PetscCall(VecDestroy(&sc->ycoupling));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3 * n, &sc->xcoupling));
  PetscCall(VecSetBlockSize(sc->xcoupling, 3));
  PetscCall(VecDuplicate(sc->xcoupling, &sc->ycoupling));
  PetscCall(SelfContactCreateScatter(sc, n, list, sc->xcoupling, &sc->coupling_scatter));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Adds the repulsion of the current contacts at (position, velocity) to force, to kv (K v; may be NULL), h2 K to A (may
   be NULL; filtered like the rest of the system) and to *energy (may be NULL). Collective. */
static PetscErrorCode AddRepulsion(ClothSelfContact sc, Vec position, Vec velocity, Vec force, Vec kv, Mat A, PetscReal h2, PetscBool psd, PetscReal *energy)
{
  PetscScalar *x, *xr, *v = NULL, *vr = NULL, *f, *fr, *k = NULL, *kr = NULL;
  BodyNormals  bn = {NULL, NULL, NULL};

  PetscFunctionBeginUser;
  if (A) {
    PetscCall(BeginCouplings(sc));
    sc->any_coupling = PETSC_FALSE;
  }
  /* no search yet, or no contact possible since the candidate list's build (on every rank alike) */
  if (!sc->remote_scatter || !sc->any_candidates) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ClothLog.self_forces, 0, 0, 0, 0));
  PetscCall(SelfContactRefreshRemote(sc, position, sc->xremote));
  if (kv) PetscCall(SelfContactRefreshRemote(sc, velocity, sc->vremote));
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
    PetscCall(RepulsionEvaluate(sc, contact, r, psd, &e, fr3, (kv || A) ? K : NULL));
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
  if (A) PetscCall(SetCouplingScatter(sc));
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
  PetscCall(SelfContactSumRemoteInto(sc, sc->fremote, force));
  if (kv) PetscCall(SelfContactSumRemoteInto(sc, sc->kvremote, kv));
  PetscCall(PetscLogEventEnd(ClothLog.self_forces, 0, 0, 0, 0));
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscReal InverseMass(ClothSelfContact sc, PetscInt natural)
{
  const ClothModel m = sc->layout.model;

  return (m->pinned[natural] || m->mass[natural] <= 0) ? 0.0 : 1.0 / m->mass[natural];
}

/* ------------------------------------------------------------------------------------------------ */
/* Friction between layers                                                                          */

/* Contact c's repulsion at the positions (x, xr) (contact-local): whether it acts (within the thickness), its normal n
   (along r, into the side of a[0]) and its magnitude push = k (thickness - |r|). */
static PetscErrorCode ContactPush(ClothSelfContact sc, PetscInt c, PetscScalar *x, PetscScalar *xr, PetscBool *acts, PetscReal n[3], PetscReal *push)
{
  const ClothContact *contact = &sc->contacts[c];
  const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
  PetscReal           r[3]    = {0, 0, 0}, e, frep[3], d;

  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
    for (PetscInt q = 0; q < 3; q++) r[q] += contact->a[j] * PetscRealPart(At(sc, x, xr, loc[j])[q]);
  d     = PetscSqrtReal(Dot3(r, r));
  *acts = (d < sc->thickness && d > 0) ? PETSC_TRUE : PETSC_FALSE; /* no repulsion (or no direction): no normal force */
  *push = 0;
  if (!*acts) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(RepulsionEvaluate(sc, contact, r, PETSC_TRUE, &e, frep, NULL));
  for (PetscInt q = 0; q < 3; q++) n[q] = r[q] / d;
  *push = PetscSqrtReal(Dot3(frep, frep));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every owned particle's net repulsion R = sum_c a_k push_c n_c (contact_push) over the contacts of all ranks, and its
   direction nu = R / |R| (support, 0 without contacts; the remote particles' in kvremote): the axis along which
   LoadVectors splits its contacts into the two sides of its layer. Collective. */
static PetscErrorCode SupportDirections(ClothSelfContact sc, PetscScalar *x, PetscScalar *xr)
{
  PetscScalar       *R, *Rr, *nu;
  const PetscScalar *Rc;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(sc->contact_push));
  PetscCall(VecZeroEntries(sc->fremote));
  PetscCall(VecGetArray(sc->contact_push, &R));
  PetscCall(VecGetArray(sc->fremote, &Rr));
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           n[3], push;
    PetscBool           acts;

    PetscCall(ContactPush(sc, c, x, xr, &acts, n, &push));
    if (!acts) continue;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) At(sc, R, Rr, loc[j])[q] += contact->a[j] * push * n[q];
  }
  PetscCall(VecRestoreArray(sc->fremote, &Rr));
  PetscCall(VecRestoreArray(sc->contact_push, &R));
  PetscCall(SelfContactSumRemoteInto(sc, sc->fremote, sc->contact_push));
  PetscCall(VecGetArrayRead(sc->contact_push, &Rc));
  PetscCall(VecGetArray(sc->support, &nu));
  for (PetscInt i = 0; i < sc->layout.nlocal; i++) {
    const PetscReal Rn = PetscSqrtReal(Dot3(&Rc[3 * i], &Rc[3 * i]));

    for (PetscInt q = 0; q < 3; q++) nu[3 * i + q] = Rn > 0 ? Rc[3 * i + q] / Rn : 0.0;
  }
  PetscCall(VecRestoreArray(sc->support, &nu));
  PetscCall(VecRestoreArrayRead(sc->contact_push, &Rc));
  PetscCall(SelfContactRefreshRemote(sc, sc->support, sc->kvremote));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Loaded views of the contacts: the particles' axes nu and load vectors w (LoadVectors: w[0] per unit push of the
   contacts that push the particle along +nu, w[1] along -nu), owned and remote. */
typedef struct {
  const PetscScalar *nu, *nur, *w, *wr;
} ContactLoadView;

/* Particle k's (contact-local loc, weight a) share of a contact with normal n, per unit of its push: the load it
   carries on the contact, max(0, a n . nu) w[0] + max(0, -a n . nu) w[1] (continuous as the contact turns). */
static PetscReal ParticleShare(ClothSelfContact sc, const ContactLoadView *view, PetscInt loc, PetscReal a, const PetscReal n[3])
{
  const PetscReal along = a * Dot3(n, AtRead(sc, view->nu, view->nur, loc));
  const PetscReal w0 = PetscRealPart(AtRead(sc, view->w, view->wr, loc)[0]), w1 = PetscRealPart(AtRead(sc, view->w, view->wr, loc)[1]);

  return PetscMax(0.0, along) * w0 + PetscMax(0.0, -along) * w1;
}

/* The two sides' estimates of contact c's normal force (side 0: a > 0, side 1: a < 0): push times the sum of their
   particles' shares. */
static void ContactSideLoads(ClothSelfContact sc, const ContactLoadView *view, PetscInt c, const PetscReal n[3], PetscReal push, PetscReal side[2])
{
  const ClothContact *contact = &sc->contacts[c];

  side[0] = side[1] = 0;
  for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) side[contact->a[j] > 0 ? 0 : 1] += push * ParticleShare(sc, view, sc->local[SELF_CONTACT_NP * c + j], contact->a[j], n);
}

/* Every owned particle's contacts split by their push on it along +nu and -nu (components 0, 1 of out): with
   view NULL the pushes themselves (pushes: U+, U-; or, as the first guess of the loads pressing it, D+, D-), else
   the loads of the contacts' other sides (ContactSideLoads): what the layers on either side press it with. Collective. */
static PetscErrorCode SumContactSides(ClothSelfContact sc, PetscScalar *x, PetscScalar *xr, const PetscScalar *nu, const PetscScalar *nur, const ContactLoadView *view, Vec out)
{
  PetscScalar *o, *orem;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(out));
  PetscCall(VecZeroEntries(sc->fremote));
  PetscCall(VecGetArray(out, &o));
  PetscCall(VecGetArray(sc->fremote, &orem));
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           n[3], push, side[2] = {0, 0};
    PetscBool           acts;

    PetscCall(ContactPush(sc, c, x, xr, &acts, n, &push));
    if (!acts) continue;
    if (view) ContactSideLoads(sc, view, c, n, push, side);
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      const PetscReal along = contact->a[j] * Dot3(n, AtRead(sc, nu, nur, loc[j]));
      const PetscReal value = view ? side[contact->a[j] > 0 ? 1 : 0] : push; /* the other side's load */

      At(sc, o, orem, loc[j])[0] += PetscMax(0.0, along) * value;
      At(sc, o, orem, loc[j])[1] += PetscMax(0.0, -along) * value;
    }
  }
  PetscCall(VecRestoreArray(sc->fremote, &orem));
  PetscCall(VecRestoreArray(out, &o));
  PetscCall(SelfContactSumRemoteInto(sc, sc->fremote, out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every particle's load vector (contact_load; the remote particles' in wremote): the friction.h normal force it
   presses the contacts that push it along +nu with, max(0, -(F - R) . nu + D-) (its force without the repulsion:
   internal, gravity, damping; D-: the layers on its other side pressing it), per unit of their push U+, in
   component 0, and the same towards -nu in component 1. Collective. */
static PetscErrorCode LoadVectors(ClothSelfContact sc, Vec force)
{
  const PetscScalar *f, *R, *U, *P, *nu;
  PetscScalar       *w;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(force, &f));
  PetscCall(VecGetArrayRead(sc->contact_push, &R));
  PetscCall(VecGetArrayRead(sc->contact_sides, &U));
  PetscCall(VecGetArrayRead(sc->contact_press, &P));
  PetscCall(VecGetArrayRead(sc->support, &nu));
  PetscCall(VecGetArray(sc->contact_load, &w));
  for (PetscInt i = 0; i < sc->layout.nlocal; i++) {
    PetscReal up[3], down[3], to_down[3], to_up[3], load[2];

    for (PetscInt q = 0; q < 3; q++) {
      up[q]      = PetscRealPart(nu[3 * i + q]);
      down[q]    = -up[q];
      to_down[q] = PetscRealPart(f[3 * i + q] - R[3 * i + q]) - PetscRealPart(P[3 * i + 1]) * up[q]; /* what presses it towards -nu */
      to_up[q]   = PetscRealPart(f[3 * i + q] - R[3 * i + q]) + PetscRealPart(P[3 * i + 0]) * up[q]; /* towards +nu */
    }
    PetscCall(ClothFrictionNormalLoad(to_down, up, &load[0]));
    PetscCall(ClothFrictionNormalLoad(to_up, down, &load[1]));
    for (PetscInt s = 0; s < 2; s++) w[3 * i + s] = PetscRealPart(U[3 * i + s]) > 0 ? load[s] / PetscRealPart(U[3 * i + s]) : 0.0;
    w[3 * i + 2] = 0;
  }
  PetscCall(VecRestoreArray(sc->contact_load, &w));
  PetscCall(VecRestoreArrayRead(sc->support, &nu));
  PetscCall(VecRestoreArrayRead(sc->contact_press, &P));
  PetscCall(VecRestoreArrayRead(sc->contact_sides, &U));
  PetscCall(VecRestoreArrayRead(sc->contact_push, &R));
  PetscCall(VecRestoreArrayRead(force, &f));
  PetscCall(SelfContactRefreshRemote(sc, sc->contact_load, sc->wremote));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The load vectors (contact_load, wremote; support and kvremote the axes nu) of the contacts at (x, xr) under the
   forces force: with the layers' repulsions as the first guess of what they press each other with, then load_sweeps
   times with the loads their other sides carry (a stack of n layers needs n - 2 sweeps to carry the top layer's load
   down to the lowest contact). Collective. */
static PetscErrorCode ContactLoads(ClothSelfContact sc, PetscScalar *x, PetscScalar *xr, Vec force)
{
  ContactLoadView view;

  PetscFunctionBeginUser;
  PetscCall(SupportDirections(sc, x, xr));
  PetscCall(VecGetArrayRead(sc->support, &view.nu));
  PetscCall(VecGetArrayRead(sc->kvremote, &view.nur));
  PetscCall(SumContactSides(sc, x, xr, view.nu, view.nur, NULL, sc->contact_sides));
  PetscCall(VecCopy(sc->contact_sides, sc->contact_press));
  PetscCall(LoadVectors(sc, force));
  for (PetscInt s = 0; s < sc->friction_load_sweeps; s++) {
    PetscCall(VecGetArrayRead(sc->contact_load, &view.w));
    PetscCall(VecGetArrayRead(sc->wremote, &view.wr));
    PetscCall(SumContactSides(sc, x, xr, view.nu, view.nur, &view, sc->contact_press));
    PetscCall(VecRestoreArrayRead(sc->wremote, &view.wr));
    PetscCall(VecRestoreArrayRead(sc->contact_load, &view.w));
    PetscCall(LoadVectors(sc, force));
  }
  PetscCall(VecRestoreArrayRead(sc->kvremote, &view.nur));
  PetscCall(VecRestoreArrayRead(sc->support, &view.nu));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The add_to_implicit_step of the self-contact contribution (cloth.h), -self_collision_friction: every contact within
   the thickness gets the regularised Coulomb friction of the body contacts (friction.h, one law for both) on the
   tangential part of the relative velocity of its closest points, v_rel = sum_k a_k v_k, with the cloth's friction
   scale. Its normal force is the load its particles carry (the larger of its sides' ContactSideLoads, lagged at the step's start as for the
   bodies), not its repulsion: sliding layers bounce by micrometres, and the repulsion at the step's start averaged
   4 % above the weight it carries (docs/self_collision.md). Particle k takes a_k f, and h a_j a_k S_j D S_k enters the
   blocks the repulsion already couples: D is symmetric positive semidefinite, so the system stays symmetric positive
   definite. Along the motion D is the drag mu N / s (drag_along), not the derivative (about 0 while sliding): with the
   derivative, a particle that several contacts press at once (a fold, two grids passing over each other) was carried
   by their summed friction through v_t = 0 into a reversal within one step (a sheet sliding at 0.18 m/s thrown back
   at 0.38 m/s); the body contacts stop such reversals after the solve, which a pair of moving layers cannot. The drag
   over-brakes a contact sliding with acceleration a at speed u by the fraction a h / u. Collective. */
static PetscErrorCode AddFrictionToImplicitStep(void *ctx, PetscReal h, Vec velocity, Vec force, Mat A)
{
  ClothSelfContact sc = (ClothSelfContact)ctx;
  PetscScalar     *x, *xr, *v, *vr, *f, *fr;
  ContactLoadView  view;
  BodyNormals      bn;
  PetscReal        scale, mu;

  PetscFunctionBeginUser;
  if (!sc->friction || sc->friction_coefficient == 0 || !sc->remote_scatter || !sc->any_candidates) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ClothLog.self_forces, 0, 0, 0, 0));
  PetscCall(ClothGetFrictionScale(sc->cloth, &scale));
  mu = scale * sc->friction_coefficient;
  if (!sc->contact_push) {
    PetscCall(VecDuplicate(sc->position, &sc->contact_push));
    PetscCall(VecDuplicate(sc->position, &sc->contact_sides));
    PetscCall(VecDuplicate(sc->position, &sc->contact_load));
    PetscCall(VecDuplicate(sc->position, &sc->contact_press));
    PetscCall(VecDuplicate(sc->position, &sc->support));
  }
  PetscCall(SelfContactRefreshRemote(sc, sc->position, sc->xremote));
  PetscCall(VecGetArray(sc->position, &x));
  PetscCall(VecGetArray(sc->xremote, &xr));
  PetscCall(ContactLoads(sc, x, xr, force));
  PetscCall(SelfContactRefreshRemote(sc, velocity, sc->vremote));
  PetscCall(VecZeroEntries(sc->fremote));
  PetscCall(BodyNormalsGet(sc, &bn));
  PetscCall(VecGetArrayRead(sc->support, &view.nu));
  PetscCall(VecGetArrayRead(sc->kvremote, &view.nur));
  PetscCall(VecGetArrayRead(sc->contact_load, &view.w));
  PetscCall(VecGetArrayRead(sc->wremote, &view.wr));
  PetscCall(VecGetArray(velocity, &v));
  PetscCall(VecGetArray(sc->vremote, &vr));
  PetscCall(VecGetArray(force, &f));
  PetscCall(VecGetArray(sc->fremote, &fr));
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           vrel[3] = {0, 0, 0}, n[3], vt[3], ff[3], D[9], vn, push, side[2];
    PetscBool           acts;

    PetscCall(ContactPush(sc, c, x, xr, &acts, n, &push));
    if (!acts) continue;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) vrel[q] += contact->a[j] * PetscRealPart(At(sc, v, vr, loc[j])[q]);
    vn = Dot3(vrel, n);
    for (PetscInt q = 0; q < 3; q++) vt[q] = vrel[q] - vn * n[q];
    ContactSideLoads(sc, &view, c, n, push, side);
    PetscCall(ClothRegularisedFriction(mu, mu, PetscMax(side[0], side[1]), sc->friction_velocity, 0.0, PETSC_TRUE, n, vt, ff, D));
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) At(sc, f, fr, loc[j])[q] += contact->a[j] * ff[q];
    PetscCall(AddContactStiffness(sc, &bn, c, D, h, A));
  }
  PetscCall(VecRestoreArray(sc->fremote, &fr));
  PetscCall(VecRestoreArray(force, &f));
  PetscCall(VecRestoreArray(sc->vremote, &vr));
  PetscCall(VecRestoreArray(velocity, &v));
  PetscCall(VecRestoreArrayRead(sc->wremote, &view.wr));
  PetscCall(VecRestoreArrayRead(sc->contact_load, &view.w));
  PetscCall(VecRestoreArrayRead(sc->kvremote, &view.nur));
  PetscCall(VecRestoreArrayRead(sc->support, &view.nu));
  PetscCall(VecRestoreArray(sc->xremote, &xr));
  PetscCall(VecRestoreArray(sc->position, &x));
  PetscCall(BodyNormalsRestore(sc, &bn));
  PetscCall(SelfContactSumRemoteInto(sc, sc->fremote, force));
  PetscCall(PetscLogEventEnd(ClothLog.self_forces, 0, 0, 0, 0));
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------ */
/* Velocity filter                                                                                  */

/* One sweep over this rank's contacts at the velocities v (owned) and vr (remote) of the sweep's start: each contact
   whose gap would fall below the target during the step gets the inelastic impulse along its normal that brings it to
   the target; its velocity changes go to dv (owned) and dvr (remote) and each particle's count of them to n (nr).
   Returns the number of contacts that needed one. */
static PetscErrorCode ImpulseSweep(ClothSelfContact sc, const BodyNormals *bn, PetscReal h, const PetscScalar v[], const PetscScalar vr[], PetscScalar dv[], PetscScalar dvr[], PetscScalar n[], PetscScalar nr[], PetscInt *active)
{
  const PetscReal target = sc->min_gap * sc->thickness;

  PetscFunctionBeginUser;
  *active = 0;
  for (PetscInt c = 0; c < sc->ncontacts; c++) {
    const ClothContact *contact = &sc->contacts[c];
    const PetscInt     *loc     = &sc->local[SELF_CONTACT_NP * c];
    PetscReal           r[3] = {0, 0, 0}, normal[3], Sn[SELF_CONTACT_NP][3], S[SELF_CONTACT_NP][9], vn = 0, wsum = 0, impulse;

    if (contact->distance <= 0) continue;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++)
      for (PetscInt q = 0; q < 3; q++) r[q] += contact->a[j] * sc->x[3 * loc[j] + q];
    for (PetscInt q = 0; q < 3; q++) normal[q] = r[q] / contact->distance;
    /* a particle that a body holds (or a pin) does not move along the constrained directions: its
       share of the impulse is filtered, S n, as in the implicit system */
    ContactFilters(sc, bn, c, S);
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      const PetscScalar *vj = AtRead(sc, v, vr, loc[j]);
      for (PetscInt q = 0; q < 3; q++) Sn[j][q] = S[j][3 * q] * normal[0] + S[j][3 * q + 1] * normal[1] + S[j][3 * q + 2] * normal[2];
      vn += contact->a[j] * PetscRealPart(normal[0] * vj[0] + normal[1] * vj[1] + normal[2] * vj[2]);
      wsum += contact->a[j] * contact->a[j] * InverseMass(sc, contact->p[j]) * Dot3(normal, Sn[j]);
    }
    /* the gap after the step, to first order along the normal at the start of the step */
    if (contact->distance + h * vn >= target * (1 - 1e-6) || wsum <= 0) continue;
    impulse = ((target - contact->distance) / h - vn) / wsum;
    (*active)++;
    for (PetscInt j = 0; j < SELF_CONTACT_NP; j++) {
      const PetscReal scale = contact->a[j] * InverseMass(sc, contact->p[j]) * impulse;
      PetscScalar    *dvj   = At(sc, dv, dvr, loc[j]);
      for (PetscInt q = 0; q < 3; q++) dvj[q] += scale * Sn[j][q];
      At(sc, n, nr, loc[j])[0] += 1;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* v += dv / n for every owned particle that had impulses (n of them): a particle pushed by several contacts takes their
   mean, so that the sweeps converge (Jacobi iteration with averaging). */
static PetscErrorCode ApplyImpulses(ClothSelfContact sc, Vec velocity)
{
  PetscScalar       *v;
  const PetscScalar *dv, *n;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(velocity, &v));
  PetscCall(VecGetArrayRead(sc->impulse_dv, &dv));
  PetscCall(VecGetArrayRead(sc->impulse_count, &n));
  for (PetscInt i = 0; i < sc->layout.nlocal; i++)
    if (PetscRealPart(n[3 * i]) > 0)
      for (PetscInt q = 0; q < 3; q++) v[3 * i + q] += dv[3 * i + q] / PetscRealPart(n[3 * i]);
  PetscCall(VecRestoreArrayRead(sc->impulse_count, &n));
  PetscCall(VecRestoreArrayRead(sc->impulse_dv, &dv));
  PetscCall(VecRestoreArray(velocity, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Sweeps of impulses (ImpulseSweep), each from the velocities of its start, the changes of every contact summed and
   averaged per particle before they apply: every contact sees the same velocities whatever the partition, so the result
   does not depend on the number of ranks (a Gauss-Seidel sweep of each rank's contacts did, when impulses acted). */
PetscErrorCode ClothSelfContactFilterVelocity(ClothSelfContact sc, PetscReal h, Vec velocity)
{
  PetscInt    it, active = 0, total = 0;
  BodyNormals bn;

  PetscFunctionBeginUser;
  PetscCheck(sc->remote_scatter, sc->comm, PETSC_ERR_ORDER, "Call ClothSelfContactUpdate before ClothSelfContactFilterVelocity");
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  /* the contacts the step will meet: those that come within the thickness at the new velocities */
  PetscCall(SelfContactSearch(sc, sc->thickness, velocity, h));
  if (!sc->any_candidates) { /* no contact on any rank */
    PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscLogEventBegin(ClothLog.self_impulses, 0, 0, 0, 0));
  if (!sc->impulse_dv) {
    PetscCall(VecDuplicate(sc->position, &sc->impulse_dv));
    PetscCall(VecDuplicate(sc->position, &sc->impulse_count));
  }
  PetscCall(BodyNormalsGet(sc, &bn));
  for (it = 0; it < sc->impulse_iterations; it++) {
    const PetscScalar *v, *vr;
    PetscScalar       *dv, *dvr, *n, *nr;

    if (it > 0) PetscCall(SelfContactRefreshRemote(sc, velocity, sc->vremote)); /* the search has refreshed them at first */
    PetscCall(VecZeroEntries(sc->impulse_dv));
    PetscCall(VecZeroEntries(sc->impulse_count));
    PetscCall(VecZeroEntries(sc->fremote));
    PetscCall(VecZeroEntries(sc->kvremote));
    PetscCall(VecGetArrayRead(velocity, &v));
    PetscCall(VecGetArrayRead(sc->vremote, &vr));
    PetscCall(VecGetArray(sc->impulse_dv, &dv));
    PetscCall(VecGetArray(sc->fremote, &dvr));
    PetscCall(VecGetArray(sc->impulse_count, &n));
    PetscCall(VecGetArray(sc->kvremote, &nr));
    PetscCall(ImpulseSweep(sc, &bn, h, v, vr, dv, dvr, n, nr, &active));
    PetscCall(VecRestoreArray(sc->kvremote, &nr));
    PetscCall(VecRestoreArray(sc->impulse_count, &n));
    PetscCall(VecRestoreArray(sc->fremote, &dvr));
    PetscCall(VecRestoreArray(sc->impulse_dv, &dv));
    PetscCall(VecRestoreArrayRead(sc->vremote, &vr));
    PetscCall(VecRestoreArrayRead(velocity, &v));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &active, 1, MPIU_INT, MPI_SUM, sc->comm));
    if (!active) break;
    total += active;
    PetscCall(SelfContactSumRemoteInto(sc, sc->fremote, sc->impulse_dv));
    PetscCall(SelfContactSumRemoteInto(sc, sc->kvremote, sc->impulse_count));
    PetscCall(ApplyImpulses(sc, velocity));
  }
  PetscCall(BodyNormalsRestore(sc, &bn));
  if (active) PetscCall(PetscInfo(NULL, "Self-collision impulses: %" PetscInt_FMT " contacts still closing after %" PetscInt_FMT " iterations\n", active, it));
  sc->impulses += total;
  PetscCall(PetscLogEventEnd(ClothLog.self_impulses, 0, 0, 0, 0));
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
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
  s->enabled              = scene->enabled;
  s->thickness            = scene->thickness;
  s->stiffness            = scene->stiffness;
  s->exclude_ring         = scene->given ? scene->exclude_ring : 0;
  s->same_piece           = scene->given ? scene->same_piece : PETSC_TRUE;
  s->min_gap              = 0.25;
  s->impulse_iterations   = 100;
  s->velocity_margin      = 0.25;
  s->exclude_thicknesses  = 2;
  s->friction             = PETSC_FALSE;
  s->friction_coefficient = 0.3;
  s->friction_velocity    = 1e-4;
  s->friction_load_sweeps = 2;
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
  PetscCall(PetscOptionsInt("-self_collision_exclude_ring", "Particles of one piece this many grid rings apart or closer never collide (0: primitives sharing a particle; widened by -self_collision_exclude_thicknesses)", "ClothSelfContactUpdate",
                            sc->exclude_ring, &sc->exclude_ring, NULL));
  PetscCall(PetscOptionsReal("-self_collision_min_gap", "Impulses keep every gap above this fraction of the thickness", "ClothSelfContactFilterVelocity", sc->min_gap, &sc->min_gap, NULL));
  PetscCall(PetscOptionsInt("-self_collision_impulse_iterations", "Largest number of Gauss-Seidel sweeps of the impulse filter per step", "ClothSelfContactFilterVelocity", sc->impulse_iterations, &sc->impulse_iterations, NULL));
  PetscCall(PetscOptionsReal("-self_collision_exclude_thicknesses", "Particles of one piece closer in the pattern than this many thicknesses never collide (the exclusion ring widens to it)", "ClothSelfContactUpdate", sc->exclude_thicknesses,
                             &sc->exclude_thicknesses, NULL));
  PetscCall(PetscOptionsReal("-self_collision_velocity_margin", "Candidates found at a step's start serve the velocity filter's search while no particle's displacement over the step has changed by more than this fraction of the thickness",
                             "ClothSelfContactUpdate", sc->velocity_margin, &sc->velocity_margin, NULL));
  PetscCall(PetscOptionsBool("-self_collision_friction", "Regularised Coulomb friction between layers in contact, in the implicit step", "ClothSelfContactGetContribution", sc->friction, &sc->friction, NULL));
  PetscCall(PetscOptionsReal("-self_collision_friction_coefficient", "Friction coefficient mu between layers", "ClothSelfContactGetContribution", sc->friction_coefficient, &sc->friction_coefficient, NULL));
  PetscCall(PetscOptionsReal("-self_collision_friction_velocity", "Friction between layers: regularisation velocity eps_v, m/s", "ClothSelfContactGetContribution", sc->friction_velocity, &sc->friction_velocity, NULL));
  PetscCall(PetscOptionsInt("-self_collision_friction_load_sweeps", "Friction between layers: sweeps carrying the loads of stacked layers down (a stack of n layers needs n - 2)", "ClothSelfContactGetContribution", sc->friction_load_sweeps,
                            &sc->friction_load_sweeps, NULL));
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
    PetscCall(ClothOptionsCheckReal(sc->comm, "-self_collision_velocity_margin", sc->velocity_margin, 0, PETSC_FALSE, 100, NULL));
    PetscCall(ClothOptionsCheckReal(sc->comm, "-self_collision_exclude_thicknesses", sc->exclude_thicknesses, 0, PETSC_FALSE, 100, NULL));
    PetscCall(ClothOptionsCheckReal(sc->comm, "-self_collision_friction_coefficient", sc->friction_coefficient, 0, PETSC_FALSE, 100, NULL));
    PetscCall(ClothOptionsCheckReal(sc->comm, "-self_collision_friction_velocity", sc->friction_velocity, 0, PETSC_TRUE, PETSC_MAX_REAL, "m/s"));
    PetscCall(ClothOptionsCheckInt(sc->comm, "-self_collision_friction_load_sweeps", sc->friction_load_sweeps, 0, 100));
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
  PetscCall(SelfContactBuildPrimitives(sc, layout->model));
  PetscCall(SelfContactBuildIncidence(layout->nglobal, sc->ntri, 3, sc->tri, &sc->tri_start, &sc->tri_of));
  PetscCall(SelfContactBuildIncidence(layout->nglobal, sc->nedge, 2, sc->edge, &sc->edge_start, &sc->edge_of));
  PetscCall(SelfContactBuildGridPositions(sc, layout->scene, layout->model));
  PetscCall(SelfContactSetExclusionRings(sc));
  PetscCall(SelfContactBuildTiles(sc, layout->scene, layout->model));
  PetscCall(PetscMalloc1(3 * layout->nlocal + 1, &sc->dx0));
  PetscCall(PetscMalloc1(layout->nglobal, &sc->contact_index));
  for (PetscInt g = 0; g < layout->nglobal; g++) sc->contact_index[g] = -1;
  PetscCall(CellGridCreate(&sc->tile_grid));
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
  *contribution = (ClothContribution){.name = "self-contact", .ctx = sc, .add = AddContribution, .add_to_implicit_step = AddFrictionToImplicitStep, .mult_coupling = MultCoupling};
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

PetscErrorCode ClothSelfContactUpdate(ClothSelfContact sc, PetscReal h)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSelfContactSetUp(sc));
  PetscCall(PetscLogEventBegin(ClothLog.self_collision, 0, 0, 0, 0));
  /* at the velocities of the start of the step; the velocity filter searches again at the new ones */
  PetscCall(SelfContactSearch(sc, sc->thickness, sc->velocity, h));
  sc->searches++;
  sc->contacts_found += sc->ncontacts;
  for (PetscInt c = 0; c < sc->ncontacts; c++) sc->edge_contacts_found += sc->contacts[c].kind == CLOTH_CONTACT_EDGE_EDGE;
  PetscCall(PetscLogEventEnd(ClothLog.self_collision, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactFind(ClothSelfContact sc, PetscReal radius)
{
  PetscFunctionBeginUser;
  PetscCall(ClothSelfContactSetUp(sc));
  PetscCall(SelfContactSearch(sc, radius, NULL, 0.0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothSelfContactGetStatistics(ClothSelfContact sc, ClothSelfContactStatistics *stats)
{
  PetscInt64 local[4] = {sc->tile_pairs, sc->tile_pairs_apart, sc->primitive_pairs_total, sc->candidates_built}, sum[4];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(local, sum, 4, MPIU_INT64, MPI_SUM, sc->comm));
  stats->builds           = sc->builds;
  stats->tile_pairs       = sum[0];
  stats->tile_pairs_apart = sum[1];
  stats->primitive_pairs  = sum[2];
  stats->candidates       = sum[3];
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
  PetscInt64 local[8] = {sc->contacts_found, sc->rank == 0 ? sc->impulses : 0, sc->nremote, sc->candidates_built, sc->edge_contacts_found, sc->tile_pairs, sc->tile_pairs_apart, sc->primitive_pairs_total}, sum[8];
  PetscInt   cmax;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(local, sum, 8, MPIU_INT64, MPI_SUM, sc->comm));
  PetscCallMPI(MPI_Allreduce(&sc->candidates_max, &cmax, 1, MPIU_INT, MPI_MAX, sc->comm));
  if (!sc->enabled) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Self-collision: off\n"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "Self-collision: thickness %g m, stiffness %g N/m, particles within %" PetscInt_FMT " ring(s) (and %g thicknesses, %" PetscInt_FMT " ring(s) on the first piece) excluded%s, impulses keep gaps above %g x thickness\n",
      (double)sc->thickness, (double)sc->stiffness, sc->exclude_ring, (double)sc->exclude_thicknesses, sc->ring ? sc->ring[0] : sc->exclude_ring, sc->same_piece ? "" : ", one piece never collides with itself", (double)sc->min_gap));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  %" PetscInt_FMT " searches, %.1f contacts per search (%.1f edge-edge), %" PetscInt_FMT " impulses, %" PetscInt_FMT " remote particles at the last search\n", sc->searches,
                                   sc->searches ? (double)sum[0] / (double)sc->searches : 0.0, sc->searches ? (double)sum[4] / (double)sc->searches : 0.0, (PetscInt)sum[1], (PetscInt)sum[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  candidates (velocity margin %g x thickness): found %" PetscInt_FMT " times, %.1f per search (%.3f per particle), at most %" PetscInt_FMT " on a rank\n", (double)sc->velocity_margin, sc->builds,
                                   sc->builds ? (double)sum[3] / (double)sc->builds : 0.0, sc->builds ? (double)sum[3] / (double)sc->builds / (double)sc->layout.nglobal : 0.0, cmax));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  broad phase (tiles of %d x %d cells): %.1f pairs of tiles near each other a search, %.1f %% of them proved apart; %.1f pairs of primitives (%.3f per particle) a search to the narrow phase\n",
                                   SELF_CONTACT_TILE, SELF_CONTACT_TILE, sc->builds ? (double)sum[5] / (double)sc->builds : 0.0, sum[5] ? 100.0 * (double)sum[6] / (double)sum[5] : 0.0, sc->builds ? (double)sum[7] / (double)sc->builds : 0.0,
                                   sc->builds ? (double)sum[7] / (double)sc->builds / (double)sc->layout.nglobal : 0.0));
  if (sc->friction)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  friction between layers: regularised Coulomb, mu %g, eps_v %g m/s, %" PetscInt_FMT " load sweeps\n", (double)sc->friction_coefficient, (double)sc->friction_velocity, sc->friction_load_sweeps));
  else
    PetscCall(PetscViewerASCIIPrintf(viewer, "  friction between layers: off\n"));
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
  PetscCall(PetscFree3(s->x, s->dx, s->x0));
  PetscCall(PetscFree(s->dx0));
  PetscCall(PetscFree(s->ring));
  PetscCall(PetscFree(s->candidates));
  PetscCall(PetscFree(s->couplings));
  PetscCall(PetscFree(s->coupling_of));
  PetscCall(SelfContactDestroyTiles(s));
  PetscCall(PetscFree2(s->contacts, s->local));
  PetscCall(VecDestroy(&s->xremote));
  PetscCall(VecDestroy(&s->vremote));
  PetscCall(VecDestroy(&s->fremote));
  PetscCall(VecDestroy(&s->kvremote));
  PetscCall(VecDestroy(&s->bremote));
  PetscCall(VecDestroy(&s->contact_push));
  PetscCall(VecDestroy(&s->contact_sides));
  PetscCall(VecDestroy(&s->contact_load));
  PetscCall(VecDestroy(&s->contact_press));
  PetscCall(VecDestroy(&s->support));
  PetscCall(VecDestroy(&s->wremote));
  PetscCall(VecDestroy(&s->impulse_dv));
  PetscCall(VecDestroy(&s->impulse_count));
  PetscCall(VecDestroy(&s->xcoupling));
  PetscCall(VecDestroy(&s->ycoupling));
  PetscCall(VecScatterDestroy(&s->coupling_scatter));
  PetscCall(PetscFree(s->coupling_remote));
  PetscCall(VecScatterDestroy(&s->remote_scatter));
  PetscCall(PetscFree(*sc));
  PetscFunctionReturn(PETSC_SUCCESS);
}
