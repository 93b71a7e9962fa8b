/* ClothSelfContact: cloth-cloth collisions (fabric against itself and against other pieces).

   Primitives: the fabric surface is every grid cell (model quad a b c d) split into the triangles
   (a b c) and (a c d); its edges are the cell sides and that diagonal. A contact is a particle within
   the detection radius of a triangle (point-triangle) or two edges within it of each other
   (edge-edge), found with a uniform cell grid over the region of this rank's particles. Pairs never
   collide when a particle of one and a particle of the other lie within exclude_ring grid rings of
   each other in one piece (by default ring 0, primitives that share a particle, widened so that particles
   closer in the pattern than 2 thicknesses never collide), when they are in one piece and same_piece is off, or
   when the exclusion callback says so (sewn pieces).

   Across ranks: every step each rank gathers the bounding boxes of the others' particles
   (MPI_Allgather) and sends them the positions of its particles inside their boxes inflated by the
   detection radius plus twice the longest triangle edge (MPI_Alltoallv of indices; a VecScatter then
   refreshes positions and velocities and sums forces back). The topology is replicated. A
   point-triangle contact is handled by the owner of the point, an edge-edge contact by the owner of
   one of its four particles chosen from the two edge numbers, so each contact is handled exactly once.

   Response: (1) a repulsion energy 0.5 k (thickness - d)^2 for d < thickness, d = |r|, r = sum_k
   a_k x_k the separation between the particle (edge point) and the closest point, with the weights a
   frozen at detection (the force is then the exact gradient of the distance energy, by the envelope
   theorem); its Hessian (a a^T) (x) K enters the implicit system, whose matrix is re-preallocated
   exactly whenever a new pair of coupled particles appears. (2) After the velocity update, an
   inelastic impulse along the contact normal for every pair (found within thickness + its relative
   travel over the step) whose gap would fall below min_gap x thickness during the step: a linearised
   continuous-time check, so that layers do not pass through each other between steps. */
#pragma once
#include <petscmat.h>
#include "cloth.h"

typedef struct _n_ClothSelfContact *ClothSelfContact; /* also in cloth.h */

/* Whether particles a and b (natural numbering) must never be treated as in contact, e.g. because
   they are sewn together (issue 8). */
typedef PetscErrorCode (*ClothSelfContactExcludeFn)(void *ctx, PetscInt a, PetscInt b, PetscBool *excluded);

typedef enum {
  CLOTH_CONTACT_POINT_TRIANGLE, /* p[0] the particle, p[1..3] the triangle */
  CLOTH_CONTACT_EDGE_EDGE       /* p[0] p[1] the edge with the lower edge number, p[2] p[3] the other */
} ClothContactKind;

/* One contact, particles in natural numbering. Separation r = sum_k a[k] x[p[k]] (sum of a is 0). */
typedef struct {
  ClothContactKind kind;
  PetscInt         p[4];
  PetscReal        a[4];
  PetscReal        r[3];     /* the separation at detection, m */
  PetscReal        distance; /* |r| at detection, m */
  PetscReal        scale;    /* the share of the repulsion stiffness it carries (edge pairs fade out towards their ends) */
} ClothContact;

/* Collective. The cloth must be set up before ClothSelfContactSetUp. */
PetscErrorCode ClothSelfContactCreate(Cloth cloth, ClothSelfContact *sc);
/* -self_collision, -self_collision_thickness, -self_collision_stiffness, -self_collision_exclude_ring,
   -self_collision_min_gap, -self_collision_impulse_iterations, -self_collision_view; the scene's
   self_collision: block gives the defaults. */
PetscErrorCode ClothSelfContactSetFromOptions(ClothSelfContact sc);
PetscErrorCode ClothSelfContactSetUp(ClothSelfContact sc);
PetscErrorCode ClothSelfContactGetEnabled(ClothSelfContact sc, PetscBool *enabled);
/* Sets the exclusion callback (NULL: none); it is asked about every particle pair of a candidate contact. */
PetscErrorCode ClothSelfContactSetExclusion(ClothSelfContact sc, ClothSelfContactExcludeFn exclude, void *ctx);
/* Finds the contacts at the cloth's current state for a step of h: primitives that come within the thickness during
   the step at the current velocities (their separation moving with the relative travel of their closest points).
   Collective. */
PetscErrorCode ClothSelfContactUpdate(ClothSelfContact sc, PetscReal h);
/* The same search within radius (no travel) and without touching the matrix pattern; for tests. */
PetscErrorCode ClothSelfContactFind(ClothSelfContact sc, PetscReal radius);
/* What the searches did since set-up, summed over ranks: how often the candidates were found anew, and over those
   searches the pairs of tiles near each other and those proved apart, the pairs of primitives given to the narrow
   phase and the candidates it kept. */
typedef struct {
  PetscInt   builds;
  PetscInt64 tile_pairs, tile_pairs_apart, primitive_pairs, candidates;
} ClothSelfContactStatistics;
/* Collective. */
PetscErrorCode ClothSelfContactGetStatistics(ClothSelfContact sc, ClothSelfContactStatistics *stats);
/* This rank's contacts from the last search (borrowed, natural numbering). Not collective. */
PetscErrorCode ClothSelfContactGetContacts(ClothSelfContact sc, PetscInt *n, const ClothContact **contacts);
/* For output: per particle, in natural order (field: one entry per particle, a Vec like
   ClothCreateStrainVec's), the number of contacts of the last search that it takes part in (each
   contact has four particles); *ncontacts: the contacts of that search and *nparticles: the particles
   taking part in one or more, both over all ranks (each contact is handled by one rank). The last
   search is the velocity filter's (or, with the explicit integrator, ClothSelfContactUpdate's) of the
   last (sub-)step: pairs within the thickness plus their relative travel over it. Collective. */
PetscErrorCode ClothSelfContactGetContactField(ClothSelfContact sc, Vec field, PetscInt *ncontacts, PetscInt *nparticles);
/* Every contact that comes within radius during a step of displacements dx (3 N; NULL: none) over the whole model at
   natural-order positions x (3 N), by testing all pairs of primitives: the reference for the search. Not collective;
   free with PetscFree. */
PetscErrorCode ClothSelfContactFindBruteForce(ClothSelfContact sc, const PetscReal x[], const PetscReal dx[], PetscReal radius, PetscInt *n, ClothContact **contacts);
/* Impulses on the velocity (after its update, before the positions move by h v): searches again at
   these velocities, then Gauss-Seidel sweeps of inelastic impulses along the contact normals (filtered
   by pins and body contacts, ClothGetContactNormals) until no contact's gap, to first order, falls
   below min_gap x thickness during the step. Collective. */
PetscErrorCode ClothSelfContactFilterVelocity(ClothSelfContact sc, PetscReal h, Vec velocity);
PetscErrorCode ClothSelfContactView(ClothSelfContact sc, PetscViewer viewer);
PetscErrorCode ClothSelfContactDestroy(ClothSelfContact *sc);

/* The contribution (cloth.h) through which the repulsion joins the cloth's forces, energies and implicit system, and
   its coupled blocks the matrix's preallocation: register it with ClothAddContribution after ClothSelfContactSetUp,
   before the matrix is created. */
PetscErrorCode ClothSelfContactGetContribution(ClothSelfContact sc, ClothContribution *contribution);
