/* Geometry (see geometry.h). */
#include "geometry.h"
#include "vec3.h"

static inline PetscReal Clamp01(PetscReal t)
{
  return t < 0 ? 0 : (t > 1 ? 1 : t);
}

/* Where the point of triangle abc closest to p lies (Ericson, Real-Time Collision Detection, 5.1.5): the
   Voronoi region of a vertex, an edge or the face. */
typedef enum {
  NEAREST_VERTEX_A,
  NEAREST_VERTEX_B,
  NEAREST_VERTEX_C,
  NEAREST_EDGE_AB,   /* at a + t (b - a) */
  NEAREST_EDGE_AC,   /* at a + t (c - a) */
  NEAREST_EDGE_BC,   /* at b + t (c - b) */
  NEAREST_FACE,      /* barycentric weights proportional to (va, vb, vc) */
  NEAREST_DEGENERATE /* a collapsed triangle whose face case cannot be solved */
} NearestRegion;

/* Ericson's tests for vertex V (b or c) and the edge from a to it, from the dots of the edge a V ("near") and
   of the other edge from a ("far") with p - a (da_) and with p - V (dv_). Returns 1 when V is nearest, 2
   when the edge a V is (*t its parameter from a), 0 otherwise; *v is the barycentric numerator of the third
   vertex, which the face case needs. */
static PetscInt VertexOrEdge(PetscReal da_near, PetscReal da_far, PetscReal dv_near, PetscReal dv_far, PetscReal *v, PetscReal *t)
{
  if (dv_near >= 0 && dv_far <= dv_near) return 1;
  *v = da_near * dv_far - dv_near * da_far;
  if (*v <= 0 && da_near >= 0 && dv_near <= 0) {
    *t = da_near / (da_near - dv_near);
    return 2;
  }
  return 0;
}

