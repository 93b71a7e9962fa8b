/* Scene: what is simulated (pieces, fabrics, gravity, run-level defaults), read from a YAML file.

   The Scene is plain data once created: modules read its fields directly and never modify them,
   except the driver, which may apply command-line overrides (-grid) before the cloth is built. */
#pragma once
#include <petscsys.h>
#include <petscviewer.h>
#include "util.h"

typedef enum {
  CLOTH_SHEAR_LINK,  /* diagonal links in every grid cell (the paper's "particle 2") */
  CLOTH_SHEAR_ANGLE, /* springs on the warp-weft angle at every cell corner (3D angle between the cell's edges) */
  CLOTH_SHEAR_CELL   /* one spring per cell on the warp-weft angle at its centre, in the tangent plane */
} ClothShearModel;
extern const char *const ClothShearModels[];

typedef enum {
  CLOTH_BEND_LINK, /* links between particles two steps apart along a thread (the paper's "particle 3") */
  CLOTH_BEND_ANGLE /* springs on the angle between consecutive thread segments */
} ClothBendModel;
extern const char *const ClothBendModels[];

typedef enum {
  CLOTH_MASS_AREA,   /* each particle carries density x its share of the cell areas (default) */
  CLOTH_MASS_UNIFORM /* every particle of a piece carries density x piece area / particle count */
} ClothMassDistribution;
extern const char *const ClothMassDistributions[];

/* A fabric's material data. Stiffnesses are per unit width (membrane moduli), so that the model's
   coefficients follow from the local grid spacing (see fabric.h). */
typedef struct {
  char            name[CLOTH_NAME_LEN];
  PetscReal       density;      /* areal density, kg/m^2 (> 0) */
  PetscReal       stretch_warp; /* tensile 2D modulus along the warp (u, i) threads, N/m (> 0) */
  PetscReal       stretch_weft; /* the same along the weft (v, j) threads, N/m (> 0) */
  PetscReal       shear;        /* in-plane shear modulus, N/m (>= 0) */
  ClothShearModel shear_model;
  PetscReal       shear_hysteresis;     /* cell model: friction shear force per unit width HG (half the KES 2HG), N/m (>= 0; 0 = elastic) */
  PetscReal       bend_warp, bend_weft; /* link model: N/m per skip-one link; angle model: bending rigidity, N m (>= 0) */
  ClothBendModel  bend_model;
  PetscReal       bend_bias;        /* angle model: bending rigidity along the bias (45 degrees to the threads), N m;
                                       0 = none (the thread springs alone give (bend_warp + bend_weft) / 4), else
                                       >= that: the difference is the cells' twisting rigidity (fabric.h) */
  PetscReal bend_hysteresis_warp;   /* angle model: friction moment per unit width HB (half the KES 2HB), N m/m (>= 0; 0 = elastic) */
  PetscReal bend_hysteresis_weft;   /* the same for bending the weft threads */
  PetscReal damping;                /* mass-proportional damping rate, 1/s (>= 0): force -damping m v */
  PetscReal repulsion;              /* stretch links repel below this fraction of their rest length (0 = off, < 1) */
  PetscReal repulsion_stiffness;    /* stiffness of that repulsion relative to the link's stretch stiffness (>= 0) */
  PetscReal stretch_knee_warp;      /* biphasic tensile curve: strain beyond which warp links stiffen (0 = linear) */
  PetscReal stretch_knee_weft;      /* the same for the weft links */
  PetscReal stretch_stiff_warp;     /* tensile 2D modulus beyond the knee, warp, N/m (defaults to stretch_warp) */
  PetscReal stretch_stiff_weft;     /* the same along the weft, N/m */
  char      preset[CLOTH_NAME_LEN]; /* measured fabric it starts from ("" = none; see fabric_presets.h) */
} SceneFabric;

/* A flat pattern piece: a logical grid of nu x nv particles (i along u = warp, j along v = weft),
   particle (i, j) numbered j*nu + i within the piece ("row by row"). */
