/* Body (see body.h). */
#include "body.h"
#include "geometry.h"
#include "winding.h"
#include "vec3.h"

struct _n_Body {
  MPI_Comm      comm;
  SceneBody     description;
  MeshTriangles mesh;           /* mesh bodies only */
  PetscReal    *face_normal;    /* 3 per triangle */
  PetscReal     lo[3], hi[3];   /* bounding box of the placed mesh */
  PetscInt      boundary_edges; /* edges used by one triangle only (holes) */
  PetscInt      nonmanifold_edges;
  PetscBool     flipped; /* the file's triangles were oriented inwards */
  WindingTree   winding; /* the inside test (mesh bodies) */
};

/* x <- R (scale x) + t with R = Rz Ry Rx (angles in degrees: about x first, then y, then z). */
static PetscErrorCode PlaceVertices(const SceneBody *d, MeshTriangles *mesh)
{
  PetscReal cs[3], sn[3], R[9];

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 3; k++) {
    cs[k] = PetscCosReal(d->rotation[k] * PETSC_PI / 180);
    sn[k] = PetscSinReal(d->rotation[k] * PETSC_PI / 180);
  }
  R[0] = cs[1] * cs[2];
  R[1] = sn[0] * sn[1] * cs[2] - cs[0] * sn[2];
  R[2] = cs[0] * sn[1] * cs[2] + sn[0] * sn[2];
  R[3] = cs[1] * sn[2];
  R[4] = sn[0] * sn[1] * sn[2] + cs[0] * cs[2];
  R[5] = cs[0] * sn[1] * sn[2] - sn[0] * cs[2];
  R[6] = -sn[1];
  R[7] = sn[0] * cs[1];
  R[8] = cs[0] * cs[1];
  for (PetscInt v = 0; v < mesh->nverts; v++) {
    PetscReal *x = &mesh->coords[3 * v], y[3];

    for (PetscInt r = 0; r < 3; r++) y[r] = d->scale * (R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2]) + d->translation[r];
    for (PetscInt r = 0; r < 3; r++) x[r] = y[r];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Orients the triangles outwards (positive enclosed volume, which holds for a mostly closed surface), then
   computes face normals and the bounding box. */
