/* Geometry: the closest-point, box and segment-triangle kernels shared by the rigid bodies (body.c), the
   collisions with them (collision_search.c, collision_response.c) and self-collision (selfcontact.c), so that one implementation serves
   all three and the brute-force tests of both searches protect it.

   These are the innermost kernels of the contact searches: they cannot fail, so they return their results
   (not a PetscErrorCode) and the two smallest are inline. Boxes are given by their low and high corners. */
#pragma once
#include <petscsys.h>

/* Do the closed boxes [alo, ahi] and [blo, bhi] overlap? */
static inline PetscBool GeometryBoxesOverlap(const PetscReal alo[3], const PetscReal ahi[3], const PetscReal blo[3], const PetscReal bhi[3])
{
  for (PetscInt k = 0; k < 3; k++)
    if (ahi[k] < blo[k] || bhi[k] < alo[k]) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The box [lo, hi] of the segment p0 p1. */
static inline void GeometrySegmentBox(const PetscReal p0[3], const PetscReal p1[3], PetscReal lo[3], PetscReal hi[3])
{
  for (PetscInt k = 0; k < 3; k++) {
    lo[k] = PetscMin(p0[k], p1[k]);
    hi[k] = PetscMax(p0[k], p1[k]);
  }
}

/* Barycentric weights w (of a, b, c) of the point of triangle abc closest to p (Ericson, Real-Time Collision
   Detection, 2005, 5.1.5). A degenerate (collapsed) triangle whose interior case cannot be solved gives the
   vertex a. */
void GeometryClosestPointTriangle(const PetscReal p[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal w[3]);
/* The point q of triangle abc closest to p (the same point as the weights above give, computed from the
   vertex, edge or face it lies on; a degenerate triangle gives the vertex a). */
void GeometryTriangleNearestPoint(const PetscReal p[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal q[3]);
/* Parameters s, t in [0, 1] of the closest points p1 + s (q1 - p1) and p2 + t (q2 - p2) of two segments
   (Ericson 5.1.9); degenerate segments (points) and parallel ones are handled. */
void GeometryClosestPointsSegments(const PetscReal p1[3], const PetscReal q1[3], const PetscReal p2[3], const PetscReal q2[3], PetscReal *s, PetscReal *t);
/* Does the segment p0 + t d, t in [0, 1], cross triangle abc from its outer side (where (b - a) x (c - a)
   points, d . n < 0)? Moller-Trumbore, with barycentric coordinates accepted down to -tolerance and up to
   1 + tolerance, so that a segment through an edge shared by two triangles hits at least one of them. On a
   crossing *t is its parameter. */
PetscBool GeometrySegmentCrossesTriangle(const PetscReal p0[3], const PetscReal d[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3], PetscReal tolerance, PetscReal *t);
