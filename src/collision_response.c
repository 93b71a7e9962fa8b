/* ClothCollision's response (collision_impl.h): a particle's contacts with every body (a mesh crossed, an analytic
   body within its thickness, a held contact kept, a mesh come within the thickness), its velocity after the step
   (the velocity into the body removed, Coulomb friction as an impulse, or with -collision_friction implicit the
   regularised friction of held contacts inside the implicit step and only what it cannot do after it: no reversal,
   static friction that holds), whether it is held for the next step, and the normal force the bodies exerted. */
#include "collision_impl.h"
#include "friction.h"
#include "geometry.h"
#include "vec3.h"

/* ------------------------------------------------------------------------------------------------------------ */
/* Velocity and friction                                                                                        */

/* Removes the velocity into the body and applies Coulomb friction with normal velocity change
   max(removed normal velocity, dvn_held) (dvn_held: what the constraint cancels, h |F_n| / m).
   Static friction must resist, over the next step, both the tangential velocity and the tangential force
   (dvt_force = h |F_t| / m): the implicit solve turns a stiff link's pull into a velocity of only
   stretch / h, so comparing that velocity alone with the friction budget kept particles stuck against
   tensions hundreds of times mu |F_n|, and locked single links of a garment at 20-30 % strain. Kinetic
   friction likewise takes the fraction mu_k dv_n / max(|v_t|, dvt_force) of the slip. Returns whether static
   friction stopped the particle. */
static PetscBool RespondVelocity(const SceneBody *d, PetscReal friction_scale, const PetscReal n[3], PetscReal dvn_held, PetscReal dvt_force, PetscScalar v[3])
{
  PetscReal vn = Dot3(v, n), dvn = 0, vt[3], vt_norm;

  if (vn < 0) {
    for (PetscInt k = 0; k < 3; k++) v[k] -= vn * n[k];
    dvn = -vn;
    vn  = 0;
  }
  dvn = PetscMax(dvn, dvn_held);
  for (PetscInt k = 0; k < 3; k++) vt[k] = v[k] - vn * n[k];
  vt_norm = PetscSqrtReal(Dot3(vt, vt));
  if (PetscMax(vt_norm, dvt_force) <= friction_scale * d->friction_static * dvn) {
    for (PetscInt k = 0; k < 3; k++) v[k] = vn * n[k];
    return PETSC_TRUE;
  }
  if (vt_norm > 0) {
    const PetscReal scale = PetscMax(0.0, 1 - friction_scale * d->friction_kinetic * dvn / PetscMax(vt_norm, dvt_force));
    for (PetscInt k = 0; k < 3; k++) v[k] = vn * n[k] + scale * vt[k];
  }
  return PETSC_FALSE;
}

/* Contacts are kept within this distance beyond the thickness (so that a particle held on a curved surface
   stays held), and held ones are released beyond it. */
PetscReal CollisionContactSlop(const SceneBody *d)
{
  return PetscMax(0.5 * d->thickness, 1e-5);
}

/* The add_to_implicit_step of the body-friction contribution (cloth.h) of -collision_friction implicit: for every owned particle held (sliding) on a body, the
   regularised friction at the step's start velocity goes into the force (so h f into the right-hand side) and h D
   onto its diagonal block: the linearised backward-Euler step with f(v + dv) ~ f(v) - D dv. The normal force is
   the push into the body of the force at the step's start, N = max(0, -F.n) (the force the constraint S = I - n n^T
   cancels). D is symmetric positive semidefinite and tangential (S D S = D): the system stays symmetric positive
   definite. */