static NearestRegion ClassifyNearest(const PetscReal p[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal *t, PetscReal v[3])
{
  PetscReal ab[3], ac[3], ap[3], bp[3], cp[3], d1, d2, d3, d4, d5, d6;
  PetscInt  near;

  for (PetscInt k = 0; k < 3; k++) {
    ab[k] = b[k] - a[k];
    ac[k] = c[k] - a[k];
    ap[k] = p[k] - a[k];
    bp[k] = p[k] - b[k];
    cp[k] = p[k] - c[k];
  }
  d1 = Dot3(ab, ap);
  d2 = Dot3(ac, ap);
  if (d1 <= 0 && d2 <= 0) return NEAREST_VERTEX_A;
  d3   = Dot3(ab, bp);
  d4   = Dot3(ac, bp);
  near = VertexOrEdge(d1, d2, d3, d4, &v[2], t);
  if (near) return near == 1 ? NEAREST_VERTEX_B : NEAREST_EDGE_AB;
  d5   = Dot3(ab, cp);
  d6   = Dot3(ac, cp);
  near = VertexOrEdge(d2, d1, d6, d5, &v[1], t);
  if (near) return near == 1 ? NEAREST_VERTEX_C : NEAREST_EDGE_AC;
  v[0] = d3 * d6 - d5 * d4;
  if (v[0] <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    *t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return NEAREST_EDGE_BC;
  }
  return v[0] + v[1] + v[2] > 0 ? NEAREST_FACE : NEAREST_DEGENERATE;
}

void GeometryClosestPointTriangle(const PetscReal p[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal w[3])
{
  PetscReal t = 0, v[3] = {0, 0, 0}, denom;

  w[0] = w[1] = w[2] = 0;
  switch (ClassifyNearest(p, a, b, c, &t, v)) {
  case NEAREST_VERTEX_B:
    w[1] = 1;
    break;
  case NEAREST_VERTEX_C:
    w[2] = 1;
    break;
  case NEAREST_EDGE_AB:
    w[1] = t, w[0] = 1 - t;
    break;
  case NEAREST_EDGE_AC:
    w[2] = t, w[0] = 1 - t;
    break;
  case NEAREST_EDGE_BC:
    w[2] = t, w[1] = 1 - t;
    break;
  case NEAREST_FACE:
    denom = v[0] + v[1] + v[2];
    w[1] = v[1] / denom, w[2] = v[2] / denom, w[0] = 1 - w[1] - w[2];
    break;
  default: /* vertex a; a degenerate triangle: the nearest vertex will do */
    w[0] = 1;
  }
}

void GeometryTriangleNearestPoint(const PetscReal p[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal q[3])
{
  PetscReal t = 0, v[3] = {0, 0, 0}, inverse;

  switch (ClassifyNearest(p, a, b, c, &t, v)) {
  case NEAREST_VERTEX_B:
    for (PetscInt k = 0; k < 3; k++) q[k] = b[k];
    break;
  case NEAREST_VERTEX_C:
    for (PetscInt k = 0; k < 3; k++) q[k] = c[k];
    break;
  case NEAREST_EDGE_AB:
    for (PetscInt k = 0; k < 3; k++) q[k] = a[k] + t * (b[k] - a[k]);
    break;
  case NEAREST_EDGE_AC:
    for (PetscInt k = 0; k < 3; k++) q[k] = a[k] + t * (c[k] - a[k]);
    break;
  case NEAREST_EDGE_BC:
    for (PetscInt k = 0; k < 3; k++) q[k] = b[k] + t * (c[k] - b[k]);
    break;
  case NEAREST_FACE:
    inverse = 1 / (v[0] + v[1] + v[2]);
    for (PetscInt k = 0; k < 3; k++) q[k] = a[k] + v[1] * inverse * (b[k] - a[k]) + v[2] * inverse * (c[k] - a[k]);
    break;
  default: /* vertex a; a degenerate triangle: the nearest vertex will do */
    for (PetscInt k = 0; k < 3; k++) q[k] = a[k];
  }
}

void GeometryClosestPointsSegments(const PetscReal p1[3], const PetscReal q1[3], const PetscReal p2[3], const PetscReal q2[3], PetscReal *s, PetscReal *t)
{
  const PetscReal eps = 1e-300; /* squared lengths below this are points */
  PetscReal       d1[3], d2[3], r[3], a, e, f, b, c, denom;

  for (PetscInt k = 0; k < 3; k++) {
    d1[k] = q1[k] - p1[k];
    d2[k] = q2[k] - p2[k];
    r[k]  = p1[k] - p2[k];
  }
  a = Dot3(d1, d1), e = Dot3(d2, d2), f = Dot3(d2, r);
  *s = *t = 0;
  if (a <= eps && e <= eps) return;
  if (a <= eps) {
    *t = Clamp01(f / e);
    return;
  }
  c = Dot3(d1, r);
  if (e <= eps) {
    *s = Clamp01(-c / a);
    return;
  }
  b     = Dot3(d1, d2);
  denom = a * e - b * b;
  *s    = denom > 0 ? Clamp01((b * f - c * e) / denom) : 0; /* parallel: any s, take 0 */
  *t    = (b * *s + f) / e;
  if (*t < 0)
    *t = 0, *s = Clamp01(-c / a);
  else if (*t > 1)
    *t = 1, *s = Clamp01((b - c) / a);
}

PetscBool GeometrySegmentCrossesTriangle(const PetscReal p0[3], const PetscReal d[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal tolerance, PetscReal *t)
{
  PetscReal e1[3], e2[3], pvec[3], s[3], q[3], det, inv, u, v;

  for (PetscInt k = 0; k < 3; k++) {
    e1[k] = b[k] - a[k];
    e2[k] = c[k] - a[k];
    s[k]  = p0[k] - a[k];
  }
  Cross3(d, e2, pvec);
  det = Dot3(e1, pvec); /* = -d . n: only segments entering from the outer side count */
  if (!(det > 0)) return PETSC_FALSE;
  inv = 1 / det;
  u   = Dot3(s, pvec) * inv;
  if (u < -tolerance || u > 1 + tolerance) return PETSC_FALSE;
  Cross3(s, e1, q);
  v = Dot3(d, q) * inv;
  if (v < -tolerance || u + v > 1 + tolerance) return PETSC_FALSE;
  *t = Dot3(e2, q) * inv;
  return (*t >= 0 && *t <= 1) ? PETSC_TRUE : PETSC_FALSE;
}
