/* WindingTree: the inside test of a triangle mesh (the generalized winding number w(x) = sum of the triangles' solid
   angles / 4 pi, inside when w > 1/2; Jacobson et al. 2013) in time logarithmic in the triangles, with the answer of
   the sum over all triangles.

   The triangles are kept in a bounding-sphere tree (median splits of their centroids). A node far from x (x outside
   a sphere of WINDING_TREE_FAR_RATIO times its radius about its centre) contributes its dipole term N . (c - x) /
   |c - x|^3 (N the node's area vector, c its area centroid; Barill et al. 2018), the solid angle of a small
   triangle being the flux of (y - x) / |y - x|^3 through it. The dipole's error on a node is at most A r 2 / (d - r)^3
   (A the node's unsigned area, r its radius, d = |c - x|: the gradient of that field has norm 2 / |y - x|^3), and
   these bounds are summed with the approximation. When w is nearer 1/2 than the bound allows to decide, the exact
   sum over all triangles decides, so the answer is always the exact sum's. */
#pragma once
#include "util.h"

typedef struct _n_WindingTree *WindingTree;

/* The tree of ntris triangles (tris: 3 vertex indices each into coords, 3 per vertex), oriented outwards. The
   arrays are borrowed and must outlive the tree. */
PetscErrorCode WindingTreeCreate(PetscInt ntris, const PetscInt tris[], const PetscReal coords[], WindingTree *tree);
/* The tree's estimate of w(x) and a bound on its error (|w - exact| <= bound). */
PetscErrorCode WindingTreeEstimate(WindingTree tree, const PetscReal x[3], PetscReal *w, PetscReal *bound);
/* Is w(x) > 1/2? exact: whether the exact sum over all triangles had to decide (may be NULL). */
PetscErrorCode WindingTreeIsInside(WindingTree tree, const PetscReal x[3], PetscBool *inside, PetscBool *exact);
/* The exact winding number at x: the sum over all triangles. */
PetscReal      WindingNumberExact(PetscInt ntris, const PetscInt tris[], const PetscReal coords[], const PetscReal x[3]);
PetscErrorCode WindingTreeDestroy(WindingTree *tree);
