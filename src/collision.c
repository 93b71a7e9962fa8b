/* ClothCollision (see collision.h). */
#include "collision.h"
#include "cellgrid.h"
#include "friction.h"
#include "geometry.h"
#include "log.h"
#include "vec3.h"
#include "options.h"

const char *const ClothCollisionSearches[]  = {"grid", "brute_force", "ClothCollisionSearch", "CLOTH_COLLISION_SEARCH_", NULL};
const char *const ClothCollisionFrictions[] = {"implicit", "explicit", "ClothCollisionFriction", "CLOTH_COLLISION_FRICTION_", NULL};

#define COLLISION_MAX_CELLS 8000000    /* the grid's cells grow beyond -collision_cell_size rather than exceed this */
#define COLLISION_BARYCENTRIC_TOL 1e-9 /* a segment through a shared edge hits at least one of its triangles */
/* A piece may start with at most this fraction of its particles inside a body (moved to the surface at set-up) unless
   -collision_allow_inside: a few are a hem touching a shoulder (tests/data/mannequin_shoulders.yaml: 30 of 1089,
   2.8 %); more are a piece laid through the body, which the push-out tears (a T-shirt front through the torso, 105 of
   its 169 particles: link strain 14, 48 of 56 seam pairs sewn, each step 15 times slower). */
#define COLLISION_MAX_INSIDE_FRACTION 0.05

/* A mesh body and this rank's cell grid over it. */
typedef struct {
  Body                 body;
  const MeshTriangles *mesh;
  const PetscReal     *face_normal;
  PetscReal            body_lo[3], body_hi[3]; /* bounding box, slightly inflated */
  PetscReal           *tri_lo, *tri_hi;        /* triangle boxes, slightly inflated, 3 per triangle */
  PetscReal            mean_edge;
  /* the grid */
  PetscBool built;
  PetscReal covered_lo[3], covered_hi[3]; /* particles inside this box are served by the grid */
  PetscReal lo[3], hi[3];                 /* the grid's box: the covered box clipped to the body box */
  CellGrid  grid;                         /* the triangles touching each cell (no cells: the covered box misses the body) */
  PetscInt *stamp;                        /* per triangle: last query that tested it */
  PetscInt  query;
} CollisionMesh;

/* The first triangle a segment crosses from the outside (smallest parameter, then lowest index). */
typedef struct {
  PetscInt  triangle; /* -1: none */
  PetscReal t;
  PetscReal point[3];
} SegmentHit;

/* The per-particle contact state (ClothCollisionGetContactField). */
enum { CONTACT_STATE_FREE, CONTACT_STATE_TOUCHING, CONTACT_STATE_HELD };

/* A contact kept from one step to the next (meshes need the plane of the triangle that was hit). */
typedef struct {
  PetscInt  body;     /* -1: none */
  PetscInt  triangle; /* meshes: the triangle that was hit */
  PetscReal normal[3];
} HeldContact;

struct _n_ClothCollision {
  Cloth                  cloth;
  MPI_Comm               comm;
  Scene                  scene;
  ClothCollisionSearch   search;
  PetscReal              cell_size, margin;
  PetscReal              friction_scale;                       /* the cloth's, read once per ClothCollisionApply */
  ClothCollisionFriction friction;                             /* where friction of held contacts acts */
  PetscReal              friction_velocity, stribeck_velocity; /* eps_v and v_s of the regularised law, m/s */
  PetscReal              stick_velocity;                       /* implicit friction: held particles slower than this may stick, m/s (< 0: 20 eps_v) */
  PetscBool              friction_solved;                      /* the step just taken had the friction of held contacts in its solve */
  PetscReal             *vt_start;                             /* per owned particle held in that solve: its tangential velocity at the step's start */
  PetscBool              verify, view, setup;
  PetscBool              allow_inside; /* -collision_allow_inside: pieces may start inside a body beyond COLLISION_MAX_INSIDE_FRACTION */
  PetscInt               nbodies;
  Body                  *bodies;
  CollisionMesh         *meshes;        /* one per body; used for mesh bodies */
  HeldContact           *held;          /* per owned particle */
  PetscInt              *state;         /* per owned particle: the contact state of ClothCollisionGetContactField */
  PetscReal             *normal_force;  /* per owned particle: ClothCollisionGetNormalForces */
  HeldContact           *held_saved[2]; /* held, state and the cloth's contact normals per save slot (ClothCollisionSave) */
  PetscInt              *state_saved[2];
  Vec                    normal_saved[2];
  Vec                    force;
  ClothCollisionStats    stats, local;
};

/* ------------------------------------------------------------------------------------------------------------ */
/* Segment against triangles                                                                                   */

