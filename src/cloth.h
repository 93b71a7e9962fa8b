/* Cloth: the fabric distributed over MPI ranks.

   Particles are partitioned (METIS) and renumbered so that each rank owns a contiguous range of the
   PETSc ("solver") numbering; files always use the natural order (pieces in scene order, row by
   row), reached through ClothScatterToNatural. Each interaction is evaluated on exactly one rank
   (the owner of its lowest-numbered particle); the particles it touches that other ranks own are
   ghosts, refreshed before and summed back after every evaluation. */
#pragma once
#include <petscmat.h>
#include "scene.h"
#include "model.h"
#include "partition.h"
#include "checkpoint.h"

typedef struct _n_Cloth            *Cloth;
typedef struct _n_ClothSelfContact *ClothSelfContact; /* see selfcontact.h */

/* Energies of the whole fabric, J. */
typedef struct {
  PetscReal kinetic, gravity, elastic;
} ClothEnergy;

PetscErrorCode ClothCreate(MPI_Comm comm, Scene scene, Cloth *cloth);
/* Reads -cloth_partition metis|block, -cloth_view_partition and -cloth_view_partition_summary. */
PetscErrorCode ClothSetFromOptions(Cloth cloth);
/* Whether ClothSetUp prints the one-line partition summary when running on more than one rank
   (default off, so that library users and tests stay quiet; the driver turns it on). */
PetscErrorCode ClothSetViewPartitionSummary(Cloth cloth, PetscBool flg);
/* Builds the model, partitions and distributes it. Collective. */
PetscErrorCode ClothSetUp(Cloth cloth);
/* Prints the partition quality: edge cut, owned, ghost and evaluated-interaction counts (min..max
   over ranks) and their imbalance (max / mean); then one line per rank. With the viewer format
   PETSC_VIEWER_ASCII_INFO only the first, one-line summary. Collective; after ClothSetUp. */
PetscErrorCode ClothView(Cloth cloth, PetscViewer viewer);
PetscErrorCode ClothDestroy(Cloth *cloth);

/* The state: position and velocity, ghosted Vecs with block size 3 in solver numbering (borrowed). */
PetscErrorCode ClothGetState(Cloth cloth, Vec *position, Vec *velocity);
/* A new ghosted Vec with the state's layout (forces, work). */
PetscErrorCode ClothCreateStateVec(Cloth cloth, Vec *v);
PetscErrorCode ClothGetSizes(Cloth cloth, PetscInt *nlocal, PetscInt *nglobal);
/* The links and angle springs (elastic and friction elements) this rank evaluates. Every interaction of the model
   is evaluated on exactly one rank, so these sum over the ranks to the model's totals. Not collective. */
PetscErrorCode ClothGetInteractionCounts(Cloth cloth, PetscInt *nlinks, PetscInt *nangles);
/* Per owned particle: mass (kg) and whether it is held fixed. Borrowed arrays. */
PetscErrorCode ClothGetMasses(Cloth cloth, const PetscReal **mass, const PetscBool **fixed);

/* force = internal + gravity + damping forces at (position, velocity). position and velocity get
   their ghosts refreshed. Collective. */
PetscErrorCode ClothComputeForces(Cloth cloth, Vec position, Vec velocity, Vec force);
/* A (sub-)step starts at position: every contribution with begin_step updates its internal state there (the
   hysteresis sliders). position gets its ghosts refreshed by those that read it. Collective. */
PetscErrorCode ClothBeginStep(Cloth cloth, Vec position);
/* Saves the contributions' internal state (the hysteresis sliders) in slot 0 or 1, and puts it back: a failed
   (sub-)step is undone completely (the integrator). Not collective. */
