/* ClothCollision (see collision.h): the object, its options and set-up (bodies built, particles that start inside
   pushed out), the step (ClothCollisionApply: the grids updated, each owned particle's contacts and response), the
   held contacts found again after a restart, save and restore of a (sub-)step's contact state, statistics and
   view. The mesh search is in collision_search.c, the response and friction in collision_response.c; the private
   struct they share is collision_impl.h. */
#include "collision_impl.h"
#include "log.h"
#include "vec3.h"
#include "options.h"

const char *const ClothCollisionSearches[]  = {"grid", "brute_force", "ClothCollisionSearch", "CLOTH_COLLISION_SEARCH_", NULL};
const char *const ClothCollisionFrictions[] = {"implicit", "explicit", "ClothCollisionFriction", "CLOTH_COLLISION_FRICTION_", NULL};

/* A piece may start with at most this fraction of its particles inside a body (moved to the surface at set-up) unless
   -collision_allow_inside: a few are a hem touching a shoulder (tests/data/mannequin_shoulders.yaml: 30 of 1089,
   2.8 %); more are a piece laid through the body, which the push-out tears (a T-shirt front through the torso, 105 of
   its 169 particles: link strain 14, 48 of 56 seam pairs sewn, each step 15 times slower). */
#define COLLISION_MAX_INSIDE_FRACTION 0.05

/* ------------------------------------------------------------------------------------------------------------ */
/* Object                                                                                                       */

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
    if (col->scene->bodies[b].type == SCENE_BODY_MESH) PetscCall(CollisionMeshSetUp(&col->meshes[b], col->bodies[b]));
  }
  PetscCall(ClothCreateStateVec(col->cloth, &col->force));
  PetscCall(PushOutStartingInside(col));
  { /* the held contacts' checkpoint field (collision_checkpoint.c) and, implicit, the friction */
    ClothContribution contacts = {.name = "body contacts", .ctx = col, .checkpoint_fields = ClothCollisionCheckpointFields_Private, .checkpoint_load = ClothCollisionCheckpointLoad_Private};

    if (col->friction == CLOTH_COLLISION_FRICTION_IMPLICIT) contacts.add_to_implicit_step = CollisionAddFrictionToImplicitStep;
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
  if (col->search == CLOTH_COLLISION_SEARCH_GRID) PetscCall(CollisionUpdateGrids(col, xp, xa, nlocal));
  for (PetscInt i = 0; i < nlocal; i++) {
    if (fixed[i]) continue;
    PetscCall(CollisionContactParticle(col, i, h, mass[i], &xp[3 * i], &f[3 * i], &xa[3 * i], &va[3 * i], &na[3 * i]));
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
    if (dist >= d->thickness + CollisionContactSlop(d) || Dot3(m, n) <= best) continue;
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
      tri = CollisionFindHeldTriangle(&col->meshes[b], &xa[3 * i], n, d->thickness + CollisionContactSlop(d));
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
                                     (double)col->stribeck_velocity, (double)CollisionStickVelocity(col)));
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
  for (PetscInt b = 0; col->meshes && b < col->nbodies; b++) PetscCall(CollisionMeshDestroy(&col->meshes[b]));
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

/* The normal force per particle (fit maps), recorded by the response (collision_response.c). */
PetscErrorCode ClothCollisionGetNormalForces(ClothCollision col, const PetscReal *force[])
{
  PetscFunctionBeginUser;
  PetscCall(ClothCollisionSetUp(col));
  *force = col->normal_force;
  PetscFunctionReturn(PETSC_SUCCESS);
}
