/* The generic scene reader: see scene_reader.h. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scene_reader.h"

static const char *const SceneRealRangeAdjective[] = {"", "positive ", "non-negative ", ""};
static const char *const SceneRealRangeSuffix[]    = {"", "", "", " in [0, 1)"};

/* YAML booleans, in the enum-list style of SceneKeyChoice (index 0 = false, 1 = true). */
const char *const SceneBooleans[] = {"false", "true", "SceneBoolean", "SCENE_BOOLEAN_", NULL};

/* ------------------------------------------------------------------------------------------------------------ */
/* Messages                                                                                                     */

/* Appends a short rendering of a node to buf: plain scalars as written, quoted ones in quotes, lists in brackets. */
PetscErrorCode SceneDescribeAppend(SceneReader *r, yaml_node_t *node, int depth, char buf[], size_t len)
{
  PetscFunctionBeginUser;
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  if (node->type == YAML_SCALAR_NODE) {
    PetscBool plain = node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE ? PETSC_TRUE : PETSC_FALSE;
    if (!plain) PetscCall(PetscStrlcat(buf, "\"", len));
    PetscCall(PetscStrlcat(buf, (const char *)node->data.scalar.value, len));
    if (!plain) PetscCall(PetscStrlcat(buf, "\"", len));
  } else if (node->type == YAML_SEQUENCE_NODE && depth < SCENE_DESCRIBE_DEPTH) {
    PetscCall(PetscStrlcat(buf, "[", len));
    for (yaml_node_item_t *item = node->data.sequence.items.start; item < node->data.sequence.items.top; item++) {
      if (item > node->data.sequence.items.start) PetscCall(PetscStrlcat(buf, ", ", len));
      PetscCall(SceneDescribeAppend(r, yaml_document_get_node(r->doc, *item), depth + 1, buf, len));
    }
    PetscCall(PetscStrlcat(buf, "]", len));
  } else {
    PetscCall(PetscStrlcat(buf, node->type == YAML_MAPPING_NODE ? "{...}" : "[...]", len));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What a node holds, for "got ...": 'text', "quoted text" (a quoted string), [a, b], a map, an empty map, nothing. */
PetscErrorCode SceneDescribeNode(SceneReader *r, yaml_node_t *node, char buf[], size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  if (node->type == YAML_MAPPING_NODE)
    PetscCall(PetscStrncpy(buf, node->data.mapping.pairs.top > node->data.mapping.pairs.start ? "a map" : "an empty map", len));
  else if (node->type == YAML_SEQUENCE_NODE)
    PetscCall(SceneDescribeAppend(r, node, 0, buf, len));
  else if (node->data.scalar.style != YAML_PLAIN_SCALAR_STYLE) {
    PetscCall(SceneDescribeAppend(r, node, 0, buf, len));
    PetscCall(PetscStrlcat(buf, " (a quoted string)", len));
  } else if (node->data.scalar.length == 0)
    PetscCall(PetscStrncpy(buf, "nothing", len));
  else
    PetscCall(PetscSNPrintf(buf, len, "'%s'", (const char *)node->data.scalar.value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Joins n names (n < 0: up to the NULL) into "a, b, c". */
PetscErrorCode SceneJoinNames(const char *const names[], PetscInt n, char buf[], size_t len)
{
  PetscFunctionBeginUser;
  buf[0] = 0;
  for (PetscInt i = 0; (n < 0 || i < n) && names[i]; i++) {
    if (i) PetscCall(PetscStrlcat(buf, ", ", len));
    PetscCall(PetscStrlcat(buf, names[i], len));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Where in the file: "key 'K' in fabric 'net'", "key 'K'", "fabric 'net'" (key NULL) or "the top level". */
PetscErrorCode SceneWhere(SceneReader *r, const char key[], char buf[], size_t len)
{
  PetscFunctionBeginUser;
  if (key && r->block[0])
    PetscCall(PetscSNPrintf(buf, len, "key '%s' in %s", key, r->block));
  else if (key)
    PetscCall(PetscSNPrintf(buf, len, "key '%s'", key));
  else
    PetscCall(PetscStrncpy(buf, r->block[0] ? r->block : "the top level", len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Fails with "scene F, line L: key 'K' in B: expected <fmt...>, got <value>" (key NULL: the block itself). */
PetscErrorCode SceneFailValue(SceneReader *r, yaml_node_t *value, const char key[], const char fmt[], ...)
{
  char    expected[SCENE_TEXT_LEN], got[SCENE_TEXT_LEN], where[SCENE_TEXT_LEN];
  va_list args;

  PetscFunctionBeginUser;
  va_start(args, fmt);
  vsnprintf(expected, sizeof(expected), fmt, args);
  va_end(args);
  PetscCall(SceneDescribeNode(r, value, got, sizeof(got)));
  PetscCall(SceneWhere(r, key, where, sizeof(where)));
  SETERRQ(r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: %s: expected %s, got %s", r->path, SceneNodeLine(value), where, expected, got);
}

/* Fails with "scene F, line L: key 'K' in B is missing: expected <fmt...>", L being the line of the block. */
PetscErrorCode SceneFailMissing(SceneReader *r, yaml_node_t *map, const char key[], const char fmt[], ...)
{
  char    expected[SCENE_TEXT_LEN], where[SCENE_TEXT_LEN];
  va_list args;

  PetscFunctionBeginUser;
  va_start(args, fmt);
  vsnprintf(expected, sizeof(expected), fmt, args);
  va_end(args);
  PetscCall(SceneWhere(r, key, where, sizeof(where)));
  SETERRQ(r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: %s is missing: expected %s", r->path, SceneNodeLine(map), where, expected);
}

/* "a positive number (kg/m^2)" (count 0) or "a list of 3 numbers (m/s^2)" */
PetscErrorCode SceneExpectReal(PetscInt count, SceneRealRange range, const char unit[], char buf[], size_t len)
{
  char units[CLOTH_NAME_LEN] = "";

  PetscFunctionBeginUser;
  if (unit) PetscCall(PetscSNPrintf(units, sizeof(units), " (%s)", unit));
  if (count)
    PetscCall(PetscSNPrintf(buf, len, "a list of %" PetscInt_FMT " %snumbers%s%s", count, SceneRealRangeAdjective[range], SceneRealRangeSuffix[range], units));
  else
    PetscCall(PetscSNPrintf(buf, len, "a %snumber%s%s", SceneRealRangeAdjective[range], SceneRealRangeSuffix[range], units));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The bound of key in the block being read (key_warp and key_weft share key's), or NULL. */
const SceneRealBound *SceneRealBoundOf(SceneReader *r, const char key[])
{
  char   base[CLOTH_NAME_LEN];
  size_t n = strlen(key);

  snprintf(base, sizeof(base), "%s", key);
  if (n > 5 && (!strcmp(key + n - 5, "_warp") || !strcmp(key + n - 5, "_weft"))) base[n - 5] = 0;
  for (const SceneRealBound *b = r->bounds; b && b->key; b++)
    if (!strcmp(b->key, base) && !strncmp(r->block, b->block, strlen(b->block))) return b;
  return NULL;
}

/* "an integer >= 2" (count 0) or "a list of 2 integers >= 2"; min PETSC_MIN_INT: no bound */
PetscErrorCode SceneExpectInt(PetscInt count, PetscInt min, char buf[], size_t len)
{
  char bound[CLOTH_NAME_LEN] = "";

  PetscFunctionBeginUser;
  if (min > PETSC_MIN_INT) PetscCall(PetscSNPrintf(bound, sizeof(bound), " >= %" PetscInt_FMT, min));
  if (count)
    PetscCall(PetscSNPrintf(buf, len, "a list of %" PetscInt_FMT " integers%s", count, bound));
  else
    PetscCall(PetscSNPrintf(buf, len, "an integer%s", bound));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Nodes                                                                                                        */

/* The value of key in map, or NULL when absent. */
PetscErrorCode SceneGetValue(SceneReader *r, yaml_node_t *map, const char key[], yaml_node_t **value)
{
  PetscFunctionBeginUser;
  *value = NULL;
  for (yaml_node_pair_t *pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top; pair++) {
    yaml_node_t *k = yaml_document_get_node(r->doc, pair->key);
    PetscBool    match;

    PetscCall(PetscStrcmp((const char *)k->data.scalar.value, key, &match)); /* keys were checked to be scalars */
    if (match) {
      *value = yaml_document_get_node(r->doc, pair->value);
      break;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The value of key, or NULL when absent and not required; a missing required key is an error. */
PetscErrorCode SceneGetValueChecked(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, const char expected[], yaml_node_t **value)
{
  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, key, value));
  if (!*value && required) PetscCall(SceneFailMissing(r, map, key, "%s", expected));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneHasKey(SceneReader *r, yaml_node_t *map, const char key[], PetscBool *has)
{
  yaml_node_t *value;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, key, &value));
  *has = value ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every key of map is a scalar, appears once and (keys not NULL) is one of keys. */
PetscErrorCode SceneCheckKeys(SceneReader *r, yaml_node_t *map, const char *const keys[])
{
  char allowed[SCENE_TEXT_LEN] = "", where[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  if (keys) PetscCall(SceneJoinNames(keys, -1, allowed, sizeof(allowed)));
  for (yaml_node_pair_t *pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top; pair++) {
    yaml_node_t *k = yaml_document_get_node(r->doc, pair->key);
    const char  *name;
    PetscBool    known = keys ? PETSC_FALSE : PETSC_TRUE;

    if (k->type != YAML_SCALAR_NODE) PetscCall(SceneFailValue(r, k, NULL, "a name as key, one of %s", keys ? allowed : "the names"));
    name = (const char *)k->data.scalar.value;
    PetscCall(SceneWhere(r, name, where, sizeof(where)));
    for (PetscInt i = 0; keys && keys[i] && !known; i++) PetscCall(PetscStrcmp(name, keys[i], &known));
    PetscCheck(known, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: %s is not allowed: expected one of %s", r->path, SceneNodeLine(k), where, allowed);
    for (yaml_node_pair_t *prev = map->data.mapping.pairs.start; prev < pair; prev++) {
      yaml_node_t *p = yaml_document_get_node(r->doc, prev->key);
      PetscBool    same;

      PetscCall(PetscStrcmp(name, (const char *)p->data.scalar.value, &same));
      PetscCheck(!same, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: %s is given twice (lines %d and %d): expected each key once", r->path, SceneNodeLine(k), where, SceneNodeLine(p), SceneNodeLine(k));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* node (the value of key; key NULL: a block) must be a map whose keys are among keys (NULL: any unique names,
   described by what). */
PetscErrorCode SceneExpectMap(SceneReader *r, yaml_node_t *node, const char key[], const char *const keys[], const char what[])
{
  char allowed[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  if (node->type != YAML_MAPPING_NODE) {
    if (keys) PetscCall(SceneJoinNames(keys, -1, allowed, sizeof(allowed)));
    PetscCall(SceneFailValue(r, node, key, "%s%s", keys ? "a map with keys among " : what, keys ? allowed : ""));
  }
  PetscCall(SceneCheckKeys(r, node, keys));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* node must be a list of count items (count < 0: any number); returns its items. */
PetscErrorCode SceneGetItems(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, const char expected[], yaml_node_item_t **items, PetscInt *n)
{
  PetscFunctionBeginUser;
  if (node->type != YAML_SEQUENCE_NODE) PetscCall(SceneFailValue(r, node, key, "%s", expected));
  *items = node->data.sequence.items.start;
  *n     = (PetscInt)(node->data.sequence.items.top - node->data.sequence.items.start);
  if (count >= 0 && *n != count) PetscCall(SceneFailValue(r, node, key, "%s", expected));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A plain scalar (numbers must not be quoted). On failure the message shows errnode (the list holding node). */
PetscErrorCode SceneGetNumberText(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], const char expected[], const char **text)
{
  PetscFunctionBeginUser;
  if (node->type != YAML_SCALAR_NODE || node->data.scalar.style != YAML_PLAIN_SCALAR_STYLE || node->data.scalar.length == 0) PetscCall(SceneFailValue(r, errnode, key, "%s", expected));
  *text = (const char *)node->data.scalar.value;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneParseReal(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], SceneRealRange range, const char expected[], PetscReal *value)
{
  const SceneRealBound *bound = SceneRealBoundOf(r, key);
  const char           *text  = NULL;
  char                 *end;
  double                x;
  PetscBool             ok;

  PetscFunctionBeginUser;
  PetscCall(SceneGetNumberText(r, node, errnode, key, expected, &text));
  errno = 0;
  x     = strtod(text, &end);
  ok    = (*end == 0 && errno == 0 && isfinite(x)) ? PETSC_TRUE : PETSC_FALSE;
  if (range == SCENE_REAL_POSITIVE) ok = (ok && x > 0) ? PETSC_TRUE : PETSC_FALSE;
  if (range == SCENE_REAL_NONNEGATIVE) ok = (ok && x >= 0) ? PETSC_TRUE : PETSC_FALSE;
  if (range == SCENE_REAL_FRACTION) ok = (ok && x >= 0 && x < 1) ? PETSC_TRUE : PETSC_FALSE;
  if (!ok) PetscCall(SceneFailValue(r, errnode, key, "%s", expected));
  if (bound && PetscAbsReal((PetscReal)x) > bound->max) PetscCall(SceneFailValue(r, errnode, key, "%s, of magnitude at most %g (beyond: %s)", expected, (double)bound->max, bound->why));
  if (bound && PetscAbsReal((PetscReal)x) < bound->min) PetscCall(SceneFailValue(r, errnode, key, "%s, of at least %g (below: %s)", expected, (double)bound->min, bound->why_min));
  *value = (PetscReal)x;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An integer in [min, max] from a plain scalar; on failure as SceneParseReal. */
static PetscErrorCode ParseIntInRange(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], PetscInt min, PetscInt max, const char expected[], PetscInt *value)
{
  const char *text = NULL;
  char       *end;
  long long   x;

  PetscFunctionBeginUser;
  PetscCall(SceneGetNumberText(r, node, errnode, key, expected, &text));
  errno = 0;
  x     = strtoll(text, &end, 10);
  if (*end || errno || x < min || x > max) PetscCall(SceneFailValue(r, errnode, key, "%s", expected));
  *value = (PetscInt)x;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneParseInt(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], PetscInt min, const char expected[], PetscInt *value)
{
  PetscFunctionBeginUser;
  PetscCall(ParseIntInRange(r, node, errnode, key, min, PETSC_MAX_INT, expected, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneParseRealList(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, SceneRealRange range, const char expected[], PetscReal values[])
{
  yaml_node_item_t *items = NULL;
  PetscInt          n;

  PetscFunctionBeginUser;
  PetscCall(SceneGetItems(r, node, key, count, expected, &items, &n));
  for (PetscInt i = 0; i < n; i++) PetscCall(SceneParseReal(r, yaml_document_get_node(r->doc, items[i]), node, key, range, expected, &values[i]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneParseIntList(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, PetscInt min, const char expected[], PetscInt values[])
{
  yaml_node_item_t *items = NULL;
  PetscInt          n;

  PetscFunctionBeginUser;
  PetscCall(SceneGetItems(r, node, key, count, expected, &items, &n));
  for (PetscInt i = 0; i < n; i++) PetscCall(SceneParseInt(r, yaml_document_get_node(r->doc, items[i]), node, key, min, expected, &values[i]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Keys: each reads map[key] into its output, which keeps its default when the key is absent and not required.  */

PetscErrorCode SceneKeyReal(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, SceneRealRange range, const char unit[], PetscReal *value)
{
  char         expected[SCENE_TEXT_LEN];
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneExpectReal(0, range, unit, expected, sizeof(expected)));
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (node) PetscCall(SceneParseReal(r, node, node, key, range, expected, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneKeyRealList(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt count, SceneRealRange range, const char unit[], PetscReal values[])
{
  char         expected[SCENE_TEXT_LEN];
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneExpectReal(count, range, unit, expected, sizeof(expected)));
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (node) PetscCall(SceneParseRealList(r, node, key, count, range, expected, values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* An optional direction: 3 numbers, not all zero, normalised on return. */
PetscErrorCode SceneKeyDirection(SceneReader *r, yaml_node_t *map, const char key[], PetscReal dir[3])
{
  const char   expected[] = "a nonzero direction (a list of 3 numbers)";
  yaml_node_t *node;
  PetscReal    norm;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValue(r, map, key, &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneParseRealList(r, node, key, 3, SCENE_REAL_ANY, expected, dir));
  norm = PetscSqrtReal(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
  if (!(norm > 0) || PetscIsInfOrNanReal(norm)) PetscCall(SceneFailValue(r, node, key, "%s", expected));
  for (PetscInt d = 0; d < 3; d++) dir[d] /= norm;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* map[key] as an integer in [min, max], refused with expected. */
static PetscErrorCode KeyIntInRange(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt min, PetscInt max, const char expected[], PetscInt *value)
{
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (node) PetscCall(ParseIntInRange(r, node, node, key, min, max, expected, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneKeyInt(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt min, PetscInt *value)
{
  char expected[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  PetscCall(SceneExpectInt(0, min, expected, sizeof(expected)));
  PetscCall(KeyIntInRange(r, map, key, required, min, PETSC_MAX_INT, expected, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneKeyIntInRange(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt min, PetscInt max, PetscInt *value)
{
  char expected[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(expected, sizeof(expected), "an integer >= %" PetscInt_FMT " and <= %" PetscInt_FMT, min, max));
  PetscCall(KeyIntInRange(r, map, key, required, min, max, expected, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneKeyIntList(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt count, PetscInt min, PetscInt values[])
{
  char         expected[SCENE_TEXT_LEN];
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneExpectInt(count, min, expected, sizeof(expected)));
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (node) PetscCall(SceneParseIntList(r, node, key, count, min, expected, values));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A name: a non-empty scalar shorter than len; returns its node (NULL when absent) for later messages. */
PetscErrorCode SceneKeyString(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, char buf[], size_t len, yaml_node_t **where)
{
  char         expected[SCENE_TEXT_LEN];
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(expected, sizeof(expected), "a name (text of 1 to %d characters)", (int)len - 1));
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (where) *where = node;
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  if (node->type != YAML_SCALAR_NODE || node->data.scalar.length == 0 || node->data.scalar.length >= len) PetscCall(SceneFailValue(r, node, key, "%s", expected));
  PetscCall(PetscStrncpy(buf, (const char *)node->data.scalar.value, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Names become file names, HDF5 groups and XDMF attributes: letters, digits and _ . + - only, not starting
   with '.', so that a name can neither leave the output directory ('/'), hide a file, nor break the XML ("<&>). */
PetscBool SceneNameIsSafe(const char name[])
{
  if (!name[0] || name[0] == '.') return PETSC_FALSE;
  for (const char *c = name; *c; c++)
    if (!isalnum((unsigned char)*c) && !strchr("_.+-", *c)) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* A name that goes into the output files (SceneNameIsSafe); returns its node like SceneKeyString. */
PetscErrorCode SceneKeyName(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, char buf[], size_t len, yaml_node_t **where)
{
  yaml_node_t *node;

  PetscFunctionBeginUser;
  PetscCall(SceneKeyString(r, map, key, required, buf, len, &node));
  if (where) *where = node;
  if (node && !SceneNameIsSafe(buf)) PetscCall(SceneFailValue(r, node, key, "a name of 1 to %d characters: " SCENE_NAME_RULE, (int)len - 1));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Errors when name is also the name of one of the n earlier items of an array of structs whose first member
   is their name (pieces, bodies): two bodies of one name would write one mesh over the other. */
PetscErrorCode SceneCheckNameUnique(SceneReader *r, yaml_node_t *node, const char kind[], const char name[], const void *items, size_t stride, PetscInt n)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) {
    PetscBool same;

    PetscCall(PetscStrcmp(name, (const char *)items + (size_t)i * stride, &same));
    if (same) PetscCall(SceneFailValue(r, node, "name", "a name not used by another %s (%s %" PetscInt_FMT " is also called '%s')", kind, kind, i + 1, name));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One of the names of a PETSc enum-style list (names..., type name, prefix, NULL); returns its index. */
PetscErrorCode SceneKeyChoice(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, const char *const choices[], PetscInt *index)
{
  char         expected[SCENE_TEXT_LEN], names[SCENE_TEXT_LEN];
  yaml_node_t *node;
  PetscInt     n = 0;

  PetscFunctionBeginUser;
  while (choices[n]) n++;
  n -= 2; /* the type name and the prefix */
  PetscCall(SceneJoinNames(choices, n, names, sizeof(names)));
  PetscCall(PetscSNPrintf(expected, sizeof(expected), "one of %s", names));
  PetscCall(SceneGetValueChecked(r, map, key, required, expected, &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  if (node->type == YAML_SCALAR_NODE) {
    for (PetscInt i = 0; i < n; i++) {
      PetscBool match;

      PetscCall(PetscStrcmp((const char *)node->data.scalar.value, choices[i], &match));
      if (match) {
        *index = i;
        PetscFunctionReturn(PETSC_SUCCESS);
      }
    }
  }
  PetscCall(SceneFailValue(r, node, key, "%s", expected));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneReadList(SceneReader *r, yaml_node_t *root, const SceneList *list, void *ctx, void *items, PetscInt *n)
{
  yaml_node_t      *node;
  yaml_node_item_t *item = NULL;

  PetscFunctionBeginUser;
  PetscCall(SceneGetValueChecked(r, root, list->key, list->required, list->expected, &node));
  if (!node) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetItems(r, node, list->key, -1, list->expected, &item, n));
  if (list->required && *n == 0) PetscCall(SceneFailValue(r, node, list->key, "%s", list->expected));
  PetscCheck(list->max < 0 || *n <= list->max, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: key '%s': expected at most %" PetscInt_FMT " %s (%s), got %" PetscInt_FMT, r->path, SceneNodeLine(node), list->key, list->max, list->key, list->why_max,
             *n);
  PetscCall(PetscCalloc((size_t)*n * list->item_size, items));
  for (PetscInt i = 0; i < *n; i++) PetscCall(list->read_item(r, yaml_document_get_node(r->doc, item[i]), ctx, i));
  r->block[0] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneCheckNesting(MPI_Comm comm, const char path[], const char bytes[], size_t len, int max_depth)
{
  yaml_parser_t parser;
  yaml_event_t  event;
  int           depth = 0, line = 0, done = 0;

  PetscFunctionBeginUser;
  PetscCheck(yaml_parser_initialize(&parser), comm, PETSC_ERR_MEM, "libyaml could not create a parser");
  yaml_parser_set_input_string(&parser, (const unsigned char *)bytes, len);
  while (!done && depth <= max_depth && yaml_parser_parse(&parser, &event)) {
    if (event.type == YAML_SEQUENCE_START_EVENT || event.type == YAML_MAPPING_START_EVENT) depth++;
    if (event.type == YAML_SEQUENCE_END_EVENT || event.type == YAML_MAPPING_END_EVENT) depth--;
    line = (int)event.start_mark.line + 1;
    done = event.type == YAML_STREAM_END_EVENT;
    yaml_event_delete(&event);
  }
  yaml_parser_delete(&parser);
  PetscCheck(depth <= max_depth, comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: lists and maps nested more than %d levels deep: expected at most %d levels (a scene needs 6)", path, line, max_depth, max_depth);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Fails with libyaml's description of a syntax error. */
PetscErrorCode SceneFailSyntax(MPI_Comm comm, const char path[], yaml_parser_t *parser)
{
  char context[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (parser->context) PetscCall(PetscSNPrintf(context, sizeof(context), " (%s at line %d)", parser->context, (int)parser->context_mark.line + 1));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "scene %s, line %d: YAML syntax error: %s%s: expected a well-formed YAML document", path, (int)parser->problem_mark.line + 1, parser->problem ? parser->problem : "unknown problem", context);
}
