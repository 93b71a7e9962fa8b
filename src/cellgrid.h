/* CellGrid: a uniform grid of cubic cells over a box, each cell listing the items whose boxes touch it
   (compressed rows). The one spatial index of the contact searches: the triangles of a mesh body near this
   rank's particles (collision_search.c) and the cloth's triangles and edges (selfcontact.c).

   Queries: the cells a box touches (CellGridGetCellRange) and the cells a segment passes through, in order
   (CellGridWalkBegin/Next, Amanatides & Woo's 3D DDA). An item may be listed in several cells, so a query
   that visits several cells meets it more than once; callers mark what they have tested. A grid is local
   to a rank (no communication). The accessors and queries cannot fail and are called from the innermost
   search loops, so they return their results rather than an error code. */
#pragma once
#include "util.h"

typedef struct _n_CellGrid *CellGrid;

/* The cells a segment passes through (see CellGridWalkBegin); its fields are the walk's own. */
typedef struct {
  PetscInt  cell[3], step[3];
  PetscReal tmax[3], tdelta[3], t1;
  PetscBool done;
} CellGridWalk;

PetscErrorCode CellGridCreate(CellGrid *grid);
/* Covers the box [lo, hi] with cubic cells of edge cell_size, grown by a factor 1.5 while there would be
   more than max_cells of them (so memory stays bounded whatever the box), and lists every item i < nitems
   whose box [item_lo + i stride, item_hi + i stride] (3 reals each) touches [lo, hi]. A box that is empty
   along some axis (lo >= hi) gives a grid without cells. Errors, rather than looping for ever, when a
   bound of the box or its extent is not finite, or the cell size is not positive (NaN included; +inf
   gives one cell); callers that can name the particle responsible check first. Not collective. */
PetscErrorCode CellGridBuild(CellGrid grid, const PetscReal lo[3], const PetscReal hi[3], PetscReal cell_size, PetscInt max_cells, PetscInt nitems, const PetscReal item_lo[], const PetscReal item_hi[], PetscInt stride);
/* Whether the last build gave cells (false before the first build and for an empty box). */
PetscBool CellGridHasCells(CellGrid grid);
/* The cells per axis n, the rows start (n0 n1 n2 + 1 entries: cell c lists items[start[c] .. start[c+1]))
   and the items; borrowed, valid until the next build. Cell (i, j, k) is c = (i n1 + j) n2 + k
   (CellGridCellIndex). */
void CellGridGetCells(CellGrid grid, PetscInt n[3], const PetscInt **start, const PetscInt **items);
/* Per item, the cell (i, j, k) of its box's low corner (clamped to the grid), 3 per item; borrowed. */
void                   CellGridGetItemLowCells(CellGrid grid, const PetscInt **low_cell);
static inline PetscInt CellGridCellIndex(const PetscInt n[3], PetscInt i, PetscInt j, PetscInt k)
{
  return (i * n[1] + j) * n[2] + k;
}
/* The cells [first, last] along each axis that the box [lo, hi] touches, clamped to the grid (first > last
   along every axis when the grid has no cells). */
void CellGridGetCellRange(CellGrid grid, const PetscReal lo[3], const PetscReal hi[3], PetscInt first[3], PetscInt last[3]);
/* Starts a walk along the segment p0 + t d, t in [0, 1], clipped to the grid's box; CellGridWalkNext then
   gives the cells it passes through, in order, and false when there are no more (at once when the segment
   misses the box or the grid has no cells). */
void           CellGridWalkBegin(CellGrid grid, const PetscReal p0[3], const PetscReal d[3], CellGridWalk *walk);
PetscBool      CellGridWalkNext(CellGrid grid, CellGridWalk *walk, PetscInt *cell);
PetscErrorCode CellGridDestroy(CellGrid *grid);
