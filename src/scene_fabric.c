/* The fabrics: block of the scene (scene_impl.h): a map of fabric name -> its properties, each given directly, as
   a measured fabric's (preset:) or from KES-F values (kes:) taken as the defaults of the other keys, with the
   cross-checks of models and values (hysteresis needs its model, the bias rigidity at least what the threads give). */
#include "scene_impl.h"
#include "fabric_presets.h"
#include "fabric.h"

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
  PetscCall(SceneFabricSetDefaults(fabric));
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

PetscErrorCode SceneReadFabrics(SceneReader *r, yaml_node_t *root, Scene scene)
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
