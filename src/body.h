/* Body: a rigid obstacle the cloth collides with (docs/model.md section 6): an analytic sphere or plane, or a
   triangle mesh read from an OBJ file (the mannequin), placed by the scene's scale, rotation and translation.

   Mesh triangles are oriented so that their normals (b - a) x (c - a) point out of the body (the orientation
   with positive enclosed volume); quads of the file are split into two triangles (see mesh_obj.h). The
   inside test of a mesh is the generalized winding number (Jacobson et al. 2013) with threshold 1/2, which
   stays meaningful when the mesh has holes or is not perfectly closed (the MakeHuman body is open at the
   neck, wrists and ankles; BodyView reports its boundary edges). */
#pragma once
#include "scene.h"
#include "mesh_obj.h"

typedef struct _n_Body *Body;

/* Builds the body from its scene description (reads and places the mesh; context starts error messages,
   e.g. "scene FILE, body 'NAME'"). Collective on comm. */
PetscErrorCode BodyCreate(MPI_Comm comm, const SceneBody *description, const char context[], Body *body);
/* The scene description (type, friction, thickness, name); borrowed. */
PetscErrorCode BodyGetDescription(Body body, const SceneBody **description);
/* Mesh bodies: the placed triangles (m), unit outward face normals (3 per triangle, 0 for degenerate
   triangles) and the bounding box; borrowed. Errors for analytic bodies. */
PetscErrorCode BodyGetMesh(Body body, const MeshTriangles **mesh, const PetscReal **face_normal, PetscReal lo[3], PetscReal hi[3]);
/* Analytic bodies: distance from the surface (negative inside) and the outward unit normal at the nearest
   surface point. Errors for meshes. */
PetscErrorCode BodySignedDistance(Body body, const PetscReal x[3], PetscReal *distance, PetscReal normal[3]);
/* Generalized winding number of the mesh at x (about 1 inside, 0 outside). */
PetscErrorCode BodyWindingNumber(Body body, const PetscReal x[3], PetscReal *winding);
/* Is x inside the body? Analytic: signed distance < 0; mesh: outside the bounding box, or winding number
   <= 1/2, is outside. */
PetscErrorCode BodyIsInside(Body body, const PetscReal x[3], PetscBool *inside);
/* The surface point nearest to x and the unit outward normal there (mesh: the face normal of the nearest
   triangle; a search over all triangles, meant for the few particles found inside). */
PetscErrorCode BodyNearestSurfacePoint(Body body, const PetscReal x[3], PetscReal point[3], PetscReal normal[3]);
/* Prints the type, placement and, for meshes, the triangle count, box and boundary-edge count. */
PetscErrorCode BodyView(Body body, PetscViewer viewer);
PetscErrorCode BodyDestroy(Body *body);
