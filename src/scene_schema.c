/* The scene's schema: the allowed keys of every block, the bounds of its reals and the defaults that are not zero.

   Format (docs/scene_format.md has the full description):

     name: hanging_sheet              # optional, default: the file's base name without extension
     gravity: [0, -9.81, 0]           # optional, default (0, -9.81, 0), m/s^2
     fabrics:                         # required, map name -> fabric (at least one)
       net:
         density: 0.2                 # kg/m^2, required, > 0
         stretch: 1000                # N/m, > 0; or stretch_warp / stretch_weft (each defaults to stretch)
         shear: 1000                  # N/m, default 0, >= 0
         shear_model: link            # link | angle | cell (default link)
         shear_hysteresis: 0          # cell model: friction shear force HG per unit width, N/m (KES 2HG / 2);
                                      # default 0 (elastic), >= 0; or shear_hysteresis_ratio: 2HG/G, rad
         bend: 10                     # link model: N/m per skip-one link; angle model: rigidity N m;
                                      # or bend_warp / bend_weft (each defaults to bend); default 0, >= 0
         bend_model: link             # link | angle (default link)
         bend_bias: 0                 # angle model: bending rigidity along the bias, N m; default 0 (no twisting
                                      # rigidity), else >= (bend_warp + bend_weft) / 4; or bend_bias_ratio: that
                                      # rigidity / the mean of bend_warp and bend_weft (0, or >= 0.5)
         bend_hysteresis: 0           # angle model: friction moment HB per unit width, N m/m (KES 2HB / 2), or
                                      # bend_hysteresis_warp / _weft; default 0 (elastic), >= 0; or
                                      # bend_hysteresis_ratio: 2HB/B, 1/m (HB = ratio B / 2 per direction)
         damping: 0.0                 # 1/s, default 0, >= 0
         repulsion: 0.0               # fraction of rest length, in [0, 1), default 0 (off)
         repulsion_stiffness: 10      # relative to the stretch stiffness, default 10, >= 0
         # also: preset: NAME (a measured fabric, fabric_presets.h) or kes: {W, B_warp, ...} (KES-F units,
         # fabric.h) as defaults for the keys above; stretch_knee[_warp|_weft] + stretch_stiff[_warp|_weft] (biphasic)
     pieces:                          # required, list, at least one
       - name: sheet                  # required, unique
         fabric: net                  # required, a key of fabrics
         grid: [65, 65]               # required: nu, nv (integers >= 2)
         size: [1.0, 1.0]             # required: extent along u and v, m (> 0)
         origin: [0, 1, 0]            # default [0, 0, 0], m
         u_axis: [1, 0, 0]            # default [1, 0, 0]; nonzero, normalised
         v_axis: [0, 0, 1]            # default [0, 1, 0]; nonzero, normalised, orthogonal to u_axis
         mass: uniform                # area | uniform (default area)
         pins: [[0, 0], [-1, 0]]      # optional list of [i, j]; negative counts from the end (-1 = last)
         # instead of size: boundaries: {bottom, right, top, left: polyline [[u, v], ...] or arc {center, radius,
         # from, to, segments}, nodes: [b, r, t, l]} (pattern.h); pin_disc: {center, radius}, pin_box: {min, max};
         # cut_disc: {center, radius}: only the cells whose centre lies in the disc are fabric (a grid cut by a circle)
     run:                             # optional defaults for run-level options (command-line options override)
       integrator: implicit           # explicit | symplectic | implicit | bdf2
       dt: 0.004166666666666667       # s, > 0
       t_final: 1.0                   # s, > 0; or steps: 240 (integer >= 1), not both
       output_every: 24               # integer >= 1
       checkpoint_every: 0            # integer >= 0

   A new key is one entry in its block's table here and one line in its block's reader (scene_fabric.c,
   scene_piece.c, scene_blocks.c); a default that is not zero is one line in the block's *SetDefaults below. */
#include <string.h>
#include "scene_impl.h"

/* ------------------------------------------------------------------------------------------------------------ */
/* Keys and bounds                                                                                              */

const char *const ClothShearModels[]       = {"link", "angle", "cell", "ClothShearModel", "CLOTH_SHEAR_", NULL};
const char *const ClothBendModels[]        = {"link", "angle", "ClothBendModel", "CLOTH_BEND_", NULL};
const char *const ClothMassDistributions[] = {"area", "uniform", "ClothMassDistribution", "CLOTH_MASS_", NULL};
/* Written in the same PETSc enum-list style so that SceneKeyChoice treats every list of names alike; the integrator
   module owns the actual type. */
const char *const SceneIntegrators[] = {"explicit", "symplectic", "implicit", "bdf2", "SceneIntegrator", "SCENE_INTEGRATOR_", NULL};

