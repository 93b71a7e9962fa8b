/* Pattern meshing (see pattern.h). */
#include "pattern.h"

enum { PATTERN_BOTTOM, PATTERN_RIGHT, PATTERN_TOP, PATTERN_LEFT };
static const char *const PatternBoundaryNames[] = {"bottom", "right", "top", "left"};

static PetscErrorCode PatternMeshRectangle(const ScenePiece *piece, PetscReal uv[])
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < piece->nv; j++)
    for (PetscInt i = 0; i < piece->nu; i++) {
      uv[2 * (j * piece->nu + i) + 0] = piece->size[0] * i / (piece->nu - 1);
      uv[2 * (j * piece->nu + i) + 1] = piece->size[1] * j / (piece->nv - 1);
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PatternResampleByArcLength(PetscInt npoints, const PetscReal points[], PetscInt n, PetscReal out[])
{
  PetscReal *length; /* arc length from the first vertex to vertex k */
  PetscInt   segment = 0;

  PetscFunctionBeginUser;
  PetscCheck(npoints >= 2 && n >= 2, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Resampling needs a polyline of at least 2 vertices and at least 2 nodes (got %" PetscInt_FMT " and %" PetscInt_FMT ")", npoints, n);
  PetscCall(PetscMalloc1(npoints, &length));
  length[0] = 0;
  for (PetscInt k = 1; k < npoints; k++) length[k] = length[k - 1] + PetscSqrtReal(PetscSqr(points[2 * k] - points[2 * k - 2]) + PetscSqr(points[2 * k + 1] - points[2 * k - 1]));
  PetscCheck(length[npoints - 1] > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "A boundary polyline has zero length: expected distinct vertices");
  for (PetscInt i = 0; i < n; i++) {
    const PetscReal target = length[npoints - 1] * i / (n - 1);
    PetscReal       t;

    while (segment < npoints - 2 && length[segment + 1] < target) segment++;
    t = (length[segment + 1] > length[segment]) ? (target - length[segment]) / (length[segment + 1] - length[segment]) : 0;
    t = PetscMin(PetscMax(t, 0.0), 1.0);
    for (PetscInt c = 0; c < 2; c++) out[2 * i + c] = (1 - t) * points[2 * segment + c] + t * points[2 * segment + 2 + c];
  }
  /* the ends exactly, so that the boundaries share their corner nodes bit for bit */
  for (PetscInt c = 0; c < 2; c++) {
    out[c]               = points[c];
    out[2 * (n - 1) + c] = points[2 * (npoints - 1) + c];
  }
  PetscCall(PetscFree(length));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The four sides' nodes at equal arc length: bottom and top nu nodes, right and left nv (2 reals each, allocated). */
static PetscErrorCode PatternResampleSides(const ScenePiece *piece, PetscReal *side[4])
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < 4; b++) {
    const PetscInt n = (b == PATTERN_BOTTOM || b == PATTERN_TOP) ? piece->nu : piece->nv;

    PetscCall(PetscMalloc1(2 * n, &side[b]));
    PetscCall(PatternResampleByArcLength(piece->boundary_npoints[b], piece->boundary_points[b], n, side[b]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Coons patch: x(s, t) = (1 - t) B(s) + t T(s) + (1 - s) L(t) + s R(t) - bilinear(corners), with s = i/(nu-1),
   t = j/(nv-1) and B, T, L, R the boundary nodes at equal arc length (so B(s_i) is node i of the bottom): row j of
   the grid (2 nu reals). */
static void TransfiniteRow(const ScenePiece *piece, PetscReal *const side[4], PetscInt j, PetscReal row[])
{
  const PetscInt nu = piece->nu, nv = piece->nv;

  for (PetscInt i = 0; i < nu; i++) {
    const PetscReal s = (PetscReal)i / (nu - 1), t = (PetscReal)j / (nv - 1);

    for (PetscInt c = 0; c < 2; c++) {
      const PetscReal corners = (1 - s) * (1 - t) * side[PATTERN_BOTTOM][c] + s * (1 - t) * side[PATTERN_BOTTOM][2 * (nu - 1) + c] + (1 - s) * t * side[PATTERN_TOP][c] + s * t * side[PATTERN_TOP][2 * (nu - 1) + c];

      row[2 * i + c] = (1 - t) * side[PATTERN_BOTTOM][2 * i + c] + t * side[PATTERN_TOP][2 * i + c] + (1 - s) * side[PATTERN_LEFT][2 * j + c] + s * side[PATTERN_RIGHT][2 * j + c] - corners;
    }
  }
}

static PetscErrorCode PatternMeshTransfinite(const ScenePiece *piece, PetscReal uv[])
{
  PetscReal *side[4];

  PetscFunctionBeginUser;
  PetscCall(PatternResampleSides(piece, side));
  for (PetscInt j = 0; j < piece->nv; j++) TransfiniteRow(piece, side, j, &uv[2 * j * piece->nu]);
  for (PetscInt b = 0; b < 4; b++) PetscCall(PetscFree(side[b]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Signed area of cell (i, j) (corners (i,j), (i+1,j), (i+1,j+1), (i,j+1)) by the shoelace formula. */
static PetscReal CellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j)
{
  const PetscInt c[4] = {j * nu + i, j * nu + i + 1, (j + 1) * nu + i + 1, (j + 1) * nu + i};
  PetscReal      area = 0;

  for (PetscInt k = 0; k < 4; k++) {
    const PetscReal *p = &uv[2 * c[k]], *q = &uv[2 * c[(k + 1) % 4]];
    area += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * area;
}

/* The first cell of row j of a grid of nu columns whose signed area is not positive (and *area), or -1. */
static PetscInt FirstFoldedCellOfRow(PetscInt nu, const PetscReal uv[], PetscInt j, PetscReal *area)
{
  for (PetscInt i = 0; i + 1 < nu; i++)
    if (!((*area = CellArea(nu, uv, i, j)) > 0)) return i;
  *area = 0;
  return -1;
}

/* The first cell (row by row) whose signed area is not positive; *i = -1 when there is none. */
static void FirstFoldedCell(const ScenePiece *piece, const PetscReal uv[], PetscInt *i, PetscInt *j, PetscReal *area)
{
  *i = *j = -1;
  *area   = 0;
  for (PetscInt jj = 0; jj + 1 < piece->nv && *i < 0; jj++)
    if ((*i = FirstFoldedCellOfRow(piece->nu, uv, jj, area)) >= 0) *j = jj;
}

static PetscErrorCode PatternMeshUnchecked(const ScenePiece *piece, PetscReal uv[])
{
  PetscFunctionBeginUser;
  if (piece->has_boundaries)
    PetscCall(PatternMeshTransfinite(piece, uv));
  else
    PetscCall(PatternMeshRectangle(piece, uv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Two rows of the grid at a time, so that the scene reader checks a grid of any size in O(nu + nv) memory: it runs
   before the run's memory check, and meshing the whole piece there took 16 bytes a particle (11 GB for the
   largest grid allowed) before the grid was known to fit. The first folded cell row by row, as FirstFoldedCell. */
PetscErrorCode PatternFindFoldedCell(const ScenePiece *piece, PetscInt *i, PetscInt *j, PetscReal *area)
{
  PetscReal *side[4], *rows; /* rows j and j + 1 */

  PetscFunctionBeginUser;
  *i = *j = -1;
  *area   = 0;
  if (!piece->has_boundaries) PetscFunctionReturn(PETSC_SUCCESS); /* a rectangle of positive size */
  PetscCall(PatternResampleSides(piece, side));
  PetscCall(PetscMalloc1(4 * piece->nu, &rows));
  TransfiniteRow(piece, side, 0, rows);
  for (PetscInt jj = 0; jj + 1 < piece->nv && *i < 0; jj++) {
    TransfiniteRow(piece, side, jj + 1, &rows[2 * piece->nu]);
    if ((*i = FirstFoldedCellOfRow(piece->nu, rows, 0, area)) >= 0) *j = jj;
    PetscCall(PetscArraycpy(rows, &rows[2 * piece->nu], 2 * piece->nu));
  }
  PetscCall(PetscFree(rows));
  for (PetscInt b = 0; b < 4; b++) PetscCall(PetscFree(side[b]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PatternMeshPiece(const ScenePiece *piece, PetscReal uv[])
{
  PetscInt  i, j;
  PetscReal area;

  PetscFunctionBeginUser;
  PetscCall(PatternMeshUnchecked(piece, uv));
  FirstFoldedCell(piece, uv, &i, &j, &area);
  PetscCheck(i < 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Piece '%s': grid cell (%" PetscInt_FMT ", %" PetscInt_FMT ") of its %" PetscInt_FMT " x %" PetscInt_FMT " grid is folded or inverted (area %g m^2): %s", piece->name, i, j, piece->nu,
             piece->nv, (double)area, PATTERN_FOLD_ADVICE);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PatternOutlineArea(const ScenePiece *piece, PetscReal *area)
{
  /* walk counter-clockwise: bottom forward, right forward, top backward, left backward */
  const PetscBool forward[4] = {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE, PETSC_FALSE};

  PetscFunctionBeginUser;
  if (!piece->has_boundaries) {
    *area = piece->size[0] * piece->size[1];
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  *area = 0;
  for (PetscInt b = 0; b < 4; b++) {
    const PetscInt   n = piece->boundary_npoints[b];
    const PetscReal *x = piece->boundary_points[b];

    for (PetscInt k = 0; k + 1 < n; k++) {
      const PetscReal *p = forward[b] ? &x[2 * k] : &x[2 * (n - 1 - k)], *q = forward[b] ? &x[2 * (k + 1)] : &x[2 * (n - 2 - k)];
      *area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
    }
  }
  PetscCheck(*area > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Piece '%s': its outline (%s, %s, %s reversed, %s reversed) encloses %g m^2: expected the boundaries to run counter-clockwise around the piece", piece->name, PatternBoundaryNames[0],
             PatternBoundaryNames[1], PatternBoundaryNames[2], PatternBoundaryNames[3], (double)*area);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscReal PatternCellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j)
{
  return CellArea(nu, uv, i, j);
}

PetscBool PatternCellKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j)
{
  const PetscInt c[4]      = {j * piece->nu + i, j * piece->nu + i + 1, (j + 1) * piece->nu + i + 1, (j + 1) * piece->nu + i};
  PetscReal      centre[2] = {0, 0};

  if (i < 0 || j < 0 || i + 1 >= piece->nu || j + 1 >= piece->nv) return PETSC_FALSE;
  if (!(piece->cut_disc[2] > 0)) return PETSC_TRUE;
  for (PetscInt k = 0; k < 4; k++)
    for (PetscInt d = 0; d < 2; d++) centre[d] += 0.25 * uv[2 * c[k] + d];
  return (PetscBool)(PetscSqr(centre[0] - piece->cut_disc[0]) + PetscSqr(centre[1] - piece->cut_disc[1]) <= PetscSqr(piece->cut_disc[2]));
}

PetscBool PatternEdgeKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j, PetscInt di, PetscInt dj)
{
  /* the cells on either side: below and above an edge along u, left and right of one along v */
  return (PetscBool)(PatternCellKept(piece, uv, i - dj, j - di) || PatternCellKept(piece, uv, i, j));
}

PetscBool PatternNodeKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j)
{
  return (PetscBool)(PatternCellKept(piece, uv, i - 1, j - 1) || PatternCellKept(piece, uv, i, j - 1) || PatternCellKept(piece, uv, i - 1, j) || PatternCellKept(piece, uv, i, j));
}