PetscErrorCode CollisionAddFrictionToImplicitStep(void *ctx, PetscReal h, Vec velocity, Vec force, Mat A)
{
  ClothCollision     col = (ClothCollision)ctx;
  Vec                normals;
  const PetscScalar *c, *v;
  PetscScalar       *f;
  const PetscBool   *fixed;
  const PetscReal   *mass;
  PetscReal          scale;
  PetscInt           nlocal;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothGetMasses(col->cloth, &mass, &fixed));
  PetscCall(ClothGetFrictionScale(col->cloth, &scale));
  PetscCall(ClothGetContactNormals(col->cloth, &normals));
  PetscCall(VecGetArrayRead(normals, &c));
  PetscCall(VecGetArrayRead(velocity, &v));
  PetscCall(VecGetArray(force, &f));
  for (PetscInt i = 0; i < nlocal; i++) {
    const SceneBody *d;
    PetscReal        n[3], vt[3], ff[3], D[9], vn, normal_force, mu_max, u, pull;
    PetscBool        could_reverse;

    for (PetscInt k = 0; k < 3; k++) col->vt_start[3 * i + k] = 0;
    /* free, pinned, or stuck (-collision_friction explicit's S = 0, e.g. from its checkpoint): nothing to add */
    if (fixed[i] || ClothContactScale(&c[3 * i]) != 1.0 || col->held[i].body < 0) continue;
    for (PetscInt k = 0; k < 3; k++) n[k] = PetscRealPart(c[3 * i + k]);
    PetscCall(ClothFrictionNormalLoad(&f[3 * i], n, &normal_force));
    PetscCall(BodyGetDescription(col->bodies[col->held[i].body], &d));
    if (normal_force == 0 || (d->friction_static == 0 && d->friction_kinetic == 0)) continue;
    vn = Dot3(&v[3 * i], n);
    for (PetscInt k = 0; k < 3; k++) vt[k] = v[3 * i + k] - vn * n[k];
    /* Friction whose impulse over the step, net of the pull along the slip, could stop the slip (h (mu N - F.t) >=
       m |v_t|) would, linearised at the start speed (D ~ 0 along the motion), carry it through v_t = 0 and throw its
       stiffly linked neighbours: then it acts as the drag mu N / s along the motion too, which slows the slip toward
       zero but cannot reverse it. A slip that the pull keeps going (an incline) keeps the full Jacobian. */
    u             = PetscSqrtReal(Dot3(vt, vt));
    pull          = u > 0 ? Dot3(&f[3 * i], vt) / u : 0.0;
    mu_max        = scale * PetscMax(d->friction_static, d->friction_kinetic);
    could_reverse = h * (mu_max * normal_force - pull) >= mass[i] * u ? PETSC_TRUE : PETSC_FALSE;
    PetscCall(ClothRegularisedFriction(scale * d->friction_static, scale * d->friction_kinetic, normal_force, col->friction_velocity, col->stribeck_velocity, could_reverse, n, vt, ff, D));
    for (PetscInt k = 0; k < 3; k++) {
      f[3 * i + k] += ff[k];
      col->vt_start[3 * i + k] = vt[k];
    }
    for (PetscInt k = 0; k < 9; k++) D[k] *= h;
    PetscCall(MatSetValuesBlockedLocal(A, 1, &i, 1, &i, D, ADD_VALUES));
  }
  PetscCall(VecRestoreArray(force, &f));
  PetscCall(VecRestoreArrayRead(velocity, &v));
  PetscCall(VecRestoreArrayRead(normals, &c));
  col->friction_solved = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After a step with friction in its solve, a held particle whose tangential velocity reversed: its friction was
   linearised across the kink at v_t = 0, where the linearisation fails (the force turns by 2 mu |F_n| within
   eps_v), and repeated reversals would leave it oscillating by about h mu |F_n| / m around rest. Friction can stop
   a particle within a step but not reverse it: it is stopped, and the next step, linearised at rest, decides
   whether it sticks. Within the regularisation band (|v_t| <= eps_v at the start) the linearised step converges
   by itself and is left alone. */
static void StopReversedSlip(const PetscReal vt_start[3], const PetscReal n[3], PetscReal eps, PetscScalar v[3])
{
  const PetscReal vn = Dot3(v, n);
  PetscReal       vt[3];

  for (PetscInt k = 0; k < 3; k++) vt[k] = v[k] - vn * n[k];
  if (Dot3(vt_start, vt_start) <= eps * eps || Dot3(vt, vt_start) >= 0) return;
  for (PetscInt k = 0; k < 3; k++) v[k] = vn * n[k];
}