typedef struct {
  char                  name[CLOTH_NAME_LEN];
  PetscInt              fabric;    /* index into Scene.fabrics */
  PetscInt              nu, nv;    /* grid size (>= 2 each) */
  PetscReal             size[2];   /* rectangle: extent along u and v, m */
  PetscReal             origin[3]; /* 3D position of particle (0, 0), m */
  PetscReal             u_axis[3]; /* unit 3D direction of increasing i (normalised by the reader) */
  PetscReal             v_axis[3]; /* unit 3D direction of increasing j (normalised, orthogonal to u_axis) */
  ClothMassDistribution mass_distribution;
  PetscInt              npins;
  PetscInt             *pins;                /* 2*npins grid indices (i, j), already resolved to 0 <= i < nu, 0 <= j < nv */
  PetscInt             *pins_given;          /* 2*npins indices exactly as written (negative counts from the end), for -grid */
  PetscInt              grid_given[2];       /* nu, nv as written in the file (before any SceneSetGridSize) */
  PetscBool             has_boundaries;      /* outline from four boundaries (docs/model.md section 3) instead of size */
  PetscInt              boundary_npoints[4]; /* vertices of the bottom, right, top, left polylines */
  PetscReal            *boundary_points[4];  /* 2 * npoints pattern-plane coordinates (u, v), m, each */
  PetscReal             pin_disc[3];         /* pin particles with |uv - (pin_disc[0], pin_disc[1])| < pin_disc[2] (radius 0 = none) */
  PetscReal             pin_box[4];          /* pin particles with u0 <= u <= u1, v0 <= v <= v1 (u0, v0, u1, v1; empty when u1 < u0) */
  PetscReal             cut_disc[3];         /* keep only the grid cells whose centre lies within cut_disc[2] of (cut_disc[0], cut_disc[1]) (radius 0 = all; pattern.h) */
  PetscBool             wrapped;             /* wrap: the flat placement is rolled onto a cylinder (arrangement around a body) */
  PetscReal             wrap_point[3];       /* a point on the cylinder's axis, m */
  PetscReal             wrap_axis[3];        /* the axis direction (unit) */
  PetscBool             wrap_cone;           /* wrap onto a cone with its apex at wrap_point instead of a cylinder */
} ScenePiece;

typedef struct {
  char      integrator[CLOTH_NAME_LEN]; /* "" when the scene gives no default */
  PetscReal dt;                         /* 0 when not given */
  PetscReal t_final;                    /* 0 when not given */
  PetscInt  steps;                      /* 0 when not given */
  PetscInt  output_every;               /* 0 when not given */
  PetscInt  checkpoint_every;           /* 0 when not given */
} SceneRunDefaults;

typedef enum {
  SCENE_BODY_SPHERE, /* analytic sphere: center, radius */
  SCENE_BODY_PLANE,  /* analytic half-space: point, outward normal */
  SCENE_BODY_MESH    /* triangle mesh from an OBJ file: file, scale, rotation, translation */
} SceneBodyType;
extern const char *const SceneBodyTypes[];

/* A rigid body the cloth collides with (see body.h). */
typedef struct {
  char          name[CLOTH_NAME_LEN];
  SceneBodyType type;
  PetscReal     center[3], radius;    /* sphere, m */
  PetscReal     point[3], normal[3];  /* plane: a point on it (m) and its unit outward normal */
  char          file[CLOTH_PATH_LEN]; /* mesh: OBJ path, resolved relative to the scene file's directory */
  PetscReal     scale;                /* mesh: file units -> m (default 1) */
  PetscReal     rotation[3];          /* mesh: degrees about x, then y, then z (after scaling) */
  PetscReal     translation[3];       /* mesh: m, applied last */
  PetscReal     friction_static;      /* Coulomb coefficients (>= 0), default 0 */
  PetscReal     friction_kinetic;
  PetscReal     thickness; /* m (>= 0): the cloth is kept this far outside the surface */
} SceneBody;

/* Cloth-cloth collisions (self_collision: block; see selfcontact.h). Off unless enabled. */
typedef struct {
  PetscBool given; /* the block is present */
  PetscBool enabled;
  PetscReal thickness;    /* m (> 0): layers are kept this far apart */
  PetscReal stiffness;    /* N/m (> 0): repulsion 0.5 k (thickness - d)^2 for d < thickness */
  PetscInt  exclude_ring; /* particles of one piece within this many grid rings never collide (default 0: sharing a particle) */
  PetscBool same_piece;   /* particles of one piece collide with each other (default true) */
} SceneSelfCollision;

/* The four sides of a piece's grid: bottom j = 0, right i = nu-1, top j = nv-1, left i = 0. */
typedef enum { CLOTH_SIDE_BOTTOM, CLOTH_SIDE_RIGHT, CLOTH_SIDE_TOP, CLOTH_SIDE_LEFT } ClothPieceSide;
extern const char *const ClothPieceSides[];

/* One side of a seam: a stretch of one side of a piece, from `from` to `to` as fractions of that side's arc
   length in index order (bottom and top by increasing i, left and right by increasing j); to < from runs
   the stretch backwards. */
typedef struct {
  PetscInt       piece;
  ClothPieceSide side;
  PetscReal      from, to;
  int            line; /* of the side in the scene file, for messages */
} SceneSeamSide;

/* A seam (seams: list): two stretches sewn together (see seam.h). */
typedef struct {
  char          name[CLOTH_NAME_LEN];
  SceneSeamSide a, b;
  PetscBool     bend; /* add bending across the seam, so that it does not fold like a hinge (default true) */
} SceneSeam;

