/* The geometry layer (src/geometry.c) and the cell grid (src/cellgrid.c) against brute force, on seeded
   random cases; prints nothing unless a check fails.
   - closest point on a triangle: no sampled point of the triangle is closer (to 1e-12 m), the point equals
     the weighted sum of the vertices, and degenerate (collinear, coincident) triangles give finite answers;
   - closest points of two segments: no sampled pair is closer;
   - cell grid, box queries: every item whose box overlaps the query box is listed in a cell of its range;
   - cell grid, segment walk: every item whose box the segment meets is listed in a cell of the walk;
   - cell grid build: a non-finite box or one whose extent overflows is an error (PETSC_ERR_FP), not an
     endless loop; a huge finite box with a tiny cell size ends with at most the allowed cells. */
#include <math.h>
#include <petscsys.h>
#include "geometry.h"
#include "cellgrid.h"
#include "vec3.h"
#include "test_support.h"

#define NCASES 2000
#define NSAMPLES 40 /* per barycentric axis / per segment */

static PetscReal Distance(const PetscReal a[3], const PetscReal b[3])
{
  PetscReal d[3];

  Sub3(a, b, d);
  return PetscSqrtReal(Dot3(d, d));
}

static PetscErrorCode RandomPoint(PetscRandom rnd, PetscReal x[3])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 3; k++) PetscCall(PetscRandomGetValueReal(rnd, &x[k]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckClosestPointTriangle(PetscRandom rnd)
{
  PetscFunctionBeginUser;
  for (PetscInt n = 0; n < NCASES; n++) {
    PetscReal p[3], v[3][3], w[3], q[3], qw[3], best = PETSC_MAX_REAL;

    PetscCall(RandomPoint(rnd, p));
    for (PetscInt k = 0; k < 3; k++) PetscCall(RandomPoint(rnd, v[k]));
    if (n % 10 == 1) /* collinear */
      for (PetscInt k = 0; k < 3; k++) v[2][k] = v[0][k] + 0.3 * (v[1][k] - v[0][k]);
    if (n % 10 == 2) /* coincident */
      for (PetscInt k = 0; k < 3; k++) v[1][k] = v[2][k] = v[0][k];
    GeometryClosestPointTriangle(p, v[0], v[1], v[2], w);
    GeometryTriangleNearestPoint(p, v[0], v[1], v[2], q);
    for (PetscInt k = 0; k < 3; k++) qw[k] = w[0] * v[0][k] + w[1] * v[1][k] + w[2] * v[2][k];
    for (PetscInt k = 0; k < 3; k++) PetscCheck(!PetscIsInfOrNanReal(w[k]) && !PetscIsInfOrNanReal(q[k]), PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": non-finite closest point", n);
    PetscCheck(PetscAbsReal(w[0] + w[1] + w[2] - 1) < 1e-12 && w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": weights (%g, %g, %g) are not barycentric", n, (double)w[0], (double)w[1],
               (double)w[2]);
    PetscCheck(Distance(q, qw) < 1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": the point and the weights disagree by %g m", n, (double)Distance(q, qw));
    for (PetscInt i = 0; i <= NSAMPLES; i++)
      for (PetscInt j = 0; i + j <= NSAMPLES; j++) {
        const PetscReal b = (PetscReal)i / NSAMPLES, c = (PetscReal)j / NSAMPLES;
        PetscReal       s[3];
        for (PetscInt k = 0; k < 3; k++) s[k] = (1 - b - c) * v[0][k] + b * v[1][k] + c * v[2][k];
        best = PetscMin(best, Distance(p, s));
      }
    PetscCheck(Distance(p, q) <= best + 1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": closest point at %.17g m, a sampled point at %.17g m", n, (double)Distance(p, q), (double)best);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckClosestPointsSegments(PetscRandom rnd)
{
  PetscFunctionBeginUser;
  for (PetscInt n = 0; n < NCASES; n++) {
    PetscReal p1[3], q1[3], p2[3], q2[3], s, t, a[3], b[3], best = PETSC_MAX_REAL;

    PetscCall(RandomPoint(rnd, p1));
    PetscCall(RandomPoint(rnd, q1));
    PetscCall(RandomPoint(rnd, p2));
    PetscCall(RandomPoint(rnd, q2));
    if (n % 10 == 1) /* parallel */
      for (PetscInt k = 0; k < 3; k++) q2[k] = p2[k] + 0.7 * (q1[k] - p1[k]);
    if (n % 10 == 2) /* a point */
      for (PetscInt k = 0; k < 3; k++) q1[k] = p1[k];
    GeometryClosestPointsSegments(p1, q1, p2, q2, &s, &t);
    PetscCheck(s >= 0 && s <= 1 && t >= 0 && t <= 1, PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": parameters (%g, %g) outside [0, 1]", n, (double)s, (double)t);
    for (PetscInt k = 0; k < 3; k++) {
      a[k] = p1[k] + s * (q1[k] - p1[k]);
      b[k] = p2[k] + t * (q2[k] - p2[k]);
    }
    for (PetscInt i = 0; i <= NSAMPLES; i++)
      for (PetscInt j = 0; j <= NSAMPLES; j++) {
        PetscReal x[3], y[3];
        for (PetscInt k = 0; k < 3; k++) {
          x[k] = p1[k] + (PetscReal)i / NSAMPLES * (q1[k] - p1[k]);
          y[k] = p2[k] + (PetscReal)j / NSAMPLES * (q2[k] - p2[k]);
        }
        best = PetscMin(best, Distance(x, y));
      }
    PetscCheck(Distance(a, b) <= best + 1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "case %" PetscInt_FMT ": closest points %.17g m apart, a sampled pair %.17g m", n, (double)Distance(a, b), (double)best);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Does the segment p0 + t d, t in [0, 1], meet the box [lo, hi]? (slabs) */
static PetscBool SegmentMeetsBox(const PetscReal p0[3], const PetscReal d[3], const PetscReal lo[3], const PetscReal hi[3])
{
  PetscReal t0 = 0, t1 = 1;

  for (PetscInt k = 0; k < 3; k++) {
    if (d[k] == 0) {
      if (p0[k] < lo[k] || p0[k] > hi[k]) return PETSC_FALSE;
      continue;
    }
    const PetscReal ta = (lo[k] - p0[k]) / d[k], tb = (hi[k] - p0[k]) / d[k];
    t0 = PetscMax(t0, PetscMin(ta, tb));
    t1 = PetscMin(t1, PetscMax(ta, tb));
  }
  return t0 <= t1 ? PETSC_TRUE : PETSC_FALSE;
}

#define NITEMS 300

static PetscErrorCode CheckCellGridQueries(PetscRandom rnd)
{
  CellGrid        grid;
  PetscReal       lo[3] = {0.1, 0.1, 0.1}, hi[3] = {0.9, 0.8, 0.7}, ilo[3 * NITEMS], ihi[3 * NITEMS];
  PetscInt        n[3], *seen;
  const PetscInt *start, *items;

  PetscFunctionBeginUser;
  PetscCall(CellGridCreate(&grid));
  PetscCall(PetscMalloc1(NITEMS, &seen));
  for (PetscInt b = 0; b < NITEMS; b++) {
    PetscReal c[3], r;
    PetscCall(RandomPoint(rnd, c));
    PetscCall(PetscRandomGetValueReal(rnd, &r));
    for (PetscInt k = 0; k < 3; k++) ilo[3 * b + k] = c[k] - 0.05 * r, ihi[3 * b + k] = c[k] + 0.05 * r;
  }
  PetscCall(CellGridBuild(grid, lo, hi, 0.07, 1000, NITEMS, ilo, ihi, 3));
  CellGridGetCells(grid, n, &start, &items);
  PetscCheck(n[0] * n[1] * n[2] <= 1000, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " cells, at most 1000 allowed", n[0] * n[1] * n[2]);
  for (PetscInt q = 0; q < NCASES; q++) {
    PetscReal p0[3], p1[3], d[3], qlo[3], qhi[3];
    PetscInt  first[3], last[3], cell;

    PetscCall(RandomPoint(rnd, p0));
    PetscCall(RandomPoint(rnd, p1));
    if (q % 10 == 1) p1[1] = p0[1]; /* parallel to an axis plane */
    for (PetscInt b = 0; b < NITEMS; b++) seen[b] = 0;
    /* box query: the segment's box, clipped to the grid's box */
    GeometrySegmentBox(p0, p1, qlo, qhi);
    CellGridGetCellRange(grid, qlo, qhi, first, last);
    for (PetscInt i = first[0]; i <= last[0]; i++)
      for (PetscInt j = first[1]; j <= last[1]; j++)
        for (PetscInt k = first[2]; k <= last[2]; k++)
          for (PetscInt e = start[CellGridCellIndex(n, i, j, k)]; e < start[CellGridCellIndex(n, i, j, k) + 1]; e++) seen[items[e]] = 1;
    for (PetscInt b = 0; b < NITEMS; b++) {
      PetscReal clo[3], chi[3];
      for (PetscInt k = 0; k < 3; k++) clo[k] = PetscMax(qlo[k], lo[k]), chi[k] = PetscMin(qhi[k], hi[k]);
      if (clo[0] <= chi[0] && clo[1] <= chi[1] && clo[2] <= chi[2] && GeometryBoxesOverlap(clo, chi, &ilo[3 * b], &ihi[3 * b]))
        PetscCheck(seen[b], PETSC_COMM_SELF, PETSC_ERR_PLIB, "query %" PetscInt_FMT ": item %" PetscInt_FMT " overlaps the box but is in none of its cells", q, b);
    }
    /* segment walk */
    for (PetscInt b = 0; b < NITEMS; b++) seen[b] = 0;
    for (PetscInt k = 0; k < 3; k++) d[k] = p1[k] - p0[k];
    CellGridWalk walk;
    for (CellGridWalkBegin(grid, p0, d, &walk); CellGridWalkNext(grid, &walk, &cell);)
      for (PetscInt e = start[cell]; e < start[cell + 1]; e++) seen[items[e]] = 1;
    for (PetscInt b = 0; b < NITEMS; b++) {
      PetscReal clo[3], chi[3];
      for (PetscInt k = 0; k < 3; k++) clo[k] = PetscMax(ilo[3 * b + k], lo[k]), chi[k] = PetscMin(ihi[3 * b + k], hi[k]);
      if (clo[0] <= chi[0] && clo[1] <= chi[1] && clo[2] <= chi[2] && SegmentMeetsBox(p0, d, clo, chi))
        PetscCheck(seen[b], PETSC_COMM_SELF, PETSC_ERR_PLIB, "segment %" PetscInt_FMT ": it meets item %" PetscInt_FMT " inside the grid but the walk missed it", q, b);
    }
  }
  PetscCall(PetscFree(seen));
  PetscCall(CellGridDestroy(&grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Builds a grid over [lo, hi]; *code: the error code of the build (0: built). */
static PetscErrorCode TryBuild(const PetscReal lo[3], const PetscReal hi[3], PetscReal cell, PetscInt max_cells, PetscErrorCode *code, PetscInt *ncells)
{
  CellGrid        grid;
  PetscReal       item_lo[3] = {0, 0, 0}, item_hi[3] = {1, 1, 1};
  PetscInt        n[3];
  const PetscInt *start, *items;

  PetscFunctionBeginUser;
  PetscCall(CellGridCreate(&grid));
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  *code = CellGridBuild(grid, lo, hi, cell, max_cells, 1, item_lo, item_hi, 3);
  PetscCall(PetscPopErrorHandler());
  CellGridGetCells(grid, n, &start, &items);
  *ncells = *code ? 0 : n[0] * n[1] * n[2];
  PetscCall(CellGridDestroy(&grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckCellGridBuildTerminates(void)
{
  const PetscReal inf = (PetscReal)INFINITY, nan = (PetscReal)NAN;
  const PetscReal bad[4][2] = {{0, inf}, {-inf, 0}, {nan, 1}, {-1e308, 1e308}}; /* the last one's extent overflows */
  PetscErrorCode  code;
  PetscInt        ncells;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < 4; c++) {
    const PetscReal lo[3] = {0, bad[c][0], 0}, hi[3] = {1, bad[c][1], 1};
    PetscCall(TryBuild(lo, hi, 0.1, 1000, &code, &ncells));
    PetscCheck(code == PETSC_ERR_FP, PETSC_COMM_SELF, PETSC_ERR_PLIB, "a box [%g, %g] along y: build returned %d, expected PETSC_ERR_FP", (double)bad[c][0], (double)bad[c][1], (int)code);
  }
  {
    const PetscReal lo[3] = {-1e300, 0, 0}, hi[3] = {1e300, 1, 1};
    PetscCall(TryBuild(lo, hi, 1e-3, 1000, &code, &ncells));
    PetscCheck(code == 0 && ncells >= 1 && ncells <= 1000, PETSC_COMM_SELF, PETSC_ERR_PLIB, "a box 2e300 m wide with 1 mm cells: build returned %d with %" PetscInt_FMT " cells", (int)code, ncells);
    PetscCall(TryBuild(lo, hi, (PetscReal)INFINITY, 1000, &code, &ncells)); /* an infinite cell: one cell */
    PetscCheck(code == 0 && ncells == 1, PETSC_COMM_SELF, PETSC_ERR_PLIB, "infinite cell size: build returned %d with %" PetscInt_FMT " cells", (int)code, ncells);
    PetscCall(TryBuild(lo, hi, 0, 1000, &code, &ncells));
    PetscCheck(code == PETSC_ERR_FP, PETSC_COMM_SELF, PETSC_ERR_PLIB, "zero cell size: build returned %d, expected PETSC_ERR_FP", (int)code);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscRandom rnd;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 2311));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(CheckClosestPointTriangle(rnd));
  PetscCall(CheckClosestPointsSegments(rnd));
  PetscCall(CheckCellGridQueries(rnd));
  PetscCall(CheckCellGridBuildTerminates());
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
