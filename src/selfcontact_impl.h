/* The private part of ClothSelfContact, shared by its three files: src/selfcontact_search.c (static topology, the
   exchange of particles near other ranks, the candidates and contacts and their brute-force reference),
   src/selfcontact_tiles.c (the broad phase: tiles of the pattern grids, pairs of tiles near each other and their pairs
   of primitives, handed to the narrow phase) and src/selfcontact.c (the response: matrix pattern, repulsion, velocity filter,
   and the object). */
#pragma once
#include "selfcontact.h"
#include "cellgrid.h"

#define SELF_CONTACT_NP 4                                                        /* particles of a contact element */
#define SELF_CONTACT_TILE 4                                                      /* cells per side of a tile, the unit of the broad phase */
#define SELF_CONTACT_CLOSURE ((SELF_CONTACT_TILE + 1) * (SELF_CONTACT_TILE + 1)) /* particles of a tile's rectangle */
#define SELF_CONTACT_PIECE_TILES 4                                               /* per piece: first tile, tiles along i and j, particles along i */

/* A tile: the cells [i0, i1) x [j0, j1) of a piece (its particles [i0, i1] x [j0, j1]), the ti-th along i and tj-th
   along j, of which ncells are in the pattern (a cut-out removes some). */
typedef struct {
  PetscInt piece, ti, tj, i0, j0, i1, j1, ncells;
} SelfContactTile;

/* A contact's couplings in the implicit system: h2 a_j a_k S_j M S_k between its particles (contact-local), M its
   stiffness (and friction Jacobian) times the step's factors, S their constraint filters (row-major). */