PetscErrorCode ClothSaveState(Cloth cloth, PetscInt slot);
PetscErrorCode ClothRestoreState(Cloth cloth, PetscInt slot);
/* The linearised backward Euler system of docs/model.md section 5, filtered by the constraints:
   A = S (M + h C + h^2 K) S + (I - S) and rhs = S h (F - h K v), K the positive semidefinite part of
   the stiffness. A must come from ClothCreateMatrix. Collective. */
PetscErrorCode ClothAssembleImplicitSystem(Cloth cloth, PetscReal h, Vec position, Vec velocity, Mat A, Vec rhs);
/* With exact = true the implicit system uses the exact stiffness (possibly indefinite) instead of its
   positive semidefinite part; for Jacobian tests against finite differences. */
PetscErrorCode ClothSetExactStiffness(Cloth cloth, PetscBool exact);
/* With factored = false the Gauss-Newton stiffness is filtered and assembled from each element's expanded matrix
   instead of its factors (-cloth_stiffness_factored): the same system up to rounding; for tests and timings. */
PetscErrorCode ClothSetFactoredStiffness(Cloth cloth, PetscBool factored);
/* Force contributions that plug into the cloth (docs/architecture.md, "Adding a force"). The cloth's own
   interactions (links, elastic angle springs and twist, gravity, damping) are built in; every other force registers
   one ClothContribution: the model's seam links (seam_links.c) and hysteresis (hysteresis.c) at ClothSetUp,
   cloth-cloth repulsion and body friction in the driver. The cloth then asks each, at every evaluation, for its
   share of the forces, the energy, K v and the implicit matrix, and, when it creates the matrix, for the blocks it
   couples beyond the interactions' pattern. A contribution reads the cloth through its public accessors
   (ClothGetState, ClothGetLayout, ClothGetContactNormals, ...). */
typedef struct {
  Vec        position, velocity; /* the state evaluated (global form, solver numbering) */
  Vec        force;              /* add the contribution's forces here (global form) */
  Vec        kv;                 /* NULL, or add K v here (the rhs of the implicit step) */
  Mat        A;                  /* NULL, or add h2 S K S here, S the constraint filter (ClothContactFilter) */
  PetscReal  h2;                 /* h^2 of the implicit step */
  PetscBool  psd;                /* the stiffness added to A must be positive semidefinite */
  PetscReal *energy;             /* NULL, or add the contribution's energy (this rank's part) here */
} ClothContributionArgs;

/* The largest element: cell shear springs (CLOTH_ANGLE_MAX_PARTICLES) and interpolated seam links
   (CLOTH_SEAM_LINK_MAX_PARTICLES). */
#define CLOTH_ELEMENT_MAX_PARTICLES PetscMax(CLOTH_ANGLE_MAX_PARTICLES, CLOTH_SEAM_LINK_MAX_PARTICLES)
/* One element in the common form of the cloth's pass over its interactions: np particles p (local numbering),
   its energy, the forces on them (3 np) and the Hessian of the energy (only when asked): in H (3np x 3np, row-major)
   or, when factored (an angle spring's Gauss-Newton form, np <= CLOTH_ANGLE_MAX_PARTICLES), as the factors K. */
typedef struct {
  PetscInt               np;
  PetscInt               p[CLOTH_ELEMENT_MAX_PARTICLES];
  PetscReal              energy;
  PetscReal              force[3 * CLOTH_ELEMENT_MAX_PARTICLES];
  PetscBool              factored;
  ClothFactoredStiffness K;
  PetscReal              H[9 * CLOTH_ELEMENT_MAX_PARTICLES * CLOTH_ELEMENT_MAX_PARTICLES];
} ClothElement;
/* Where a contribution's elements go during the cloth's pass (add_elements): opaque. */
typedef struct _n_ClothElementSink *ClothElementSink;
/* What the pass evaluates: positions in local form (owned then ghosts, fresh), whether elements must give their
   Hessian, and the form of the angle elements' stiffness (ClothAngleEvaluate). */
