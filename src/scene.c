/* Scene reader: a YAML scene file -> struct _n_Scene (see scene.h), with validation.

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

   How it reads: rank 0 reads the bytes, broadcasts them, and every rank parses the same bytes with libyaml's
   document API, so every rank fails or succeeds alike. Each block has a table of its allowed keys
   (SceneTopKeys, SceneFabricKeys, ScenePieceKeys, SceneRunKeys) checked before any value is read, and a reader
   that reads one key per line with a helper per kind of value (SceneKeyReal, SceneKeyRealList, SceneKeyInt, SceneKeyIntList,
   SceneKeyString, SceneKeyChoice, SceneKeyDirection). A new key is one entry in the table and one line in the reader; a new
   block (bodies:, seams:) is one table and one reader function.

   Every error names the file, the line (libyaml's mark, 1-based), the key and the block, what was expected and
   what was found:  scene FILE, line L: key 'KEY' in fabric 'NAME': expected a positive number (kg/m^2), got '-1' */
#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <petscviewer.h>
#include <yaml.h>
#include "scene.h"
#include "scene_reader.h"
#include "fabric_presets.h"
#include "fabric.h"
#include "pattern.h"

const char *const ClothShearModels[]       = {"link", "angle", "cell", "ClothShearModel", "CLOTH_SHEAR_", NULL};
const char *const ClothBendModels[]        = {"link", "angle", "ClothBendModel", "CLOTH_BEND_", NULL};
const char *const ClothMassDistributions[] = {"area", "uniform", "ClothMassDistribution", "CLOTH_MASS_", NULL};
/* Written in the same PETSc enum-list style so that SceneKeyChoice treats every list of names alike; the integrator
   module owns the actual type. */
static const char *const SceneIntegrators[] = {"explicit", "symplectic", "implicit", "bdf2", "SceneIntegrator", "SCENE_INTEGRATOR_", NULL};