typedef struct {
  PetscReal a[SELF_CONTACT_NP], M[9], S[SELF_CONTACT_NP][9];
  PetscInt  local[SELF_CONTACT_NP];   /* contact-local */
  PetscInt  local_c[SELF_CONTACT_NP]; /* owned, then the place among the couplings' remote particles (SetCouplingScatter) */
} SelfContactCoupling;

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
  PetscReal                 velocity_margin;      /* candidates: change of a displacement over the step allowed before they are found again, as a fraction of the thickness */
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
  PetscReal                 exclude_thicknesses; /* pairs closer in the pattern than this many thicknesses never collide */
  PetscBool                 same_piece;
  ClothSelfContactExcludeFn exclude;
  void                     *exclude_ctx;

  /* static topology, natural numbering */
  PetscInt         ntri, *tri;                 /* 3 per triangle */
  PetscInt         nedge, *edge;               /* 2 per edge, lower particle first */
  PetscInt        *tri_start, *tri_of;         /* particle -> incident triangles (CSR) */
  PetscInt        *edge_start, *edge_of;       /* particle -> incident edges (CSR) */
  PetscInt        *piece_of, *grid_i, *grid_j; /* per particle: its piece and grid position in it */
  PetscInt         ntiles, *piece_tiles;       /* tiles; per piece SELF_CONTACT_PIECE_TILES numbers */
  SelfContactTile *tiles;
  PetscInt        *tile_tri_start, *tile_tri_of;           /* tile -> triangles (CSR) */
  PetscInt        *tile_edge_start, *tile_edge_of;         /* tile -> edges */
  PetscInt        *tile_particle_start, *tile_particle_of; /* tile -> particles */

  /* the last search: "contact-local" particles are the owned ones (0 .. nlocal-1, solver order)
     followed by the remote ones received from other ranks */
  PetscInt      nremote, *remote_natural;
  PetscInt      nremote_prev;             /* remote particles listed in natural_of */
  PetscInt     *tile_present, *tile_mark; /* per tile: its index among the present tiles of the search (-1: none); the query that last visited a present tile */
  PetscInt     *present_tiles, npresent_tiles, maxpresent_tiles;
  PetscInt      visit;
  PetscInt     *scratch_ids, *scratch_ij; /* room (scratch_room each) for the triangles and edges of two tiles, their particles' grid positions and their boxes */
  PetscInt      scratch_room;
  PetscReal    *scratch_boxes;
  PetscInt     *natural_of;                                            /* contact-local -> natural */
  PetscInt     *contact_index;                                         /* natural -> contact-local, -1 when not present (size N) */
  PetscReal    *x, *dx;                                                /* contact-local positions at the search, displacements over the step */
  PetscReal    *x0;                                                    /* contact-local positions when the candidates were found */
  PetscReal    *dx0;                                                   /* the owned particles' displacements over the step then (3 nlocal) */
  PetscInt      nalloc;                                                /* contact-local particles natural_of, x, dx, x0 have room for */
  Vec           xremote, vremote, fremote, kvremote, bremote, wremote; /* bremote: body-contact normals; wremote: load vectors */
  VecScatter    remote_scatter;                                        /* cloth state -> remote particles */
  CellGrid      tile_grid;                                             /* the cell grid of the tiles' boxes of the last search */
  PetscInt      ncontacts, maxcontacts;
  ClothContact *contacts; /* natural numbering */
  PetscInt     *local;    /* 4 contact-local indices per contact */

  /* the candidates: every pair of primitives that comes within list_radius + 2 list_margin during the step at the
     positions x0 and displacements dx0 of their search (swept boxes). They hold every contact within list_radius for
     displacements that differ from dx0 by at most list_margin per particle at the same positions: the velocity
     filter's search after the solve keeps them; the next step finds them anew. */
  PetscBool             list_valid;
  PetscBool             any_candidates;           /* on some rank: without, the searches, forces and impulses have nothing to do (collective) */
  PetscReal             list_radius, list_margin; /* the search radius they serve; the change of displacement they allow */
  PetscInt              ncandidates, maxcandidates;
  SelfContactCandidate *candidates; /* sorted by kind, then particles: the contacts come out in this order */
  PetscInt              builds;     /* statistics: searches that found candidates anew, candidates summed over them and the most at one (this rank) */
  PetscInt64            candidates_built;
  PetscInt              candidates_max;
  PetscInt64            primitive_pairs_total;        /* statistics: pairs of primitives given to the narrow phase, summed over searches */
  PetscInt64            tile_pairs, tile_pairs_apart; /* statistics: pairs of tiles whose boxes overlapped, those proved apart */
  PetscInt             *ring;                         /* per piece: particles this many grid rings apart or closer never collide (SelfContactSetExclusionRings) */

  /* the couplings of the last assembly (AddContactStiffness, MultCoupling): per contact with a share in it, its record */
  PetscInt             ncouplings, maxcouplings, *coupling_of, maxcoupling_of; /* coupling_of: contact -> record, -1: none */
  SelfContactCoupling *couplings;
  PetscBool            any_coupling;              /* on some rank (collective) */
  Vec                  xcoupling, ycoupling;      /* the couplings' remote particles' entries of a product */
  Vec                  impulse_dv, impulse_count; /* a sweep of impulses: the owned particles' velocity changes and their number */
  VecScatter           coupling_scatter;
  PetscInt             ncoupling_remote, *coupling_remote;
  PetscInt             searches, impulses;                  /* statistics for the view (summed over ranks where relevant) */
  PetscInt64           contacts_found, edge_contacts_found; /* contacts at the step's starts, and of them edge-edge ones */
};

/* qsort order of PetscInt64 keys, increasing. */
int SelfContactCompareInt64(const void *a, const void *b);

/* Triangles (a b c), (a c d) of every quad, and the unique edges: the quad sides and that diagonal. */
PetscErrorCode SelfContactBuildPrimitives(ClothSelfContact sc, ClothModel m);

/* particle -> primitives with nv vertices each (CSR) */
PetscErrorCode SelfContactBuildIncidence(PetscInt nparticles, PetscInt nprim, PetscInt nv, const PetscInt prim[], PetscInt **start, PetscInt **of);

/* Each particle's piece and (i, j) grid position, for the ring exclusion. */
PetscErrorCode SelfContactBuildGridPositions(ClothSelfContact sc, Scene scene, ClothModel m);

