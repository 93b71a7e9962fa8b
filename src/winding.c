/* WindingTree (see winding.h). */
#include "winding.h"
#include "vec3.h"

/* Triangles per leaf. */
#define WINDING_TREE_LEAF 8
/* A node counts as far (its dipole term) only when x lies outside twice its radius and its error bound is at most
   this many steradians; the bounds of all far nodes together stay a small part of the 2 pi that separates w = 1/2
   from a point well inside or outside. */
#define WINDING_TREE_NODE_BOUND 0.01
/* Deepest tree: median splits halve the triangles, so 2^64 would be needed to exceed it. */
#define WINDING_TREE_MAX_DEPTH 64

typedef struct {
  PetscReal c[3];     /* area centroid */
  PetscReal N[3];     /* area vector: the sum of the triangles' (b - a) x (c - a) / 2 */
  PetscReal r, area;  /* radius of the sphere about c holding the triangles; unsigned area */
  PetscInt  first, n; /* triangles order[first .. first + n) */
  PetscInt  child[2]; /* -1: a leaf */
} WindingNode;

struct _n_WindingTree {
  PetscInt         ntris;
  const PetscInt  *tris;
  const PetscReal *coords;
  PetscInt        *order;    /* triangle indices, each node's contiguous */
  PetscReal       *centroid; /* 3 per triangle */
  PetscReal       *key;      /* sort keys, scratch of the build (NULL after it) */
  WindingNode     *nodes;
  PetscInt         nnodes;
};

/* Solid angle of triangle (a, b, c) seen from x (Van Oosterom & Strackee 1983), signed by orientation. */
static PetscReal TriangleSolidAngle(const PetscReal x[3], const PetscReal a[3], const PetscReal b[3], const PetscReal c[3])
{
  PetscReal p[3], q[3], r[3], qr[3], lp, lq, lr, numerator, denominator;

  Sub3(a, x, p);
  Sub3(b, x, q);
  Sub3(c, x, r);
  lp = PetscSqrtReal(Dot3(p, p));
  lq = PetscSqrtReal(Dot3(q, q));
  lr = PetscSqrtReal(Dot3(r, r));
  Cross3(q, r, qr);
  numerator   = Dot3(p, qr);
  denominator = lp * lq * lr + Dot3(p, q) * lr + Dot3(p, r) * lq + Dot3(q, r) * lp;
  return 2 * PetscAtan2Real(numerator, denominator);
}

static const PetscReal *Vertex(WindingTree t, PetscInt tri, PetscInt k)
{
  return &t->coords[3 * t->tris[3 * tri + k]];
}

PetscReal WindingNumberExact(PetscInt ntris, const PetscInt tris[], const PetscReal coords[], const PetscReal x[3])
{
  PetscReal sum = 0;

  for (PetscInt t = 0; t < ntris; t++) sum += TriangleSolidAngle(x, &coords[3 * tris[3 * t]], &coords[3 * tris[3 * t + 1]], &coords[3 * tris[3 * t + 2]]);
  return sum / (4 * PETSC_PI);
}

/* The node's area vector, unsigned area, area centroid (the plain centroid if the area is zero) and radius. */
static void MeasureNode(WindingTree t, WindingNode *node)
{
  PetscReal mean[3] = {0, 0, 0};

  for (PetscInt k = 0; k < 3; k++) node->N[k] = node->c[k] = 0;
  node->area = node->r = 0;
  for (PetscInt i = node->first; i < node->first + node->n; i++) {
    const PetscInt   tri = t->order[i];
    const PetscReal *a = Vertex(t, tri, 0), *b = Vertex(t, tri, 1), *c = Vertex(t, tri, 2), *g = &t->centroid[3 * tri];
    PetscReal        e1[3], e2[3], n[3], area;

    Sub3(b, a, e1);
    Sub3(c, a, e2);
    Cross3(e1, e2, n);
    area = 0.5 * PetscSqrtReal(Dot3(n, n));
    for (PetscInt k = 0; k < 3; k++) {
      node->N[k] += 0.5 * n[k];
      node->c[k] += area * g[k];
      mean[k] += g[k] / node->n;
    }
    node->area += area;
  }
  for (PetscInt k = 0; k < 3; k++) node->c[k] = node->area > 0 ? node->c[k] / node->area : mean[k];
  for (PetscInt i = node->first; i < node->first + node->n; i++)
    for (PetscInt v = 0; v < 3; v++) {
      PetscReal d[3];
      Sub3(Vertex(t, t->order[i], v), node->c, d);
      node->r = PetscMax(node->r, PetscSqrtReal(Dot3(d, d)));
    }
}

/* Node *index over triangles order[first .. first + n), split at the median centroid along the longest side of the
   centroids' box. */
