/* The private part of ClothSelfContact, shared by its two files: src/selfcontact_search.c (static topology, the
   exchange of particles near other ranks, the proximity search and its brute-force reference) and
   src/selfcontact.c (the response: matrix pattern, repulsion, velocity filter, and the object). */
#pragma once
#include "selfcontact.h"
#include "cellgrid.h"

#define SELF_CONTACT_NP 4 /* particles of a contact element */

/* A pair of primitives of the candidate list: kind and particles as in ClothContact (natural numbering), and their
   contact-local indices. */
typedef struct {
  ClothContactKind kind;
  PetscInt         p[SELF_CONTACT_NP];
  PetscInt         local[SELF_CONTACT_NP];
} SelfContactCandidate;

struct _n_ClothSelfContact {
  Cloth                     cloth; /* borrowed; read through its public accessors only */
  Scene                     scene;
  ClothLayout               layout;             /* the cloth's particle distribution (after set-up) */
  Vec                       position, velocity; /* the cloth's state (borrowed) */
  MPI_Comm                  comm;
  PetscMPIInt               size, rank;
  PetscBool                 enabled, view, setup;
  PetscReal                 thickness, stiffness, min_gap;
  PetscReal                 skin;                 /* candidate list: motion allowed before a rebuild, as a fraction of the radius */
  PetscBool                 friction;             /* regularised Coulomb friction between layers in the implicit step */
  PetscReal                 friction_coefficient; /* mu */
  PetscReal                 friction_velocity;    /* eps_v of the regularised law, m/s */
  Vec                       contact_push;         /* friction: each particle's net repulsion, then its load vector */
  Vec                       contact_sides;        /* friction: its contacts' pushes along +nu and -nu */
  Vec                       contact_press;        /* friction: what the layers on either side press it with */
  Vec                       contact_load;         /* friction: its load per unit push, towards +nu and -nu */
  Vec                       support;              /* friction: the direction nu of its net repulsion */
  PetscInt                  friction_load_sweeps; /* friction: sweeps carrying the loads of stacked layers down */
  PetscInt                  exclude_ring, impulse_iterations;
  PetscBool                 same_piece;
  ClothSelfContactExcludeFn exclude;
  void                     *exclude_ctx;

  /* static topology, natural numbering */
  PetscInt  ntri, *tri;                 /* 3 per triangle */
  PetscInt  nedge, *edge;               /* 2 per edge, lower particle first */
  PetscInt *tri_start, *tri_of;         /* particle -> incident triangles (CSR) */
  PetscInt *edge_start, *edge_of;       /* particle -> incident edges (CSR) */
  PetscInt *piece_of, *grid_i, *grid_j; /* per particle: its piece and grid position in it */

  /* the last search: "contact-local" particles are the owned ones (0 .. nlocal-1, solver order)
     followed by the remote ones received from other ranks */
  PetscInt      nremote, *remote_natural;
  PetscInt      nremote_prev;         /* remote particles listed in natural_of */
  PetscInt     *tri_mark, *edge_mark; /* per primitive: the search (or query) that last visited it */
  PetscInt      visit;
  PetscInt     *natural_of;                                            /* contact-local -> natural */
  PetscInt     *contact_index;                                         /* natural -> contact-local, -1 when not present (size N) */
  PetscReal    *x, *dx;                                                /* contact-local positions at the search, displacements over the step */
  PetscReal    *x0;                                                    /* contact-local positions when the candidate list was built */
  PetscInt      nalloc;                                                /* contact-local particles natural_of, x, dx, x0 have room for */
  Vec           xremote, vremote, fremote, kvremote, bremote, wremote; /* bremote: body-contact normals; wremote: load vectors */
  VecScatter    remote_scatter;                                        /* cloth state -> remote particles */
  CellGrid      triangle_grid, edge_grid;                              /* the cell grids of the last search */
  PetscInt      ncontacts, maxcontacts;
  ClothContact *contacts; /* natural numbering */
  PetscInt     *local;    /* 4 contact-local indices per contact */

  /* the candidate list (a Verlet list): every pair of primitives closer than list_radius = radius + 2 list_budget at
     the positions x0 of its build. A pair within the radius plus its travel at a later search is among them as long
     as no particle has moved more than the largest displacement since the build plus the largest travel over the
     step sum to at most list_budget (each of the pair's closest points moves at most that far), so the later
     searches only test the candidates; the list is built again when that bound fails. */
  PetscBool             list_valid;
  PetscBool             any_candidates;           /* on some rank: without, the searches, forces and impulses have nothing to do (collective) */
  PetscReal             list_radius, list_budget; /* the search radius it serves; the motion it allows */
  PetscInt              ncandidates, maxcandidates;
  SelfContactCandidate *candidates; /* sorted by kind, then particles: the contacts come out in this order */
  PetscInt              builds;     /* statistics: list builds, candidates summed over the builds (this rank) */
  PetscInt64            candidates_built;

  /* keys of the contact blocks this rank has sent to the rows' owners and found in the matrix pattern since it last
     changed (sorted): contacts whose blocks are all here need no exchange to know the pattern holds them */
  PetscInt   *row_start; /* solver numbering: rank r owns the rows row_start[r] .. row_start[r + 1] - 1 */
  PetscInt    nknown;
  PetscInt64 *known;

  /* blocks of the implicit matrix beyond the static pattern, for owned rows: keys row * N + col (solver) */
  PetscInt    nextra;
  PetscInt64 *extra;
  PetscInt    rebuilds;                           /* how often the matrix pattern had to grow */
  PetscInt    searches, contacts_found, impulses; /* statistics for the view (summed over ranks where relevant) */
};

/* qsort order of PetscInt64 keys, increasing. */
int SelfContactCompareInt64(const void *a, const void *b);

/* Triangles (a b c), (a c d) of every quad, and the unique edges: the quad sides and that diagonal. */
PetscErrorCode SelfContactBuildPrimitives(ClothSelfContact sc, ClothModel m);

/* particle -> primitives with nv vertices each (CSR) */
PetscErrorCode SelfContactBuildIncidence(PetscInt nparticles, PetscInt nprim, PetscInt nv, const PetscInt prim[], PetscInt **start, PetscInt **of);

/* Each particle's piece and (i, j) grid position, for the ring exclusion. */
PetscErrorCode SelfContactBuildGridPositions(ClothSelfContact sc, Scene scene, ClothModel m);

/* The remote particles' entries of global (the cloth's state) into remote. Collective. */
PetscErrorCode SelfContactRefreshRemote(ClothSelfContact sc, Vec global, Vec remote);

/* Adds the remote particles' entries of remote into their owners' entries of global. Collective. */
PetscErrorCode SelfContactSumRemoteInto(ClothSelfContact sc, Vec remote, Vec global);

/* All contacts within radius, plus the relative travel of their closest points over a step of h at
   velocity (NULL: no travel), at the cloth's current positions, in the order of the candidate list (kind, then
   particles), from the candidate list, built again first when the particles moved beyond its budget. Collective. */
PetscErrorCode SelfContactSearch(ClothSelfContact sc, PetscReal radius, Vec velocity, PetscReal h);