PetscErrorCode ClothElementSinkGetInput(ClothElementSink sink, const PetscScalar **x, PetscBool *want_hessian, ClothStiffness *form);
/* Adds one element to what the pass accumulates: energy, forces, K v, and its stiffness filtered by the
   constraints into the matrix (element->H is overwritten by h^2 S H S, element->K by S K). Not collective. */
PetscErrorCode ClothElementSinkAdd(ClothElementSink sink, ClothElement *element);
/* The element of an angle spring or friction element (forces.h) at local positions x. */
PetscErrorCode ClothElementFromAngle(const ClothAngle *angle, const PetscScalar *x, PetscBool want_hessian, ClothStiffness form, ClothElement *element);

typedef struct {
  const char *name; /* for messages, and ClothGetContribution */
  void       *ctx;  /* the contribution's object; identifies it in ClothRemoveContribution */
  /* Adds forces and what else args asks for, at every evaluation, after the cloth's pass (global form: for forces
     that reach particles beyond the ghosts). May be NULL. Collective. */
  PetscErrorCode (*add)(void *ctx, const ClothContributionArgs *args);
  /* Adds, per owned particle (row), the 3x3 blocks coupled beyond the interactions' pattern: diagonal / off-diagonal
     part of the matrix, and of them those above the diagonal. May be NULL. Not collective. */
  PetscErrorCode (*count_row_blocks)(void *ctx, PetscInt dnnz[], PetscInt onnz[], PetscInt dnnzu[], PetscInt onnzu[]);
  /* y += C x: the couplings of the implicit system between particles that no interaction of the model joins (contacts
     that come and go as layers slide), which the assembled matrix leaves out: it gets their diagonal blocks (in add or
     add_to_implicit_step), and this applies the rest at every product of the implicit operator
     (ClothCreateImplicitOperator), so that the matrix's pattern never changes. Of the last assembly. May be NULL.
     Collective. */
  PetscErrorCode (*mult_coupling)(void *ctx, Vec x, Vec y);
  /* Forces of the implicit step alone that depend on the whole force at the step's start (body friction, whose normal
     force is the push into the body: collision.c, -collision_friction implicit). Called by ClothAssembleImplicitSystem
     after every other force and diagonal block, with the step size h, the velocity at the step's start, the force F
     there (owned entries complete) and the matrix being assembled: adds its force to F (so that it enters the
     right-hand side) and h times minus its velocity Jacobian to the owned diagonal blocks of A. May be NULL. */
  PetscErrorCode (*add_to_implicit_step)(void *ctx, PetscReal h, Vec velocity, Vec force, Mat A);
  /* Adds elements whose particles are all owned or ghosts (interactions of the model: ClothLocalizeInteraction)
     inside the cloth's own pass, before the ghosts are summed back: no communication of its own. May be NULL.
     Not collective. */
  PetscErrorCode (*add_elements)(void *ctx, ClothElementSink sink);
  /* ClothBeginStep: a (sub-)step starts at position. May be NULL. Collective. */
  PetscErrorCode (*begin_step)(void *ctx, Vec position);
  /* ClothSaveState, ClothRestoreState: save the internal state in slot 0 or 1, put it back. May be NULL. */
  PetscErrorCode (*save)(void *ctx, PetscInt slot);
  PetscErrorCode (*restore)(void *ctx, PetscInt slot);
  /* The state a restart needs that the contribution keeps (hysteresis sliders, sewn seams, held body contacts), as
     per-particle checkpoint fields (checkpoint.h), so that the run writes and reads them without knowing them.
     checkpoint_fields declares up to CLOTH_CONTRIBUTION_MAX_FIELDS: name, whether a restart requires it, and a new
     natural-order Vec (destroyed by the caller: ClothRestoreCheckpointFields), filled with the current state when
     write is true. checkpoint_load takes the state back after a read: fields are all the contributions' (find its own
     by name, ClothCheckpointFieldFind; found says whether the file had it), info the checkpoint's (its time). Both
     NULL or both given. Collective. */
  PetscErrorCode (*checkpoint_fields)(void *ctx, PetscBool write, ClothCheckpointField fields[], PetscInt *nfields);
  PetscErrorCode (*checkpoint_load)(void *ctx, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[]);
  /* NULL: the caller owns ctx; else the cloth does, and destroys it with this when it is removed or destroyed. */
  PetscErrorCode (*destroy)(void *ctx);
} ClothContribution;
#define CLOTH_MAX_CONTRIBUTIONS 8
#define CLOTH_CONTRIBUTION_MAX_FIELDS 2
/* Counts the block (row, col) (solver indices, row owned: rstart <= row < rend) in its row's preallocation: the
   diagonal part (col owned) or the off-diagonal one, and, when above the diagonal, the upper-triangle counts (SBAIJ). */
