/* The generic part of the scene reader (the schema and the blocks are in src/scene.c and its files, scene_impl.h):
   typed access to the keys of a YAML map parsed by libyaml's document API, each error one line naming the file,
   the line (libyaml's mark, 1-based), the key and the block, what was expected and what was found:
     scene FILE, line L: key 'KEY' in fabric 'NAME': expected a positive number (kg/m^2), got '-1'
   Every function is collective on the reader's communicator: every rank parses the same bytes and fails or
   succeeds alike. Keys: SceneKey* read map[key] into their output, which keeps its default when the key is
   absent and not required. */
#pragma once
#include <yaml.h>
#include <petscsys.h>
#include "util.h"

#define SCENE_TEXT_LEN 1024    /* room for an expectation or a description in a message */
#define SCENE_DESCRIBE_DEPTH 3 /* nested lists shown in messages (aliases may make cycles) */

/* 1-based line of a node, as editors count */
#define SceneNodeLine(node) ((int)(node)->start_mark.line + 1)

/* Admissible ranges of real values; each has the words used in messages. */
typedef enum {
  SCENE_REAL_ANY,
  SCENE_REAL_POSITIVE,
  SCENE_REAL_NONNEGATIVE,
  SCENE_REAL_FRACTION /* [0, 1) */
} SceneRealRange;

/* An upper bound of the magnitude of a real key (in blocks whose name starts with block; "" any block): beyond it
   the value is no physical cloth scene but a typo or a unit mistake (1e308, mg for kg, mm for m), which would
   overflow the arithmetic or throw the fabric; why says so in the message. A positive key may also have a lower
   bound min (0: none), below which it is as absurd (a density of 1e-300 kg/m^2 leaves the implicit system without
   mass: the first Krylov solve fails), why_min saying so. docs/scene_format.md lists them. */
typedef struct {
  const char *block, *key;
  PetscReal   max;
  const char *why;
  PetscReal   min;
  const char *why_min;
} SceneRealBound;

/* What is being read: the document, its file (for messages), the block being read and the bounds of its reals. */
typedef struct {
  MPI_Comm              comm;
  const char           *path;
  yaml_document_t      *doc;
  char                  block[2 * CLOTH_NAME_LEN + 16]; /* the block being read: "fabric 'net'", "piece 2", "run"; "" at the top level */
  const SceneRealBound *bounds;                         /* upper bounds of real keys, ended by a NULL key */
} SceneReader;

/* YAML booleans, in the enum-list style of SceneKeyChoice (index 0 = false, 1 = true). */
extern const char *const SceneBooleans[];
/* The rule of names (of the scene, pieces, bodies, seams), in messages. */
#define SCENE_NAME_RULE "letters, digits and _ . + - only, not starting with '.'"

/* Appends a short rendering of a node to buf: plain scalars as written, quoted ones in quotes, lists in brackets. */
PetscErrorCode SceneDescribeAppend(SceneReader *r, yaml_node_t *node, int depth, char buf[], size_t len);

/* What a node holds, for "got ...": 'text', "quoted text" (a quoted string), [a, b], a map, an empty map, nothing. */
PetscErrorCode SceneDescribeNode(SceneReader *r, yaml_node_t *node, char buf[], size_t len);

/* Joins n names (n < 0: up to the NULL) into "a, b, c". */
PetscErrorCode SceneJoinNames(const char *const names[], PetscInt n, char buf[], size_t len);

/* Where in the file: "key 'K' in fabric 'net'", "key 'K'", "fabric 'net'" (key NULL) or "the top level". */
PetscErrorCode SceneWhere(SceneReader *r, const char key[], char buf[], size_t len);

/* Fails with "scene F, line L: key 'K' in B: expected <fmt...>, got <value>" (key NULL: the block itself). */
PetscErrorCode SceneFailValue(SceneReader *r, yaml_node_t *value, const char key[], const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(4, 5);

/* Fails with "scene F, line L: key 'K' in B is missing: expected <fmt...>", L being the line of the block. */
PetscErrorCode SceneFailMissing(SceneReader *r, yaml_node_t *map, const char key[], const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(4, 5);

/* "a positive number (kg/m^2)" (count 0) or "a list of 3 numbers (m/s^2)" */
PetscErrorCode SceneExpectReal(PetscInt count, SceneRealRange range, const char unit[], char buf[], size_t len);

/* The bound of key in the block being read (key_warp and key_weft share key's), or NULL. */
const SceneRealBound *SceneRealBoundOf(SceneReader *r, const char key[]);

/* "an integer >= 2" (count 0) or "a list of 2 integers >= 2"; min PETSC_MIN_INT: no bound */
PetscErrorCode SceneExpectInt(PetscInt count, PetscInt min, char buf[], size_t len);

/* The value of key in map, or NULL when absent. */
PetscErrorCode SceneGetValue(SceneReader *r, yaml_node_t *map, const char key[], yaml_node_t **value);

/* The value of key, or NULL when absent and not required; a missing required key is an error. */
PetscErrorCode SceneGetValueChecked(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, const char expected[], yaml_node_t **value);

/* Whether map has key. */
PetscErrorCode SceneHasKey(SceneReader *r, yaml_node_t *map, const char key[], PetscBool *has);

/* Every key of map is a scalar, appears once and (keys not NULL) is one of keys. */
PetscErrorCode SceneCheckKeys(SceneReader *r, yaml_node_t *map, const char *const keys[]);

/* node (the value of key; key NULL: a block) must be a map whose keys are among keys (NULL: any unique names,
   described by what). */
PetscErrorCode SceneExpectMap(SceneReader *r, yaml_node_t *node, const char key[], const char *const keys[], const char what[]);

/* node must be a list of count items (count < 0: any number); returns its items. */
PetscErrorCode SceneGetItems(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, const char expected[], yaml_node_item_t **items, PetscInt *n);

/* A plain scalar (numbers must not be quoted). On failure the message shows errnode (the list holding node). */
PetscErrorCode SceneGetNumberText(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], const char expected[], const char **text);

/* A real in range (and within the reader's bound of key) from a plain scalar; on failure the message says
   expected and shows errnode. */
PetscErrorCode SceneParseReal(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], SceneRealRange range, const char expected[], PetscReal *value);

