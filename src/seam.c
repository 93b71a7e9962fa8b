/* Seams and sewing forces (see seam.h). */
#include "seam.h"

static void GapVector(const ClothSeamLink *link, const PetscReal *const x[], PetscReal g[3])
{
  g[0] = g[1] = g[2] = 0;
  for (PetscInt k = 0; k < link->np; k++)
    for (PetscInt c = 0; c < 3; c++) g[c] += link->c[k] * x[k][c];
}

PetscReal ClothSeamLinkGap(const ClothSeamLink *link, const PetscReal *const x[])
{
  PetscReal g[3];

  GapVector(link, x, g);
  return PetscSqrtReal(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

PetscErrorCode ClothSeamLinkEvaluate(const ClothSeamLink *link, const PetscReal *const x[], PetscReal *energy, PetscReal force[], PetscReal H[])
{
  const PetscInt n = 3 * link->np;
  PetscReal      g[3], d, dEdg[3], Hg[9];

  PetscFunctionBeginUser;
  GapVector(link, x, g);
  d = PetscSqrtReal(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (link->pull_force <= 0 || d * link->k <= link->pull_force) {
    /* quadratic core: E = 0.5 k d^2 */
    if (energy) *energy = 0.5 * link->k * d * d;
    for (PetscInt c = 0; c < 3; c++) dEdg[c] = link->k * g[c];
    for (PetscInt r = 0; r < 9; r++) Hg[r] = (r % 4 == 0) ? link->k : 0.0;
  } else {
    /* constant pull F beyond r = F / k: E = F (d - r / 2); Hessian F/d (I - g g^T / d^2), PSD */
    const PetscReal F = link->pull_force, r = F / link->k;
    if (energy) *energy = F * (d - 0.5 * r);
    for (PetscInt c = 0; c < 3; c++) dEdg[c] = F * g[c] / d;
    for (PetscInt a = 0; a < 3; a++)
      for (PetscInt b = 0; b < 3; b++) Hg[3 * a + b] = F / d * ((a == b ? 1.0 : 0.0) - g[a] * g[b] / (d * d));
  }
  if (force)
    for (PetscInt k = 0; k < link->np; k++)
      for (PetscInt c = 0; c < 3; c++) force[3 * k + c] = -link->c[k] * dEdg[c];
  if (H)
    for (PetscInt k = 0; k < link->np; k++)
      for (PetscInt l = 0; l < link->np; l++)
        for (PetscInt a = 0; a < 3; a++)
          for (PetscInt b = 0; b < 3; b++) H[n * (3 * k + a) + 3 * l + b] = link->c[k] * link->c[l] * Hg[3 * a + b];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Piece-local node (i, j) of the k-th node of a side in index order, and its inward neighbour. */
static void SideNode(const ScenePiece *piece, ClothPieceSide side, PetscInt k, PetscInt *node, PetscInt *inner)
{
  const PetscInt nu = piece->nu, nv = piece->nv;

  switch (side) {
  case CLOTH_SIDE_BOTTOM:
    *node  = k;
    *inner = nu + k;
    break;
  case CLOTH_SIDE_TOP:
    *node  = (nv - 1) * nu + k;
    *inner = (nv - 2) * nu + k;
    break;
  case CLOTH_SIDE_LEFT:
    *node  = k * nu;
    *inner = k * nu + 1;
    break;
  default:
    *node  = k * nu + nu - 1;
    *inner = k * nu + nu - 2;
    break; /* right */
  }
}

PetscErrorCode SeamSideCreate(const Scene scene, const SceneSeam *seam, const SceneSeamSide *side, const PetscReal uv[], SeamSide *out)
{
  const ScenePiece *piece = &scene->pieces[side->piece];
  const PetscInt    count = (side->side == CLOTH_SIDE_BOTTOM || side->side == CLOTH_SIDE_TOP) ? piece->nu : piece->nv;
  const PetscReal   lo = PetscMin(side->from, side->to), hi = PetscMax(side->from, side->to), eps = 1e-9;
  PetscReal        *s;
  PetscInt          first = -1, last = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(count, &s));
  s[0] = 0;
  for (PetscInt k = 1; k < count; k++) {
    PetscInt a, b, ia, ib;
    SideNode(piece, side->side, k - 1, &a, &ia);
    SideNode(piece, side->side, k, &b, &ib);
    s[k] = s[k - 1] + PetscSqrtReal(PetscSqr(uv[2 * b] - uv[2 * a]) + PetscSqr(uv[2 * b + 1] - uv[2 * a + 1]));
  }
  for (PetscInt k = 0; k < count; k++) {
    const PetscReal f = s[k] / s[count - 1];
    if (f >= lo - eps && f <= hi + eps) {
      if (first < 0) first = k;
      last = k;
    }
  }
  /* the grid decides (-grid N may change it after the scene was read): named with the file and the side's line */
  PetscCheck(first >= 0 && last > first, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
             "scene %s, line %d: seam '%s', side %s: the stretch %g..%g of the %s side of piece '%s' holds fewer than two of the side's %" PetscInt_FMT " nodes: expected from and to at least one node spacing apart (%g of the side), or a finer grid",
             scene->path, side->line, seam->name, side == &seam->a ? "a" : "b", (double)side->from, (double)side->to, ClothPieceSides[side->side], piece->name, count, 1.0 / (double)(count - 1));
  out->n = last - first + 1;
  PetscCall(PetscMalloc3(out->n, &out->node, out->n, &out->inner, out->n, &out->t));
  for (PetscInt m = 0; m < out->n; m++) {
    const PetscInt k = (side->from <= side->to) ? first + m : last - m;
    SideNode(piece, side->side, k, &out->node[m], &out->inner[m]);
    out->t[m] = PetscAbsReal(s[k] - s[(side->from <= side->to) ? first : last]) / (s[last] - s[first]);
  }
  PetscCall(PetscFree(s));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SeamSideDestroy(SeamSide *side)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(side->node, side->inner, side->t));
  side->n = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Pairs every node of `dense` with the point at the same arc-length fraction on `other`. */
static void LinkSides(PetscInt seam_index, const SeamSide *dense, PetscInt offset_dense, const SeamSide *other, PetscInt offset_other, ClothSeamLink links[], SeamBendSite bend[])
{
  PetscInt m = 0;

  for (PetscInt k = 0; k < dense->n; k++) {
    ClothSeamLink  *link = &links[k];
    const PetscReal t    = dense->t[k];
    PetscReal       w;

    while (m + 2 < other->n && other->t[m + 1] < t) m++;
    w                = (t - other->t[m]) / (other->t[m + 1] - other->t[m]);
    w                = PetscMin(PetscMax(w, 0.0), 1.0);
    link->seam       = seam_index;
    link->p[0]       = offset_dense + dense->node[k];
    link->c[0]       = 1.0;
    link->pull_force = 0;
    link->k          = 0;
    if (w < 1e-12 || w > 1 - 1e-12) { /* the point is a node of the other side */
      link->np   = 2;
      link->p[1] = offset_other + other->node[w < 0.5 ? m : m + 1];
      link->c[1] = -1.0;
    } else {
      link->np   = 3;
      link->p[1] = offset_other + other->node[m];
      link->p[2] = offset_other + other->node[m + 1];
      link->c[1] = -(1.0 - w);
      link->c[2] = -w;
    }
    if (bend && link->np == 3)
      bend[k].inner = -1; /* no bending site: see seam.h */
    else if (bend) {
      bend[k].inner       = offset_dense + dense->inner[k];
      bend[k].node        = offset_dense + dense->node[k];
      bend[k].along       = offset_dense + dense->node[k + 1 < dense->n ? k + 1 : k - 1];
      bend[k].other_node  = offset_other + other->node[w < 0.5 ? m : m + 1];
      bend[k].other_inner = offset_other + other->inner[w < 0.5 ? m : m + 1];
    }
  }
}

PetscErrorCode SeamBuildLinks(PetscInt seam_index, const SceneSeam *seam, const SeamSide *a, PetscInt offset_a, const SeamSide *b, PetscInt offset_b, ClothSeamLink links[], SeamBendSite bend[], PetscInt *nadded)
{
  const PetscBool      a_dense = a->n >= b->n ? PETSC_TRUE : PETSC_FALSE;
  const SceneSeamSide *dense   = a_dense ? &seam->a : &seam->b;

  PetscFunctionBeginUser;
  if (a_dense)
    LinkSides(seam_index, a, offset_a, b, offset_b, links, bend);
  else
    LinkSides(seam_index, b, offset_b, a, offset_a, links, bend);
  *nadded = PetscMax(a->n, b->n);
  for (PetscInt k = 0; bend && k < *nadded; k++) {
    bend[k].dense_piece = dense->piece;
    bend[k].dense_warp  = (dense->side == CLOTH_SIDE_LEFT || dense->side == CLOTH_SIDE_RIGHT) ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
