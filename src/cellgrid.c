/* CellGrid (see cellgrid.h). */
#include "cellgrid.h"
#include "geometry.h"

#define CELL_GRID_GROWTH 1.5 /* the factor by which cells grow while there would be too many */

struct _n_CellGrid {
  PetscReal lo[3], hi[3]; /* the box covered */
  PetscReal h;            /* cell edge */
  PetscInt  n[3];         /* cells per axis; 0 when the box is empty */
  PetscInt *start, *item; /* CSR: the items touching each cell */
  PetscInt *low_cell;     /* per item: the cell (i, j, k) of its box's low corner */
};

PetscErrorCode CellGridCreate(CellGrid *grid)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscBool CellGridHasCells(CellGrid grid)
{
  return grid->n[0] > 0 ? PETSC_TRUE : PETSC_FALSE;
}

void CellGridGetCells(CellGrid grid, PetscInt n[3], const PetscInt **start, const PetscInt **items)
{
  for (PetscInt k = 0; k < 3; k++) n[k] = grid->n[k];
  *start = grid->start;
  *items = grid->item;
}

void CellGridGetItemLowCells(CellGrid grid, const PetscInt **low_cell)
{
  *low_cell = grid->low_cell;
}

void CellGridGetCellRange(CellGrid g, const PetscReal lo[3], const PetscReal hi[3], PetscInt first[3], PetscInt last[3])
{
  for (PetscInt k = 0; k < 3; k++) {
    if (!g->n[0]) {
      first[k] = 0, last[k] = -1;
      continue;
    }
    first[k] = (PetscInt)PetscFloorReal((lo[k] - g->lo[k]) / g->h);
    last[k]  = (PetscInt)PetscFloorReal((hi[k] - g->lo[k]) / g->h);
    first[k] = PetscMax(0, PetscMin(first[k], g->n[k] - 1));
    last[k]  = PetscMax(0, PetscMin(last[k], g->n[k] - 1));
  }
}

