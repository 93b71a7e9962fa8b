/* Seams: corresponding points of two pattern pieces' boundaries, and the forces that sew them
   (docs/model.md section 7).

   A seam joins a stretch of one piece's boundary to a stretch of another's. Corresponding points are
   matched by arc length: every node of the side with more nodes is paired with the point at the
   same fraction of arc length on the other side, which in general lies between two of its nodes. A
   seam link then holds the node and that interpolated point together; its "gap" is their distance.

   Sewing pulls every pair towards the midpoint between them with a force that acts like gravity:
   of constant magnitude (mass x pull acceleration) while the pair is far apart, and falling linearly
   to zero over the last pull_radius metres, so the energy is smooth (C1) and its Hessian exists
   everywhere. Once a pair is closer than the tolerance it is sewn: from then on it is held by a stiff
   zero-length spring. Sewn pairs stay separate particles (rather than being merged) so that the
   particle graph, its partition and the matrix pattern never change during a run. */
#pragma once
#include "scene.h"

#define CLOTH_SEAM_LINK_MAX_PARTICLES 3

typedef struct {
  PetscInt  np;                               /* 2, or 3 when the point on the other side is interpolated */
  PetscInt  p[CLOTH_SEAM_LINK_MAX_PARTICLES]; /* p[0]: the node; p[1..]: the other side's nodes */
  PetscReal c[CLOTH_SEAM_LINK_MAX_PARTICLES]; /* gap vector = sum_k c[k] x[p[k]]; c[0] = 1, the rest sum to -1 */
  PetscInt  seam;                             /* index into Scene.seams */
  PetscReal pull_force;                       /* N: the constant pull while far apart (0 once sewn) */
  PetscReal k;                                /* N/m: stiffness near the pair (pull) or of the sewn spring */
} ClothSeamLink;

/* Energy, forces (3 np) and Hessian (3np x 3np, row-major) of a seam link at positions x[k] of its
   particles p[k]. Any output may be NULL. */
PetscErrorCode ClothSeamLinkEvaluate(const ClothSeamLink *link, const PetscReal *const x[], PetscReal *energy, PetscReal force[], PetscReal H[]);
/* Distance between the two sewn points. */
PetscReal ClothSeamLinkGap(const ClothSeamLink *link, const PetscReal *const x[]);

/* One side of a seam resolved to nodes: piece-local node indices in seam order, the node one step
   inside the piece from each (for bending across the seam) and the normalised arc length t in [0, 1]
   of each node along the stretch. */
typedef struct {
  PetscInt   n;
  PetscInt  *node, *inner;
  PetscReal *t;
} SeamSide;

/* Resolves a seam side of a piece (nu x nv grid with flat coordinates uv) to nodes. The stretch runs
   from `from` to `to` (fractions of the side's arc length, in index order: bottom and top by
   increasing i, left and right by increasing j; to < from reverses it). Errors name the seam. */
PetscErrorCode SeamSideCreate(const Scene scene, const SceneSeam *seam, const SceneSeamSide *side, const PetscReal uv[], SeamSide *out);
PetscErrorCode SeamSideDestroy(SeamSide *side);

/* Where bending across a seam acts, for one seam link: the node, the node inside its piece next to it,
   and the node inside the other piece next to the node it is sewn to (global numbers). Only links that
   join a node to a node get one (inner = -1 for the others): there the three nodes lie on one straight
   line across the sewn seam, while a site at an interpolated point would see an in-plane kink of up to
   half a node spacing and fight the seam. With equal node counts every link has a site; with n and m
   nodes, the links at the nodes that meet (every (n-1)/gcd(n-1, m-1)-th, and always both ends). */
typedef struct {
  PetscInt  inner, node, other_node, other_inner;
  PetscInt  along;      /* a neighbour of node along its side: the seam's local node spacing is |x_node - x_along| */
  PetscBool dense_warp; /* the node's inward step runs along the warp (left/right sides) */
  PetscInt  dense_piece;
} SeamBendSite;

/* Builds the links of one seam from its two resolved sides (pieces ia, ib; piece offsets give global
   numbering). Writes max(nA, nB) links and as many bending sites (bend may be NULL). */
PetscErrorCode SeamBuildLinks(PetscInt seam_index, const SceneSeam *seam, const SeamSide *a, PetscInt offset_a, const SeamSide *b, PetscInt offset_b, ClothSeamLink links[], SeamBendSite bend[], PetscInt *nadded);