/* An integer >= min (and <= PETSC_MAX_INT) from a plain scalar; on failure as SceneParseReal. */
PetscErrorCode SceneParseInt(SceneReader *r, yaml_node_t *node, yaml_node_t *errnode, const char key[], PetscInt min, const char expected[], PetscInt *value);

/* A list of count reals (count < 0: any number), each as SceneParseReal. */
PetscErrorCode SceneParseRealList(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, SceneRealRange range, const char expected[], PetscReal values[]);

/* A list of count integers, each as SceneParseInt. */
PetscErrorCode SceneParseIntList(SceneReader *r, yaml_node_t *node, const char key[], PetscInt count, PetscInt min, const char expected[], PetscInt values[]);

/* A real in range, unit (may be NULL) named in messages. */
PetscErrorCode SceneKeyReal(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, SceneRealRange range, const char unit[], PetscReal *value);

/* A list of count reals in range. */
PetscErrorCode SceneKeyRealList(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt count, SceneRealRange range, const char unit[], PetscReal values[]);

/* An optional direction: 3 numbers, not all zero, normalised on return. */
PetscErrorCode SceneKeyDirection(SceneReader *r, yaml_node_t *map, const char key[], PetscReal dir[3]);

/* An integer >= min. */
PetscErrorCode SceneKeyInt(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt min, PetscInt *value);

/* An integer >= min and <= max: a count that sizes an allocation (an arc's segments) has an upper bound. */
PetscErrorCode SceneKeyIntInRange(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt min, PetscInt max, PetscInt *value);

/* A list of count integers >= min. */
PetscErrorCode SceneKeyIntList(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, PetscInt count, PetscInt min, PetscInt values[]);

/* A name: a non-empty scalar shorter than len; returns its node (NULL when absent) for later messages. */
PetscErrorCode SceneKeyString(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, char buf[], size_t len, yaml_node_t **where);

/* Names become file names, HDF5 groups and XDMF attributes: letters, digits and _ . + - only, not starting
   with '.', so that a name can neither leave the output directory ('/'), hide a file, nor break the XML ("<&>). */
PetscBool SceneNameIsSafe(const char name[]);

/* A name that goes into the output files (SceneNameIsSafe); returns its node like SceneKeyString. */
PetscErrorCode SceneKeyName(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, char buf[], size_t len, yaml_node_t **where);

/* Errors when name is also the name of one of the n earlier items of an array of structs whose first member
   is their name (pieces, bodies): two bodies of one name would write one mesh over the other. */
PetscErrorCode SceneCheckNameUnique(SceneReader *r, yaml_node_t *node, const char kind[], const char name[], const void *items, size_t stride, PetscInt n);

/* One of the names of a PETSc enum-style list (names..., type name, prefix, NULL); returns its index. */
PetscErrorCode SceneKeyChoice(SceneReader *r, yaml_node_t *map, const char key[], PetscBool required, const char *const choices[], PetscInt *index);

/* Reads item number index of a list block (SceneReadList) into the caller's array; ctx is the caller's (the scene). */
typedef PetscErrorCode (*SceneItemReader)(SceneReader *r, yaml_node_t *item, void *ctx, PetscInt index);

/* A top-level list of items (pieces:, bodies:, seams:) and how each item is read. */
typedef struct {
  const char     *key;       /* its key in the top-level map */
  const char     *expected;  /* what it must be, in messages */
  PetscBool       required;  /* it must be given, with at least one item */
  PetscInt        max;       /* the most items (< 0: any number) */
  const char     *why_max;   /* why, in the message */
  size_t          item_size; /* bytes of one item of the array */
  SceneItemReader read_item; /* reads one item */
} SceneList;

/* Reads root[list->key], a list of items: *n items, in *items (the address of the array's pointer), allocated and
   zeroed, each read in order by list->read_item; r->block is "" afterwards. Absent and not required: *n and *items
   are left as they are. */
PetscErrorCode SceneReadList(SceneReader *r, yaml_node_t *root, const SceneList *list, void *ctx, void *items, PetscInt *n);

/* The deepest nesting of lists and maps a scene may have; a scene needs 6 (pieces, a piece, its boundaries, a
   boundary, a point under the top-level map). */
#define SCENE_MAX_DEPTH 32

/* Errors (naming the file and the line) when the YAML bytes nest lists and maps more than max_depth levels deep.
   libyaml's scanner takes time quadratic in the depth of flow collections ([[[...]]]: it checks every open level at
   every token; measured 8.7 s for 40,000 levels, so about 1.5 hours for a million), while a document of that depth
   cannot be a scene. The check reads libyaml's events, so it stops at the first level too deep, after O(max_depth^2)
   work. A syntax error is left to the loader, which reports it. Collective on comm (every rank reads the same bytes). */
PetscErrorCode SceneCheckNesting(MPI_Comm comm, const char path[], const char bytes[], size_t len, int max_depth);

/* Fails with libyaml's description of a syntax error. */
PetscErrorCode SceneFailSyntax(MPI_Comm comm, const char path[], yaml_parser_t *parser);