/* The tiles of every piece and their triangles, edges and particles (after the primitives and grid positions). */
PetscErrorCode SelfContactBuildTiles(ClothSelfContact sc, Scene scene, ClothModel m);
PetscErrorCode SelfContactDestroyTiles(ClothSelfContact sc);
/* The tile of natural particle g. */
PetscInt SelfContactParticleTile(const ClothSelfContact sc, PetscInt g);
/* Gives SelfContactTestPair the pairs of primitives that may come within rho during the step at the contact-local
   state (x, dx): particle-triangle pairs of this rank's particles and edge pairs this rank handles, allowed by the
   exclusion ring, whose boxes over the step (relative to their tiles' mean motion) come within rho of each other.
   region: the box of every present particle over the step, inflated by rho. */
PetscErrorCode SelfContactPairPrimitives(ClothSelfContact sc, const PetscReal region[6], PetscReal rho);
/* The narrow phase of one pair of primitives (a particle a and triangle b, or edges a < b): a candidate when it comes
   within rho during the step (at the contact-local state x, dx), its particle-triangle pair holding the particle's
   nearest point on the fabric, its edge pair's closest points inside both edges. */
PetscErrorCode SelfContactTestPair(ClothSelfContact sc, ClothContactKind kind, PetscInt a, PetscInt b, PetscReal rho);
/* The box of natural particles v[0..nv) over the step, their displacements less u (NULL: none), inflated by inflate. */
void SelfContactSweptBox(ClothSelfContact sc, const PetscInt v[], PetscInt nv, PetscReal inflate, const PetscReal u[3], PetscReal box[6]);
/* Whether primitives with natural particles pa[0..na) and pb[0..nb) lie within their piece's exclusion ring (or in one
   piece with same_piece off). */
PetscBool SelfContactRingExcluded(ClothSelfContact sc, const PetscInt pa[], PetscInt na, const PetscInt pb[], PetscInt nb);
/* Whether this rank handles the edge-edge pair of edges e1, e2 (particles p). */
PetscBool SelfContactHandlesEdgePair(ClothSelfContact sc, PetscInt e1, PetscInt e2, const PetscInt p[4]);

/* Whether every rank's sorted list of natural particles (n of them) equals its old one (nold; have: an old one
   exists). Collective. */
PetscErrorCode SelfContactSameParticles(ClothSelfContact sc, PetscBool have, PetscInt n, const PetscInt list[], PetscInt nold, const PetscInt old[], PetscBool *all_same);
/* A scatter from the cloth's state to target (3 entries a particle) for the natural particles natural[0..n). */
PetscErrorCode SelfContactCreateScatter(ClothSelfContact sc, PetscInt n, const PetscInt natural[], Vec target, VecScatter *scatter);

/* Makes room in *array (elements of size bytes, n of them in use, *max allocated) when it is full: *max becomes
   2 *max + extra and the n elements move to the new allocation. */
PetscErrorCode SelfContactGrowArray(size_t size, PetscInt n, PetscInt *max, PetscInt extra, void *array);

/* Each piece's exclusion ring: at least exclude_ring, and wide enough that particles closer in the pattern than
   exclude_thicknesses x thickness never collide (a flat layer's own neighbourhood, and a fold tighter than the
   thickness allows). Collective. */
PetscErrorCode SelfContactSetExclusionRings(ClothSelfContact sc);

/* The remote particles' entries of global (the cloth's state) into remote. Collective. */
PetscErrorCode SelfContactRefreshRemote(ClothSelfContact sc, Vec global, Vec remote);

/* Adds the remote particles' entries of remote into their owners' entries of global. Collective. */
PetscErrorCode SelfContactSumRemoteInto(ClothSelfContact sc, Vec remote, Vec global);

/* All contacts within radius, plus the relative travel of their closest points over a step of h at
   velocity (NULL: no travel), at the cloth's current positions, in the order of the candidate list (kind, then
   particles), from the candidate list, built again first when the particles moved beyond its budget. Collective. */
PetscErrorCode SelfContactSearch(ClothSelfContact sc, PetscReal radius, Vec velocity, PetscReal h);