/* Static friction that holds (implicit friction; docs/collisions.md, "Static friction that holds"): a particle pressed
   onto the body (F.n < 0) whose tangential velocity is below the stick velocity and whose tangential force static
   friction can cancel, |F_t| <= mu_s |F.n| (F the particle's force without friction at the step's start, as for the
   release), sticks: the next solve holds it still (S = 0), where the regularised law alone would let it creep at
   eps_v |F_t| / sqrt((mu_s |F.n|)^2 - |F_t|^2). Every step decides again, so it slides as soon as its neighbours or
   gravity pull harder than mu_s |F.n|. The stick velocity lies above every steady creep of the regularised law (at
   most about 10 eps_v at the defaults), so a creeping particle sticks, and far below real sliding. */
PetscReal CollisionStickVelocity(const ClothCollision col)
{
  return col->stick_velocity < 0 ? 20 * col->friction_velocity : col->stick_velocity;
}

static PetscBool StaticFrictionHolds(const ClothCollision col, const SceneBody *d, const PetscReal n[3], PetscReal fn, const PetscReal ft[3], const PetscScalar v[3])
{
  const PetscReal vn = Dot3(v, n);
  PetscReal       vt[3];

  for (PetscInt k = 0; k < 3; k++) vt[k] = v[k] - vn * n[k];
  return (fn < 0 && CollisionStickVelocity(col) > 0 && Dot3(vt, vt) <= PetscSqr(CollisionStickVelocity(col)) && PetscSqrtReal(Dot3(ft, ft)) <= col->friction_scale * d->friction_static * (-fn)) ? PETSC_TRUE : PETSC_FALSE;
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Contacts of one particle                                                                                     */

/* Mesh body b: the first triangle crossed puts the particle at the crossing point, offset by the thickness. */
static PetscErrorCode ContactMesh(ClothCollision col, PetscInt b, const PetscReal p0[3], PetscScalar x[3], HeldContact *contact)
{
  CollisionMesh   *cm = &col->meshes[b];
  const SceneBody *d;
  SegmentHit       hit, check;

  PetscFunctionBeginUser;
  PetscCall(BodyGetDescription(cm->body, &d));
  CollisionSearchSegment(col, cm, p0, x, &hit);
  if (col->verify) {
    PetscInt64 ignored = 0;
    CollisionSearchBruteForce(cm, p0, x, &check, &ignored);
    PetscCheck(hit.triangle == check.triangle && (hit.triangle < 0 || hit.t == check.t), PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "Collision search %s found triangle %" PetscInt_FMT " (t = %.17g), brute force triangle %" PetscInt_FMT " (t = %.17g), for the segment (%g, %g, %g) -> (%g, %g, %g)", ClothCollisionSearches[col->search], hit.triangle, (double)hit.t,
               check.triangle, (double)check.t, (double)p0[0], (double)p0[1], (double)p0[2], (double)x[0], (double)x[1], (double)x[2]);
    if (hit.triangle >= 0) col->local.verified++;
  }
  if (hit.triangle < 0) PetscFunctionReturn(PETSC_SUCCESS);
  col->local.crossings++;
  contact->body     = b;
  contact->triangle = hit.triangle;
  for (PetscInt k = 0; k < 3; k++) {
    contact->normal[k] = cm->face_normal[3 * hit.triangle + k];
    x[k]               = hit.point[k] + d->thickness * contact->normal[k];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Analytic body b: within the thickness (plus the slop) is a contact; inside the thickness is pushed out. */
static PetscErrorCode ContactAnalytic(ClothCollision col, PetscInt b, PetscScalar x[3], HeldContact *contact)
{
  const SceneBody *d;
  PetscReal        dist, n[3];

  PetscFunctionBeginUser;
  PetscCall(BodyGetDescription(col->bodies[b], &d));
  PetscCall(BodySignedDistance(col->bodies[b], x, &dist, n));
  if (dist >= d->thickness + CollisionContactSlop(d)) PetscFunctionReturn(PETSC_SUCCESS);
  if (dist < d->thickness)
    for (PetscInt k = 0; k < 3; k++) x[k] += (d->thickness - dist) * n[k];
  contact->body = b;
  for (PetscInt k = 0; k < 3; k++) contact->normal[k] = n[k];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A particle that neither crossed a mesh nor was held, but has come within the thickness of it from the
   outside (the search only sees crossings of the surface itself): a contact on the nearest triangle, as if
   held on it. Without this a particle drifted through the thickness layer unseen until it crossed the
   surface, and was then thrown out by up to the whole thickness in one step, which its stiff links turned
   into jitter (a dress's free particles at up to 0.9 m/s, 4 mm corrections on 5 particles every step).
   Within the thickness only: the thickness plus the slop (as for spheres and planes) caught falling
   particles up to the slop above the surface and froze them there. */
static PetscErrorCode ContactMeshProximity(ClothCollision col, PetscInt b, PetscScalar x[3], HeldContact *contact)
{
  CollisionMesh   *cm = &col->meshes[b];
  const SceneBody *d;
  PetscReal        q[3], r[3];
  PetscInt         tri;

  PetscFunctionBeginUser;
  PetscCall(BodyGetDescription(cm->body, &d));
  tri = CollisionNearestTriangleWithin(col, cm, x, d->thickness, q);
  if (tri < 0) PetscFunctionReturn(PETSC_SUCCESS);
  Sub3(x, q, r);
  if (Dot3(r, &cm->face_normal[3 * tri]) <= 0) PetscFunctionReturn(PETSC_SUCCESS); /* behind its triangle: not from the outside */
  contact->body     = b;
  contact->triangle = tri;
  for (PetscInt k = 0; k < 3; k++) contact->normal[k] = cm->face_normal[3 * tri + k];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A mesh contact held from the last step, without a new crossing: kept while the particle stays within the
   slop of the triangle it hit (pushed back to the thickness if it sank below its plane). Near the triangle,
   not only its plane: a particle that slid past the edge of a table or a shoulder was otherwise held on
   the plane's extension, a ledge that is not there, and friction on it stopped a hanging strip sliding off. */
static PetscErrorCode KeepHeldMeshContact(ClothCollision col, const HeldContact *held, PetscScalar x[3], HeldContact *contact)
{
  const SceneBody     *d;
  const MeshTriangles *m;
  const PetscInt      *tri;
  PetscReal            r[3], q[3], dist;

  PetscFunctionBeginUser;
  if (held->body < 0 || !col->meshes[held->body].mesh) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(BodyGetDescription(col->bodies[held->body], &d));
  m   = col->meshes[held->body].mesh;
  tri = &m->tris[3 * held->triangle];
  GeometryTriangleNearestPoint(x, &m->coords[3 * tri[0]], &m->coords[3 * tri[1]], &m->coords[3 * tri[2]], q);
  Sub3(x, q, r);
  if (Dot3(r, r) >= PetscSqr(d->thickness + CollisionContactSlop(d))) PetscFunctionReturn(PETSC_SUCCESS);
  /* the distance from the triangle's plane, measured from its first vertex: a restart, which knows the
     triangle, computes it bit for bit as the run did */
  for (PetscInt k = 0; k < 3; k++) r[k] = x[k] - m->coords[3 * tri[0] + k];
  dist = Dot3(r, held->normal);
  if (dist < d->thickness)
    for (PetscInt k = 0; k < 3; k++) x[k] += (d->thickness - dist) * held->normal[k];
  *contact = *held;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The corrections (offset, held-contact projection, friction) move the particle from where the search left it;
   in a concave region (neck and shoulders) that move may enter the body. The segment from the previous position
   (outside) to the corrected one is searched again, and a crossing puts the particle halfway between the previous
   position and that crossing, which is outside. */
static PetscErrorCode KeepOutside(ClothCollision col, const PetscReal p0[3], PetscScalar x[3])
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < col->nbodies; b++) {
    CollisionMesh *cm = &col->meshes[b];
    SegmentHit     hit;

    if (!cm->mesh) continue;
    CollisionSearchSegment(col, cm, p0, x, &hit);
    if (hit.triangle < 0) continue;
    for (PetscInt k = 0; k < 3; k++) x[k] = p0[k] + 0.5 * hit.t * (x[k] - p0[k]);
    col->local.fallbacks++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The body's normal force on particle i in this response: the larger of the force the held constraint
   cancels (the part of the particle's force into the body, -fn) and the force that removed the normal
   velocity dvn within the step (m dvn / h, an impact). At rest only the first remains. */
static PetscErrorCode RecordNormalForce(ClothCollision col, PetscInt i, PetscReal mass, PetscReal fn, PetscReal dvn, PetscReal h)
{
  PetscFunctionBeginUser;
  col->normal_force[i] = PetscMax(PetscMax(0.0, -fn), h > 0 ? mass * dvn / h : 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One owned particle: detection against every body, response, and whether it is held for the next step. */
PetscErrorCode CollisionContactParticle(ClothCollision col, PetscInt i, PetscReal h, PetscReal mass, const PetscScalar p0[3], const PetscScalar f[3], PetscScalar x[3], PetscScalar v[3], PetscScalar normal[3])
{
  HeldContact      contact = {-1, -1, {0, 0, 0}};
  const SceneBody *d;
  PetscReal        fn, ft[3], dv[3], dvn;
  PetscBool        stuck = PETSC_FALSE;
  /* held during the step just taken, with its friction in the solve */
  const PetscBool held_in_solve = (col->friction_solved && ClothContactScale(normal) > 0) ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  col->normal_force[i] = 0;
  for (PetscInt b = 0; b < col->nbodies; b++) {
    if (col->meshes[b].mesh)
      PetscCall(ContactMesh(col, b, p0, x, &contact));
    else
      PetscCall(ContactAnalytic(col, b, x, &contact));
  }
  if (contact.body < 0) PetscCall(KeepHeldMeshContact(col, &col->held[i], x, &contact));
  for (PetscInt b = 0; b < col->nbodies && contact.body < 0; b++) {
    HeldContact near = {-1, -1, {0, 0, 0}};

    if (!col->meshes[b].mesh) continue;
    PetscCall(ContactMeshProximity(col, b, x, &near));
    if (near.body >= 0) PetscCall(KeepHeldMeshContact(col, &near, x, &contact));
  }
  col->held[i].body = -1;
  col->state[i]     = CONTACT_STATE_FREE;
  for (PetscInt k = 0; k < 3; k++) normal[k] = 0;
  if (contact.body < 0) PetscFunctionReturn(PETSC_SUCCESS);
  col->local.contacts++;
  col->state[i] = CONTACT_STATE_TOUCHING;
  PetscCall(BodyGetDescription(col->bodies[contact.body], &d));
  fn = Dot3(f, contact.normal);
  for (PetscInt k = 0; k < 3; k++) ft[k] = f[k] - fn * contact.normal[k];
  for (PetscInt k = 0; k < 3; k++) dv[k] = -v[k];
  if (!col->friction_solved) /* -collision_friction explicit (or an integrator without the implicit solve) */
    stuck = RespondVelocity(d, col->friction_scale, contact.normal, h * PetscMax(0.0, -fn) / mass, h * PetscSqrtReal(Dot3(ft, ft)) / mass, v);
  else if (held_in_solve) { /* friction acted in the solve: only the velocity into the body, and no reversal */
    (void)RespondVelocity(d, 0.0, contact.normal, 0, 0, v);
    StopReversedSlip(&col->vt_start[3 * i], contact.normal, col->friction_velocity, v);
  } else /* an impact: Coulomb's impulse, bounded by the normal velocity the contact removed */
    (void)RespondVelocity(d, col->friction_scale, contact.normal, 0, 0, v);
  if (col->friction_solved) stuck = StaticFrictionHolds(col, d, contact.normal, fn, ft, v);
  /* The step moved the particle by h v_{n+1} (both Euler forms that hold contacts do; BDF2 by 2h/3 v_{n+1} plus its
     history's part, the same to within its 3/2): redo the tangential part with the velocity friction left, or a stuck
     particle would still creep by h^2 a_t every step. */
  for (PetscInt k = 0; k < 3; k++) dv[k] += v[k];
  dvn = Dot3(dv, contact.normal);
  PetscCall(RecordNormalForce(col, i, mass, fn, dvn, h));
  for (PetscInt k = 0; k < 3; k++) x[k] += h * (dv[k] - dvn * contact.normal[k]);
  PetscCall(KeepOutside(col, p0, x));
  if (fn < 0) { /* the force pushes into the body: hold the particle on the surface during the next step */
    col->held[i]  = contact;
    col->state[i] = CONTACT_STATE_HELD;
    for (PetscInt k = 0; k < 3; k++) normal[k] = (stuck ? CLOTH_CONTACT_STUCK : 1.0) * contact.normal[k];
    if (stuck) /* held still: the next step constrains all of its motion, so nothing of v may remain */
      for (PetscInt k = 0; k < 3; k++) v[k] = 0;
    col->local.held++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