/* Terminates: with a finite extent (CellGridBuild checks it) and a positive h the count falls to 1 as h grows. */
static PetscErrorCode ChooseCellSize(CellGrid g, PetscReal h, PetscInt max_cells)
{
  PetscFunctionBeginUser;
  PetscCheck(h > 0, PETSC_COMM_SELF, PETSC_ERR_FP, "Cell grid: the cell size must be positive, got %g", (double)h); /* +inf: one cell */
  PetscCheck(max_cells >= 1, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "Cell grid: at least one cell must be allowed, got %" PetscInt_FMT, max_cells);
  for (;;) {
    PetscReal cells = 1;
    for (PetscInt k = 0; k < 3; k++) cells *= PetscFloorReal((g->hi[k] - g->lo[k]) / h) + 1;
    if (cells <= max_cells) break;
    h *= CELL_GRID_GROWTH;
  }
  g->h = h;
  for (PetscInt k = 0; k < 3; k++) g->n[k] = (PetscInt)PetscFloorReal((g->hi[k] - g->lo[k]) / h) + 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CellGridBuild(CellGrid g, const PetscReal lo[3], const PetscReal hi[3], PetscReal cell_size, PetscInt max_cells, PetscInt nitems, const PetscReal item_lo[], const PetscReal item_hi[], PetscInt stride)
{
  PetscBool empty = PETSC_FALSE;
  PetscInt  ncells, *fill, first[3], last[3];

  PetscFunctionBeginUser;
  PetscCall(PetscFree(g->start));
  PetscCall(PetscFree(g->item));
  PetscCall(PetscFree(g->low_cell));
  for (PetscInt k = 0; k < 3; k++) {
    PetscCheck(!PetscIsInfOrNanReal(lo[k]) && !PetscIsInfOrNanReal(hi[k]) && !PetscIsInfOrNanReal(hi[k] - lo[k]), PETSC_COMM_SELF, PETSC_ERR_FP,
               "Cell grid: the box [%g, %g] along axis %" PetscInt_FMT " is not finite or too large (a diverged state?)", (double)lo[k], (double)hi[k], k);
    g->lo[k] = lo[k];
    g->hi[k] = hi[k];
    g->n[k]  = 0;
    if (!(lo[k] < hi[k])) empty = PETSC_TRUE;
  }
  PetscCall(PetscMalloc1(3 * nitems + 1, &g->low_cell));
  if (empty) {
    for (PetscInt i = 0; i < 3 * nitems; i++) g->low_cell[i] = 0;
    PetscCall(PetscCalloc1(1, &g->start));
    PetscCall(PetscMalloc1(1, &g->item));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(ChooseCellSize(g, cell_size, max_cells));
  ncells = g->n[0] * g->n[1] * g->n[2];
  PetscCall(PetscCalloc1(ncells + 1, &g->start));
  PetscCall(PetscCalloc1(ncells, &fill));
  for (PetscInt pass = 0; pass < 2; pass++) { /* one pass counts, one fills */
    for (PetscInt b = 0; b < nitems; b++) {
      const PetscReal *blo = &item_lo[stride * b], *bhi = &item_hi[stride * b];

      CellGridGetCellRange(g, blo, bhi, first, last);
      for (PetscInt k = 0; k < 3; k++) g->low_cell[3 * b + k] = first[k];
      if (!GeometryBoxesOverlap(blo, bhi, g->lo, g->hi)) continue;
      for (PetscInt i = first[0]; i <= last[0]; i++)
        for (PetscInt j = first[1]; j <= last[1]; j++)
          for (PetscInt l = first[2]; l <= last[2]; l++) {
            const PetscInt c = CellGridCellIndex(g->n, i, j, l);
            if (pass == 0)
              g->start[c + 1]++;
            else
              g->item[g->start[c] + fill[c]++] = b;
          }
    }
    if (pass == 0) {
      for (PetscInt c = 0; c < ncells; c++) g->start[c + 1] += g->start[c];
      PetscCall(PetscMalloc1(g->start[ncells] + 1, &g->item));
    }
  }
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Clips p0 + t d to the grid's box: [*t0, *t1] (empty when *t0 > *t1). */
static void ClipToBox(CellGrid g, const PetscReal p0[3], const PetscReal d[3], PetscReal *t0, PetscReal *t1)
{
  *t0 = 0;
  *t1 = 1;
  for (PetscInt k = 0; k < 3 && *t0 <= *t1; k++) {
    if (d[k] == 0) {
      if (p0[k] < g->lo[k] || p0[k] > g->hi[k]) *t0 = 2;
      continue;
    }
    PetscReal ta = (g->lo[k] - p0[k]) / d[k], tb = (g->hi[k] - p0[k]) / d[k];
    *t0 = PetscMax(*t0, PetscMin(ta, tb));
    *t1 = PetscMin(*t1, PetscMax(ta, tb));
  }
}

void CellGridWalkBegin(CellGrid g, const PetscReal p0[3], const PetscReal d[3], CellGridWalk *w)
{
  PetscReal t0;

  w->done = PETSC_TRUE;
  if (!g->n[0]) return;
  ClipToBox(g, p0, d, &t0, &w->t1);
  if (t0 > w->t1) return;
  w->done = PETSC_FALSE;
  for (PetscInt k = 0; k < 3; k++) {
    const PetscReal s = p0[k] + t0 * d[k];
    w->cell[k]        = PetscMin(g->n[k] - 1, PetscMax(0, (PetscInt)PetscFloorReal((s - g->lo[k]) / g->h)));
    w->step[k]        = d[k] > 0 ? 1 : (d[k] < 0 ? -1 : 0);
    w->tmax[k]        = w->step[k] ? (g->lo[k] + (w->cell[k] + (w->step[k] > 0 ? 1 : 0)) * g->h - p0[k]) / d[k] : PETSC_MAX_REAL;
    w->tdelta[k]      = w->step[k] ? g->h / PetscAbsReal(d[k]) : PETSC_MAX_REAL;
  }
}

PetscBool CellGridWalkNext(CellGrid g, CellGridWalk *w, PetscInt *cell)
{
  PetscInt k = 0;

  if (w->done) return PETSC_FALSE;
  *cell = CellGridCellIndex(g->n, w->cell[0], w->cell[1], w->cell[2]);
  /* then step into the neighbour whose face the segment reaches first */
  if (w->tmax[1] < w->tmax[k]) k = 1;
  if (w->tmax[2] < w->tmax[k]) k = 2;
  if (w->tmax[k] > w->t1)
    w->done = PETSC_TRUE;
  else {
    w->cell[k] += w->step[k];
    if (w->cell[k] < 0 || w->cell[k] >= g->n[k])
      w->done = PETSC_TRUE;
    else
      w->tmax[k] += w->tdelta[k];
  }
  return PETSC_TRUE;
}

PetscErrorCode CellGridDestroy(CellGrid *grid)
{
  PetscFunctionBeginUser;
  if (!*grid) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree((*grid)->start));
  PetscCall(PetscFree((*grid)->item));
  PetscCall(PetscFree((*grid)->low_cell));
  PetscCall(PetscFree(*grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}