/* Allowed keys per block (NULL-terminated). */
const char *const SceneTopKeys[]           = {"name", "gravity", "fabrics", "pieces", "run", "bodies", "self_collision", "seams", "sewing", NULL};
const char *const SceneFabricKeys[]        = {"density",
                                              "stretch",
                                              "stretch_warp",
                                              "stretch_weft",
                                              "shear",
                                              "shear_model",
                                              "bend",
                                              "bend_warp",
                                              "bend_weft",
                                              "bend_model",
                                              "bend_bias",
                                              "bend_bias_ratio",
                                              "bend_hysteresis",
                                              "bend_hysteresis_warp",
                                              "bend_hysteresis_weft",
                                              "bend_hysteresis_ratio",
                                              "shear_hysteresis",
                                              "shear_hysteresis_ratio",
                                              "damping",
                                              "repulsion",
                                              "repulsion_stiffness",
                                              "preset",
                                              "kes",
                                              "stretch_knee",
                                              "stretch_knee_warp",
                                              "stretch_knee_weft",
                                              "stretch_stiff",
                                              "stretch_stiff_warp",
                                              "stretch_stiff_weft",
                                              NULL};
const char *const ScenePieceKeys[]         = {"name", "fabric", "grid", "size", "boundaries", "origin", "u_axis", "v_axis", "mass", "pins", "pin_disc", "pin_box", "cut_disc", "wrap", NULL};
const char *const SceneWrapKeys[]          = {"axis_point", "apex", "axis", NULL};
const char *const SceneBoundaryKeys[]      = {"bottom", "right", "top", "left", "nodes", NULL}; /* bottom, right, top, left: the order of ScenePiece.boundary_* */
const char *const SceneKESKeys[]           = {"W", "B_warp", "B_weft", "G", "EMT_warp", "EMT_weft", "LT_warp", "LT_weft", "2HB_warp", "2HB_weft", "2HG", NULL};
const char *const SceneArcKeys[]           = {"center", "radius", "from", "to", "segments", NULL};
const char *const ScenePinDiscKeys[]       = {"center", "radius", NULL};
const char *const ScenePinBoxKeys[]        = {"min", "max", NULL};
const char *const SceneRunKeys[]           = {"integrator", "dt", "t_final", "steps", "output_every", "checkpoint_every", NULL};
const char *const SceneBodyKeys[]          = {"name", "type", "center", "radius", "point", "normal", "file", "scale", "rotation", "translation", "friction", "thickness", NULL};
const char *const SceneFrictionKeys[]      = {"static", "kinetic", NULL};
const char *const SceneSeamKeys[]          = {"name", "a", "b", "bend", NULL};
const char *const SceneSeamSideKeys[]      = {"piece", "side", "from", "to", NULL};
const char *const SceneSewingKeys[]        = {"pull_acceleration", "pull_radius", "sewn_stiffness", "tolerance", "max_time", "pull_friction", NULL};
const char *const ClothPieceSides[]        = {"bottom", "right", "top", "left", "ClothPieceSide", "CLOTH_SIDE_", NULL};
const char *const SceneSelfCollisionKeys[] = {"enabled", "thickness", "stiffness", "exclude_ring", "same_piece", NULL};
/* The keys that only one type of body uses, per SceneBodyType (NULL-terminated). */
const char *const SceneBodyTypeKeys[][5] = {{"center", "radius", NULL}, {"point", "normal", NULL}, {"file", "scale", "rotation", "translation", NULL}};
const char *const SceneBodyTypes[]       = {"sphere", "plane", "mesh", "SceneBodyType", "SCENE_BODY_", NULL};

/* Densest sheet: 1 cm of steel, 78 kg/m^2 (fabrics: below 2); lightest: 1 g/m^2 (fabrics: 10 g/m^2, tulle, and more).
   Stiffest sheet: 5 mm of steel, E t = 1e9 N/m (fabrics: below 1e5 N/m). Friction coefficients of fabrics: below 2. */