/* How seams are sewn (sewing: block; see sewing.h). */
typedef struct {
  PetscReal pull_acceleration; /* m/s^2: the pull on each pair acts like gravity of this strength (default 9.81) */
  PetscReal pull_radius;       /* m: within this gap the pull falls linearly to zero (default 0.01) */
  PetscReal sewn_stiffness;    /* N/m: the spring that holds a sewn pair (default 2000) */
  PetscReal tolerance;         /* m: a pair closer than this is sewn (default 0.002) */
  PetscReal max_time;          /* s: gravity comes on after this much pulling even with pairs open (default 2) */
  PetscReal pull_friction;     /* body friction is multiplied by this while pairs are pulled (default 1) */
} SceneSewing;

typedef struct _n_Scene *Scene;
struct _n_Scene {
  char               path[CLOTH_PATH_LEN]; /* the file it was read from */
  char               name[CLOTH_NAME_LEN]; /* scene name (defaults to the file's base name without .yaml) */
  PetscReal          gravity[3];           /* m/s^2 */
  PetscInt           nfabrics;
  SceneFabric       *fabrics;
  PetscInt           npieces;
  ScenePiece        *pieces;
  SceneRunDefaults   run;
  PetscInt           nbodies;
  SceneBody         *bodies;         /* rigid bodies (bodies: list), in scene order */
  SceneSelfCollision self_collision; /* cloth-cloth collisions (self_collision: block) */
  PetscInt           nseams;
  SceneSeam         *seams;            /* seams: list, in scene order */
  SceneSewing        sewing;           /* sewing: block (defaults when absent) */
  PetscBool          single_grid;      /* exactly one rectangular piece: -grid N may resize it */
  PetscInt64         fingerprint;      /* FNV-1a hash of the file bytes (mixed with -grid), kept in checkpoints */
  PetscInt64         file_fingerprint; /* FNV-1a hash of the file bytes alone */
  MPI_Comm           comm;             /* the communicator it was read on (errors from SceneSetGridSize use it) */
  char              *text;             /* the file's bytes, NUL-terminated: kept in every output file (provenance) */
};

/* Reads and validates a scene file. Collective on comm: rank 0 reads the bytes, every rank parses
   the same bytes, so every rank fails (or succeeds) alike. Errors name the file, line, key and
   what was expected. */
PetscErrorCode SceneCreateFromFile(MPI_Comm comm, const char path[], Scene *scene);
/* Resizes the single rectangular piece to n x n particles (n >= 2); pins given with negative indices follow
   the edges, the size stays. The fingerprint becomes the file's hash mixed with n (the file's own hash again
   when n x n is the grid the file gives). Errors unless scene->single_grid. Not collective (every rank holds the
   same scene and must call it alike). */
PetscErrorCode SceneSetGridSize(Scene scene, PetscInt n);
/* The particles of all pieces (at most PETSC_MAX_INT / 3: the reader and SceneSetGridSize refuse more). */
PetscErrorCode SceneGetParticleCount(Scene scene, PetscInt *n);
/* The largest distance between neighbouring particles over all pieces, m, in their flat layout. */
PetscErrorCode SceneGetLargestSpacing(Scene scene, PetscReal *spacing);
/* The most particle spacings (SceneGetLargestSpacing) a self-collision thickness may span: layers a few spacings
   apart are what it is for; far beyond, it throws the fabric (a 10 m thickness threw a sheet 15 m). */
#define SCENE_SELF_COLLISION_MAX_SPACINGS 50
/* The most seams a scene may have: a checkpoint stores the sewn seams of a particle as the sum of 2^s over its
   sewn seams s in a float64 (src/sewing.c, ClothSewingGetStateVec), exact for s < 53 (the bits of a double's
   significand); beyond, seams would come back from a restart unsewn or sewn wrongly. The sewing's own masks hold
   64 (SEWING_MAX_SEAMS). */
#define SCENE_MAX_SEAMS 53
/* The longest stretch of a seam may be at most this many times its shorter one: a gathered seam (a sleeve cap, a
   ruffle) eases up to about 3 times its length onto the other side; beyond, the sides are a unit mistake (0.2 m
   against 20 m was accepted and ended in a late warning that the sewing time ran out). */
#define SCENE_SEAM_MAX_LENGTH_RATIO 4
/* The longest time step and simulated time, s, of the scene's run: block and of -dt, -t_final and -steps: a cloth
   step of more than 10 s, or more than 11 days of simulated time, is a unit mistake (-dt 1e9 -steps 3 ran). */
#define SCENE_MAX_DT 10.0
#define SCENE_MAX_T_FINAL 1e6
/* Prints a short summary (pieces with grid and particle count, fabrics, gravity, run defaults) to an ASCII viewer
   (NULL: stdout of the scene's communicator). */
PetscErrorCode SceneView(Scene scene, PetscViewer viewer);
/* Frees the scene; NULL-safe, sets *scene to NULL. */
PetscErrorCode SceneDestroy(Scene *scene);