/* The paper's triangle-box rejection, then the exact test; keeps the first hit. */
static void TestTriangle(const CollisionMesh *cm, PetscInt tri, const PetscReal p0[3], const PetscReal d[3], const PetscReal seg_lo[3], const PetscReal seg_hi[3], SegmentHit *hit, PetscInt64 *tests)
{
  const PetscInt *v = &cm->mesh->tris[3 * tri];
  PetscReal       t;

  if (!GeometryBoxesOverlap(seg_lo, seg_hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) return;
  if (Dot3(&cm->face_normal[3 * tri], &cm->face_normal[3 * tri]) == 0) return; /* degenerate */
  (*tests)++;
  if (!GeometrySegmentCrossesTriangle(p0, d, &cm->mesh->coords[3 * v[0]], &cm->mesh->coords[3 * v[1]], &cm->mesh->coords[3 * v[2]], COLLISION_BARYCENTRIC_TOL, &t)) return;
  if (hit->triangle < 0 || t < hit->t || (t == hit->t && tri < hit->triangle)) {
    hit->triangle = tri;
    hit->t        = t;
  }
}

static void FinishHit(const PetscReal p0[3], const PetscReal d[3], SegmentHit *hit)
{
  if (hit->triangle >= 0)
    for (PetscInt k = 0; k < 3; k++) hit->point[k] = p0[k] + hit->t * d[k];
}

static void SearchBruteForce(const CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit, PetscInt64 *tests)
{
  PetscReal d[3], lo[3], hi[3];

  hit->triangle = -1;
  for (PetscInt k = 0; k < 3; k++) d[k] = p1[k] - p0[k];
  GeometrySegmentBox(p0, p1, lo, hi);
  if (!GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return;
  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) TestTriangle(cm, tri, p0, d, lo, hi, hit, tests);
  FinishHit(p0, d, hit);
}

/* The cell grid: every cell the segment passes through, in order, each triangle tested once per query. */
static void SearchGrid(CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit, PetscInt64 *tests)
{
  PetscReal       d[3], lo[3], hi[3];
  PetscInt        n[3], c;
  const PetscInt *start, *tris;
  CellGridWalk    walk;

  hit->triangle = -1;
  for (PetscInt k = 0; k < 3; k++) d[k] = p1[k] - p0[k];
  GeometrySegmentBox(p0, p1, lo, hi);
  if (!CellGridHasCells(cm->grid) || !GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return;
  CellGridGetCells(cm->grid, n, &start, &tris);
  cm->query++;
  for (CellGridWalkBegin(cm->grid, p0, d, &walk); CellGridWalkNext(cm->grid, &walk, &c);)
    for (PetscInt j = start[c]; j < start[c + 1]; j++) {
      const PetscInt tri = tris[j];
      if (cm->stamp[tri] == cm->query) continue;
      cm->stamp[tri] = cm->query;
      TestTriangle(cm, tri, p0, d, lo, hi, hit, tests);
    }
  FinishHit(p0, d, hit);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* The per-rank grid                                                                                           */

/* Builds the grid over the particle box [plo, phi] grown by the margin and clipped to the body's box. */
static PetscErrorCode GridBuild(CollisionMesh *cm, const PetscReal plo[3], const PetscReal phi[3], PetscReal margin, PetscReal cell_size)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.collision_grid, 0, 0, 0, 0));
  for (PetscInt k = 0; k < 3; k++) {
    cm->covered_lo[k] = plo[k] - margin;
    cm->covered_hi[k] = phi[k] + margin;
    cm->lo[k]         = PetscMax(cm->covered_lo[k], cm->body_lo[k]);
    cm->hi[k]         = PetscMin(cm->covered_hi[k], cm->body_hi[k]);
  }
  cm->built = PETSC_TRUE;
  PetscCall(CellGridBuild(cm->grid, cm->lo, cm->hi, cell_size > 0 ? cell_size : 2 * cm->mean_edge, COLLISION_MAX_CELLS, cm->mesh->ntris, cm->tri_lo, cm->tri_hi, 3));
  PetscCall(PetscLogEventEnd(ClothLog.collision_grid, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Triangle boxes, the body box and the mean edge length (the default cell size is twice that). The boxes are
   inflated by a small fraction of the mean edge so that round-off in the grid walk cannot skip a triangle. */
static PetscErrorCode MeshSetUp(CollisionMesh *cm, Body body)
{
  PetscReal eps, sum = 0;

  PetscFunctionBeginUser;
  cm->body = body;
  PetscCall(CellGridCreate(&cm->grid));
  PetscCall(BodyGetMesh(body, &cm->mesh, &cm->face_normal, cm->body_lo, cm->body_hi));
  PetscCall(PetscMalloc3(3 * cm->mesh->ntris, &cm->tri_lo, 3 * cm->mesh->ntris, &cm->tri_hi, cm->mesh->ntris, &cm->stamp));
  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) {
    const PetscInt *v = &cm->mesh->tris[3 * tri];
    cm->stamp[tri]    = -1;
    for (PetscInt k = 0; k < 3; k++) {
      const PetscReal a = cm->mesh->coords[3 * v[0] + k], b = cm->mesh->coords[3 * v[1] + k], c = cm->mesh->coords[3 * v[2] + k];
      cm->tri_lo[3 * tri + k] = PetscMin(a, PetscMin(b, c));
      cm->tri_hi[3 * tri + k] = PetscMax(a, PetscMax(b, c));
    }
    for (PetscInt e = 0; e < 3; e++) {
      const PetscReal *a = &cm->mesh->coords[3 * v[e]], *b = &cm->mesh->coords[3 * v[(e + 1) % 3]];
      sum += PetscSqrtReal((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
  }
  cm->mean_edge = sum / (3 * cm->mesh->ntris);
  eps           = 1e-3 * cm->mean_edge;
  for (PetscInt j = 0; j < 3 * cm->mesh->ntris; j++) {
    cm->tri_lo[j] -= eps;
    cm->tri_hi[j] += eps;
  }
  for (PetscInt k = 0; k < 3; k++) {
    cm->body_lo[k] -= eps;
    cm->body_hi[k] += eps;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rebuilds each mesh grid when a segment end lies outside the region it covers. Local (no communication). */
static PetscErrorCode UpdateGrids(ClothCollision col, const PetscScalar *xp, const PetscScalar *x, PetscInt nlocal)
{
  PetscReal lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};

  PetscFunctionBeginUser;
  if (nlocal == 0) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt k = 0; k < 3; k++) {
      lo[k] = PetscMin(lo[k], PetscMin(xp[3 * i + k], x[3 * i + k]));
      hi[k] = PetscMax(hi[k], PetscMax(xp[3 * i + k], x[3 * i + k]));
    }
  for (PetscInt b = 0; b < col->nbodies; b++) {
    CollisionMesh *cm = &col->meshes[b];
    PetscBool      inside;

    if (!cm->mesh) continue;
    inside = cm->built;
    for (PetscInt k = 0; k < 3 && inside; k++)
      if (lo[k] < cm->covered_lo[k] || hi[k] > cm->covered_hi[k]) inside = PETSC_FALSE;
    if (inside) continue;
    PetscCall(GridBuild(cm, lo, hi, col->margin, col->cell_size));
    col->local.grid_rebuilds++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Response                                                                                                    */

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
static PetscReal ContactSlop(const SceneBody *d)
{
  return PetscMax(0.5 * d->thickness, 1e-5);
}

/* The add_to_implicit_step of the body-friction contribution (cloth.h) of -collision_friction implicit: for every owned particle held (sliding) on a body, the
   regularised friction at the step's start velocity goes into the force (so h f into the right-hand side) and h D
   onto its diagonal block: the linearised backward-Euler step with f(v + dv) ~ f(v) - D dv. The normal force is
   the push into the body of the force at the step's start, N = max(0, -F.n) (the force the constraint S = I - n n^T
   cancels). D is symmetric positive semidefinite and tangential (S D S = D): the system stays symmetric positive
   definite. */
static PetscErrorCode AddFrictionToImplicitStep(void *ctx, PetscReal h, Vec velocity, Vec force, Mat A)
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
static PetscReal StickVelocity(const ClothCollision col)
{
  return col->stick_velocity < 0 ? 20 * col->friction_velocity : col->stick_velocity;
}

static PetscBool StaticFrictionHolds(const ClothCollision col, const SceneBody *d, const PetscReal n[3], PetscReal fn, const PetscReal ft[3], const PetscScalar v[3])
{
  const PetscReal vn = Dot3(v, n);
  PetscReal       vt[3];

  for (PetscInt k = 0; k < 3; k++) vt[k] = v[k] - vn * n[k];
  return (fn < 0 && StickVelocity(col) > 0 && Dot3(vt, vt) <= PetscSqr(StickVelocity(col)) && PetscSqrtReal(Dot3(ft, ft)) <= col->friction_scale * d->friction_static * (-fn)) ? PETSC_TRUE : PETSC_FALSE;
}

/* The first triangle of mesh cm that the segment p0 -> p1 crosses from the outside, by the chosen search. */
static void SearchSegment(ClothCollision col, CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit)
{
  if (col->search == CLOTH_COLLISION_SEARCH_GRID)
    SearchGrid(cm, p0, p1, hit, &col->local.triangle_tests);
  else
    SearchBruteForce(cm, p0, p1, hit, &col->local.triangle_tests);
}

/* Mesh body b: the first triangle crossed puts the particle at the crossing point, offset by the thickness. */
static PetscErrorCode ContactMesh(ClothCollision col, PetscInt b, const PetscReal p0[3], PetscScalar x[3], HeldContact *contact)
{
  CollisionMesh   *cm = &col->meshes[b];
  const SceneBody *d;
  SegmentHit       hit, check;

  PetscFunctionBeginUser;
  PetscCall(BodyGetDescription(cm->body, &d));
  SearchSegment(col, cm, p0, x, &hit);
  if (col->verify) {
    PetscInt64 ignored = 0;
    SearchBruteForce(cm, p0, x, &check, &ignored);
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
  if (dist >= d->thickness + ContactSlop(d)) PetscFunctionReturn(PETSC_SUCCESS);
  if (dist < d->thickness)
    for (PetscInt k = 0; k < 3; k++) x[k] += (d->thickness - dist) * n[k];
  contact->body = b;
  for (PetscInt k = 0; k < 3; k++) contact->normal[k] = n[k];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Tests triangle tri of cm for the nearest point to x closer than *best_d2; keeps the best. */
static void NearestOnTriangle(const CollisionMesh *cm, PetscInt tri, const PetscScalar x[3], PetscReal *best_d2, PetscInt *best, PetscReal q[3])
{
  const PetscInt *v = &cm->mesh->tris[3 * tri];
  PetscReal       p[3], r[3];

  if (Dot3(&cm->face_normal[3 * tri], &cm->face_normal[3 * tri]) == 0) return; /* degenerate */
  GeometryTriangleNearestPoint(x, &cm->mesh->coords[3 * v[0]], &cm->mesh->coords[3 * v[1]], &cm->mesh->coords[3 * v[2]], p);
  Sub3(x, p, r);
  if (Dot3(r, r) < *best_d2 || (Dot3(r, r) == *best_d2 && *best >= 0 && tri < *best)) {
    *best_d2 = Dot3(r, r);
    *best    = tri;
    for (PetscInt k = 0; k < 3; k++) q[k] = p[k];
  }
}

/* The triangle of mesh cm nearest to x within radius (-1: none) and the nearest point q on it, through the
   cell grid (every triangle that comes within radius of x overlaps the box x +- radius) or by brute force. */
static PetscInt NearestTriangleWithin(ClothCollision col, CollisionMesh *cm, const PetscScalar x[3], PetscReal radius, PetscReal q[3])
{
  PetscReal       lo[3], hi[3], best_d2 = radius * radius;
  PetscInt        best = -1, first[3], last[3], n[3];
  const PetscInt *start, *tris;

  for (PetscInt k = 0; k < 3; k++) {
    lo[k] = x[k] - radius;
    hi[k] = x[k] + radius;
  }
  if (!GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return -1;
  if (col->search == CLOTH_COLLISION_SEARCH_BRUTE_FORCE) {
    for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++)
      if (GeometryBoxesOverlap(lo, hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
    return best;
  }
  if (!CellGridHasCells(cm->grid) || !GeometryBoxesOverlap(lo, hi, cm->lo, cm->hi)) return -1;
  CellGridGetCells(cm->grid, n, &start, &tris);
  cm->query++;
  CellGridGetCellRange(cm->grid, lo, hi, first, last);
  for (PetscInt i = first[0]; i <= last[0]; i++)
    for (PetscInt j = first[1]; j <= last[1]; j++)
      for (PetscInt l = first[2]; l <= last[2]; l++) {
        const PetscInt c = CellGridCellIndex(n, i, j, l);
        for (PetscInt e = start[c]; e < start[c + 1]; e++) {
          const PetscInt tri = tris[e];
          if (cm->stamp[tri] == cm->query) continue;
          cm->stamp[tri] = cm->query;
          if (GeometryBoxesOverlap(lo, hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
        }
      }
  return best;
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
  tri = NearestTriangleWithin(col, cm, x, d->thickness, q);
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
  if (Dot3(r, r) >= PetscSqr(d->thickness + ContactSlop(d))) PetscFunctionReturn(PETSC_SUCCESS);
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
    SearchSegment(col, cm, p0, x, &hit);
    if (hit.triangle < 0) continue;
    for (PetscInt k = 0; k < 3; k++) x[k] = p0[k] + 0.5 * hit.t * (x[k] - p0[k]);
    col->local.fallbacks++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode RecordNormalForce(ClothCollision, PetscInt, PetscReal, PetscReal, PetscReal, PetscReal);

/* One owned particle: detection against every body, response, and whether it is held for the next step. */
static PetscErrorCode ContactParticle(ClothCollision col, PetscInt i, PetscReal h, PetscReal mass, const PetscScalar p0[3], const PetscScalar f[3], PetscScalar x[3], PetscScalar v[3], PetscScalar normal[3])
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

/* ------------------------------------------------------------------------------------------------------------ */
/* Object                                                                                                      */

PetscErrorCode ClothCollisionCreate(Cloth cloth, Scene scene, ClothCollision *collision)
{
  ClothCollision col;

  PetscFunctionBeginUser;
  PetscCall(ClothLogRegister());
  PetscCall(PetscNew(&col));
  col->cloth             = cloth;
  col->scene             = scene;
  col->comm              = scene->comm;
  col->nbodies           = scene->nbodies;
  col->search            = CLOTH_COLLISION_SEARCH_GRID;
  col->margin            = 0.05;
  col->friction          = CLOTH_COLLISION_FRICTION_IMPLICIT;
  col->friction_velocity = 1e-4; /* creep of a stuck particle: at most a few eps_v (docs/collisions.md) */
  col->stribeck_velocity = 1e-2;
  col->stick_velocity    = -1; /* 20 eps_v, once eps_v is known */
  *collision             = col;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSetSearch(ClothCollision col, ClothCollisionSearch search)
{
  PetscFunctionBeginUser;
  col->search = search;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSetFriction(ClothCollision col, ClothCollisionFriction friction)
{
  PetscFunctionBeginUser;
  PetscCheck(!col->setup, col->comm, PETSC_ERR_ORDER, "Set the friction treatment before ClothCollisionSetUp");
  col->friction = friction;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSetVerify(ClothCollision col, PetscBool verify)
{
  PetscFunctionBeginUser;
  col->verify = verify;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSetFromOptions(ClothCollision col)
{
  PetscBool stick_set;

  PetscFunctionBeginUser;
  PetscOptionsBegin(col->comm, NULL, "Collisions with rigid bodies", "ClothCollision");
  PetscCall(PetscOptionsEnum("-collision_search", "How segments find the triangles they may cross", "ClothCollisionSetSearch", ClothCollisionSearches, (PetscEnum)col->search, (PetscEnum *)&col->search, NULL));
  PetscCall(PetscOptionsReal("-collision_cell_size", "Edge of a grid cell, m (0: twice the mean triangle edge)", "ClothCollisionSetUp", col->cell_size, &col->cell_size, NULL));
  PetscCall(PetscOptionsReal("-collision_grid_margin", "The grid covers this rank's particles plus this margin, m; it is rebuilt when a particle leaves that region", "ClothCollisionApply", col->margin, &col->margin, NULL));
  PetscCall(PetscOptionsBool("-collision_verify", "Search every segment with the grid and brute force too; error if they differ", "ClothCollisionSetVerify", col->verify, &col->verify, NULL));
  PetscCall(PetscOptionsBool("-collision_view", "Print the bodies and the collision set-up", "ClothCollisionView", col->view, &col->view, NULL));
  PetscCall(
      PetscOptionsBool("-collision_allow_inside", "Let a piece start with more than 5 % of its particles inside a body (they are moved to its surface, which tears the piece)", "ClothCollisionSetUp", col->allow_inside, &col->allow_inside, NULL));
  PetscCall(PetscOptionsEnum("-collision_friction", "Friction of held contacts: implicit (regularised Coulomb law and its Jacobian in the implicit step) or explicit (velocity filter after the step)", "ClothCollisionSetFriction",
                             ClothCollisionFrictions, (PetscEnum)col->friction, (PetscEnum *)&col->friction, NULL));
  PetscCall(PetscOptionsReal("-collision_friction_velocity", "Implicit friction: regularisation velocity eps_v, m/s (a stuck particle creeps at about eps_v |F_t| / (mu_s |F_n|))", "ClothCollisionSetFromOptions", col->friction_velocity,
                             &col->friction_velocity, NULL));
  PetscCall(PetscOptionsReal("-collision_friction_stribeck_velocity", "Implicit friction: the coefficient falls from static to kinetic as exp(-(|v_t|/v_s)^2), v_s in m/s (0: kinetic only)", "ClothCollisionSetFromOptions", col->stribeck_velocity,
                             &col->stribeck_velocity, NULL));
  PetscCall(PetscOptionsReal("-collision_friction_stick_velocity",
                             "Implicit friction: a held particle slower than this (m/s) whose tangential force static friction can hold is held still (default 20 times eps_v; 0: never, the regularised law alone)", "ClothCollisionSetFromOptions",
                             col->stick_velocity, &col->stick_velocity, &stick_set));
  PetscOptionsEnd();
  if (stick_set) PetscCall(ClothOptionsCheckReal(col->comm, "-collision_friction_stick_velocity", col->stick_velocity, 0, PETSC_FALSE, PETSC_MAX_REAL, "m/s"));
  PetscCall(ClothOptionsCheckReal(col->comm, "-collision_friction_velocity", col->friction_velocity, 0, PETSC_TRUE, PETSC_MAX_REAL, "m/s"));
  PetscCall(ClothOptionsCheckReal(col->comm, "-collision_friction_stribeck_velocity", col->stribeck_velocity, 0, PETSC_FALSE, PETSC_MAX_REAL, "m/s"));
  PetscCall(ClothOptionsCheckReal(col->comm, "-collision_cell_size", col->cell_size, 0, PETSC_FALSE, PETSC_MAX_REAL, "m"));
  /* positive: corrected particles may move slightly beyond their segment */
  PetscCall(ClothOptionsCheckReal(col->comm, "-collision_grid_margin", col->margin, 0, PETSC_TRUE, PETSC_MAX_REAL, "m"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The offset direction for a point x inside the body whose nearest surface point is q: from x to q, which is
   outward also when q is on an edge or vertex (where the face normal n of one triangle may point into a
   concave neighbour); n when x is on the surface already. */
static PetscErrorCode OutwardFromInside(const PetscScalar x[3], const PetscReal q[3], PetscReal n[3])
{
  PetscReal u[3], len;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 3; k++) u[k] = q[k] - x[k];
  len = PetscSqrtReal(Dot3(u, u));
  if (len > 1e-12)
    for (PetscInt k = 0; k < 3; k++) n[k] = u[k] / len;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The piece of natural particle g. */
static PetscInt PieceOfParticle(ClothModel model, PetscInt npieces, PetscInt g)
{
  PetscInt p = 0;

  while (p + 1 < npieces && g >= model->piece_offset[p + 1]) p++;
  return p;
}

/* Names the pieces that started inside bodies (inside: per piece and body, piece_inside: per piece), summed over the
   ranks: a warning for each, and a refusal when a piece has more than COLLISION_MAX_INSIDE_FRACTION of its particles
   inside, unless -collision_allow_inside. */
static PetscErrorCode ReportStartingInside(ClothCollision col, const PetscInt inside[], const PetscInt piece_inside[])
{
  const Scene scene = col->scene;
  ClothModel  model;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(col->cloth, &model));
  for (PetscInt p = 0; p < scene->npieces; p++) {
    const PetscInt n    = model->piece_offset[p + 1] - model->piece_offset[p];
    PetscInt       most = 0; /* the body that holds most of it */

    for (PetscInt b = 1; b < col->nbodies; b++)
      if (inside[p * col->nbodies + b] > inside[p * col->nbodies + most]) most = b;
    PetscCheck(col->allow_inside || piece_inside[p] <= COLLISION_MAX_INSIDE_FRACTION * n, col->comm, PETSC_ERR_USER_INPUT,
               "scene %s: %" PetscInt_FMT " of the %" PetscInt_FMT
               " particles of piece '%s' (%.0f %%) start inside body '%s': expected at most %d %% of a piece (moved to the body's surface, it would be torn): place the piece outside the body, or allow it with -collision_allow_inside",
               scene->path, piece_inside[p], n, scene->pieces[p].name, 100.0 * (double)piece_inside[p] / (double)n, scene->bodies[most].name, (int)(100 * COLLISION_MAX_INSIDE_FRACTION + 0.5));
  }
  for (PetscInt p = 0; p < scene->npieces; p++)
    for (PetscInt b = 0; b < col->nbodies; b++)
      if (inside[p * col->nbodies + b])
        PetscCall(PetscFPrintf(col->comm, PETSC_STDERR, "WARNING: scene %s: %" PetscInt_FMT " of the %" PetscInt_FMT " particles of piece '%s' start inside body '%s': moved to its surface\n", scene->path, inside[p * col->nbodies + b],
                               model->piece_offset[p + 1] - model->piece_offset[p], scene->pieces[p].name, scene->bodies[b].name));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Particles that start inside a body go to the nearest surface point, offset by the thickness, at rest; the pieces
   they belong to are named (ReportStartingInside). */
static PetscErrorCode PushOutStartingInside(ClothCollision col)
{
  Vec          x, v;
  PetscScalar *xa, *va;
  PetscInt     nlocal, pushed = 0, *inside, *piece_inside, npieces = col->scene->npieces;
  ClothLayout  layout;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(col->cloth, &x, &v));
  PetscCall(ClothGetLayout(col->cloth, &layout));
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(PetscCalloc2(npieces * col->nbodies, &inside, npieces, &piece_inside));
  PetscCall(VecGetArray(x, &xa));
  PetscCall(VecGetArray(v, &va));
  for (PetscInt i = 0; i < nlocal; i++) {
    const PetscInt p   = PieceOfParticle(layout.model, npieces, layout.natural_of_local[i]);
    PetscBool      any = PETSC_FALSE;

    for (PetscInt b = 0; b < col->nbodies; b++) {
      const SceneBody *d;
      PetscBool        is_inside;
      PetscReal        q[3], n[3];

      PetscCall(BodyIsInside(col->bodies[b], &xa[3 * i], &is_inside));
      if (!is_inside) continue;
      PetscCall(BodyGetDescription(col->bodies[b], &d));
      PetscCall(BodyNearestSurfacePoint(col->bodies[b], &xa[3 * i], q, n));
      PetscCall(OutwardFromInside(&xa[3 * i], q, n));
      for (PetscInt k = 0; k < 3; k++) {
        xa[3 * i + k] = q[k] + d->thickness * n[k];
        va[3 * i + k] = 0;
      }
      pushed++;
      inside[p * col->nbodies + b]++;
      any = PETSC_TRUE;
    }
    if (any) piece_inside[p]++;
  }
  PetscCall(VecRestoreArray(v, &va));
  PetscCall(VecRestoreArray(x, &xa));
  PetscCallMPI(MPI_Allreduce(&pushed, &col->stats.pushed_out, 1, MPIU_INT, MPI_SUM, col->comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, inside, (PetscMPIInt)(npieces * col->nbodies), MPIU_INT, MPI_SUM, col->comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, piece_inside, (PetscMPIInt)npieces, MPIU_INT, MPI_SUM, col->comm));
  PetscCall(ReportStartingInside(col, inside, piece_inside));
  PetscCall(PetscFree2(inside, piece_inside));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSetUp(ClothCollision col)
{
  PetscInt nlocal;

  PetscFunctionBeginUser;
  if (col->setup) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(PetscCalloc2(col->nbodies, &col->bodies, col->nbodies, &col->meshes));
  PetscCall(PetscMalloc1(nlocal, &col->held));
  PetscCall(PetscCalloc1(3 * nlocal, &col->vt_start));
  PetscCall(PetscCalloc1(nlocal, &col->state)); /* CONTACT_STATE_FREE */
  PetscCall(PetscCalloc1(nlocal, &col->normal_force));
  for (PetscInt i = 0; i < nlocal; i++) col->held[i].body = -1;
  for (PetscInt b = 0; b < col->nbodies; b++) {
    char context[CLOTH_PATH_LEN + CLOTH_NAME_LEN + 32];

    PetscCall(PetscSNPrintf(context, sizeof(context), "scene %s, body '%s'", col->scene->path, col->scene->bodies[b].name));
    PetscCall(BodyCreate(col->comm, &col->scene->bodies[b], context, &col->bodies[b]));
    if (col->scene->bodies[b].type == SCENE_BODY_MESH) PetscCall(MeshSetUp(&col->meshes[b], col->bodies[b]));
  }
  PetscCall(ClothCreateStateVec(col->cloth, &col->force));
  PetscCall(PushOutStartingInside(col));
  { /* the held contacts' checkpoint field (collision_checkpoint.c) and, implicit, the friction */
    ClothContribution contacts = {.name = "body contacts", .ctx = col, .checkpoint_fields = ClothCollisionCheckpointFields_Private, .checkpoint_load = ClothCollisionCheckpointLoad_Private};

    if (col->friction == CLOTH_COLLISION_FRICTION_IMPLICIT) contacts.add_to_implicit_step = AddFrictionToImplicitStep;
    PetscCall(ClothAddContribution(col->cloth, &contacts));
  }
  col->setup = PETSC_TRUE;
  if (col->view) PetscCall(ClothCollisionView(col, PETSC_VIEWER_STDOUT_(col->comm)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionGetBodies(ClothCollision col, PetscInt *nbodies, const Body **bodies)
{
  PetscFunctionBeginUser;
  if (nbodies) *nbodies = col->nbodies;
  if (bodies) *bodies = col->bodies;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionGetCloth(ClothCollision col, Cloth *cloth)
{
  PetscFunctionBeginUser;
  *cloth = col->cloth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Sums this step's local counts into stats (grid rebuilds accumulate over the run). */
static PetscErrorCode ReduceStats(ClothCollision col)
{
  PetscInt   local[6] = {col->local.contacts, col->local.held, col->local.crossings, col->local.verified, col->local.grid_rebuilds, col->local.fallbacks}, global[6];
  PetscInt64 tests;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(local, global, 6, MPIU_INT, MPI_SUM, col->comm));
  PetscCallMPI(MPI_Allreduce(&col->local.triangle_tests, &tests, 1, MPIU_INT64, MPI_SUM, col->comm));
  col->stats.contacts  = global[0];
  col->stats.held      = global[1];
  col->stats.crossings = global[2];
  col->stats.verified += global[3];
  col->stats.grid_rebuilds  = global[4];
  col->stats.fallbacks      = global[5];
  col->stats.triangle_tests = tests;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionApply(ClothCollision col, Vec previous, PetscReal h)
{
  Vec                x, v, normals;
  const PetscScalar *xp, *f;
  PetscScalar       *xa, *va, *na;
  const PetscReal   *mass;
  const PetscBool   *fixed;
  PetscInt           nlocal;

  PetscFunctionBeginUser;
  if (!col->nbodies) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothCollisionSetUp(col));
  PetscCall(ClothGetState(col->cloth, &x, &v));
  PetscCall(ClothComputeForces(col->cloth, previous, v, col->force)); /* decides friction and release; outside the event */
  PetscCall(PetscLogEventBegin(ClothLog.collision, 0, 0, 0, 0));
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothGetMasses(col->cloth, &mass, &fixed));
  PetscCall(ClothGetContactNormals(col->cloth, &normals));
  PetscCall(VecGetArrayRead(previous, &xp));
  PetscCall(VecGetArrayRead(col->force, &f));
  PetscCall(VecGetArray(x, &xa));
  PetscCall(VecGetArray(v, &va));
  PetscCall(VecGetArray(normals, &na));
  col->local.contacts = col->local.held = col->local.crossings = col->local.verified = col->local.fallbacks = 0;
  col->local.triangle_tests                                                                                 = 0;
  PetscCall(ClothGetFrictionScale(col->cloth, &col->friction_scale));
  if (col->search == CLOTH_COLLISION_SEARCH_GRID) PetscCall(UpdateGrids(col, xp, xa, nlocal));
  for (PetscInt i = 0; i < nlocal; i++) {
    if (fixed[i]) continue;
    PetscCall(ContactParticle(col, i, h, mass[i], &xp[3 * i], &f[3 * i], &xa[3 * i], &va[3 * i], &na[3 * i]));
  }
  PetscCall(VecRestoreArray(normals, &na));
  PetscCall(VecRestoreArray(v, &va));
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecRestoreArrayRead(col->force, &f));
  PetscCall(VecRestoreArrayRead(previous, &xp));
  col->friction_solved = PETSC_FALSE; /* until the next solve with friction in it */
  PetscCall(PetscLogEventEnd(ClothLog.collision, 0, 0, 0, 0));
  PetscCall(ReduceStats(col));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The triangle of mesh cm nearest to x, within reach, whose face normal is exactly n (-1: none). */
static PetscInt FindHeldTriangle(const CollisionMesh *cm, const PetscScalar x[3], const PetscReal n[3], PetscReal reach)
{
  PetscReal best_d2 = reach * reach, q[3];
  PetscInt  best    = -1;

  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) {
    const PetscReal *fn = &cm->face_normal[3 * tri];

    if (fn[0] == n[0] && fn[1] == n[1] && fn[2] == n[2]) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
  }
  return best;
}

/* The sphere or plane a held particle at x with contact normal n is on: within the thickness plus the slop, the
   surface normal closest to n (-1: none). Implicit friction needs the body (its coefficients) of every held
   particle. */
static PetscErrorCode FindHeldAnalyticBody(ClothCollision col, const PetscScalar x[3], const PetscReal n[3], PetscInt *body)
{
  PetscReal best = -PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  *body = -1;
  for (PetscInt b = 0; b < col->nbodies; b++) {
    const SceneBody *d;
    PetscReal        dist, m[3];

    if (col->meshes[b].mesh) continue;
    PetscCall(BodyGetDescription(col->bodies[b], &d));
    PetscCall(BodySignedDistance(col->bodies[b], x, &dist, m));
    if (dist >= d->thickness + ContactSlop(d) || Dot3(m, n) <= best) continue;
    best  = Dot3(m, n);
    *body = b;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A held particle's constraint is its triangle's face normal, bit for bit (times CLOTH_CONTACT_STUCK when
   stuck), so the triangle is the nearest one within the thickness plus the slop with exactly that normal;
   from it the run continues bit for bit. Particles held on a sphere or plane need nothing: those contacts
   are found anew every step. */
PetscErrorCode ClothCollisionRestoreHeldContacts(ClothCollision col)
{
  Vec                normals, x;
  const PetscScalar *c, *xa;
  PetscInt           nlocal, restored = 0, unmatched = 0;

  PetscFunctionBeginUser;
  PetscCheck(col->setup, col->comm, PETSC_ERR_ORDER, "Call ClothCollisionSetUp before ClothCollisionRestoreHeldContacts");
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothGetContactNormals(col->cloth, &normals));
  PetscCall(ClothGetState(col->cloth, &x, NULL));
  PetscCall(VecGetArrayRead(normals, &c));
  PetscCall(VecGetArrayRead(x, &xa));
  for (PetscInt i = 0; i < nlocal; i++) {
    const PetscReal scale = ClothContactScale(&c[3 * i]);
    PetscReal       n[3];
    PetscBool       found = PETSC_FALSE;

    if (scale == 0) continue;
    for (PetscInt k = 0; k < 3; k++) n[k] = c[3 * i + k] / scale;
    for (PetscInt b = 0; b < col->nbodies && !found; b++) {
      const SceneBody *d;
      PetscInt         tri;

      if (!col->meshes[b].mesh) continue;
      PetscCall(BodyGetDescription(col->bodies[b], &d));
      tri = FindHeldTriangle(&col->meshes[b], &xa[3 * i], n, d->thickness + ContactSlop(d));
      if (tri < 0) continue;
      col->held[i]  = (HeldContact){b, tri, {n[0], n[1], n[2]}};
      col->state[i] = CONTACT_STATE_HELD;
      found         = PETSC_TRUE;
    }
    if (found)
      restored++;
    else {
      PetscInt b;

      PetscCall(FindHeldAnalyticBody(col, &xa[3 * i], n, &b));
      if (b >= 0) {
        col->held[i]  = (HeldContact){b, -1, {n[0], n[1], n[2]}};
        col->state[i] = CONTACT_STATE_HELD;
      }
      unmatched++;
    }
  }
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscCall(VecRestoreArrayRead(normals, &c));
  PetscCall(PetscInfo(NULL, "Restored %" PetscInt_FMT " held mesh contacts; %" PetscInt_FMT " held particles matched no mesh triangle (analytic bodies)\n", restored, unmatched));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionGetStats(ClothCollision col, ClothCollisionStats *stats)
{
  PetscFunctionBeginUser;
  *stats = col->stats;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionGetContactField(ClothCollision col, Vec field, PetscInt *contacts)
{
  Vec          work;
  PetscScalar *w;
  PetscInt     nlocal;

  PetscFunctionBeginUser;
  PetscCall(ClothCollisionSetUp(col));
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothCreateStateVec(col->cloth, &work));
  PetscCall(VecGetArrayWrite(work, &w));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt k = 0; k < 3; k++) w[3 * i + k] = (PetscScalar)col->state[i];
  PetscCall(VecRestoreArrayWrite(work, &w));
  PetscCall(ClothScatterParticleValuesToNatural(col->cloth, work, field));
  PetscCall(VecDestroy(&work));
  *contacts = col->stats.contacts;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionCountInside(ClothCollision col, PetscInt *inside)
{
  Vec                x;
  const PetscScalar *xa;
  PetscInt           nlocal, count = 0;

  PetscFunctionBeginUser;
  PetscCall(ClothCollisionSetUp(col));
  PetscCall(ClothGetState(col->cloth, &x, NULL));
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(VecGetArrayRead(x, &xa));
  for (PetscInt i = 0; i < nlocal; i++) {
    PetscBool in = PETSC_FALSE;
    for (PetscInt b = 0; b < col->nbodies && !in; b++) PetscCall(BodyIsInside(col->bodies[b], &xa[3 * i], &in));
    if (in) count++;
  }
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscCallMPI(MPI_Allreduce(&count, inside, 1, MPIU_INT, MPI_SUM, col->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionView(ClothCollision col, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Collisions: %" PetscInt_FMT " bod%s, search %s, grid margin %g m, cell size %s", col->nbodies, col->nbodies == 1 ? "y" : "ies", ClothCollisionSearches[col->search], (double)col->margin,
                                   col->cell_size > 0 ? "" : "twice the mean triangle edge"));
  if (col->cell_size > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "%g m", (double)col->cell_size));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", col->verify ? ", verified against brute force" : ""));
  if (col->friction == CLOTH_COLLISION_FRICTION_IMPLICIT)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Friction of held contacts: implicit (regularised Coulomb, eps_v %g m/s, Stribeck velocity %g m/s; held still below %g m/s where static friction holds)\n", (double)col->friction_velocity,
                                     (double)col->stribeck_velocity, (double)StickVelocity(col)));
  else
    PetscCall(PetscViewerASCIIPrintf(viewer, "Friction of held contacts: explicit (velocity filter after the step)\n"));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  for (PetscInt b = 0; b < col->nbodies && col->setup; b++) PetscCall(BodyView(col->bodies[b], viewer));
  if (col->setup) PetscCall(PetscViewerASCIIPrintf(viewer, "%" PetscInt_FMT " particles started inside a body and were pushed out\n", col->stats.pushed_out));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionSave(ClothCollision col, PetscInt slot)
{
  PetscInt nlocal;
  Vec      normal;

  PetscFunctionBeginUser;
  PetscCheck(slot == 0 || slot == 1, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Contact save slot %" PetscInt_FMT ": expected 0 or 1", slot);
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothGetContactNormals(col->cloth, &normal));
  if (!col->held_saved[slot]) {
    PetscCall(PetscMalloc2(nlocal, &col->held_saved[slot], nlocal, &col->state_saved[slot]));
    PetscCall(VecDuplicate(normal, &col->normal_saved[slot]));
  }
  PetscCall(PetscArraycpy(col->held_saved[slot], col->held, nlocal));
  PetscCall(PetscArraycpy(col->state_saved[slot], col->state, nlocal));
  PetscCall(VecCopy(normal, col->normal_saved[slot]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionRestore(ClothCollision col, PetscInt slot)
{
  PetscInt nlocal;
  Vec      normal;

  PetscFunctionBeginUser;
  PetscCheck(col->held_saved[slot], PETSC_COMM_SELF, PETSC_ERR_ORDER, "ClothCollisionRestore of slot %" PetscInt_FMT " before ClothCollisionSave", slot);
  PetscCall(ClothGetSizes(col->cloth, &nlocal, NULL));
  PetscCall(ClothGetContactNormals(col->cloth, &normal));
  PetscCall(PetscArraycpy(col->held, col->held_saved[slot], nlocal));
  PetscCall(PetscArraycpy(col->state, col->state_saved[slot], nlocal));
  PetscCall(VecCopy(col->normal_saved[slot], normal));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionDestroy(ClothCollision *collision)
{
  ClothCollision col = *collision;

  PetscFunctionBeginUser;
  if (!col) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt b = 0; col->meshes && b < col->nbodies; b++) {
    PetscCall(PetscFree3(col->meshes[b].tri_lo, col->meshes[b].tri_hi, col->meshes[b].stamp));
    PetscCall(CellGridDestroy(&col->meshes[b].grid));
  }
  for (PetscInt b = 0; col->bodies && b < col->nbodies; b++) PetscCall(BodyDestroy(&col->bodies[b]));
  PetscCall(PetscFree2(col->bodies, col->meshes));
  PetscCall(PetscFree(col->held));
  PetscCall(PetscFree(col->vt_start));
  if (col->setup) PetscCall(ClothRemoveContribution(col->cloth, col));
  PetscCall(PetscFree(col->state));
  PetscCall(PetscFree(col->normal_force));
  for (PetscInt slot = 0; slot < 2; slot++) {
    PetscCall(PetscFree2(col->held_saved[slot], col->state_saved[slot]));
    PetscCall(VecDestroy(&col->normal_saved[slot]));
  }
  PetscCall(VecDestroy(&col->force));
  PetscCall(PetscFree(*collision));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Normal contact force (fit maps)                                                                             */

/* The body's normal force on particle i in this response: the larger of the force the held constraint
   cancels (the part of the particle's force into the body, -fn) and the force that removed the normal
   velocity dvn within the step (m dvn / h, an impact). At rest only the first remains. */
static PetscErrorCode RecordNormalForce(ClothCollision col, PetscInt i, PetscReal mass, PetscReal fn, PetscReal dvn, PetscReal h)
{
  PetscFunctionBeginUser;
  col->normal_force[i] = PetscMax(PetscMax(0.0, -fn), h > 0 ? mass * dvn / h : 0.0);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCollisionGetNormalForces(ClothCollision col, const PetscReal *force[])
{
  PetscFunctionBeginUser;
  PetscCall(ClothCollisionSetUp(col));
  *force = col->normal_force;
  PetscFunctionReturn(PETSC_SUCCESS);
}
