/* The smaller blocks of the scene (scene_impl.h): run: (defaults of the run-level options), bodies: (spheres,
   planes and meshes, their friction and thickness), self_collision:, seams: (two stretches of piece sides, checked
   apart and of comparable lengths) and sewing:. */
#include <string.h>
#include "scene_impl.h"

PetscErrorCode SceneReadRun(SceneReader *r, yaml_node_t *root, SceneRunDefaults *run)
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

/* Item index of the bodies: list (a SceneItemReader; ctx: the scene). */
static PetscErrorCode SceneReadBody(SceneReader *r, yaml_node_t *map, void *ctx, PetscInt index)
{
  Scene        scene = (Scene)ctx;
  SceneBody   *body  = &scene->bodies[index];
  PetscInt     type  = -1;
  yaml_node_t *name;

  PetscFunctionBeginUser;
  PetscCall(SceneBodySetDefaults(body, index));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "body %" PetscInt_FMT, index + 1));
  PetscCall(SceneExpectMap(r, map, NULL, SceneBodyKeys, NULL));
  PetscCall(SceneKeyName(r, map, "name", PETSC_FALSE, body->name, sizeof(body->name), &name));
  PetscCall(SceneCheckNameUnique(r, name ? name : map, "body", body->name, scene->bodies, sizeof(SceneBody), index));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "body '%s'", body->name));
  PetscCall(SceneKeyChoice(r, map, "type", PETSC_TRUE, SceneBodyTypes, &type));
  body->type = (SceneBodyType)type;
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

PetscErrorCode SceneReadBodies(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const SceneList list = {"bodies", "a list of bodies (maps with a type: sphere, plane or mesh)", PETSC_FALSE, -1, NULL, sizeof(SceneBody), SceneReadBody};

  PetscFunctionBeginUser;
  PetscCall(SceneReadList(r, root, &list, scene, &scene->bodies, &scene->nbodies));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The optional self_collision: block (cloth-cloth contact, see selfcontact.h); thickness and stiffness are
   required when it is enabled. */
PetscErrorCode SceneReadSelfCollision(SceneReader *r, yaml_node_t *root, Scene scene)
{
  SceneSelfCollision *self = &scene->self_collision;
  yaml_node_t        *map;
  PetscInt            enabled, same_piece;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, root, "self_collision", &map));
  if (!map) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneExpectMap(r, map, "self_collision", SceneSelfCollisionKeys, NULL));
  PetscCall(PetscStrncpy(r->block, "self_collision", sizeof(r->block)));
  PetscCall(SceneSelfCollisionSetDefaults(self));
  enabled    = self->enabled;
  same_piece = self->same_piece;
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

/* Item index of the seams: list (a SceneItemReader; ctx: the scene). */
static PetscErrorCode SceneReadSeam(SceneReader *r, yaml_node_t *map, void *ctx, PetscInt index)
{
  Scene      scene = (Scene)ctx;
  SceneSeam *seam  = &scene->seams[index];
  PetscInt   bend;

  PetscFunctionBeginUser;
  PetscCall(SceneSeamSetDefaults(seam, index));
  bend = seam->bend;
  PetscCall(SceneExpectMap(r, map, "seams", SceneSeamKeys, NULL));
  PetscCall(SceneKeyName(r, map, "name", PETSC_FALSE, seam->name, sizeof(seam->name), NULL));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "seam '%s'", seam->name));
  PetscCall(SceneReadSeamSide(r, map, "a", scene, &seam->a));
  PetscCall(SceneReadSeamSide(r, map, "b", scene, &seam->b));
  PetscCall(SceneCheckSeamSidesApart(r, map, scene, seam));
  PetscCall(SceneCheckSeamLengths(r, map, scene, seam));
  PetscCall(SceneKeyChoice(r, map, "bend", PETSC_FALSE, SceneBooleans, &bend));
  seam->bend = bend ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneReadSeams(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const SceneList list = {"seams", "a list of seams (maps with a, b and optionally name, bend)", PETSC_FALSE, SCENE_MAX_SEAMS, "what a checkpoint stores exactly: the sewn seams of a particle are bits of a float64", sizeof(SceneSeam), SceneReadSeam};

  PetscFunctionBeginUser;
  PetscCall(SceneReadList(r, root, &list, scene, &scene->seams, &scene->nseams));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The sewing: block; its defaults (SceneSetDefaults) hold without it. */
PetscErrorCode SceneReadSewing(SceneReader *r, yaml_node_t *root, SceneSewing *sewing)
{
  yaml_node_t *map;

  PetscFunctionBeginUser;
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
