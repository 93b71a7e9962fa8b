/* Private: the body of the Cloth object, shared by cloth.c (set-up, layout), cloth_assembly.c (forces, Jacobians,
   energies, the contributions' calls), cloth_regis.c (the registry of contributions) and cloth_strain.c. Every other
   module uses cloth.h. */
#pragma once
#include "cloth.h"
#include "forces.h"

struct _n_Cloth {
  MPI_Comm           comm;
  Scene              scene;
  ClothModel         model;
  ClothPartitionType partition_type;
  PetscBool          view_partition;
  PetscBool          view_partition_summary; /* one line at set-up on more than one rank (the driver's default) */
  PetscBool          setup;
  ClothStiffness     stiffness;    /* form of the angle and twist elements' stiffness in the implicit system */
  PetscBool          factored;     /* assemble the Gauss-Newton form from its factors (-cloth_stiffness_factored) */
  PetscReal          perturbation; /* amplitude, m, of the seeded start imperfections (0: none) */
  PetscInt           perturbation_seed;
  PetscReal          perturbation_wavelength; /* m: 0 independent per particle, > 0 a smooth field (model.h) */

  PetscInt  nglobal, nlocal, nghost, rstart;
  PetscInt *part;              /* natural -> rank */
  PetscInt *solver_of_natural; /* natural -> solver index */
  PetscInt *natural_of_local;  /* local (owned, then ghosts) -> natural */
  PetscInt *ghosts;            /* solver indices of the ghosts, ascending */
  PetscInt  edge_cut;

  PetscReal    *mass, *damping; /* owned */
  PetscReal    *thread_width;   /* owned and ghosts, 2 each: the fabric width a thread along u, along v carries there (cloth_strain.c) */
  PetscReal    *area;           /* owned: the fabric area of each particle (cloth_strain.c) */
  PetscBool    *fixed;          /* owned and ghosts */
  PetscInt      nlinks, nangles;
  ClothLinkRef *links;       /* local particle indices and the index of their parameters in link_params */
  ClothLink    *link_params; /* the distinct parameter sets of this rank's links (their p unused) */
  PetscInt      nlink_params;
  ClothAngle   *angles;            /* the elastic ones (slip 0; friction elements: hysteresis.c), local particle indices */
  PetscInt      nangles_evaluated; /* every angle element of the model this rank evaluates, elastic or friction */
  PetscReal     gravity_scale;     /* 1, or 0 while seams are pulled together (sewing.h) */
  PetscReal     friction_scale;    /* multiplies body friction: 1, or sewing's pull_friction while seams are pulled */
  PetscInt     *xadj, *adjncy;     /* natural-order adjacency, kept for preallocation (NULL after ClothReleaseGraph) */
  PetscInt      nedges;            /* its edges, each counted once */

  Vec        position, velocity, work_force, work_kv;
  PetscReal *filter;                                                  /* each local particle's constraint filter S (9), refreshed by every assembly of the implicit system */
  PetscBool *filtered;                                                /* ... and whether S differs from I */
  PetscInt   nfilter;                                                 /* particles the two hold room for */
  Vec        contact_normal;                                          /* ghosted, bs 3: unit normal of each particle's contact constraint, 0 when free
                                                                         (created by ClothGetContactNormals; NULL: no contacts) */
  struct _n_ClothSelfContact *self_contact;                           /* cloth-cloth contacts whose updates the integrator applies (borrowed, NULL: off) */
  ClothContribution           contributions[CLOTH_MAX_CONTRIBUTIONS]; /* plugged-in forces (cloth.h) */
  PetscInt                    ncontributions;
  Vec                         natural; /* layout of natural-order Vecs (no values of its own) */
  VecScatter                  to_natural;
};

/* Registers the model's own contributions (cloth_regis.c's table: hysteresis, seam links) at ClothSetUp. */
PETSC_INTERN PetscErrorCode ClothRegisterModelContributions_Private(Cloth cloth);

/* The rest measures the fit maps need (thread_width, area), from the model's initial positions while they exist:
   after them the fit maps read no per-particle data of the whole fabric (cloth_strain.c). */
PETSC_INTERN PetscErrorCode ClothComputeRestMeasures(Cloth cloth);