static inline void ClothCountRowBlock(PetscInt rstart, PetscInt rend, PetscInt row, PetscInt col, PetscInt dnnz[], PetscInt onnz[], PetscInt dnnzu[], PetscInt onnzu[])
{
  const PetscBool owned = (col >= rstart && col < rend) ? PETSC_TRUE : PETSC_FALSE;
  const PetscInt  i     = row - rstart;

  if (owned)
    dnnz[i]++;
  else
    onnz[i]++;
  if (col > row) {
    if (owned)
      dnnzu[i]++;
    else
      onnzu[i]++;
  }
}
/* Registers a contribution (copied); at most CLOTH_MAX_CONTRIBUTIONS. Matrices created before do not have its
   blocks: register before ClothCreateMatrix. Not collective, but every rank registers the same ones. */
PetscErrorCode ClothAddContribution(Cloth cloth, const ClothContribution *contribution);
/* Unregisters the contribution whose ctx this is (no-op when none). */
PetscErrorCode ClothRemoveContribution(Cloth cloth, void *ctx);
/* The ctx of the registered contribution of this name, or NULL when none. */
PetscErrorCode ClothGetContribution(Cloth cloth, const char *name, void **ctx);
/* The checkpoint fields of every registered contribution (checkpoint_fields), in the order they were registered, into
   fields[0..max); with write true filled with the current state. Lent: give them back with
   ClothRestoreCheckpointFields. Collective. */
PetscErrorCode ClothGetCheckpointFields(Cloth cloth, PetscBool write, PetscInt max, ClothCheckpointField fields[], PetscInt *nfields);
/* After ClothCheckpointRead into the fields of ClothGetCheckpointFields: every contribution takes its state back
   (checkpoint_load). Collective. */
PetscErrorCode ClothLoadCheckpointFields(Cloth cloth, const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[]);
/* Destroys the fields' Vecs (from ClothGetCheckpointFields). */
PetscErrorCode ClothRestoreCheckpointFields(Cloth cloth, PetscInt nfields, ClothCheckpointField fields[]);
/* Whether this rank evaluates the interaction of the model on natural particles natural[0..np) (the owner of its
   lowest-numbered particle in solver numbering, as for the cloth's own interactions) and, if so, their local
   numbers. Every interaction of the model (links, angles, seam links) is in the interaction graph, so its
   particles are owned or ghosts here and in the matrix's pattern. After the partition (ClothSetUp). Not collective. */
PetscErrorCode ClothLocalizeInteraction(Cloth cloth, PetscInt np, const PetscInt natural[], PetscBool *here, PetscInt local[]);

/* The distribution of the particles, read-only and borrowed, for contributions and other modules built on the
   cloth. Solver numbering: each rank owns [rstart, rstart + nlocal); local numbering: owned then ghosts. */
