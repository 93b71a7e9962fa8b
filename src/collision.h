/* ClothCollision: the cloth against rigid bodies (docs/model.md section 6).

   After every (sub-)step, each rank tests the segment that each of its owned particles travelled, from its
   previous to its new position:
   - mesh bodies: the paper's rejections (segment box against the body box, then against each triangle's
     box), then an exact segment-triangle test for triangles crossed from the outside. The triangles come
     from a per-rank uniform grid of cells (-collision_search grid, default) covering this rank's particles
     with a margin (-collision_grid_margin) clipped to the body's box; every cell the segment passes through
     is visited (3D DDA); the grid is rebuilt only when a particle leaves the covered region. With
     -collision_search brute_force every triangle is tested instead (for checks and timings).
   - spheres and planes: analytic signed distance at the new position.
   A hit puts the particle back outside at the body's thickness (meshes: at the crossing point, offset along
   the face normal; analytic bodies: the nearest point of the offset surface), removes the velocity
   component into the body and applies Coulomb friction to the tangential velocity (static: it is zeroed when
   |v_t| <= mu_s dv_n; kinetic: |v_t| is reduced by mu_k dv_n, dv_n being the normal velocity change).
   Particles in contact whose force pushes into the body are held on the surface for the next step: their
   contact normal n goes to the cloth (ClothGetContactNormals), so that every integrator filters the
   direction n out (S = I - n n^T). A contact is released when the force on the particle pulls it away from
   the body, or when the particle has moved off the surface. Particles that start inside a body (winding
   number / signed distance) are pushed out to the nearest surface point at set-up.
   With -collision_friction implicit (default) the friction of held contacts is not applied after the step but is
   part of the implicit step itself: a regularised Coulomb force -mu(|v_t|) |F_n| v_t / sqrt(|v_t|^2 + eps_v^2)
   and its velocity Jacobian, added through a ClothContribution (cloth.h, add_to_implicit_step); only impacts get the Coulomb impulse after
   the step. */
#pragma once
#include "cloth.h"
#include "body.h"

typedef struct _n_ClothCollision *ClothCollision;

typedef enum {
  CLOTH_COLLISION_SEARCH_GRID,       /* per-rank uniform cell grid (the fast path) */
  CLOTH_COLLISION_SEARCH_BRUTE_FORCE /* every triangle for every particle */
} ClothCollisionSearch;
extern const char *const ClothCollisionSearches[];

/* Where Coulomb friction with bodies acts (docs/collisions.md, "Friction inside the implicit step"). */
typedef enum {
  CLOTH_COLLISION_FRICTION_IMPLICIT, /* held contacts: a regularised Coulomb force and its velocity Jacobian in the
                                        linearised backward-Euler system (implicit integrator; others fall back to explicit) */
  CLOTH_COLLISION_FRICTION_EXPLICIT  /* the velocity filter after the step, stuck particles held still in the next solve */
} ClothCollisionFriction;
extern const char *const ClothCollisionFrictions[];

/* Counts of the last ClothCollisionApply, summed over ranks (grid_rebuilds, pushed_out, verified: since set-up). */
typedef struct {
  PetscInt   contacts;       /* particles corrected or held in contact */
  PetscInt   held;           /* of which held as constraints for the next step */
  PetscInt   crossings;      /* mesh triangles crossed (new hits) */
  PetscInt64 triangle_tests; /* exact segment-triangle tests done (after the box rejections) */
  PetscInt   grid_rebuilds;  /* since set-up, summed over ranks */
  PetscInt   pushed_out;     /* particles found inside a body at set-up */
  PetscInt   fallbacks;      /* corrected particles whose corrected move entered a body: put back halfway to the crossing */
  PetscInt   verified;       /* with -collision_verify: crossings both searches found identically, since set-up */
} ClothCollisionStats;

/* The bodies of the cloth's scene; nothing is read until ClothCollisionSetUp. */
PetscErrorCode ClothCollisionCreate(Cloth cloth, Scene scene, ClothCollision *collision);
/* -collision_search grid|brute_force, -collision_cell_size, -collision_grid_margin, -collision_verify,
   -collision_view, -collision_friction implicit|explicit, -collision_friction_velocity,
   -collision_friction_stribeck_velocity. */
