/* The private part of ClothCollision, shared by its three files: src/collision_search.c (the mesh search: each mesh
   body's per-rank cell grid, the first triangle a particle's segment crosses, the nearest triangle to a point),
   src/collision_response.c (the response: a particle's contacts with every body, its velocity and friction after
   the step, held contacts, the friction of held contacts in the implicit step, the normal force) and
   src/collision.c (the object: options, set-up and push-out, the step's loop over particles, restart, save and
   restore, statistics, view). */
#pragma once
#include "collision.h"
#include "cellgrid.h"

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

/* collision_search.c */
/* Triangle boxes, the body box and the mean edge length of mesh body `body`; its grid is built on first use. */
PetscErrorCode CollisionMeshSetUp(CollisionMesh *cm, Body body);
PetscErrorCode CollisionMeshDestroy(CollisionMesh *cm);
/* Rebuilds each mesh grid when a segment end lies outside the region it covers. Local (no communication). */
PetscErrorCode CollisionUpdateGrids(ClothCollision col, const PetscScalar *xp, const PetscScalar *x, PetscInt nlocal);
/* The first triangle of mesh cm that the segment p0 -> p1 crosses from the outside, by the chosen search (counted
   in col->local.triangle_tests). */
void CollisionSearchSegment(ClothCollision col, CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit);
/* The same by testing every triangle (-collision_search brute_force, and the reference of -collision_verify). */
void CollisionSearchBruteForce(const CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit, PetscInt64 *tests);
/* The triangle of mesh cm nearest to x within radius (-1: none) and the nearest point q on it. */
PetscInt CollisionNearestTriangleWithin(ClothCollision col, CollisionMesh *cm, const PetscScalar x[3], PetscReal radius, PetscReal q[3]);
/* The triangle of mesh cm nearest to x, within reach, whose face normal is exactly n (-1: none); for a restart. */
PetscInt CollisionFindHeldTriangle(const CollisionMesh *cm, const PetscScalar x[3], const PetscReal n[3], PetscReal reach);

/* collision_response.c */
/* Contacts are kept within this distance beyond the body's thickness, and held ones are released beyond it. */
PetscReal CollisionContactSlop(const SceneBody *d);
/* Implicit friction: held particles slower than this may stick, m/s (-collision_friction_stick_velocity). */
PetscReal CollisionStickVelocity(const ClothCollision col);
/* The add_to_implicit_step of the body-friction contribution (cloth.h) of -collision_friction implicit. */
PetscErrorCode CollisionAddFrictionToImplicitStep(void *ctx, PetscReal h, Vec velocity, Vec force, Mat A);
/* One owned particle i (its mass, previous position p0, force f at the step's start; position x, velocity v and
   contact normal updated in place): detection against every body, response, and whether it is held for the next step. */
PetscErrorCode CollisionContactParticle(ClothCollision col, PetscInt i, PetscReal h, PetscReal mass, const PetscScalar p0[3], const PetscScalar f[3], PetscScalar x[3], PetscScalar v[3], PetscScalar normal[3]);