typedef struct {
  MPI_Comm            comm;
  PetscInt            nglobal, nlocal, nghost, rstart;
  const PetscInt     *part;              /* natural -> owning rank */
  const PetscInt     *solver_of_natural; /* natural -> solver index */
  const PetscInt     *natural_of_local;  /* local -> natural */
  const PetscInt     *xadj, *adjncy;     /* the interaction graph in natural order (CSR, sorted neighbours) */
  PetscInt            nlinks;            /* the links this rank evaluates, in local particle numbers */
  const ClothLinkRef *links;             /* their particles and parameters: ClothLinkExpand(link_params, links[l]) */
  const ClothLink    *link_params;
  const PetscBool    *fixed; /* local: pinned particles */
  ClothModel          model;
  Scene               scene;
} ClothLayout;
/* After ClothSetUp. */
PetscErrorCode ClothGetLayout(Cloth cloth, ClothLayout *layout);
/* Whether ClothSetUp has run. */
PetscErrorCode ClothIsSetUp(Cloth cloth, PetscBool *setup);
/* The contact normals if any particle was ever constrained by a body contact (else NULL; ClothGetContactNormals
   creates them). Borrowed. */
PetscErrorCode ClothPeekContactNormals(Cloth cloth, Vec *normals);

/* The cloth-cloth contacts (selfcontact.h) whose searches and velocity impulses the integrator applies around each
   step; borrowed (the caller destroys it after the cloth); NULL: none. Their forces join through their
   ClothContribution (ClothSelfContactGetContribution). */
PetscErrorCode ClothSetSelfContact(Cloth cloth, ClothSelfContact sc);
PetscErrorCode ClothGetSelfContact(Cloth cloth, ClothSelfContact *sc);
/* A symmetric block (bs 3) matrix with exactly the nonzero pattern of the interactions, preallocated, of the given
   type (MATBAIJ, or MATSBAIJ: only the upper triangle stored) unless -implicit_mat_type says otherwise. */
PetscErrorCode ClothCreateMatrix(Cloth cloth, MatType type, Mat *A);
/* The operator of the implicit system assembled into A (ClothAssembleImplicitSystem): A itself (a new reference) when
   no contribution couples particles beyond the interactions (mult_coupling), else a shell that applies A and those
   couplings. Krylov solvers take it as their operator and A as the matrix to precondition with. Collective. */
PetscErrorCode ClothCreateImplicitOperator(Cloth cloth, Mat A, Mat *op);
/* Frees the interaction graph of the whole fabric (ClothLayout's xadj, adjncy become NULL): once the implicit matrix
   exists nothing reads it again (its pattern never changes: contacts' couplings are applied apart,
   ClothCreateImplicitOperator), and every rank holds it whole (about 50 bytes per particle of the sheet).
   ClothCreateMatrix fails after it. Not collective. */
PetscErrorCode ClothReleaseGraph(Cloth cloth);
/* Zeroes the constrained components of a vector of per-particle 3-vectors (v <- S v). Per particle,
   S = 0 when pinned or stuck, S = I - n n^T when held against a body with unit normal n (see
   ClothGetContactNormals), S = I when free. */
PetscErrorCode ClothApplyConstraints(Cloth cloth, Vec v);
/* The contact constraints (a ghosted Vec with the state's layout, borrowed; created zero on first call): the
   caller writes the owned entries, per particle 0 (free), a unit normal n (held on a body, sliding along it)
   or CLOTH_CONTACT_STUCK n (held and stuck by static friction: all of its motion is constrained); the
   ghosts are refreshed by every use. Collective on the first call. */
