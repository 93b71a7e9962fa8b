/* Pattern meshing: the flat 2D grid of a pattern piece (docs/model.md section 3).

   A piece is either a rectangle (size) or an outline of four boundaries, bottom, right, top, left:
   polylines in the pattern plane with any number of vertices. Bottom and top carry nu nodes, left and
   right nv nodes, placed at equal arc length along each boundary; interior nodes come from the
   transfinite (Coons) interpolation between opposite boundaries, so the grid follows the outline.
   Node (i, j): i along u (the warp), j along v (the weft); bottom is j = 0 (left to right), top
   j = nv - 1 (left to right), left i = 0 (bottom to top), right i = nu - 1 (bottom to top). */
#pragma once
#include "scene.h"

/* Fills uv (2 * nu * nv reals, caller-allocated) with the flat pattern coordinates, in metres, of
   particle (i, j) at uv[2 * (j * nu + i)]. Rejects folded or inverted cells with a clear error. */
PetscErrorCode PatternMeshPiece(const ScenePiece *piece, PetscReal uv[]);
/* Meshes the piece and returns the first grid cell (row by row) that is folded or inverted (signed area <= 0), or
 *i = *j = -1 when every cell is positive: lets the scene reader refuse a bad outline with its file and line. */
PetscErrorCode PatternFindFoldedCell(const ScenePiece *piece, PetscInt *i, PetscInt *j, PetscReal *area);
#define PATTERN_FOLD_ADVICE "expected bottom and top to run from left to right and left and right from bottom to top (counter-clockwise around the piece), and an outline not too concave for its node counts"
/* Places n >= 2 nodes (out: 2 n reals) at equal arc length along a polyline of npoints vertices (2 npoints
   reals), the first and last on its ends. */
PetscErrorCode PatternResampleByArcLength(PetscInt npoints, const PetscReal points[], PetscInt n, PetscReal out[]);
/* Area enclosed by the piece's outline as given (the four polylines joined, or the rectangle), m^2. */
PetscErrorCode PatternOutlineArea(const ScenePiece *piece, PetscReal *area);
/* Signed area of grid cell (i, j) of a piece with nu columns, from its flat coordinates. */
PetscReal PatternCellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j);
/* Whether grid cell (i, j) is fabric: every cell, or with cut_disc only those whose centre (the mean of their corners)
   lies in the disc. A cut piece keeps its whole grid; nodes outside every kept cell carry no fabric. */
PetscBool PatternCellKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j);
/* Whether the grid edge from node (i, j) to its neighbour (i + di, j + dj) (di + dj = 1) borders a kept cell. */
PetscBool PatternEdgeKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j, PetscInt di, PetscInt dj);
/* Whether node (i, j) is a corner of a kept cell. */
PetscBool PatternNodeKept(const ScenePiece *piece, const PetscReal uv[], PetscInt i, PetscInt j);
