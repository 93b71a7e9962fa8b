/* ClothCollision's mesh search (collision_impl.h): the first triangle of a mesh body a particle's segment crosses from
   the outside, through this rank's cell grid over the body (built over its particles plus a margin, rebuilt when a
   particle leaves it; every cell the segment passes through visited) or by brute force, and the triangle nearest to
   a point (a particle that came within the thickness, a held contact found again after a restart). */
#include "collision_impl.h"
#include "geometry.h"
#include "log.h"
#include "vec3.h"

#define COLLISION_MAX_CELLS 8000000    /* the grid's cells grow beyond -collision_cell_size rather than exceed this */
#define COLLISION_BARYCENTRIC_TOL 1e-9 /* a segment through a shared edge hits at least one of its triangles */

/* ------------------------------------------------------------------------------------------------------------ */
/* Segment against triangles                                                                                    */

/* The paper's triangle-box rejection, then the exact test; keeps the first hit. */
static void TestTriangle(const CollisionMesh *cm, PetscInt tri, const PetscReal p0[3], const PetscReal d[3], const PetscReal seg_lo[3], const PetscReal seg_hi[3], SegmentHit *hit, PetscInt64 *tests)
{
  const PetscInt *v = &cm->mesh->tris[3 * tri];
  PetscReal       t;

  if (!GeometryBoxesOverlap(seg_lo, seg_hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) return;
  if (Dot3(&cm->face_normal[3 * tri], &cm->face_normal[3 * tri]) == 0) return; /* degenerate */
  (*tests)++;
  if (!GeometrySegmentCrossesTriangle(p0, d, &cm->mesh->coords[3 * v[0]], &cm->mesh->coords[3 * v[1]], &cm->mesh->coords[3 * v[2]], COLLISION_BARYCENTRIC_TOL, &t)) return;
  if (hit->triangle < 0 || t < hit->t || (t == hit->t && tri < hit->triangle)) {
    hit->triangle = tri;
    hit->t        = t;
  }
}

static void FinishHit(const PetscReal p0[3], const PetscReal d[3], SegmentHit *hit)
{
  if (hit->triangle >= 0)
    for (PetscInt k = 0; k < 3; k++) hit->point[k] = p0[k] + hit->t * d[k];
}

void CollisionSearchBruteForce(const CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit, PetscInt64 *tests)
{
  PetscReal d[3], lo[3], hi[3];

  hit->triangle = -1;
  for (PetscInt k = 0; k < 3; k++) d[k] = p1[k] - p0[k];
  GeometrySegmentBox(p0, p1, lo, hi);
  if (!GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return;
  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) TestTriangle(cm, tri, p0, d, lo, hi, hit, tests);
  FinishHit(p0, d, hit);
}

/* The cell grid: every cell the segment passes through, in order, each triangle tested once per query. */
static void SearchGrid(CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit, PetscInt64 *tests)
{
  PetscReal       d[3], lo[3], hi[3];
  PetscInt        n[3], c;
  const PetscInt *start, *tris;
  CellGridWalk    walk;

  hit->triangle = -1;
  for (PetscInt k = 0; k < 3; k++) d[k] = p1[k] - p0[k];
  GeometrySegmentBox(p0, p1, lo, hi);
  if (!CellGridHasCells(cm->grid) || !GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return;
  CellGridGetCells(cm->grid, n, &start, &tris);
  cm->query++;
  for (CellGridWalkBegin(cm->grid, p0, d, &walk); CellGridWalkNext(cm->grid, &walk, &c);)
    for (PetscInt j = start[c]; j < start[c + 1]; j++) {
      const PetscInt tri = tris[j];
      if (cm->stamp[tri] == cm->query) continue;
      cm->stamp[tri] = cm->query;
      TestTriangle(cm, tri, p0, d, lo, hi, hit, tests);
    }
  FinishHit(p0, d, hit);
}

/* The first triangle of mesh cm that the segment p0 -> p1 crosses from the outside, by the chosen search. */
void CollisionSearchSegment(ClothCollision col, CollisionMesh *cm, const PetscReal p0[3], const PetscReal p1[3], SegmentHit *hit)
{
  if (col->search == CLOTH_COLLISION_SEARCH_GRID)
    SearchGrid(cm, p0, p1, hit, &col->local.triangle_tests);
  else
    CollisionSearchBruteForce(cm, p0, p1, hit, &col->local.triangle_tests);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* The per-rank grid                                                                                            */

/* Builds the grid over the particle box [plo, phi] grown by the margin and clipped to the body's box. */
static PetscErrorCode GridBuild(CollisionMesh *cm, const PetscReal plo[3], const PetscReal phi[3], PetscReal margin, PetscReal cell_size)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.collision_grid, 0, 0, 0, 0));
  for (PetscInt k = 0; k < 3; k++) {
    cm->covered_lo[k] = plo[k] - margin;
    cm->covered_hi[k] = phi[k] + margin;
    cm->lo[k]         = PetscMax(cm->covered_lo[k], cm->body_lo[k]);
    cm->hi[k]         = PetscMin(cm->covered_hi[k], cm->body_hi[k]);
  }
  cm->built = PETSC_TRUE;
  PetscCall(CellGridBuild(cm->grid, cm->lo, cm->hi, cell_size > 0 ? cell_size : 2 * cm->mean_edge, COLLISION_MAX_CELLS, cm->mesh->ntris, cm->tri_lo, cm->tri_hi, 3));
  PetscCall(PetscLogEventEnd(ClothLog.collision_grid, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Triangle boxes, the body box and the mean edge length (the default cell size is twice that). The boxes are
   inflated by a small fraction of the mean edge so that round-off in the grid walk cannot skip a triangle. */
PetscErrorCode CollisionMeshSetUp(CollisionMesh *cm, Body body)
{
  PetscReal eps, sum = 0;

  PetscFunctionBeginUser;
  cm->body = body;
  PetscCall(CellGridCreate(&cm->grid));
  PetscCall(BodyGetMesh(body, &cm->mesh, &cm->face_normal, cm->body_lo, cm->body_hi));
  PetscCall(PetscMalloc3(3 * cm->mesh->ntris, &cm->tri_lo, 3 * cm->mesh->ntris, &cm->tri_hi, cm->mesh->ntris, &cm->stamp));
  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) {
    const PetscInt *v = &cm->mesh->tris[3 * tri];
    cm->stamp[tri]    = -1;
    for (PetscInt k = 0; k < 3; k++) {
      const PetscReal a = cm->mesh->coords[3 * v[0] + k], b = cm->mesh->coords[3 * v[1] + k], c = cm->mesh->coords[3 * v[2] + k];
      cm->tri_lo[3 * tri + k] = PetscMin(a, PetscMin(b, c));
      cm->tri_hi[3 * tri + k] = PetscMax(a, PetscMax(b, c));
    }
    for (PetscInt e = 0; e < 3; e++) {
      const PetscReal *a = &cm->mesh->coords[3 * v[e]], *b = &cm->mesh->coords[3 * v[(e + 1) % 3]];
      sum += PetscSqrtReal((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
  }
  cm->mean_edge = sum / (3 * cm->mesh->ntris);
  eps           = 1e-3 * cm->mean_edge;
  for (PetscInt j = 0; j < 3 * cm->mesh->ntris; j++) {
    cm->tri_lo[j] -= eps;
    cm->tri_hi[j] += eps;
  }
  for (PetscInt k = 0; k < 3; k++) {
    cm->body_lo[k] -= eps;
    cm->body_hi[k] += eps;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode CollisionMeshDestroy(CollisionMesh *cm)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(cm->tri_lo, cm->tri_hi, cm->stamp));
  PetscCall(CellGridDestroy(&cm->grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rebuilds each mesh grid when a segment end lies outside the region it covers. Local (no communication). */
PetscErrorCode CollisionUpdateGrids(ClothCollision col, const PetscScalar *xp, const PetscScalar *x, PetscInt nlocal)
{
  PetscReal lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};

  PetscFunctionBeginUser;
  if (nlocal == 0) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt k = 0; k < 3; k++) {
      lo[k] = PetscMin(lo[k], PetscMin(xp[3 * i + k], x[3 * i + k]));
      hi[k] = PetscMax(hi[k], PetscMax(xp[3 * i + k], x[3 * i + k]));
    }
  for (PetscInt b = 0; b < col->nbodies; b++) {
    CollisionMesh *cm = &col->meshes[b];
    PetscBool      inside;

    if (!cm->mesh) continue;
    inside = cm->built;
    for (PetscInt k = 0; k < 3 && inside; k++)
      if (lo[k] < cm->covered_lo[k] || hi[k] > cm->covered_hi[k]) inside = PETSC_FALSE;
    if (inside) continue;
    PetscCall(GridBuild(cm, lo, hi, col->margin, col->cell_size));
    col->local.grid_rebuilds++;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Nearest triangles                                                                                            */

/* Tests triangle tri of cm for the nearest point to x closer than *best_d2; keeps the best. */
static void NearestOnTriangle(const CollisionMesh *cm, PetscInt tri, const PetscScalar x[3], PetscReal *best_d2, PetscInt *best, PetscReal q[3])
{
  const PetscInt *v = &cm->mesh->tris[3 * tri];
  PetscReal       p[3], r[3];

  if (Dot3(&cm->face_normal[3 * tri], &cm->face_normal[3 * tri]) == 0) return; /* degenerate */
  GeometryTriangleNearestPoint(x, &cm->mesh->coords[3 * v[0]], &cm->mesh->coords[3 * v[1]], &cm->mesh->coords[3 * v[2]], p);
  Sub3(x, p, r);
  if (Dot3(r, r) < *best_d2 || (Dot3(r, r) == *best_d2 && *best >= 0 && tri < *best)) {
    *best_d2 = Dot3(r, r);
    *best    = tri;
    for (PetscInt k = 0; k < 3; k++) q[k] = p[k];
  }
}

/* The triangle of mesh cm nearest to x within radius (-1: none) and the nearest point q on it, through the
   cell grid (every triangle that comes within radius of x overlaps the box x +- radius) or by brute force. */
PetscInt CollisionNearestTriangleWithin(ClothCollision col, CollisionMesh *cm, const PetscScalar x[3], PetscReal radius, PetscReal q[3])
{
  PetscReal       lo[3], hi[3], best_d2 = radius * radius;
  PetscInt        best = -1, first[3], last[3], n[3];
  const PetscInt *start, *tris;

  for (PetscInt k = 0; k < 3; k++) {
    lo[k] = x[k] - radius;
    hi[k] = x[k] + radius;
  }
  if (!GeometryBoxesOverlap(lo, hi, cm->body_lo, cm->body_hi)) return -1;
  if (col->search == CLOTH_COLLISION_SEARCH_BRUTE_FORCE) {
    for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++)
      if (GeometryBoxesOverlap(lo, hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
    return best;
  }
  if (!CellGridHasCells(cm->grid) || !GeometryBoxesOverlap(lo, hi, cm->lo, cm->hi)) return -1;
  CellGridGetCells(cm->grid, n, &start, &tris);
  cm->query++;
  CellGridGetCellRange(cm->grid, lo, hi, first, last);
  for (PetscInt i = first[0]; i <= last[0]; i++)
    for (PetscInt j = first[1]; j <= last[1]; j++)
      for (PetscInt l = first[2]; l <= last[2]; l++) {
        const PetscInt c = CellGridCellIndex(n, i, j, l);
        for (PetscInt e = start[c]; e < start[c + 1]; e++) {
          const PetscInt tri = tris[e];
          if (cm->stamp[tri] == cm->query) continue;
          cm->stamp[tri] = cm->query;
          if (GeometryBoxesOverlap(lo, hi, &cm->tri_lo[3 * tri], &cm->tri_hi[3 * tri])) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
        }
      }
  return best;
}

/* The triangle of mesh cm nearest to x, within reach, whose face normal is exactly n (-1: none). */
PetscInt CollisionFindHeldTriangle(const CollisionMesh *cm, const PetscScalar x[3], const PetscReal n[3], PetscReal reach)
{
  PetscReal best_d2 = reach * reach, q[3];
  PetscInt  best    = -1;

  for (PetscInt tri = 0; tri < cm->mesh->ntris; tri++) {
    const PetscReal *fn = &cm->face_normal[3 * tri];

    if (fn[0] == n[0] && fn[1] == n[1] && fn[2] == n[2]) NearestOnTriangle(cm, tri, x, &best_d2, &best, q);
  }
  return best;
}