static PetscErrorCode OrientAndMeasure(Body body)
{
  MeshTriangles *m      = &body->mesh;
  PetscReal      volume = 0;

  PetscFunctionBeginUser;
  for (PetscInt t = 0; t < m->ntris; t++) {
    const PetscReal *a = &m->coords[3 * m->tris[3 * t]], *b = &m->coords[3 * m->tris[3 * t + 1]], *c = &m->coords[3 * m->tris[3 * t + 2]];
    PetscReal        bc[3];

    Cross3(b, c, bc);
    volume += Dot3(a, bc) / 6;
  }
  body->flipped = volume < 0 ? PETSC_TRUE : PETSC_FALSE;
  if (body->flipped)
    for (PetscInt t = 0; t < m->ntris; t++) {
      const PetscInt swap = m->tris[3 * t + 1];
      m->tris[3 * t + 1]  = m->tris[3 * t + 2];
      m->tris[3 * t + 2]  = swap;
    }
  PetscCall(PetscMalloc1(3 * m->ntris, &body->face_normal));
  for (PetscInt t = 0; t < m->ntris; t++) {
    const PetscReal *a = &m->coords[3 * m->tris[3 * t]], *b = &m->coords[3 * m->tris[3 * t + 1]], *c = &m->coords[3 * m->tris[3 * t + 2]];
    PetscReal        e1[3], e2[3], *n                                                                = &body->face_normal[3 * t], len;

    Sub3(b, a, e1);
    Sub3(c, a, e2);
    Cross3(e1, e2, n);
    len = PetscSqrtReal(Dot3(n, n));
    for (PetscInt k = 0; k < 3; k++) n[k] = len > 0 ? n[k] / len : 0;
  }
  for (PetscInt k = 0; k < 3; k++) {
    body->lo[k] = PETSC_MAX_REAL;
    body->hi[k] = -PETSC_MAX_REAL;
  }
  for (PetscInt v = 0; v < m->nverts; v++)
    for (PetscInt k = 0; k < 3; k++) {
      body->lo[k] = PetscMin(body->lo[k], m->coords[3 * v + k]);
      body->hi[k] = PetscMax(body->hi[k], m->coords[3 * v + k]);
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Counts edges used by one triangle (boundary: the mesh has holes) or by more than two (non-manifold). */
static PetscErrorCode CountOpenEdges(Body body)
{
  const MeshTriangles *m = &body->mesh;
  PetscInt64          *key;
  const PetscInt64     nv = m->nverts;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(3 * m->ntris, &key));
  for (PetscInt t = 0; t < m->ntris; t++)
    for (PetscInt k = 0; k < 3; k++) {
      const PetscInt64 a = m->tris[3 * t + k], b = m->tris[3 * t + (k + 1) % 3];
      key[3 * t + k] = PetscMin(a, b) * nv + PetscMax(a, b);
    }
  PetscCall(PetscSortInt64(3 * m->ntris, key));
  body->boundary_edges = body->nonmanifold_edges = 0;
  for (PetscInt i = 0, j; i < 3 * m->ntris; i = j) {
    for (j = i + 1; j < 3 * m->ntris && key[j] == key[i];) j++;
    if (j - i == 1) body->boundary_edges++;
    if (j - i > 2) body->nonmanifold_edges++;
  }
  PetscCall(PetscFree(key));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyCreate(MPI_Comm comm, const SceneBody *description, const char context[], Body *body)
{
  Body b;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&b));
  b->comm        = comm;
  b->description = *description;
  if (description->type == SCENE_BODY_MESH) {
    PetscCall(MeshObjRead(comm, description->file, context, &b->mesh));
    PetscCall(PlaceVertices(description, &b->mesh));
    PetscCall(OrientAndMeasure(b));
    PetscCall(CountOpenEdges(b));
    PetscCall(WindingTreeCreate(b->mesh.ntris, b->mesh.tris, b->mesh.coords, &b->winding));
  }
  *body = b;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyGetDescription(Body body, const SceneBody **description)
{
  PetscFunctionBeginUser;
  *description = &body->description;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyGetMesh(Body body, const MeshTriangles **mesh, const PetscReal **face_normal, PetscReal lo[3], PetscReal hi[3])
{
  PetscFunctionBeginUser;
  PetscCheck(body->description.type == SCENE_BODY_MESH, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Body '%s' is a %s, not a mesh", body->description.name, SceneBodyTypes[body->description.type]);
  if (mesh) *mesh = &body->mesh;
  if (face_normal) *face_normal = body->face_normal;
  for (PetscInt k = 0; k < 3; k++) {
    if (lo) lo[k] = body->lo[k];
    if (hi) hi[k] = body->hi[k];
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodySignedDistance(Body body, const PetscReal x[3], PetscReal *distance, PetscReal normal[3])
{
  const SceneBody *d = &body->description;
  PetscReal        r[3], len;

  PetscFunctionBeginUser;
  if (d->type == SCENE_BODY_SPHERE) {
    Sub3(x, d->center, r);
    len = PetscSqrtReal(Dot3(r, r));
    for (PetscInt k = 0; k < 3; k++) normal[k] = len > 0 ? r[k] / len : (k == 1 ? 1.0 : 0.0); /* the centre itself: push up */
    *distance = len - d->radius;
  } else {
    PetscCheck(d->type == SCENE_BODY_PLANE, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Body '%s' is a mesh: it has no analytic distance", d->name);
    Sub3(x, d->point, r);
    for (PetscInt k = 0; k < 3; k++) normal[k] = d->normal[k];
    *distance = Dot3(r, d->normal);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyWindingNumber(Body body, const PetscReal x[3], PetscReal *winding)
{
  const MeshTriangles *m = &body->mesh;

  PetscFunctionBeginUser;
  PetscCheck(body->description.type == SCENE_BODY_MESH, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Body '%s' is not a mesh", body->description.name);
  *winding = WindingNumberExact(m->ntris, m->tris, m->coords, x);
  PetscCall(PetscLogFlops(60.0 * m->ntris));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyIsInside(Body body, const PetscReal x[3], PetscBool *inside)
{
  PetscReal d, n[3];

  PetscFunctionBeginUser;
  *inside = PETSC_FALSE;
  if (body->description.type != SCENE_BODY_MESH) {
    PetscCall(BodySignedDistance(body, x, &d, n));
    *inside = d < 0 ? PETSC_TRUE : PETSC_FALSE;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt k = 0; k < 3; k++)
    if (x[k] < body->lo[k] || x[k] > body->hi[k]) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(WindingTreeIsInside(body->winding, x, inside, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyNearestSurfacePoint(Body body, const PetscReal x[3], PetscReal point[3], PetscReal normal[3])
{
  const MeshTriangles *m    = &body->mesh;
  PetscReal            best = PETSC_MAX_REAL, d;

  PetscFunctionBeginUser;
  if (body->description.type != SCENE_BODY_MESH) {
    PetscCall(BodySignedDistance(body, x, &d, normal));
    for (PetscInt k = 0; k < 3; k++) point[k] = x[k] - d * normal[k];
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt t = 0; t < m->ntris; t++) {
    PetscReal q[3], r[3];

    if (Dot3(&body->face_normal[3 * t], &body->face_normal[3 * t]) == 0) continue; /* degenerate */
    GeometryTriangleNearestPoint(x, &m->coords[3 * m->tris[3 * t]], &m->coords[3 * m->tris[3 * t + 1]], &m->coords[3 * m->tris[3 * t + 2]], q);
    Sub3(q, x, r);
    if (Dot3(r, r) < best) {
      best = Dot3(r, r);
      for (PetscInt k = 0; k < 3; k++) {
        point[k]  = q[k];
        normal[k] = body->face_normal[3 * t + k];
      }
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyView(Body body, PetscViewer viewer)
{
  const SceneBody *d = &body->description;

  PetscFunctionBeginUser;
  if (d->type != SCENE_BODY_MESH) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "body '%s': %s, friction %g/%g, thickness %g m\n", d->name, SceneBodyTypes[d->type], (double)d->friction_static, (double)d->friction_kinetic, (double)d->thickness));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "body '%s': mesh %s, %" PetscInt_FMT " vertices, %" PetscInt_FMT " faces -> %" PetscInt_FMT " triangles%s\n", d->name, d->file, body->mesh.nverts, body->mesh.npolygons, body->mesh.ntris,
                                   body->flipped ? " (reoriented outwards)" : ""));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "box [%g, %g] x [%g, %g] x [%g, %g] m; %" PetscInt_FMT " boundary edges, %" PetscInt_FMT " non-manifold edges (inside test: winding number > 1/2)\n", (double)body->lo[0], (double)body->hi[0],
                                   (double)body->lo[1], (double)body->hi[1], (double)body->lo[2], (double)body->hi[2], body->boundary_edges, body->nonmanifold_edges));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode BodyDestroy(Body *body)
{
  PetscFunctionBeginUser;
  if (!*body) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(WindingTreeDestroy(&(*body)->winding));
  if ((*body)->description.type == SCENE_BODY_MESH) PetscCall(MeshTrianglesFree(&(*body)->mesh));
  PetscCall(PetscFree((*body)->face_normal));
  PetscCall(PetscFree(*body));
  PetscFunctionReturn(PETSC_SUCCESS);
}