/* clang-format off */
const SceneRealBound SceneRealBounds[] = {
  {"",        "density",              100,                     "a sheet denser than 1 cm of steel, 78 kg/m^2",          1e-3,  "a sheet lighter than 1 g/m^2 (fabrics: 10 g/m^2 and more), an implicit system without mass"},
  {"",        "W",                    1e4,                     "100 kg/m^2, a sheet denser than 1 cm of steel",         0.1,   "1 g/m^2, a sheet lighter than any fabric, an implicit system without mass"},
  {"",        "EMT",                  PETSC_MAX_REAL,          NULL,                                                    1e-4,  "a strain of 1e-6 under the KES load of 500 gf/cm, a stretch modulus beyond 1e8 N/m"},
  {"",        "stretch",              1e9,                     "stiffer than a 5 mm steel plate, E t = 1e9 N/m",        0,     NULL},
  {"",        "stretch_stiff",        1e9,                     "stiffer than a 5 mm steel plate, E t = 1e9 N/m",        0,     NULL},
  {"",        "shear",                1e9,                     "stiffer than a 5 mm steel plate, E t = 1e9 N/m",        0,     NULL},
  {"",        "bend",                 1e9,                     "as a link stiffness, stiffer than a 5 mm steel plate",  0,     NULL},
  {"",        "damping",              1e6,                     "a relaxation time below 1 microsecond",                 0,     NULL},
  {"",        "repulsion_stiffness",  1e6,                     "a million times the stretch stiffness",                 0,     NULL},
  {"",        "static",               10,                      "friction coefficients of fabrics are below 2",          0,     NULL},
  {"",        "kinetic",              10,                      "friction coefficients of fabrics are below 2",          0,     NULL},
  {"",        "size",                 SCENE_MAX_PIECE_EXTENT,  "a piece a kilometre across: a unit mistake",            0,     NULL},
  {"",        "radius",               1e3,                     "a kilometre: a unit mistake",                           0,     NULL},
  {"body",    "thickness",            1,                       "a contact shell a metre thick",                         0,     NULL},
  {"",        "dt",                   SCENE_MAX_DT,            "a cloth time step of more than 10 s",                   0,     NULL},
  {"",        "t_final",              SCENE_MAX_T_FINAL,       "more than 11 days of simulated time",                   0,     NULL},
  {"",        "gravity",              1e3,                     "100 g",                                                 0,     NULL},
  {"",        "center",               1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "point",                1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "origin",               1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "translation",          1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "axis_point",           1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "apex",                 1e6,                     "1000 km, the bound of mesh coordinates",                0,     NULL},
  {"",        "scale",                1e3,                     "a mesh scaled beyond metres from millimetres",          0,     NULL},
  {"self",    "stiffness",            1e9,                     "stiffer than a 5 mm steel plate, E t = 1e9 N/m",        0,     NULL},
  {"sewing",  "pull_acceleration",    1e4,                     "a pull of 1000 g",                                      0,     NULL},
  {"sewing",  "pull_radius",          10,                      "a pull reaching 10 m",                                  0,     NULL},
  {"sewing",  "sewn_stiffness",       1e9,                     "stiffer than a 5 mm steel plate, E t = 1e9 N/m",        0,     NULL},
  {"sewing",  "tolerance",            1,                       "pairs a metre apart counted as sewn",                   0,     NULL},
  {"sewing",  "max_time",             1e6,                     "more than 11 days of simulated time",                   0,     NULL},
  {"sewing",  "pull_friction",        10,                      "friction coefficients of fabrics are below 2",          0,     NULL},
  {NULL,      NULL,                   0,                       NULL,                                                    0,     NULL}
};
/* clang-format on */

/* ------------------------------------------------------------------------------------------------------------ */
/* Defaults                                                                                                     */

/* The scene's defaults that are not zero, and its name from the path: "input/hanging_sheet.yaml" -> "hanging_sheet";
   the sewing block's, which hold when it is absent. */
PetscErrorCode SceneSetDefaults(Scene scene, const char path[])
{
  const char *base = strrchr(path, '/');
  char       *dot;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(scene->path, path, sizeof(scene->path)));
  PetscCall(PetscStrncpy(scene->name, base ? base + 1 : path, sizeof(scene->name)));
  dot = strrchr(scene->name, '.');
  if (dot && dot != scene->name) *dot = 0;
  scene->gravity[1]               = -9.81;
  scene->sewing.pull_acceleration = 9.81;
  scene->sewing.pull_radius       = 0.01;
  scene->sewing.sewn_stiffness    = 2000;
  scene->sewing.tolerance         = 0.002;
  scene->sewing.max_time          = 2.0;
  scene->sewing.pull_friction     = 1.0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A preset or a kes: block may set other defaults over these (scene_fabric.c). */
PetscErrorCode SceneFabricSetDefaults(SceneFabric *fabric)
{
  PetscFunctionBeginUser;
  fabric->repulsion_stiffness = 10;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ScenePieceSetDefaults(ScenePiece *piece)
{
  PetscFunctionBeginUser;
  piece->u_axis[0] = 1;
  piece->v_axis[1] = 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneBodySetDefaults(SceneBody *body, PetscInt index)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(body->name, sizeof(body->name), "body%" PetscInt_FMT, index + 1));
  body->scale     = 1;
  body->normal[1] = 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* When the block is given (off without it). */
PetscErrorCode SceneSelfCollisionSetDefaults(SceneSelfCollision *self)
{
  PetscFunctionBeginUser;
  self->given        = PETSC_TRUE;
  self->enabled      = PETSC_FALSE;
  self->exclude_ring = 0;
  self->same_piece   = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each side the whole of its side of the piece; bending across the seam. */
PetscErrorCode SceneSeamSetDefaults(SceneSeam *seam, PetscInt index)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(seam->name, sizeof(seam->name), "seam%" PetscInt_FMT, index));
  seam->a.from = seam->b.from = 0;
  seam->a.to = seam->b.to = 1;
  seam->bend              = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}
