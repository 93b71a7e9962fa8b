/* The pieces: list of the scene (scene_impl.h): each piece's fabric, grid, rectangle or outline of four boundaries
   (polylines or arcs, joined at the corners, no folded cell), placement (origin, axes, wrap onto a cylinder or a
   cone), mass distribution, pins and pinned or cut regions; the geometry of a piece the other blocks check against
   (its particle spacing, its pins on the current grid). */
#include "scene_impl.h"
#include "pattern.h"

/* The largest distance between neighbouring particles of a piece in its flat layout, m (from its size, or the
   bounding box of its outline). */
PetscReal ScenePieceLargestSpacing(const ScenePiece *piece)
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

/* Resolves pins_given (negative: from the end) into pins for the piece's current grid. */
PetscErrorCode ScenePieceResolvePins(MPI_Comm comm, const char path[], ScenePiece *piece)
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

/* Item index of the pieces: list (a SceneItemReader; ctx: the scene). */
static PetscErrorCode SceneReadPiece(SceneReader *r, yaml_node_t *map, void *ctx, PetscInt index)
{
  Scene        scene = (Scene)ctx;
  ScenePiece  *piece = &scene->pieces[index];
  yaml_node_t *name;
  PetscInt     mass = CLOTH_MASS_AREA;

  PetscFunctionBeginUser;
  PetscCall(ScenePieceSetDefaults(piece));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "piece %" PetscInt_FMT, index + 1));
  PetscCall(SceneExpectMap(r, map, NULL, ScenePieceKeys, NULL));
  PetscCall(SceneKeyName(r, map, "name", PETSC_TRUE, piece->name, sizeof(piece->name), &name));
  PetscCall(SceneCheckNameUnique(r, name, "piece", piece->name, scene->pieces, sizeof(ScenePiece), index));
  PetscCall(PetscSNPrintf(r->block, sizeof(r->block), "piece '%s'", piece->name));
  PetscCall(ReadFabricName(r, map, scene, piece));
  PetscCall(ReadGridAndSize(r, map, piece));
  PetscCall(SceneKeyRealList(r, map, "origin", PETSC_FALSE, 3, SCENE_REAL_ANY, "m", piece->origin));
  PetscCall(ReadAxes(r, map, piece));
  PetscCall(ReadWrap(r, map, piece));
  PetscCall(SceneKeyChoice(r, map, "mass", PETSC_FALSE, ClothMassDistributions, &mass));
  piece->mass_distribution = (ClothMassDistribution)mass;
  PetscCall(ReadPins(r, map, piece));
  PetscCall(ReadPinRegions(r, map, piece));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneReadPieces(SceneReader *r, yaml_node_t *root, Scene scene)
{
  const SceneList list = {"pieces", "a list of pieces, with at least one piece", PETSC_TRUE, -1, NULL, sizeof(ScenePiece), SceneReadPiece};

  PetscFunctionBeginUser;
  PetscCall(SceneReadList(r, root, &list, scene, &scene->pieces, &scene->npieces));
  PetscCall(SceneCheckParticleCount(scene, ""));
  scene->single_grid = scene->npieces == 1 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}