static PetscErrorCode BuildNode(WindingTree t, PetscInt first, PetscInt n, PetscInt depth, PetscInt *index)
{
  WindingNode *node;
  PetscReal    lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  PetscInt     axis = 0, child[2];

  PetscFunctionBeginUser;
  PetscCheck(depth < WINDING_TREE_MAX_DEPTH, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Winding tree deeper than %d levels", WINDING_TREE_MAX_DEPTH);
  *index         = t->nnodes++;
  node           = &t->nodes[*index];
  node->first    = first;
  node->n        = n;
  node->child[0] = node->child[1] = -1;
  MeasureNode(t, node);
  if (n <= WINDING_TREE_LEAF) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt i = first; i < first + n; i++)
    for (PetscInt k = 0; k < 3; k++) {
      lo[k] = PetscMin(lo[k], t->centroid[3 * t->order[i] + k]);
      hi[k] = PetscMax(hi[k], t->centroid[3 * t->order[i] + k]);
    }
  for (PetscInt k = 1; k < 3; k++)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  for (PetscInt i = first; i < first + n; i++) t->key[i] = t->centroid[3 * t->order[i] + axis];
  PetscCall(PetscSortRealWithArrayInt(n, &t->key[first], &t->order[first]));
  PetscCall(BuildNode(t, first, n / 2, depth + 1, &child[0]));
  PetscCall(BuildNode(t, first + n / 2, n - n / 2, depth + 1, &child[1]));
  node->child[0] = child[0]; /* the node array is allocated once: node is still valid */
  node->child[1] = child[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode WindingTreeCreate(PetscInt ntris, const PetscInt tris[], const PetscReal coords[], WindingTree *tree)
{
  WindingTree t;
  PetscInt    root;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&t));
  t->ntris  = ntris;
  t->tris   = tris;
  t->coords = coords;
  /* a binary tree whose leaves hold at least one triangle has fewer than 2 ntris nodes */
  PetscCall(PetscMalloc3(ntris, &t->order, 3 * ntris, &t->centroid, 2 * ntris + 1, &t->nodes));
  PetscCall(PetscMalloc1(ntris, &t->key));
  for (PetscInt i = 0; i < ntris; i++) {
    t->order[i] = i;
    for (PetscInt k = 0; k < 3; k++) t->centroid[3 * i + k] = (Vertex(t, i, 0)[k] + Vertex(t, i, 1)[k] + Vertex(t, i, 2)[k]) / 3;
  }
  if (ntris > 0) PetscCall(BuildNode(t, 0, ntris, 0, &root));
  PetscCall(PetscFree(t->key));
  *tree = t;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode WindingTreeEstimate(WindingTree t, const PetscReal x[3], PetscReal *w, PetscReal *bound)
{
  PetscInt  stack[2 * WINDING_TREE_MAX_DEPTH + 2], top = 0;
  PetscReal sum = 0, error_sum = 0;

  PetscFunctionBeginUser;
  if (t->nnodes) stack[top++] = 0;
  while (top > 0) {
    const WindingNode *node = &t->nodes[stack[--top]];
    PetscReal          d[3], dist, error;

    Sub3(node->c, x, d);
    dist  = PetscSqrtReal(Dot3(d, d));
    error = dist > 2 * node->r ? 2 * node->area * node->r / PetscPowRealInt(dist - node->r, 3) : PETSC_MAX_REAL;
    if (error <= WINDING_TREE_NODE_BOUND) {
      sum += Dot3(node->N, d) / (dist * dist * dist);
      error_sum += error;
    } else if (node->child[0] < 0) {
      for (PetscInt i = node->first; i < node->first + node->n; i++) sum += TriangleSolidAngle(x, Vertex(t, t->order[i], 0), Vertex(t, t->order[i], 1), Vertex(t, t->order[i], 2));
    } else {
      stack[top++] = node->child[0];
      stack[top++] = node->child[1];
    }
  }
  *w     = sum / (4 * PETSC_PI);
  *bound = error_sum / (4 * PETSC_PI);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode WindingTreeIsInside(WindingTree t, const PetscReal x[3], PetscBool *inside, PetscBool *exact)
{
  PetscReal w, bound;

  PetscFunctionBeginUser;
  PetscCall(WindingTreeEstimate(t, x, &w, &bound));
  if (exact) *exact = PETSC_FALSE;
  if (PetscAbsReal(w - 0.5) <= bound + 1e-12) { /* too close to decide within the bound: the exact sum */
    w = WindingNumberExact(t->ntris, t->tris, t->coords, x);
    if (exact) *exact = PETSC_TRUE;
  }
  *inside = w > 0.5 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode WindingTreeDestroy(WindingTree *tree)
{
  PetscFunctionBeginUser;
  if (!*tree) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree3((*tree)->order, (*tree)->centroid, (*tree)->nodes));
  PetscCall(PetscFree(*tree));
  PetscFunctionReturn(PETSC_SUCCESS);
}
