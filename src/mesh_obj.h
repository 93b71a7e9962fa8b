/* Wavefront OBJ reader: the vertices and faces of a triangle mesh (the mannequin).

   Reads 'v x y z' and 'f' lines; faces may be triangles, quads or larger convex polygons, written
   with any of the forms v, v/vt, v//vn, v/vt/vn and with negative (relative) indices. Polygons
   are split into triangles as a fan from their first vertex (a quad a b c d -> a b c, a c d).
   Texture coordinates, normals, groups, objects, smoothing groups, materials and lines are
   ignored; any other statement is an error naming the file and the line. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* A triangle mesh: nverts points (coords, 3 per point) and ntris triangles (tris, 3 zero-based
   point indices each). */
typedef struct {
  PetscInt   nverts;
  PetscReal *coords;
  PetscInt   ntris;
  PetscInt  *tris;
  PetscInt   npolygons; /* faces as written in the file (before splitting) */
} MeshTriangles;

/* Reads path into mesh (arrays allocated here; free with MeshTrianglesFree). Collective on comm:
   rank 0 reads the file and broadcasts the result, so every rank fails or succeeds alike. Errors read
   "<context>: mesh FILE, line L: what was expected" (context: who asked for the file, e.g. the scene
   and body; may be NULL). */
PetscErrorCode MeshObjRead(MPI_Comm comm, const char path[], const char context[], MeshTriangles *mesh);
PetscErrorCode MeshTrianglesFree(MeshTriangles *mesh);