PetscErrorCode ClothCollisionSetFromOptions(ClothCollision collision);
PetscErrorCode ClothCollisionSetSearch(ClothCollision collision, ClothCollisionSearch search);
/* Before ClothCollisionSetUp. */
PetscErrorCode ClothCollisionSetFriction(ClothCollision collision, ClothCollisionFriction friction);
/* With verify, every mesh segment is searched with both the grid and brute force and a difference is an error. */
PetscErrorCode ClothCollisionSetVerify(ClothCollision collision, PetscBool verify);
/* Builds the bodies (reads meshes) and pushes particles that start inside a body out. Needs the cloth set up.
   Collective. */
PetscErrorCode ClothCollisionSetUp(ClothCollision collision);
/* The bodies (borrowed). */
PetscErrorCode ClothCollisionGetBodies(ClothCollision collision, PetscInt *nbodies, const Body **bodies);
/* The cloth it acts on (borrowed). */
PetscErrorCode ClothCollisionGetCloth(ClothCollision collision, Cloth *cloth);
/* Detects and resolves the contacts of the step that went from previous (the positions before the step) to
   the cloth's current state, h seconds later; sets the contact constraints for the next step. Collective. */
PetscErrorCode ClothCollisionApply(ClothCollision collision, Vec previous, PetscReal h);
/* After a restart has set the cloth's state and contact constraints (ClothGetContactNormals) from a
   checkpoint: finds again the mesh triangle each held particle was held on, so that the run continues as
   it would have without the restart. Needs ClothCollisionSetUp. Not collective. */
PetscErrorCode ClothCollisionRestoreHeldContacts(ClothCollision collision);
PetscErrorCode ClothCollisionGetStats(ClothCollision collision, ClothCollisionStats *stats);
/* Per particle, in natural order (field: one entry per particle, a Vec like ClothCreateStrainVec's), the
   contact state left by the last ClothCollisionApply: 0 free, 1 in contact with a body (corrected onto its
   surface or kept within the slop of it), 2 in contact and held on the surface for the next step; 0 for
   every particle before the first step. *contacts: the particles in contact (state 1 or 2), summed over
   ranks (ClothCollisionStats.contacts). Collective. */
PetscErrorCode ClothCollisionGetContactField(ClothCollision collision, Vec field, PetscInt *contacts);
/* Per owned particle (local numbering, borrowed), the normal force in N the bodies exerted on it in the last
   ClothCollisionApply: the part of its force into the body that a held contact cancels, or the force that
   stopped its motion into the body within the step, whichever is larger; 0 for a free particle and before the
   first step. The contact pressure of the fit maps is this over the particle's fabric area
   (ClothComputeContactPressure). Collective (the first call sets the collisions up). */
PetscErrorCode ClothCollisionGetNormalForces(ClothCollision collision, const PetscReal *force[]);
/* Counts the owned particles inside any body by the robust inside test (winding number for meshes), summed
   over ranks. Collective. */
PetscErrorCode ClothCollisionCountInside(ClothCollision collision, PetscInt *inside);
PetscErrorCode ClothCollisionView(ClothCollision collision, PetscViewer viewer);
/* Saves the contact state a step changes (held contacts, their states, the cloth's contact normals) in slot 0 or 1,
   and puts it back: a failed (sub-)step is undone completely (the integrator). Not collective. */
PetscErrorCode ClothCollisionSave(ClothCollision collision, PetscInt slot);
PetscErrorCode ClothCollisionRestore(ClothCollision collision, PetscInt slot);
PetscErrorCode ClothCollisionDestroy(ClothCollision *collision);
/* The checkpoint hooks of the collision's ClothContribution (cloth.h; ctx the ClothCollision; collision_checkpoint.c):
   the field contact_normal, the cloth's contact constraints in natural order, and after a read the held contacts
   found again from them (ClothCollisionRestoreHeldContacts). */
PetscErrorCode ClothCollisionCheckpointFields_Private(void *ctx, PetscBool write, ClothCheckpointField fields[], PetscInt *nfields);
PetscErrorCode ClothCollisionCheckpointLoad_Private(void *ctx, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[]);