PetscErrorCode ClothGetContactNormals(Cloth cloth, Vec *normals);
#define CLOTH_CONTACT_STUCK 2.0
/* The length of entry c of the contact constraints: 0 (free), 1 (held, sliding) or CLOTH_CONTACT_STUCK. */
static inline PetscReal ClothContactScale(const PetscScalar c[3])
{
  const PetscReal c2 = PetscRealPart(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  return c2 == 0 ? 0.0 : (c2 > 1.5 ? CLOTH_CONTACT_STUCK : 1.0);
}
/* One particle's filter S (row-major 3x3) from its entry c of the contact constraints (NULL: free) and
   whether it is pinned; returns whether S differs from I. */
PetscBool      ClothContactFilter(const PetscScalar *c, PetscBool pinned, PetscReal S[9]);
PetscErrorCode ClothComputeEnergy(Cloth cloth, Vec position, Vec velocity, ClothEnergy *energy);

/* Natural-order Vecs (PETSc's default contiguous layout, block size 3) for files. */
PetscErrorCode ClothCreateNaturalVec(Cloth cloth, Vec *natural);
/* SCATTER_FORWARD: solver -> natural; SCATTER_REVERSE: natural -> solver. */
PetscErrorCode ClothScatterToNatural(Cloth cloth, Vec solver, Vec natural, ScatterMode mode);
/* One value per particle for files: component 0 of each particle's block of solver (state layout,
   solver numbering) into values (natural order, one entry per particle: a Vec like
   ClothCreateStrainVec's). Collective. */
PetscErrorCode ClothScatterParticleValuesToNatural(Cloth cloth, Vec solver, Vec values);
/* Strain for output (cloth_strain.c): per particle, the largest relative elongation (l - l0) / l0 of
   its stretch links (negative when all are compressed), in natural order, one value per particle, in
   a Vec from ClothCreateStrainVec. position (solver numbering) gets its ghosts refreshed. Collective. */
PetscErrorCode ClothCreateStrainVec(Cloth cloth, Vec *strain);
PetscErrorCode ClothComputeStrain(Cloth cloth, Vec position, Vec strain);
/* Fit maps for output (cloth_strain.c), in Vecs like ClothCreateStrainVec's. Stress: per particle, the largest
   membrane stress of its stretch links, N/m: the link's tension over the width of fabric it carries (the mean
   spacing of the threads beside it, as its stiffness E w / l0 takes it), so E times the strain for a linear
   fabric. position as for ClothComputeStrain. Collective. */
PetscErrorCode ClothComputeStress(Cloth cloth, Vec position, Vec stress);
/* Contact pressure, N/m^2: per particle the body's normal force on it (normal_force per owned particle, as
   ClothCollisionGetNormalForces gives it; NULL: no bodies, all zero) over its fabric area (a quarter of each grid
   cell it is a corner of, at the initial positions). Collective. */
PetscErrorCode ClothComputeContactPressure(Cloth cloth, const PetscReal normal_force[], Vec pressure);
/* Gravity is multiplied by scale (0 while seams are pulled together, 1 otherwise). */
PetscErrorCode ClothSetGravityScale(Cloth cloth, PetscReal scale);
/* Friction with bodies is multiplied by scale (sewing's pull_friction while seams are pulled, 1 otherwise). */
PetscErrorCode ClothSetFrictionScale(Cloth cloth, PetscReal scale);
PetscErrorCode ClothGetFrictionScale(Cloth cloth, PetscReal *scale);
/* Positions of owned particles then ghosts (local numbering), ghosts refreshed first. Collective. */
PetscErrorCode ClothGetLocalPositionArray(Cloth cloth, const PetscScalar **x);
PetscErrorCode ClothRestoreLocalPositionArray(Cloth cloth, const PetscScalar **x);
/* The global model (every rank holds it; read-only): topology for output, counts. */
PetscErrorCode ClothGetModel(Cloth cloth, ClothModel *model);
/* The scene the cloth was built from (borrowed). */
PetscErrorCode ClothGetScene(Cloth cloth, Scene *scene);
/* The communicator the cloth lives on (the one given to ClothCreate): the objects built on the cloth use it. */
PetscErrorCode ClothGetComm(Cloth cloth, MPI_Comm *comm);
/* Names natural particle g as "piece (i, j)": its piece and grid node, for diagnostics. Not collective. */
PetscErrorCode ClothGetParticleName(Cloth cloth, PetscInt g, char name[], size_t len);