/* Allowed keys per block (NULL-terminated). */
static const char *const SceneTopKeys[]           = {"name", "gravity", "fabrics", "pieces", "run", "bodies", "self_collision", "seams", "sewing", NULL};
static const char *const SceneFabricKeys[]        = {"density",
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
static const char *const ScenePieceKeys[]         = {"name", "fabric", "grid", "size", "boundaries", "origin", "u_axis", "v_axis", "mass", "pins", "pin_disc", "pin_box", "cut_disc", "wrap", NULL};
static const char *const SceneWrapKeys[]          = {"axis_point", "apex", "axis", NULL};
static const char *const SceneBoundaryKeys[]      = {"bottom", "right", "top", "left", "nodes", NULL}; /* bottom, right, top, left: the order of ScenePiece.boundary_* */
static const char *const SceneKESKeys[]           = {"W", "B_warp", "B_weft", "G", "EMT_warp", "EMT_weft", "LT_warp", "LT_weft", "2HB_warp", "2HB_weft", "2HG", NULL};
static const char *const SceneArcKeys[]           = {"center", "radius", "from", "to", "segments", NULL};
static const char *const ScenePinDiscKeys[]       = {"center", "radius", NULL};
static const char *const ScenePinBoxKeys[]        = {"min", "max", NULL};
static const char *const SceneRunKeys[]           = {"integrator", "dt", "t_final", "steps", "output_every", "checkpoint_every", NULL};
static const char *const SceneBodyKeys[]          = {"name", "type", "center", "radius", "point", "normal", "file", "scale", "rotation", "translation", "friction", "thickness", NULL};
static const char *const SceneFrictionKeys[]      = {"static", "kinetic", NULL};
static const char *const SceneSeamKeys[]          = {"name", "a", "b", "bend", NULL};
static const char *const SceneSeamSideKeys[]      = {"piece", "side", "from", "to", NULL};
static const char *const SceneSewingKeys[]        = {"pull_acceleration", "pull_radius", "sewn_stiffness", "tolerance", "max_time", "pull_friction", NULL};
const char *const        ClothPieceSides[]        = {"bottom", "right", "top", "left", "ClothPieceSide", "CLOTH_SIDE_", NULL};
static const char *const SceneSelfCollisionKeys[] = {"enabled", "thickness", "stiffness", "exclude_ring", "same_piece", NULL};
/* The keys that only one type of body uses, per SceneBodyType (NULL-terminated). */
static const char *const SceneBodyTypeKeys[][5] = {{"center", "radius", NULL}, {"point", "normal", NULL}, {"file", "scale", "rotation", "translation", NULL}};
const char *const        SceneBodyTypes[]       = {"sphere", "plane", "mesh", "SceneBodyType", "SCENE_BODY_", NULL};

#define SCENE_ORTHOGONALITY_TOL 1e-6  /* |u.v| of unit axes that count as orthogonal (and parallel: 1 - it) */
#define SCENE_CORNER_JOIN_RTOL 1e-6   /* boundary ends this fraction of the outline's size apart still meet: coordinates typed with 7 digits join */
#define SCENE_PLANE_DISTANCE_TOL 1e-6 /* m: a point this close to a piece's plane lies in it (a cone's apex; not a cylinder's axis point) */
/* The most particles a scene may have: the state vectors hold 3 coordinates per particle, indexed by PetscInt
   (32 bits in Debian's PETSc). Sizes are multiplied in 64 bits, so that a grid beyond it is named, not wrapped. */
#define SCENE_MAX_PARTICLES ((PetscInt64)PETSC_MAX_INT / 3)
/* The largest extent of a piece, m (size, and the coordinates of an outline): a kilometre is a unit mistake. */
#define SCENE_MAX_PIECE_EXTENT 1e3
/* The most segments of an arc boundary: its points are allocated before anything else (segments: 2147483647 ended in
   the allocator); 100,000 segments put a vertex every 0.06 mm of a 1 m circle, far finer than any grid. */
#define SCENE_MAX_ARC_SEGMENTS 100000
#define SCENE_FNV_OFFSET UINT64_C(0xcbf29ce484222325)
#define SCENE_FNV_PRIME UINT64_C(0x100000001b3)

/* Densest sheet: 1 cm of steel, 78 kg/m^2 (fabrics: below 2); lightest: 1 g/m^2 (fabrics: 10 g/m^2, tulle, and more).
   Stiffest sheet: 5 mm of steel, E t = 1e9 N/m (fabrics: below 1e5 N/m). Friction coefficients of fabrics: below 2. */
/* clang-format off */
static const SceneRealBound SceneRealBounds[] = {
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

/* The particles of all pieces, counted in 64 bits. */
static PetscInt64 SceneCountParticles(Scene scene)
{
  PetscInt64 n = 0;

  for (PetscInt p = 0; p < scene->npieces; p++) n += (PetscInt64)scene->pieces[p].nu * scene->pieces[p].nv;
  return n;
}

/* Errors when the pieces have more than SCENE_MAX_PARTICLES particles in all; cause says what set the grids
   ("" for the file, "-grid N"). */
static PetscErrorCode SceneCheckParticleCount(Scene scene, const char cause[])
{
  const PetscInt64 n = SceneCountParticles(scene);

  PetscFunctionBeginUser;
  PetscCheck(n <= SCENE_MAX_PARTICLES, scene->comm, PETSC_ERR_USER_INPUT, "scene %s%s%s: the pieces have %" PetscInt64_FMT " particles in all: expected at most %" PetscInt64_FMT " (3 coordinates each, indexed by a %d-bit PetscInt)", scene->path,
             cause[0] ? ", " : "", cause, n, SCENE_MAX_PARTICLES, (int)(8 * sizeof(PetscInt)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The largest distance between neighbouring particles of a piece in its flat layout, m (from its size, or the
   bounding box of its outline). */
static PetscReal ScenePieceLargestSpacing(const ScenePiece *piece)
{
  PetscReal extent[2] = {piece->size[0], piece->size[1]};

  if (piece->has_boundaries) {
    PetscReal lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL};

    for (PetscInt b = 0; b < 4; b++)
      for (PetscInt k = 0; k < piece->boundary_npoints[b]; k++)
        for (PetscInt c = 0; c < 2; c++) {
          lo[c] = PetscMin(lo[c], piece->boundary_points[b][2 * k + c]);
          hi[c] = PetscMax(hi[c], piece->boundary_points[b][2 * k + c]);
        }
    extent[0] = hi[0] - lo[0];
    extent[1] = hi[1] - lo[1];
  }
  return PetscMax(extent[0] / (PetscReal)(piece->nu - 1), extent[1] / (PetscReal)(piece->nv - 1));
}

PetscErrorCode SceneGetLargestSpacing(Scene scene, PetscReal *spacing)
{
  PetscFunctionBeginUser;
  *spacing = 0;
  for (PetscInt p = 0; p < scene->npieces; p++) *spacing = PetscMax(*spacing, ScenePieceLargestSpacing(&scene->pieces[p]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Blocks                                                                                                       */

/* A stiffness given as key or as key_warp / key_weft (each defaulting to key); required: in one of these forms. */
static PetscErrorCode ReadWarpWeft(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, SceneRealRange range, const char unit[], PetscReal *warp, PetscReal *weft)
{
  char      key_warp[CLOTH_NAME_LEN], key_weft[CLOTH_NAME_LEN], expected[SCENE_TEXT_LEN];
  PetscBool has = PETSC_FALSE, has_warp = PETSC_FALSE, has_weft = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(key_warp, sizeof(key_warp), "%s_warp", key));
  PetscCall(PetscSNPrintf(key_weft, sizeof(key_weft), "%s_weft", key));
  PetscCall(SceneHasKey(r, map, key, &has));
  PetscCall(SceneHasKey(r, map, key_warp, &has_warp));
  PetscCall(SceneHasKey(r, map, key_weft, &has_weft));
  if (required && !has && !(has_warp && has_weft)) {
    PetscCall(SceneExpectReal(0, range, unit, expected, sizeof(expected)));
    PetscCall(SceneFailMissing(r, map, key, "%s, or both %s and %s", expected, key_warp, key_weft));
  }
  PetscCall(SceneKeyReal(r, map, key, PETSC_FALSE, range, unit, warp));
  if (has) *weft = *warp; /* otherwise both keep their defaults (a preset's may differ) */
  PetscCall(SceneKeyReal(r, map, key_warp, PETSC_FALSE, range, unit, warp));
  PetscCall(SceneKeyReal(r, map, key_weft, PETSC_FALSE, range, unit, weft));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* preset: the name of a measured fabric (fabric_presets.h); its values become the defaults of the other keys. */
static PetscErrorCode ReadFabricPreset(SceneReader *r, yaml_node_t *map, SceneFabric *fabric)
{
  char         names[SCENE_TEXT_LEN];
  yaml_node_t *node  = NULL;
  PetscBool    found = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(SceneKeyString(r, map, "preset", PETSC_FALSE, fabric->preset, sizeof(fabric->preset), &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(FabricPresetApply(fabric->preset, fabric, &found));
  if (!found) {
    PetscCall(FabricPresetListNames(names, sizeof(names)));
    PetscCall(SceneFailValue(r, node, "preset", "the name of a measured fabric, one of %s", names));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* kes: {W, B_warp, B_weft, G, EMT_warp, EMT_weft, LT_warp, LT_weft} in KES-F units (fabric.h); the values it
   maps to become the defaults of the other keys, like a preset's. */
static PetscErrorCode ReadFabricKES(SceneReader *r, yaml_node_t *map, SceneFabric *fabric)
{
  FabricKES    kes = {0};
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, "kes", &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  if (fabric->preset[0]) PetscCall(SceneFailValue(r, node, "kes", "no kes block together with a preset (give one of them)"));
  PetscCall(SceneExpectMap(r, node, "kes", SceneKESKeys, NULL));
  PetscCall(SceneKeyReal(r, node, "W", PETSC_TRUE, SCENE_REAL_POSITIVE, "mg/cm^2", &kes.weight));
  PetscCall(SceneKeyReal(r, node, "B_warp", PETSC_TRUE, SCENE_REAL_NONNEGATIVE, "gf cm^2/cm", &kes.bend_warp));
  PetscCall(SceneKeyReal(r, node, "B_weft", PETSC_TRUE, SCENE_REAL_NONNEGATIVE, "gf cm^2/cm", &kes.bend_weft));
  PetscCall(SceneKeyReal(r, node, "G", PETSC_TRUE, SCENE_REAL_NONNEGATIVE, "gf/cm/degree", &kes.shear));
  PetscCall(SceneKeyReal(r, node, "EMT_warp", PETSC_TRUE, SCENE_REAL_POSITIVE, "%", &kes.emt_warp));
  PetscCall(SceneKeyReal(r, node, "EMT_weft", PETSC_TRUE, SCENE_REAL_POSITIVE, "%", &kes.emt_weft));
  PetscCall(SceneKeyReal(r, node, "LT_warp", PETSC_FALSE, SCENE_REAL_POSITIVE, NULL, &kes.lt_warp));
  PetscCall(SceneKeyReal(r, node, "LT_weft", PETSC_FALSE, SCENE_REAL_POSITIVE, NULL, &kes.lt_weft));
  PetscCall(SceneKeyReal(r, node, "2HB_warp", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "gf cm/cm", &kes.hysteresis_warp));
  PetscCall(SceneKeyReal(r, node, "2HB_weft", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "gf cm/cm", &kes.hysteresis_weft));
  PetscCall(SceneKeyReal(r, node, "2HG", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "gf/cm", &kes.shear_hysteresis));
  if ((kes.lt_warp > 0) != (kes.lt_weft > 0) || (kes.lt_warp > 0 && (kes.lt_warp <= 0.5 || kes.lt_warp >= 1.5 || kes.lt_weft <= 0.5 || kes.lt_weft >= 1.5)))
    PetscCall(SceneFailValue(r, node, "kes", "LT_warp and LT_weft both given or both absent, each in (0.5, 1.5) (a biphasic curve with its knee at EMT/2)"));
  PetscCall(FabricSetFromKES(&kes, fabric));
  PetscCall(PetscStrncpy(fabric->preset, "kes", sizeof(fabric->preset)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Biphasic tensile curve: stretch_knee[_warp|_weft] (strain) and stretch_stiff[_warp|_weft] (modulus beyond it, default: stretch). */
static PetscErrorCode ReadStretchCurve(SceneReader *r, yaml_node_t *map, SceneFabric *fabric)
{
  PetscFunctionBeginUser;
  if (fabric->stretch_knee_warp == 0 && fabric->stretch_knee_weft == 0) { /* no biphasic default: the stiff branch defaults to the (possibly overridden) modulus */
    fabric->stretch_stiff_warp = fabric->stretch_warp;
    fabric->stretch_stiff_weft = fabric->stretch_weft;
  }
  PetscCall(ReadWarpWeft(r, map, "stretch_knee", PETSC_FALSE, SCENE_REAL_FRACTION, "strain", &fabric->stretch_knee_warp, &fabric->stretch_knee_weft));
  PetscCall(ReadWarpWeft(r, map, "stretch_stiff", PETSC_FALSE, SCENE_REAL_POSITIVE, "N/m", &fabric->stretch_stiff_warp, &fabric->stretch_stiff_weft));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Bending hysteresis: HB per direction (bend_hysteresis[_warp|_weft]), or the KES ratio 2HB/B (bend_hysteresis_ratio,
   1/m), which sets HB = ratio B / 2 from the fabric's own rigidities; not both. */
static PetscErrorCode ReadBendHysteresis(SceneReader *r, yaml_node_t *map, SceneFabric *fabric)
{
  PetscBool has_ratio = PETSC_FALSE, has_hb = PETSC_FALSE, has_warp = PETSC_FALSE, has_weft = PETSC_FALSE;
  PetscReal ratio = 0;

  PetscFunctionBeginUser;
  PetscCall(ReadWarpWeft(r, map, "bend_hysteresis", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "friction moment per unit width HB, N m/m", &fabric->bend_hysteresis_warp, &fabric->bend_hysteresis_weft));
  PetscCall(SceneHasKey(r, map, "bend_hysteresis_ratio", &has_ratio));
  if (!has_ratio) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneHasKey(r, map, "bend_hysteresis", &has_hb));
  PetscCall(SceneHasKey(r, map, "bend_hysteresis_warp", &has_warp));
  PetscCall(SceneHasKey(r, map, "bend_hysteresis_weft", &has_weft));
  if (has_hb || has_warp || has_weft) {
    yaml_node_t *node;

    PetscCall(SceneGetValue(r, map, "bend_hysteresis_ratio", &node));
    PetscCall(SceneFailValue(r, node, "bend_hysteresis_ratio", "no bend_hysteresis_ratio beside bend_hysteresis[_warp|_weft] (give one of them)"));
  }
  PetscCall(SceneKeyReal(r, map, "bend_hysteresis_ratio", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "2HB/B, 1/m", &ratio));
  fabric->bend_hysteresis_warp = 0.5 * ratio * fabric->bend_warp;
  fabric->bend_hysteresis_weft = 0.5 * ratio * fabric->bend_weft;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Shear hysteresis: HG (shear_hysteresis, N/m), or the KES ratio 2HG/G (shear_hysteresis_ratio, rad: the KES
   ratio in degrees times pi/180), which sets HG = ratio G / 2 from the fabric's own shear modulus; not both.
   Needs the cell shear model, whose spring measures the shear angle the friction acts on. */
static PetscErrorCode ReadShearHysteresis(SceneReader *r, yaml_node_t *map, PetscInt shear_model, SceneFabric *fabric)
{
  PetscBool has_ratio = PETSC_FALSE, has_hg = PETSC_FALSE;
  PetscReal ratio = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneKeyReal(r, map, "shear_hysteresis", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "friction shear force per unit width HG, N/m", &fabric->shear_hysteresis));
  PetscCall(SceneHasKey(r, map, "shear_hysteresis_ratio", &has_ratio));
  if (has_ratio) {
    yaml_node_t *node;

    PetscCall(SceneHasKey(r, map, "shear_hysteresis", &has_hg));
    PetscCall(SceneGetValue(r, map, "shear_hysteresis_ratio", &node));
    if (has_hg) PetscCall(SceneFailValue(r, node, "shear_hysteresis_ratio", "no shear_hysteresis_ratio beside shear_hysteresis (give one of them)"));
    PetscCall(SceneKeyReal(r, map, "shear_hysteresis_ratio", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "2HG/G, rad", &ratio));
    fabric->shear_hysteresis = 0.5 * ratio * fabric->shear;
  }
  if (fabric->shear_hysteresis > 0 && shear_model != CLOTH_SHEAR_CELL) PetscCall(SceneFailValue(r, map, "shear_hysteresis", "shear hysteresis needs shear_model: cell"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* bend_bias: the measured bending rigidity along the bias, or bend_bias_ratio: it as a multiple of the mean of
   bend_warp and bend_weft (not both); without either, a preset's measured one. The thread-angle springs already give
   (bend_warp + bend_weft) / 4 there and the twist elements can only add to it. */
static PetscErrorCode ReadBendBias(SceneReader *r, yaml_node_t *map, PetscInt bend_model, SceneFabric *fabric)
{
  const PetscReal threads  = 0.25 * (fabric->bend_warp + fabric->bend_weft);
  const char     *key      = "bend_bias";
  PetscBool       has_bias = PETSC_FALSE, has_ratio = PETSC_FALSE;
  yaml_node_t    *value;

  PetscFunctionBeginUser;
  PetscCall(SceneHasKey(r, map, "bend_bias", &has_bias));
  PetscCall(SceneHasKey(r, map, "bend_bias_ratio", &has_ratio));
  if (has_ratio) {
    PetscReal ratio = 0;

    key = "bend_bias_ratio";
    PetscCall(SceneGetValue(r, map, key, &value));
    if (has_bias) PetscCall(SceneFailValue(r, value, key, "no bend_bias_ratio beside bend_bias (give one of them)"));
    PetscCall(SceneKeyReal(r, map, key, PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "bias rigidity / mean of warp and weft", &ratio));
    fabric->bend_bias = 0.5 * ratio * (fabric->bend_warp + fabric->bend_weft);
  } else
    PetscCall(SceneKeyReal(r, map, key, PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "bending rigidity along the bias, N m", &fabric->bend_bias));
  if (fabric->bend_bias <= 0) PetscFunctionReturn(PETSC_SUCCESS);
  if (!has_bias && !has_ratio) { /* the preset's: it belongs to the preset's angle model and rigidities */
    if (bend_model != CLOTH_BEND_ANGLE)
      fabric->bend_bias = 0;
    else if (fabric->bend_bias < threads * (1 - 1e-12)) { /* the scene's own bend, bend_warp or bend_weft raised the threads' share */
      const char *bend_keys[] = {"bend", "bend_warp", "bend_weft"};

      value = NULL;
      for (PetscInt k = 0; k < 3 && !value; k++) {
        key = bend_keys[k];
        PetscCall(SceneGetValue(r, map, key, &value));
      }
      PetscCall(SceneFailValue(r, value ? value : map, key, "bending rigidities whose thread springs give at most the preset's bias rigidity, %g N m, along the bias ((bend_warp + bend_weft) / 4 = %g N m here), or bend_bias beside them (0: none)",
                               (double)fabric->bend_bias, (double)threads));
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(SceneGetValue(r, map, key, &value));
  if (bend_model != CLOTH_BEND_ANGLE) PetscCall(SceneFailValue(r, value, key, "no %s with bend_model: link (the twist elements complete the angle model)", key));
  if (fabric->bend_bias < threads * (1 - 1e-12)) {
    if (has_ratio) PetscCall(SceneFailValue(r, value, key, "0 (none) or at least 0.5: the thread springs alone give half the mean rigidity along the bias"));
    PetscCall(SceneFailValue(r, value, key, "0 (none) or at least %g N m, what the thread springs alone give along the bias ((bend_warp + bend_weft) / 4)", (double)threads));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadFabric(SceneReader *r, yaml_node_t *name, yaml_node_t *map, SceneFabric *fabric)
{
  PetscInt shear_model = CLOTH_SHEAR_LINK, bend_model = CLOTH_BEND_LINK;

  PetscFunctionBeginUser;
  PetscCheck(name->data.scalar.length > 0 && name->data.scalar.length < CLOTH_NAME_LEN, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: fabric name '%s': expected a name of 1 to %d characters", r->path, SceneNodeLine(name),
             (const char *)name->data.scalar.value, CLOTH_NAME_LEN - 1);
  PetscCall(PetscStrncpy(fabric->name, (const char *)name->data.scalar.value, sizeof(fabric->name)));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "fabric '%s'", fabric->name));
  PetscCall(SceneExpectMap(r, map, NULL, SceneFabricKeys, NULL));
  fabric->repulsion_stiffness = 10;
  PetscCall(ReadFabricPreset(r, map, fabric));
  PetscCall(ReadFabricKES(r, map, fabric));
  shear_model = fabric->shear_model; /* a preset's or the KES block's models are the defaults */
  bend_model  = fabric->bend_model;
  PetscCall(SceneKeyReal(r, map, "density", fabric->preset[0] ? PETSC_FALSE : PETSC_TRUE, SCENE_REAL_POSITIVE, "kg/m^2", &fabric->density));
  PetscCall(ReadWarpWeft(r, map, "stretch", fabric->preset[0] ? PETSC_FALSE : PETSC_TRUE, SCENE_REAL_POSITIVE, "N/m", &fabric->stretch_warp, &fabric->stretch_weft));
  PetscCall(ReadStretchCurve(r, map, fabric));
  PetscCall(SceneKeyReal(r, map, "shear", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "N/m", &fabric->shear));
  PetscCall(SceneKeyChoice(r, map, "shear_model", PETSC_FALSE, ClothShearModels, &shear_model));
  PetscCall(ReadShearHysteresis(r, map, shear_model, fabric));
  PetscCall(SceneKeyChoice(r, map, "bend_model", PETSC_FALSE, ClothBendModels, &bend_model));
  PetscCall(ReadWarpWeft(r, map, "bend", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, bend_model == CLOTH_BEND_LINK ? "N/m per skip-one link" : "bending rigidity, N m", &fabric->bend_warp, &fabric->bend_weft));
  PetscCall(ReadBendBias(r, map, bend_model, fabric));
  PetscCall(ReadBendHysteresis(r, map, fabric));
  if ((fabric->bend_hysteresis_warp > 0 || fabric->bend_hysteresis_weft > 0) && bend_model != CLOTH_BEND_ANGLE) PetscCall(SceneFailValue(r, map, "bend_hysteresis", "bending hysteresis needs bend_model: angle"));
  PetscCall(SceneKeyReal(r, map, "damping", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "1/s", &fabric->damping));
  PetscCall(SceneKeyReal(r, map, "repulsion", PETSC_FALSE, SCENE_REAL_FRACTION, "fraction of the rest length", &fabric->repulsion));
  PetscCall(SceneKeyReal(r, map, "repulsion_stiffness", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "relative to the stretch stiffness", &fabric->repulsion_stiffness));
  fabric->shear_model = (ClothShearModel)shear_model;
  fabric->bend_model  = (ClothBendModel)bend_model;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadFabrics(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const char   expected[] = "a map of fabric name -> fabric properties, with at least one fabric";
  yaml_node_t *map;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, root, "fabrics", PETSC_TRUE, expected, &map));
  PetscCall(SceneExpectMap(r, map, "fabrics", NULL, expected));
  scene->nfabrics = (PetscInt)(map->data.mapping.pairs.top - map->data.mapping.pairs.start);
  if (scene->nfabrics == 0) PetscCall(SceneFailValue(r, map, "fabrics", "%s", expected));
  PetscCall(PetscCalloc1(scene->nfabrics, &scene->fabrics));
  for (PetscInt f = 0; f < scene->nfabrics; f++) {
    yaml_node_pair_t *pair = &map->data.mapping.pairs.start[f];

    PetscCall(SceneReadFabric(r, yaml_document_get_node(r->doc, pair->key), yaml_document_get_node(r->doc, pair->value), &scene->fabrics[f]));
  }
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Resolves pins_given (negative: from the end) into pins for the piece's current grid. */
static PetscErrorCode ScenePieceResolvePins(MPI_Comm comm, const char path[], ScenePiece *piece)
{
  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < piece->npins; p++) {
    PetscInt i = piece->pins_given[2 * p], j = piece->pins_given[2 * p + 1];

    piece->pins[2 * p]     = i < 0 ? piece->nu + i : i;
    piece->pins[2 * p + 1] = j < 0 ? piece->nv + j : j;
    PetscCheck(piece->pins[2 * p] >= 0 && piece->pins[2 * p] < piece->nu && piece->pins[2 * p + 1] >= 0 && piece->pins[2 * p + 1] < piece->nv, comm, PETSC_ERR_USER_INPUT,
               "scene %s: pin [%" PetscInt_FMT ", %" PetscInt_FMT "] of piece '%s' lies outside its %" PetscInt_FMT " x %" PetscInt_FMT " grid: expected -%" PetscInt_FMT " <= i < %" PetscInt_FMT " and -%" PetscInt_FMT " <= j < %" PetscInt_FMT, path,
               i, j, piece->name, piece->nu, piece->nv, piece->nu, piece->nu, piece->nv, piece->nv);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* pins: [[i, j], ...] within the grid (read after it). */
static PetscErrorCode ReadPins(SceneReader *r, yaml_node_t *map, ScenePiece *piece)
{
  char              expected[SCENE_TEXT_LEN];
  yaml_node_t      *node;
  yaml_node_item_t *items = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(expected, sizeof(expected),
                          "a list of grid indices [i, j] with -%" PetscInt_FMT " <= i < %" PetscInt_FMT " and -%" PetscInt_FMT " <= j < %" PetscInt_FMT " (grid %" PetscInt_FMT " x %" PetscInt_FMT "; negative indices count from the end)", piece->nu,
                          piece->nu, piece->nv, piece->nv, piece->nu, piece->nv));
  PetscCall(SceneGetValue(r, map, "pins", &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetItems(r, node, "pins", -1, expected, &items, &piece->npins));
  PetscCall(PetscMalloc1(2 * piece->npins, &piece->pins));
  PetscCall(PetscMalloc1(2 * piece->npins, &piece->pins_given));
  for (PetscInt p = 0; p < piece->npins; p++) {
    yaml_node_t *pair = yaml_document_get_node(r->doc, items[p]);
    PetscInt    *ij   = &piece->pins_given[2 * p];

    PetscCall(SceneParseIntList(r, pair, "pins", 2, PETSC_MIN_INT, expected, ij));
    if (ij[0] < -piece->nu || ij[0] >= piece->nu || ij[1] < -piece->nv || ij[1] >= piece->nv) PetscCall(SceneFailValue(r, pair, "pins", "%s", expected));
  }
  PetscCall(ScenePieceResolvePins(r->comm, r->path, piece));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* fabric: the name of one of the scene's fabrics. */
static PetscErrorCode ReadFabricName(SceneReader *r, yaml_node_t *map, Scene scene, ScenePiece *piece)
{
  char         name[CLOTH_NAME_LEN], names[SCENE_TEXT_LEN] = "";
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneKeyString(r, map, "fabric", PETSC_TRUE, name, sizeof(name), &node));
  for (PetscInt f = 0; f < scene->nfabrics; f++) {
    PetscBool match;

    PetscCall(PetscStrcmp(name, scene->fabrics[f].name, &match));
    if (match) {
      piece->fabric = f;
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    if (f) PetscCall(PetscStrlcat(names, ", ", sizeof(names)));
    PetscCall(PetscStrlcat(names, scene->fabrics[f].name, sizeof(names)));
  }
  PetscCall(SceneFailValue(r, node, "fabric", "the name of a fabric given under 'fabrics' (one of %s)", names));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* u_axis and v_axis: unit vectors, orthogonal within SCENE_ORTHOGONALITY_TOL. */
static PetscErrorCode ReadAxes(SceneReader *r, yaml_node_t *map, ScenePiece *piece)
{
  yaml_node_t *node;
  PetscReal    dot;

  PetscFunctionBeginUser;
  PetscCall(SceneKeyDirection(r, map, "u_axis", piece->u_axis));
  PetscCall(SceneKeyDirection(r, map, "v_axis", piece->v_axis));
  dot = piece->u_axis[0] * piece->v_axis[0] + piece->u_axis[1] * piece->v_axis[1] + piece->u_axis[2] * piece->v_axis[2];
  if (PetscAbsReal(dot) > SCENE_ORTHOGONALITY_TOL) {
    PetscCall(SceneGetValue(r, map, "v_axis", &node));
    if (node)
      PetscCall(SceneFailValue(r, node, "v_axis", "a direction orthogonal to u_axis = (%g, %g, %g) (|u.v| <= %g after normalising; here u.v = %g)", (double)piece->u_axis[0], (double)piece->u_axis[1], (double)piece->u_axis[2], SCENE_ORTHOGONALITY_TOL,
                               (double)dot));
    PetscCall(SceneGetValue(r, map, "u_axis", &node));
    PetscCall(SceneFailValue(r, node, "u_axis", "a direction orthogonal to the default v_axis = (0, 1, 0) (|u.v| <= %g after normalising; here u.v = %g)", SCENE_ORTHOGONALITY_TOL, (double)dot));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A boundary's vertices (read or made from an arc) lie within SCENE_MAX_PIECE_EXTENT of the pattern's origin, as a
   piece's size does (an outline 1e27 m across ran), and span a positive length (else the grid is meshed from
   nothing, refused later without the file or the line). */
static PetscErrorCode CheckBoundaryPoints(SceneReader *r, yaml_node_t *node, const char key[], PetscInt npoints, const PetscReal points[])
{
  PetscReal length = 0;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < npoints; k++)
    if (PetscMax(PetscAbsReal(points[2 * k]), PetscAbsReal(points[2 * k + 1])) > SCENE_MAX_PIECE_EXTENT)
      PetscCall(SceneFailValue(r, node, key, "a boundary whose vertices have coordinates of magnitude at most %g m (beyond: a piece a kilometre across, a unit mistake); vertex %" PetscInt_FMT " is (%g, %g)", SCENE_MAX_PIECE_EXTENT, k,
                               (double)points[2 * k], (double)points[2 * k + 1]));
  for (PetscInt k = 1; k < npoints; k++) length += PetscSqrtReal(PetscSqr(points[2 * k] - points[2 * k - 2]) + PetscSqr(points[2 * k + 1] - points[2 * k - 1]));
  if (!(length > 0)) PetscCall(SceneFailValue(r, node, key, "a boundary of positive length; its %" PetscInt_FMT " vertices all lie at (%g, %g)", npoints, (double)points[0], (double)points[1]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One boundary: a polyline [[u, v], ...] of at least 2 vertices, or an arc {center, radius, from, to, segments}
   (angles in degrees, counter-clockwise from the u axis; the arc runs from `from` to `to`). */
static PetscErrorCode ReadBoundary(SceneReader *r, yaml_node_t *map, const char key[], PetscInt *npoints, PetscReal **points)
{
  const char        expected[] = "a polyline [[u, v], [u, v], ...] of at least 2 points (m), or an arc {center: [u, v], radius: r, from: degrees, to: degrees, segments: n}";
  yaml_node_t      *node;
  yaml_node_item_t *items = NULL;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, map, key, PETSC_TRUE, expected, &node));
  if (node->type == YAML_MAPPING_NODE) {
    PetscReal center[2], radius, from, to;
    PetscInt  segments = 32;

    PetscCall(SceneExpectMap(r, node, key, SceneArcKeys, expected));
    PetscCall(SceneKeyRealList(r, node, "center", PETSC_TRUE, 2, SCENE_REAL_ANY, "m", center));
    PetscCall(SceneKeyReal(r, node, "radius", PETSC_TRUE, SCENE_REAL_POSITIVE, "m", &radius));
    PetscCall(SceneKeyReal(r, node, "from", PETSC_TRUE, SCENE_REAL_ANY, "degrees", &from));
    PetscCall(SceneKeyReal(r, node, "to", PETSC_TRUE, SCENE_REAL_ANY, "degrees", &to));
    PetscCall(SceneKeyIntInRange(r, node, "segments", PETSC_FALSE, 1, SCENE_MAX_ARC_SEGMENTS, &segments));
    *npoints = segments + 1;
    PetscCall(PetscMalloc1(2 * *npoints, points));
    for (PetscInt k = 0; k <= segments; k++) {
      const PetscReal angle = (from + (to - from) * k / segments) * PETSC_PI / 180;

      (*points)[2 * k]     = center[0] + radius * PetscCosReal(angle);
      (*points)[2 * k + 1] = center[1] + radius * PetscSinReal(angle);
    }
  } else {
    PetscCall(SceneGetItems(r, node, key, -1, expected, &items, npoints));
    if (*npoints < 2) PetscCall(SceneFailValue(r, node, key, "%s", expected));
    PetscCall(PetscMalloc1(2 * *npoints, points));
    for (PetscInt k = 0; k < *npoints; k++) PetscCall(SceneParseRealList(r, yaml_document_get_node(r->doc, items[k]), key, 2, SCENE_REAL_ANY, expected, &(*points)[2 * k]));
  }
  PetscCall(CheckBoundaryPoints(r, node, key, *npoints, *points));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The four boundaries must join at the corners: bottom and left start at (0, 0), bottom ends where right starts,
   left ends where top starts, top and right end at the far corner. */
static PetscErrorCode CheckBoundaryCorners(SceneReader *r, yaml_node_t *node, const ScenePiece *piece)
{
  /* {boundary, end (0 first, 1 last)} pairs that must coincide */
  const PetscInt meet[4][4] = {{0, 0, 3, 0}, {0, 1, 1, 0}, {3, 1, 2, 0}, {2, 1, 1, 1}};
  PetscReal      extent     = 0;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < 4; b++)
    for (PetscInt k = 0; k < 2 * piece->boundary_npoints[b]; k++) extent = PetscMax(extent, PetscAbsReal(piece->boundary_points[b][k]));
  for (PetscInt c = 0; c < 4; c++) {
    const PetscReal *p = &piece->boundary_points[meet[c][0]][meet[c][1] ? 2 * (piece->boundary_npoints[meet[c][0]] - 1) : 0];
    const PetscReal *q = &piece->boundary_points[meet[c][2]][meet[c][3] ? 2 * (piece->boundary_npoints[meet[c][2]] - 1) : 0];

    if (PetscSqrtReal(PetscSqr(p[0] - q[0]) + PetscSqr(p[1] - q[1])) > SCENE_CORNER_JOIN_RTOL * extent)
      PetscCall(SceneFailValue(r, node, "boundaries",
                               "boundaries that meet at the corners (bottom and left from corner (0, 0), bottom to right, left to top, right and top to the far corner); here the %s of %s is (%g, %g) but the %s of %s is (%g, %g)",
                               meet[c][1] ? "end" : "start", SceneBoundaryKeys[meet[c][0]], (double)p[0], (double)p[1], meet[c][3] ? "end" : "start", SceneBoundaryKeys[meet[c][2]], (double)q[0], (double)q[1]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* boundaries: {bottom, right, top, left: polylines or arcs, nodes: [bottom, right, top, left]} (docs/model.md section 3).
   Sets *nodes_given when the node counts are given (they then set the grid). */
static PetscErrorCode ReadBoundaries(SceneReader *r, yaml_node_t *map, ScenePiece *piece, PetscBool *nodes_given)
{
  yaml_node_t *node, *nodes;
  PetscInt     count[4];

  PetscFunctionBeginUser;
  *nodes_given = PETSC_FALSE;
  PetscCall(SceneGetValue(r, map, "boundaries", &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  piece->has_boundaries = PETSC_TRUE;
  PetscCall(SceneExpectMap(r, node, "boundaries", SceneBoundaryKeys, NULL));
  for (PetscInt b = 0; b < 4; b++) PetscCall(ReadBoundary(r, node, SceneBoundaryKeys[b], &piece->boundary_npoints[b], &piece->boundary_points[b]));
  PetscCall(CheckBoundaryCorners(r, node, piece));
  PetscCall(SceneGetValue(r, node, "nodes", &nodes));
  if (!nodes) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneKeyIntList(r, node, "nodes", PETSC_TRUE, 4, 2, count));
  if (count[0] != count[2] || count[1] != count[3])
    PetscCall(SceneFailValue(r, nodes, "nodes",
                             "node counts [bottom, right, top, left] with bottom = top and right = left (opposite boundaries carry the same threads); here bottom %" PetscInt_FMT ", top %" PetscInt_FMT ", right %" PetscInt_FMT ", left %" PetscInt_FMT,
                             count[0], count[2], count[1], count[3]));
  piece->grid_given[0] = count[0];
  piece->grid_given[1] = count[1];
  *nodes_given         = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* pin_disc: {center: [u, v], radius: r} and pin_box: {min: [u, v], max: [u, v]}, in pattern coordinates (m); and
   cut_disc: {center, radius}, the disc the grid is cut to. */
static PetscErrorCode ReadPinRegions(SceneReader *r, yaml_node_t *map, ScenePiece *piece)
{
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, "cut_disc", &node));
  if (node) {
    PetscCall(SceneExpectMap(r, node, "cut_disc", ScenePinDiscKeys, NULL));
    PetscCall(SceneKeyRealList(r, node, "center", PETSC_TRUE, 2, SCENE_REAL_ANY, "m", piece->cut_disc));
    PetscCall(SceneKeyReal(r, node, "radius", PETSC_TRUE, SCENE_REAL_POSITIVE, "m", &piece->cut_disc[2]));
  }
  PetscCall(SceneGetValue(r, map, "pin_disc", &node));
  if (node) {
    PetscCall(SceneExpectMap(r, node, "pin_disc", ScenePinDiscKeys, NULL));
    PetscCall(SceneKeyRealList(r, node, "center", PETSC_TRUE, 2, SCENE_REAL_ANY, "m", piece->pin_disc));
    PetscCall(SceneKeyReal(r, node, "radius", PETSC_TRUE, SCENE_REAL_POSITIVE, "m", &piece->pin_disc[2]));
  }
  PetscCall(SceneGetValue(r, map, "pin_box", &node));
  if (node) {
    PetscCall(SceneExpectMap(r, node, "pin_box", ScenePinBoxKeys, NULL));
    PetscCall(SceneKeyRealList(r, node, "min", PETSC_TRUE, 2, SCENE_REAL_ANY, "m", &piece->pin_box[0]));
    PetscCall(SceneKeyRealList(r, node, "max", PETSC_TRUE, 2, SCENE_REAL_ANY, "m", &piece->pin_box[2]));
    if (!(piece->pin_box[2] > piece->pin_box[0] && piece->pin_box[3] > piece->pin_box[1])) PetscCall(SceneFailValue(r, node, "pin_box", "a box with max > min in both coordinates"));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* grid (required unless the boundaries give node counts, then it must agree) and size (rectangles only). */
static PetscErrorCode ReadGridAndSize(SceneReader *r, yaml_node_t *map, ScenePiece *piece)
{
  PetscBool    nodes_given;
  PetscInt     grid[2];
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(ReadBoundaries(r, map, piece, &nodes_given));
  grid[0] = piece->grid_given[0];
  grid[1] = piece->grid_given[1];
  PetscCall(SceneKeyIntList(r, map, "grid", nodes_given ? PETSC_FALSE : PETSC_TRUE, 2, 2, grid));
  if (nodes_given && (grid[0] != piece->grid_given[0] || grid[1] != piece->grid_given[1])) {
    PetscCall(SceneGetValue(r, map, "grid", &node));
    PetscCall(SceneFailValue(r, node, "grid", "[%" PetscInt_FMT ", %" PetscInt_FMT "], the node counts the boundaries give (bottom/top, left/right), or no grid", piece->grid_given[0], piece->grid_given[1]));
  }
  if ((PetscInt64)grid[0] * grid[1] > SCENE_MAX_PARTICLES) {
    PetscCall(SceneGetValue(r, map, "grid", &node));
    PetscCall(SceneFailValue(r, node ? node : map, "grid", "a grid of at most %" PetscInt64_FMT " particles (3 coordinates each, indexed by a %d-bit PetscInt); this one has %" PetscInt64_FMT, SCENE_MAX_PARTICLES, (int)(8 * sizeof(PetscInt)),
                             (PetscInt64)grid[0] * grid[1]));
  }
  piece->grid_given[0] = piece->nu = grid[0];
  piece->grid_given[1] = piece->nv = grid[1];
  if (piece->has_boundaries) {
    PetscInt  i, j;
    PetscReal area;

    PetscCall(PatternFindFoldedCell(piece, &i, &j, &area));
    PetscCall(SceneGetValue(r, map, "boundaries", &node));
    if (i >= 0)
      PetscCall(SceneFailValue(r, node, "boundaries", "an outline whose %" PetscInt_FMT " x %" PetscInt_FMT " transfinite grid has no folded cell; cell (%" PetscInt_FMT ", %" PetscInt_FMT ") has area %g m^2: " PATTERN_FOLD_ADVICE, piece->nu,
                               piece->nv, i, j, (double)area));
  }
  PetscCall(SceneGetValue(r, map, "size", &node));
  if (node && piece->has_boundaries) PetscCall(SceneFailValue(r, node, "size", "no size when the piece has boundaries (its outline gives its size)"));
  PetscCall(SceneKeyRealList(r, map, "size", piece->has_boundaries ? PETSC_FALSE : PETSC_TRUE, 2, SCENE_REAL_POSITIVE, "m", piece->size));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* wrap: {axis_point: [x, y, z], axis: [ax, ay, az]}: the piece, placed flat by origin/u_axis/v_axis as a
   tangent plane, is rolled onto the cylinder around that axis that touches it (model.c). The axis must be
   parallel to the piece's plane and must not pass through it.
   wrap: {apex: [x, y, z], axis: [ax, ay, az]}: rolled onto the cone with that apex and axis (pointing from
   the apex into the cone) that touches the plane: the apex must lie in the plane, and the cone's half-angle
   is the axis's angle with the plane (strictly between 0 and 90 degrees). A flared skirt panel is a piece of
   a cone's development, so it is placed without distortion. */
static PetscErrorCode ReadWrap(SceneReader *r, yaml_node_t *map, ScenePiece *piece)
{
  yaml_node_t *wrap, *point, *apex;
  PetscReal    normal[3], along, offset = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, "wrap", &wrap));
  if (!wrap) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, wrap, "wrap", SceneWrapKeys, NULL));
  PetscCall(SceneGetValue(r, wrap, "axis_point", &point));
  PetscCall(SceneGetValue(r, wrap, "apex", &apex));
  if ((point == NULL) == (apex == NULL)) PetscCall(SceneFailValue(r, wrap, "wrap", "either axis_point (a cylinder) or apex (a cone)"));
  piece->wrap_cone = apex ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(SceneKeyRealList(r, wrap, apex ? "apex" : "axis_point", PETSC_TRUE, 3, SCENE_REAL_ANY, "m", piece->wrap_point));
  piece->wrap_axis[0] = piece->wrap_axis[2] = 0;
  piece->wrap_axis[1]                       = 1;
  PetscCall(SceneKeyDirection(r, wrap, "axis", piece->wrap_axis));
  normal[0] = piece->u_axis[1] * piece->v_axis[2] - piece->u_axis[2] * piece->v_axis[1];
  normal[1] = piece->u_axis[2] * piece->v_axis[0] - piece->u_axis[0] * piece->v_axis[2];
  normal[2] = piece->u_axis[0] * piece->v_axis[1] - piece->u_axis[1] * piece->v_axis[0];
  along     = normal[0] * piece->wrap_axis[0] + normal[1] * piece->wrap_axis[1] + normal[2] * piece->wrap_axis[2];
  for (PetscInt c = 0; c < 3; c++) offset += normal[c] * (piece->origin[c] - piece->wrap_point[c]);
  if (piece->wrap_cone) {
    if (PetscAbsReal(offset) > SCENE_PLANE_DISTANCE_TOL) PetscCall(SceneFailValue(r, wrap, "wrap", "an apex in the piece's plane (the cone touches the plane along a line through its apex)"));
    if (PetscAbsReal(along) < SCENE_ORTHOGONALITY_TOL || PetscAbsReal(along) > 1 - SCENE_ORTHOGONALITY_TOL)
      PetscCall(SceneFailValue(r, wrap, "wrap", "an axis at an angle strictly between 0 and 90 degrees to the piece's plane (the cone's half-angle)"));
  } else {
    if (PetscAbsReal(along) > SCENE_ORTHOGONALITY_TOL) PetscCall(SceneFailValue(r, wrap, "wrap", "an axis parallel to the piece's plane (u_axis, v_axis)"));
    if (PetscAbsReal(offset) < SCENE_PLANE_DISTANCE_TOL) PetscCall(SceneFailValue(r, wrap, "wrap", "an axis_point off the piece's plane (the cylinder's radius is its distance from the plane)"));
    /* a smaller cylinder puts neighbouring particles more than a radian apart: the piece winds into a knot */
    if (PetscAbsReal(offset) < ScenePieceLargestSpacing(piece))
      PetscCall(SceneFailValue(r, wrap, "wrap", "a cylinder radius (the axis_point's distance from the piece's plane) of at least the particle spacing, %g m; it is %g m", (double)ScenePieceLargestSpacing(piece), (double)PetscAbsReal(offset)));
  }
  piece->wrapped = PETSC_TRUE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadPiece(SceneReader *r, yaml_node_t *map, Scene scene, PetscInt index)
{
  ScenePiece  *piece = &scene->pieces[index];
  yaml_node_t *name;
  PetscInt     mass = CLOTH_MASS_AREA;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "piece %" PetscInt_FMT, index + 1));
  PetscCall(SceneExpectMap(r, map, NULL, ScenePieceKeys, NULL));
  PetscCall(SceneKeyName(r, map, "name", PETSC_TRUE, piece->name, sizeof(piece->name), &name));
  PetscCall(SceneCheckNameUnique(r, name, "piece", piece->name, scene->pieces, sizeof(ScenePiece), index));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "piece '%s'", piece->name));
  PetscCall(ReadFabricName(r, map, scene, piece));
  PetscCall(ReadGridAndSize(r, map, piece));
  PetscCall(SceneKeyRealList(r, map, "origin", PETSC_FALSE, 3, SCENE_REAL_ANY, "m", piece->origin));
  piece->u_axis[0] = 1;
  piece->v_axis[1] = 1;
  PetscCall(ReadAxes(r, map, piece));
  PetscCall(ReadWrap(r, map, piece));
  PetscCall(SceneKeyChoice(r, map, "mass", PETSC_FALSE, ClothMassDistributions, &mass));
  piece->mass_distribution = (ClothMassDistribution)mass;
  PetscCall(ReadPins(r, map, piece));
  PetscCall(ReadPinRegions(r, map, piece));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadPieces(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const char        expected[] = "a list of pieces, with at least one piece";
  yaml_node_t      *list;
  yaml_node_item_t *items = NULL;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, root, "pieces", PETSC_TRUE, expected, &list));
  PetscCall(SceneGetItems(r, list, "pieces", -1, expected, &items, &scene->npieces));
  if (scene->npieces == 0) PetscCall(SceneFailValue(r, list, "pieces", "%s", expected));
  PetscCall(PetscCalloc1(scene->npieces, &scene->pieces));
  for (PetscInt p = 0; p < scene->npieces; p++) PetscCall(SceneReadPiece(r, yaml_document_get_node(r->doc, items[p]), scene, p));
  r->block[0] = 0;
  PetscCall(SceneCheckParticleCount(scene, ""));
  scene->single_grid = scene->npieces == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadRun(SceneReader *r, yaml_node_t *root, SceneRunDefaults *run)
{
  yaml_node_t *map;
  PetscInt     integrator  = -1;
  PetscBool    has_t_final = PETSC_FALSE, has_steps = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, root, "run", &map));
  if (!map) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, map, "run", SceneRunKeys, NULL));
  PetscCall(PetscStrncpy(r->block, "run", sizeof(r->block)));
  PetscCall(SceneKeyChoice(r, map, "integrator", PETSC_FALSE, SceneIntegrators, &integrator));
  if (integrator >= 0) PetscCall(PetscStrncpy(run->integrator, SceneIntegrators[integrator], sizeof(run->integrator)));
  PetscCall(SceneKeyReal(r, map, "dt", PETSC_FALSE, SCENE_REAL_POSITIVE, "s", &run->dt));
  PetscCall(SceneKeyReal(r, map, "t_final", PETSC_FALSE, SCENE_REAL_POSITIVE, "s", &run->t_final));
  PetscCall(SceneKeyInt(r, map, "steps", PETSC_FALSE, 1, &run->steps));
  PetscCall(SceneHasKey(r, map, "t_final", &has_t_final));
  PetscCall(SceneHasKey(r, map, "steps", &has_steps));
  PetscCheck(!(has_t_final && has_steps), r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: keys 't_final' and 'steps' in run are both given: expected one of them", r->path, SceneNodeLine(map));
  PetscCall(SceneKeyInt(r, map, "output_every", PETSC_FALSE, 1, &run->output_every));
  PetscCall(SceneKeyInt(r, map, "checkpoint_every", PETSC_FALSE, 0, &run->checkpoint_every));
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A key that belongs to another type of body is an error (a plane with a radius is a typo, not a default). */
static PetscErrorCode SceneCheckBodyTypeKeys(SceneReader *r, yaml_node_t *map, const SceneBody *body)
{
  PetscFunctionBeginUser;
  for (PetscInt t = 0; t < 3; t++) {
    if (t == (PetscInt)body->type) continue;
    for (PetscInt k = 0; SceneBodyTypeKeys[t][k]; k++) {
      yaml_node_t *node;

      PetscCall(SceneGetValue(r, map, SceneBodyTypeKeys[t][k], &node));
      PetscCheck(!node, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: key '%s' in %s belongs to a %s body, not to a %s", r->path, SceneNodeLine(node), SceneBodyTypeKeys[t][k], r->block, SceneBodyTypes[t], SceneBodyTypes[body->type]);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* friction: {static: mu_s, kinetic: mu_k}; kinetic defaults to static. */
static PetscErrorCode ReadFriction(SceneReader *r, yaml_node_t *map, SceneBody *body)
{
  yaml_node_t *friction;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, "friction", &friction));
  if (!friction) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, friction, "friction", SceneFrictionKeys, NULL));
  PetscCall(SceneKeyReal(r, friction, "static", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, NULL, &body->friction_static));
  body->friction_kinetic = body->friction_static;
  PetscCall(SceneKeyReal(r, friction, "kinetic", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, NULL, &body->friction_kinetic));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A mesh file given relative to the scene file's directory (absolute paths are kept). */
static PetscErrorCode ReadBodyFile(SceneReader *r, yaml_node_t *map, SceneBody *body)
{
  char        file[CLOTH_PATH_LEN] = "";
  const char *slash                = strrchr(r->path, '/');

  PetscFunctionBeginUser;
  PetscCall(SceneKeyString(r, map, "file", PETSC_TRUE, file, sizeof(file), NULL));
  if (file[0] == '/' || !slash)
    PetscCall(PetscStrncpy(body->file, file, sizeof(body->file)));
  else
    PetscCall(PetscSNPrintf(body->file, sizeof(body->file), "%.*s/%s", (int)(slash - r->path), r->path, file));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadBody(SceneReader *r, yaml_node_t *map, Scene scene, PetscInt index)
{
  SceneBody   *body = &scene->bodies[index];
  PetscInt     type = -1;
  yaml_node_t *name;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "body %" PetscInt_FMT, index + 1));
  PetscCall(SceneExpectMap(r, map, NULL, SceneBodyKeys, NULL));
  PetscCall(PetscSNPrintf(body->name, sizeof(body->name), "body%" PetscInt_FMT, index + 1));
  PetscCall(SceneKeyName(r, map, "name", PETSC_FALSE, body->name, sizeof(body->name), &name));
  PetscCall(SceneCheckNameUnique(r, name ? name : map, "body", body->name, scene->bodies, sizeof(SceneBody), index));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "body '%s'", body->name));
  PetscCall(SceneKeyChoice(r, map, "type", PETSC_TRUE, SceneBodyTypes, &type));
  body->type      = (SceneBodyType)type;
  body->scale     = 1;
  body->normal[1] = 1;
  PetscCall(SceneCheckBodyTypeKeys(r, map, body));
  if (body->type == SCENE_BODY_SPHERE) {
    PetscCall(SceneKeyRealList(r, map, "center", PETSC_TRUE, 3, SCENE_REAL_ANY, "m", body->center));
    PetscCall(SceneKeyReal(r, map, "radius", PETSC_TRUE, SCENE_REAL_POSITIVE, "m", &body->radius));
  } else if (body->type == SCENE_BODY_PLANE) {
    PetscCall(SceneKeyRealList(r, map, "point", PETSC_TRUE, 3, SCENE_REAL_ANY, "m", body->point));
    PetscCall(SceneKeyDirection(r, map, "normal", body->normal));
  } else {
    PetscCall(ReadBodyFile(r, map, body));
    PetscCall(SceneKeyReal(r, map, "scale", PETSC_FALSE, SCENE_REAL_POSITIVE, NULL, &body->scale));
    PetscCall(SceneKeyRealList(r, map, "rotation", PETSC_FALSE, 3, SCENE_REAL_ANY, "degrees", body->rotation));
    PetscCall(SceneKeyRealList(r, map, "translation", PETSC_FALSE, 3, SCENE_REAL_ANY, "m", body->translation));
  }
  PetscCall(ReadFriction(r, map, body));
  PetscCall(SceneKeyReal(r, map, "thickness", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "m", &body->thickness));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadBodies(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const char        expected[] = "a list of bodies (maps with a type: sphere, plane or mesh)";
  yaml_node_t      *list;
  yaml_node_item_t *items = NULL;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, root, "bodies", &list));
  if (!list) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetItems(r, list, "bodies", -1, expected, &items, &scene->nbodies));
  PetscCall(PetscCalloc1(scene->nbodies, &scene->bodies));
  for (PetscInt b = 0; b < scene->nbodies; b++) PetscCall(SceneReadBody(r, yaml_document_get_node(r->doc, items[b]), scene, b));
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The optional self_collision: block (cloth-cloth contact, see selfcontact.h); thickness and stiffness are
   required when it is enabled. */
static PetscErrorCode SceneReadSelfCollision(SceneReader *r, yaml_node_t *root, Scene scene)
{
  SceneSelfCollision *self = &scene->self_collision;
  yaml_node_t        *map;
  PetscInt            enabled = 0, same_piece = 1;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, root, "self_collision", &map));
  if (!map) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, map, "self_collision", SceneSelfCollisionKeys, NULL));
  PetscCall(PetscStrncpy(r->block, "self_collision", sizeof(r->block)));
  self->given        = PETSC_TRUE;
  self->exclude_ring = 0;
  PetscCall(SceneKeyChoice(r, map, "enabled", PETSC_FALSE, SceneBooleans, &enabled));
  self->enabled = enabled ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(SceneKeyReal(r, map, "thickness", self->enabled, SCENE_REAL_POSITIVE, "m", &self->thickness));
  if (self->enabled) {
    yaml_node_t *node;
    PetscReal    spacing;

    PetscCall(SceneGetLargestSpacing(scene, &spacing));
    PetscCall(SceneGetValue(r, map, "thickness", &node));
    if (self->thickness > SCENE_SELF_COLLISION_MAX_SPACINGS * spacing)
      PetscCall(SceneFailValue(r, node, "thickness", "a positive number (m) of at most %d particle spacings, %g m (the coarsest piece's spacing is %g m)", SCENE_SELF_COLLISION_MAX_SPACINGS, (double)(SCENE_SELF_COLLISION_MAX_SPACINGS * spacing),
                               (double)spacing));
  }
  PetscCall(SceneKeyReal(r, map, "stiffness", self->enabled, SCENE_REAL_POSITIVE, "N/m", &self->stiffness));
  PetscCall(SceneKeyInt(r, map, "exclude_ring", PETSC_FALSE, 0, &self->exclude_ring));
  PetscCall(SceneKeyChoice(r, map, "same_piece", PETSC_FALSE, SceneBooleans, &same_piece));
  self->same_piece = same_piece ? PETSC_TRUE : PETSC_FALSE;
  r->block[0]      = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A seam side: {piece: NAME, side: bottom|right|top|left, from: 0, to: 1}. */
static PetscErrorCode SceneReadSeamSide(SceneReader *r, yaml_node_t *seam, const char key[], Scene scene, SceneSeamSide *side)
{
  yaml_node_t *map, *where;
  char         name[CLOTH_NAME_LEN];
  PetscInt     s = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, seam, key, PETSC_TRUE, "a map {piece: NAME, side: bottom|right|top|left, from: 0, to: 1}", &map));
  PetscCall(SceneExpectMap(r, map, key, SceneSeamSideKeys, NULL));
  side->line = SceneNodeLine(map);
  PetscCall(SceneKeyString(r, map, "piece", PETSC_TRUE, name, sizeof(name), &where));
  side->piece = -1;
  for (PetscInt p = 0; p < scene->npieces; p++) {
    PetscBool match;
    PetscCall(PetscStrcmp(name, scene->pieces[p].name, &match));
    if (match) side->piece = p;
  }
  if (side->piece < 0) PetscCall(SceneFailValue(r, where, "piece", "the name of a piece given under 'pieces'"));
  PetscCall(SceneKeyChoice(r, map, "side", PETSC_TRUE, ClothPieceSides, &s));
  side->side = (ClothPieceSide)s;
  side->from = 0;
  side->to   = 1;
  PetscCall(SceneKeyReal(r, map, "from", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "fraction of the side's length", &side->from));
  PetscCall(SceneKeyReal(r, map, "to", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "fraction of the side's length", &side->to));
  if (side->from > 1 || side->to > 1 || side->from == side->to) PetscCall(SceneFailValue(r, map, key, "from and to: two different fractions in [0, 1]"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A seam joins two different stretches: the same side of one piece in both a and b, with stretches that meet,
   would pair particles with themselves (a link of zero length, which stops the run at its first step). */
static PetscErrorCode SceneCheckSeamSidesApart(SceneReader *r, yaml_node_t *map, Scene scene, const SceneSeam *seam)
{
  const SceneSeamSide *a = &seam->a, *b = &seam->b;

  PetscFunctionBeginUser;
  if (a->piece != b->piece || a->side != b->side) PetscFunctionReturn(PETSC_SUCCESS);
  if (PetscMax(a->from, a->to) < PetscMin(b->from, b->to) || PetscMax(b->from, b->to) < PetscMin(a->from, a->to)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneFailValue(r, map, NULL, "sides a and b on two different stretches; both are on the %s side of piece '%s' (%g..%g and %g..%g), so the seam would join particles to themselves", ClothPieceSides[a->side], scene->pieces[a->piece].name,
                           (double)a->from, (double)a->to, (double)b->from, (double)b->to));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The length of a seam side's stretch in the flat pattern, m: its fraction of the side's length (the outline's
   boundary, or the rectangle's edge). */
static PetscReal SceneSeamSideLength(Scene scene, const SceneSeamSide *side)
{
  const ScenePiece *piece  = &scene->pieces[side->piece];
  PetscReal         length = 0;

  if (!piece->has_boundaries)
    length = piece->size[side->side == CLOTH_SIDE_BOTTOM || side->side == CLOTH_SIDE_TOP ? 0 : 1];
  else {
    const PetscReal *x = piece->boundary_points[side->side]; /* ClothPieceSide and the boundaries: one order */

    for (PetscInt k = 1; k < piece->boundary_npoints[side->side]; k++) length += PetscSqrtReal(PetscSqr(x[2 * k] - x[2 * k - 2]) + PetscSqr(x[2 * k + 1] - x[2 * k - 1]));
  }
  return length * PetscAbsReal(side->to - side->from);
}

/* The two stretches of a seam have lengths within SCENE_SEAM_MAX_LENGTH_RATIO of each other. */
static PetscErrorCode SceneCheckSeamLengths(SceneReader *r, yaml_node_t *map, Scene scene, const SceneSeam *seam)
{
  const PetscReal a = SceneSeamSideLength(scene, &seam->a), b = SceneSeamSideLength(scene, &seam->b);

  PetscFunctionBeginUser;
  if (PetscMax(a, b) <= SCENE_SEAM_MAX_LENGTH_RATIO * PetscMin(a, b)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneFailValue(r, map, NULL,
                           "sides a and b whose lengths differ at most %d times (a gathered seam eases up to about 3 times its length); a (%s side of piece '%s', %g..%g) is %g m, b (%s side of piece '%s', %g..%g) is %g m: a unit mistake?",
                           SCENE_SEAM_MAX_LENGTH_RATIO, ClothPieceSides[seam->a.side], scene->pieces[seam->a.piece].name, (double)seam->a.from, (double)seam->a.to, (double)a, ClothPieceSides[seam->b.side], scene->pieces[seam->b.piece].name,
                           (double)seam->b.from, (double)seam->b.to, (double)b));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadSeams(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const char        expected[] = "a list of seams (maps with a, b and optionally name, bend)";
  yaml_node_t      *list;
  yaml_node_item_t *items = NULL;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, root, "seams", &list));
  if (!list) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetItems(r, list, "seams", -1, expected, &items, &scene->nseams));
  PetscCheck(scene->nseams <= SCENE_MAX_SEAMS, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: key 'seams': expected at most %d seams (what a checkpoint stores exactly: the sewn seams of a particle are bits of a float64), got %" PetscInt_FMT,
             r->path, SceneNodeLine(list), SCENE_MAX_SEAMS, scene->nseams);
  PetscCall(PetscCalloc1(scene->nseams, &scene->seams));
  for (PetscInt k = 0; k < scene->nseams; k++) {
    yaml_node_t *map  = yaml_document_get_node(r->doc, items[k]);
    SceneSeam   *seam = &scene->seams[k];
    PetscInt     bend = 1;

    PetscCall(SceneExpectMap(r, map, "seams", SceneSeamKeys, NULL));
    PetscCall(PetscSNPrintf(seam->name, sizeof(seam->name), "seam%" PetscInt_FMT, k));
    PetscCall(SceneKeyName(r, map, "name", PETSC_FALSE, seam->name, sizeof(seam->name), NULL));
    PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "seam '%s'", seam->name));
    PetscCall(SceneReadSeamSide(r, map, "a", scene, &seam->a));
    PetscCall(SceneReadSeamSide(r, map, "b", scene, &seam->b));
    PetscCall(SceneCheckSeamSidesApart(r, map, scene, seam));
    PetscCall(SceneCheckSeamLengths(r, map, scene, seam));
    PetscCall(SceneKeyChoice(r, map, "bend", PETSC_FALSE, SceneBooleans, &bend));
    seam->bend = bend ? PETSC_TRUE : PETSC_FALSE;
  }
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadSewing(SceneReader *r, yaml_node_t *root, SceneSewing *sewing)
{
  yaml_node_t *map;

  PetscFunctionBeginUser;
  sewing->pull_acceleration = 9.81;
  sewing->pull_radius       = 0.01;
  sewing->sewn_stiffness    = 2000;
  sewing->tolerance         = 0.002;
  sewing->max_time          = 2.0;
  sewing->pull_friction     = 1.0;
  PetscCall(SceneGetValue(r, root, "sewing", &map));
  if (!map) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, map, "sewing", SceneSewingKeys, NULL));
  PetscCall(PetscStrncpy(r->block, "sewing", sizeof(r->block)));
  PetscCall(SceneKeyReal(r, map, "pull_acceleration", PETSC_FALSE, SCENE_REAL_POSITIVE, "m/s^2", &sewing->pull_acceleration));
  PetscCall(SceneKeyReal(r, map, "pull_radius", PETSC_FALSE, SCENE_REAL_POSITIVE, "m", &sewing->pull_radius));
  PetscCall(SceneKeyReal(r, map, "sewn_stiffness", PETSC_FALSE, SCENE_REAL_POSITIVE, "N/m", &sewing->sewn_stiffness));
  PetscCall(SceneKeyReal(r, map, "tolerance", PETSC_FALSE, SCENE_REAL_POSITIVE, "m", &sewing->tolerance));
  PetscCall(SceneKeyReal(r, map, "max_time", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "s", &sewing->max_time));
  PetscCall(SceneKeyReal(r, map, "pull_friction", PETSC_FALSE, SCENE_REAL_NONNEGATIVE, "", &sewing->pull_friction));
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A piece cut to a disc (cut_disc) keeps its whole grid of particles, those outside held still without mass; seams
   (sides of the grid) and cloth-cloth contact (the grid's triangles) do not know the cut, so they are refused. */
static PetscErrorCode SceneCheckCutPieces(SceneReader *r, Scene scene)
{
  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < scene->npieces; p++) {
    if (!(scene->pieces[p].cut_disc[2] > 0)) continue;
    PetscCheck(!scene->self_collision.enabled, r->comm, PETSC_ERR_USER_INPUT, "scene %s: piece '%s': expected no cut_disc with self_collision enabled (the contact search does not know the cut), got both", r->path, scene->pieces[p].name);
    for (PetscInt s = 0; s < scene->nseams; s++)
      PetscCheck(scene->seams[s].a.piece != p && scene->seams[s].b.piece != p, r->comm, PETSC_ERR_USER_INPUT, "scene %s: seam '%s': expected no seam on piece '%s', which is cut to a disc (cut_disc), got one", r->path, scene->seams[s].name,
                 scene->pieces[p].name);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadDocument(SceneReader *r, Scene scene)
{
  yaml_node_t *root = yaml_document_get_root_node(r->doc), *name;
  char         keys[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  PetscCall(SceneJoinNames(SceneTopKeys, -1, keys, sizeof(keys)));
  PetscCheck(root, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line 1: the file is empty: expected a map with keys among %s", r->path, keys);
  PetscCall(SceneExpectMap(r, root, NULL, SceneTopKeys, NULL));
  PetscCall(SceneKeyName(r, root, "name", PETSC_FALSE, scene->name, sizeof(scene->name), &name));
  PetscCheck(name || SceneNameIsSafe(scene->name), r->comm, PETSC_ERR_USER_INPUT, "scene %s: the scene is named '%s' after its file, which names the output files: expected a key 'name' (" SCENE_NAME_RULE ") or a file name of such characters",
             r->path, scene->name);
  PetscCall(SceneKeyRealList(r, root, "gravity", PETSC_FALSE, 3, SCENE_REAL_ANY, "m/s^2", scene->gravity));
  PetscCall(SceneReadFabrics(r, root, scene));
  PetscCall(SceneReadPieces(r, root, scene));
  PetscCall(SceneReadRun(r, root, &scene->run));
  PetscCall(SceneReadBodies(r, root, scene));
  PetscCall(SceneReadSelfCollision(r, root, scene));
  PetscCall(SceneReadSeams(r, root, scene));
  PetscCall(SceneReadSewing(r, root, &scene->sewing));
  PetscCall(SceneCheckCutPieces(r, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* File and YAML                                                                                                */

/* The largest scene file read: far above any scene (the garment is 10 kB), and a limit for what is not one
   (-scene /dev/zero, a checkpoint given by mistake), which is refused before it fills the memory. */
#define SCENE_MAX_FILE_BYTES (64ll << 20)

/* Rank 0 only, never raises: reads the whole file (up to one byte beyond SCENE_MAX_FILE_BYTES, enough to tell
   that it is too large), or returns the errno of the failure. */
static PetscErrorCode SceneReadFileSerial(const char path[], char **bytes, long long *len, long long *err)
{
  FILE  *fp;
  size_t cap = 1 << 16, n = 0, got;

  PetscFunctionBeginUser;
  *bytes = NULL;
  *len   = 0;
  *err   = 0;
  if (!(fp = fopen(path, "rb"))) {
    *err = errno;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscMalloc1(cap, bytes));
  while (n <= SCENE_MAX_FILE_BYTES && (got = fread(*bytes + n, 1, cap - n, fp)) > 0) {
    n += got;
    if (n == cap) {
      cap *= 2;
      PetscCall(PetscRealloc(cap, bytes));
    }
  }
  if (ferror(fp)) *err = errno ? errno : EIO;
  fclose(fp);
  *len = (long long)n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Collective: every rank gets the file's bytes (NUL-terminated) from rank 0. */
static PetscErrorCode SceneReadBytes(MPI_Comm comm, const char path[], char **bytes, size_t *len)
{
  PetscMPIInt rank;
  long long   header[2] = {0, 0}; /* length, errno */
  char       *buf       = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(SceneReadFileSerial(path, &buf, &header[0], &header[1]));
  PetscCallMPI(MPI_Bcast(header, 2, MPI_LONG_LONG, 0, comm));
  if (header[1]) PetscCall(PetscFree(buf));
  PetscCheck(!header[1], comm, PETSC_ERR_FILE_OPEN, "scene %s: cannot read the file (%s): expected a readable YAML scene file", path, strerror((int)header[1]));
  if (header[0] > SCENE_MAX_FILE_BYTES) PetscCall(PetscFree(buf));
  PetscCheck(header[0] <= SCENE_MAX_FILE_BYTES, comm, PETSC_ERR_USER_INPUT, "scene %s: the file is larger than %lld MB: expected a YAML scene file (a few kB)", path, SCENE_MAX_FILE_BYTES >> 20);
  if (rank == 0)
    PetscCall(PetscRealloc((size_t)header[0] + 1, &buf));
  else
    PetscCall(PetscMalloc1((size_t)header[0] + 1, &buf));
  PetscCallMPI(MPI_Bcast(buf, (PetscMPIInt)header[0], MPI_CHAR, 0, comm));
  buf[header[0]] = 0;
  *bytes         = buf;
  *len           = (size_t)header[0];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Parses the bytes (the same on every rank) and reads the document into scene. */
static PetscErrorCode SceneParse(MPI_Comm comm, const char bytes[], size_t len, Scene scene)
{
  yaml_parser_t   parser;
  yaml_document_t doc, extra;
  SceneReader     reader = {comm, scene->path, &doc, "", SceneRealBounds};
  PetscErrorCode  ierr;
  PetscBool       more;

  PetscFunctionBeginUser;
  PetscCall(SceneCheckNesting(comm, scene->path, bytes, len, SCENE_MAX_DEPTH)); /* before the loader, which would take hours */
  PetscCheck(yaml_parser_initialize(&parser), comm, PETSC_ERR_MEM, "libyaml could not create a parser");
  yaml_parser_set_input_string(&parser, (const unsigned char *)bytes, len);
  if (!yaml_parser_load(&parser, &doc)) {
    ierr = SceneFailSyntax(comm, scene->path, &parser);
    yaml_parser_delete(&parser);
    PetscCall(ierr);
  }
  if (!yaml_parser_load(&parser, &extra)) {
    ierr = SceneFailSyntax(comm, scene->path, &parser);
    yaml_document_delete(&doc);
    yaml_parser_delete(&parser);
    PetscCall(ierr);
  }
  more = yaml_document_get_root_node(&extra) ? PETSC_TRUE : PETSC_FALSE;
  yaml_document_delete(&extra);
  /* Read, then free libyaml's memory whatever happened; the error (if any) is raised after. */
  ierr = more ? PETSC_SUCCESS : SceneReadDocument(&reader, scene);
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  PetscCheck(!more, comm, PETSC_ERR_USER_INPUT, "scene %s: the file holds more than one YAML document: expected exactly one", scene->path);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* FNV-1a, 64 bits, continued from hash over n bytes. */
static PetscErrorCode SceneHashBytes(uint64_t *hash, const unsigned char bytes[], size_t n)
{
  PetscFunctionBeginUser;
  for (size_t i = 0; i < n; i++) *hash = (*hash ^ bytes[i]) * SCENE_FNV_PRIME;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Defaults that are not zero, and the name from the path: "input/hanging_sheet.yaml" -> "hanging_sheet". */
static PetscErrorCode SceneSetDefaults(Scene scene, const char path[])
{
  const char *base = strrchr(path, '/');
  char       *dot;

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(scene->path, path, sizeof(scene->path)));
  PetscCall(PetscStrncpy(scene->name, base ? base + 1 : path, sizeof(scene->name)));
  dot = strrchr(scene->name, '.');
  if (dot && dot != scene->name) *dot = 0;
  scene->gravity[1] = -9.81;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneCreateFromFile(MPI_Comm comm, const char path[], Scene *scene)
{
  Scene          s;
  char          *bytes;
  size_t         len;
  uint64_t       hash = SCENE_FNV_OFFSET;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  *scene = NULL;
  PetscCheck(strlen(path) < CLOTH_PATH_LEN, comm, PETSC_ERR_ARG_SIZ, "scene %s: the path is too long: expected less than %d characters", path, CLOTH_PATH_LEN);
  PetscCall(SceneReadBytes(comm, path, &bytes, &len));
  PetscCall(PetscNew(&s));
  s->comm = comm;
  PetscCall(SceneSetDefaults(s, path));
  PetscCall(SceneHashBytes(&hash, (const unsigned char *)bytes, len));
  s->file_fingerprint = s->fingerprint = (PetscInt64)hash;
  ierr                                 = SceneParse(comm, bytes, len, s);
  if (!ierr) {
    PetscCall(PetscMalloc1(len + 1, &s->text));
    PetscCall(PetscArraycpy(s->text, bytes, len));
    s->text[len] = 0;
  }
  PetscCall(PetscFree(bytes));
  if (ierr) PetscCall(SceneDestroy(&s));
  PetscCall(ierr);
  *scene = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneSetGridSize(Scene scene, PetscInt n)
{
  ScenePiece   *piece;
  uint64_t      hash = (uint64_t)scene->file_fingerprint;
  unsigned char nbytes[8];
  char          cause[64];

  PetscFunctionBeginUser;
  PetscCheck(scene->single_grid, scene->comm, PETSC_ERR_USER_INPUT, "scene %s: -grid %" PetscInt_FMT ": expected a scene of one rectangular piece, got %" PetscInt_FMT " pieces", scene->path, n, scene->npieces);
  PetscCheck(n >= 2, scene->comm, PETSC_ERR_USER_INPUT, "scene %s: -grid %" PetscInt_FMT ": expected an integer >= 2", scene->path, n);
  piece     = &scene->pieces[0];
  piece->nu = piece->nv = n;
  PetscCall(PetscSNPrintf(cause, sizeof(cause), "-grid %" PetscInt_FMT, n));
  PetscCall(SceneCheckParticleCount(scene, cause));
  PetscCall(ScenePieceResolvePins(scene->comm, scene->path, piece));
  for (int b = 0; b < 8; b++) nbytes[b] = (unsigned char)(((uint64_t)n >> (8 * b)) & 0xff); /* little-endian on every host */
  if (n != piece->grid_given[0] || n != piece->grid_given[1]) PetscCall(SceneHashBytes(&hash, nbytes, sizeof(nbytes)));
  scene->fingerprint = (PetscInt64)hash;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* View and destroy                                                                                             */

/* Appends ", <fmt...>" (without the comma when buf is empty) to a list being built in buf. */
static PetscErrorCode SceneAppendItem(char buf[], size_t len, const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
static PetscErrorCode SceneAppendItem(char buf[], size_t len, const char fmt[], ...)
{
  char    item[SCENE_TEXT_LEN];
  va_list args;

  PetscFunctionBeginUser;
  va_start(args, fmt);
  vsnprintf(item, sizeof(item), fmt, args);
  va_end(args);
  if (buf[0]) PetscCall(PetscStrlcat(buf, ", ", len));
  PetscCall(PetscStrlcat(buf, item, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneFabricView(const SceneFabric *f, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (f->preset[0]) PetscCall(SceneAppendItem(list, sizeof(list), "preset %s", f->preset));
  PetscCall(SceneAppendItem(list, sizeof(list), "density %g kg/m^2", (double)f->density));
  PetscCall(SceneAppendItem(list, sizeof(list), "stretch %g/%g N/m (warp/weft)", (double)f->stretch_warp, (double)f->stretch_weft));
  if (f->stretch_knee_warp > 0 || f->stretch_knee_weft > 0)
    PetscCall(SceneAppendItem(list, sizeof(list), "beyond strain %g/%g: %g/%g N/m", (double)f->stretch_knee_warp, (double)f->stretch_knee_weft, (double)f->stretch_stiff_warp, (double)f->stretch_stiff_weft));
  PetscCall(SceneAppendItem(list, sizeof(list), "shear %g N/m (%s)", (double)f->shear, ClothShearModels[f->shear_model]));
  if (f->shear_hysteresis > 0) PetscCall(SceneAppendItem(list, sizeof(list), "shear friction HG %g N/m", (double)f->shear_hysteresis));
  PetscCall(SceneAppendItem(list, sizeof(list), "bend %g/%g %s (warp/weft, %s)", (double)f->bend_warp, (double)f->bend_weft, f->bend_model == CLOTH_BEND_LINK ? "N/m" : "N m", ClothBendModels[f->bend_model]));
  if (f->bend_bias > 0) PetscCall(SceneAppendItem(list, sizeof(list), "bias bend %g N m (twisting rigidity %g N m)", (double)f->bend_bias, (double)FabricTwistRigidity(f)));
  if (f->bend_hysteresis_warp > 0 || f->bend_hysteresis_weft > 0) PetscCall(SceneAppendItem(list, sizeof(list), "bending friction HB %g/%g N m/m (warp/weft)", (double)f->bend_hysteresis_warp, (double)f->bend_hysteresis_weft));
  PetscCall(SceneAppendItem(list, sizeof(list), "damping %g 1/s", (double)f->damping));
  if (f->repulsion > 0)
    PetscCall(SceneAppendItem(list, sizeof(list), "repulsion below %g of the rest length (stiffness x %g)", (double)f->repulsion, (double)f->repulsion_stiffness));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "repulsion off"));
  PetscCall(PetscViewerASCIIPrintf(viewer, "fabric '%s': %s\n", f->name, list));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ScenePieceView(Scene scene, const ScenePiece *p, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "", frame[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  PetscCall(SceneAppendItem(list, sizeof(list), "fabric '%s'", scene->fabrics[p->fabric].name));
  PetscCall(SceneAppendItem(list, sizeof(list), "grid %" PetscInt_FMT " x %" PetscInt_FMT " = %" PetscInt_FMT " particles", p->nu, p->nv, p->nu * p->nv));
  if (p->has_boundaries)
    PetscCall(SceneAppendItem(list, sizeof(list), "outline from 4 boundaries (%" PetscInt_FMT "/%" PetscInt_FMT "/%" PetscInt_FMT "/%" PetscInt_FMT " vertices)", p->boundary_npoints[0], p->boundary_npoints[1], p->boundary_npoints[2],
                              p->boundary_npoints[3]));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "size %g x %g m", (double)p->size[0], (double)p->size[1]));
  PetscCall(SceneAppendItem(list, sizeof(list), "mass %s", ClothMassDistributions[p->mass_distribution]));
  PetscCall(SceneAppendItem(list, sizeof(list), "%" PetscInt_FMT " pin%s", p->npins, p->npins == 1 ? "" : "s"));
  if (p->pin_disc[2] > 0) PetscCall(SceneAppendItem(list, sizeof(list), "pinned within %g m of (%g, %g)", (double)p->pin_disc[2], (double)p->pin_disc[0], (double)p->pin_disc[1]));
  if (p->pin_box[2] > p->pin_box[0]) PetscCall(SceneAppendItem(list, sizeof(list), "pinned in [%g, %g] x [%g, %g]", (double)p->pin_box[0], (double)p->pin_box[2], (double)p->pin_box[1], (double)p->pin_box[3]));
  if (p->cut_disc[2] > 0) PetscCall(SceneAppendItem(list, sizeof(list), "cut to the cells within %g m of (%g, %g)", (double)p->cut_disc[2], (double)p->cut_disc[0], (double)p->cut_disc[1]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "origin (%g, %g, %g) m", (double)p->origin[0], (double)p->origin[1], (double)p->origin[2]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "u_axis (%g, %g, %g)", (double)p->u_axis[0], (double)p->u_axis[1], (double)p->u_axis[2]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "v_axis (%g, %g, %g)", (double)p->v_axis[0], (double)p->v_axis[1], (double)p->v_axis[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "piece '%s': %s\n", p->name, list));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", frame));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneRunView(const SceneRunDefaults *run, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (run->integrator[0]) PetscCall(SceneAppendItem(list, sizeof(list), "integrator %s", run->integrator));
  if (run->dt > 0) PetscCall(SceneAppendItem(list, sizeof(list), "dt %g s", (double)run->dt));
  if (run->t_final > 0) PetscCall(SceneAppendItem(list, sizeof(list), "t_final %g s", (double)run->t_final));
  if (run->steps > 0) PetscCall(SceneAppendItem(list, sizeof(list), "steps %" PetscInt_FMT, run->steps));
  if (run->output_every > 0) PetscCall(SceneAppendItem(list, sizeof(list), "output_every %" PetscInt_FMT, run->output_every));
  if (run->checkpoint_every > 0) PetscCall(SceneAppendItem(list, sizeof(list), "checkpoint_every %" PetscInt_FMT, run->checkpoint_every));
  PetscCall(PetscViewerASCIIPrintf(viewer, "run defaults (options override them): %s\n", list[0] ? list : "none"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneBodyView(const SceneBody *b, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (b->type == SCENE_BODY_SPHERE)
    PetscCall(SceneAppendItem(list, sizeof(list), "sphere, center (%g, %g, %g) m, radius %g m", (double)b->center[0], (double)b->center[1], (double)b->center[2], (double)b->radius));
  else if (b->type == SCENE_BODY_PLANE)
    PetscCall(SceneAppendItem(list, sizeof(list), "plane through (%g, %g, %g) m, normal (%g, %g, %g)", (double)b->point[0], (double)b->point[1], (double)b->point[2], (double)b->normal[0], (double)b->normal[1], (double)b->normal[2]));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "mesh %s, scale %g, rotation (%g, %g, %g) deg, translation (%g, %g, %g) m", b->file, (double)b->scale, (double)b->rotation[0], (double)b->rotation[1], (double)b->rotation[2],
                              (double)b->translation[0], (double)b->translation[1], (double)b->translation[2]));
  PetscCall(SceneAppendItem(list, sizeof(list), "friction %g/%g (static/kinetic), thickness %g m", (double)b->friction_static, (double)b->friction_kinetic, (double)b->thickness));
  PetscCall(PetscViewerASCIIPrintf(viewer, "body '%s': %s\n", b->name, list));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneGetParticleCount(Scene scene, PetscInt *n)
{
  PetscFunctionBeginUser;
  *n = (PetscInt)SceneCountParticles(scene); /* fits: checked when the grids were set */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneView(Scene scene, PetscViewer viewer)
{
  PetscBool iascii;
  PetscInt  particles;
  char      gravity[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (!viewer) PetscCall(PetscViewerASCIIGetStdout(scene->comm, &viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (!iascii) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetParticleCount(scene, &particles));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Scene '%s' from %s (fingerprint %016" PRIx64 "): %" PetscInt_FMT " piece%s, %" PetscInt_FMT " particles\n", scene->name, scene->path, (uint64_t)scene->fingerprint, scene->npieces,
                                   scene->npieces == 1 ? "" : "s", particles));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(SceneAppendItem(gravity, sizeof(gravity), "gravity (%g, %g, %g) m/s^2", (double)scene->gravity[0], (double)scene->gravity[1], (double)scene->gravity[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", gravity));
  for (PetscInt f = 0; f < scene->nfabrics; f++) PetscCall(SceneFabricView(&scene->fabrics[f], viewer));
  for (PetscInt p = 0; p < scene->npieces; p++) PetscCall(ScenePieceView(scene, &scene->pieces[p], viewer));
  PetscCall(SceneRunView(&scene->run, viewer));
  for (PetscInt b = 0; b < scene->nbodies; b++) PetscCall(SceneBodyView(&scene->bodies[b], viewer));
  if (scene->self_collision.enabled)
    PetscCall(PetscViewerASCIIPrintf(viewer, "self-collision: thickness %g m, stiffness %g N/m, %" PetscInt_FMT " ring(s) excluded%s\n", (double)scene->self_collision.thickness, (double)scene->self_collision.stiffness,
                                     scene->self_collision.exclude_ring, scene->self_collision.same_piece ? "" : ", pieces do not collide with themselves"));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneDestroy(Scene *scene)
{
  PetscFunctionBeginUser;
  if (!scene || !*scene) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt p = 0; p < (*scene)->npieces && (*scene)->pieces; p++) {
    PetscCall(PetscFree((*scene)->pieces[p].pins));
    PetscCall(PetscFree((*scene)->pieces[p].pins_given));
    for (PetscInt b = 0; b < 4; b++) PetscCall(PetscFree((*scene)->pieces[p].boundary_points[b]));
  }
  PetscCall(PetscFree((*scene)->pieces));
  PetscCall(PetscFree((*scene)->text));
  PetscCall(PetscFree((*scene)->fabrics));
  PetscCall(PetscFree((*scene)->bodies));
  PetscCall(PetscFree((*scene)->seams));
  PetscCall(PetscFree(*scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}
