/* ClothModel (see model.h): particles, masses and interactions of every piece. */
#include <stdint.h>
#include "model.h"
#include "fabric.h"
#include "pattern.h"
#include "vec3.h"

/* Everything needed while one piece's interactions are generated. */
typedef struct {
  const ScenePiece  *piece;
  const SceneFabric *fabric;
  const PetscReal   *uv;     /* flat pattern coordinates */
  PetscInt           offset; /* global index of particle (0, 0) */
} PieceContext;

static inline PetscInt PieceNode(const PieceContext *pc, PetscInt i, PetscInt j)
{
  return j * pc->piece->nu + i;
}

/* Whether the edge from node (i, j) to node (i + di, j + dj) (di, dj in {-1, 0, 1}, one of them 0) is fabric. */
static PetscBool PieceEdgeKept(const PieceContext *pc, PetscInt i, PetscInt j, PetscInt di, PetscInt dj)
{
  return PatternEdgeKept(pc->piece, pc->uv, PetscMin(i, i + di), PetscMin(j, j + dj), PetscAbsInt(di), PetscAbsInt(dj));
}

static PetscReal FlatDistance(const PieceContext *pc, PetscInt a, PetscInt b)
{
  const PetscReal du = pc->uv[2 * a] - pc->uv[2 * b], dv = pc->uv[2 * a + 1] - pc->uv[2 * b + 1];
  return PetscSqrtReal(du * du + dv * dv);
}

/* Mean rest length of the links at node (i, j) across the direction of thread `warp`: the width
   that thread carries there. */
static PetscReal ThreadWidth(const PieceContext *pc, PetscInt i, PetscInt j, PetscBool warp)
{
  const PetscInt n = warp ? pc->piece->nv : pc->piece->nu, at = warp ? j : i;
  PetscReal      sum   = 0;
  PetscInt       count = 0;

  for (PetscInt s = -1; s <= 1; s += 2) {
    const PetscInt other = at + s;
    if (other < 0 || other >= n || !PieceEdgeKept(pc, i, j, warp ? 0 : s, warp ? s : 0)) continue;
    sum += FlatDistance(pc, PieceNode(pc, i, j), warp ? PieceNode(pc, i, other) : PieceNode(pc, other, j));
    count++;
  }
  return sum / count;
}

/* The strip of fabric a thread owns at node (i, j): half the distance to each neighbouring parallel thread, so
   that a thread on the piece's edge owns half a spacing and the widths add up to the piece's width, as the
   particles' masses do (a quarter of each cell). The rigidities E, B are per unit width of real fabric: with the
   mean spacing (ThreadWidth) an edge thread would carry a full spacing's stiffness on half a spacing's mass, and a
   strip of n threads would stretch and bend n / (n - 1) times too stiffly (1.5 for 3). */
static PetscReal ThreadOwnWidth(const PieceContext *pc, PetscInt i, PetscInt j, PetscBool warp)
{
  const PetscInt n = warp ? pc->piece->nv : pc->piece->nu, at = warp ? j : i;
  PetscReal      width = 0;

  for (PetscInt s = -1; s <= 1; s += 2) {
    const PetscInt other = at + s;
    if (other < 0 || other >= n || !PieceEdgeKept(pc, i, j, warp ? 0 : s, warp ? s : 0)) continue;
    width += 0.5 * FlatDistance(pc, PieceNode(pc, i, j), warp ? PieceNode(pc, i, other) : PieceNode(pc, other, j));
  }
  return width;
}

/* The width whose stiffness the links along a thread carry at node (i, j) (stretch, and bending in the link model):
   the thread's own strip (ThreadOwnWidth), as its mass is. A `mass: uniform` piece is a net of equal particles, an
   edge one as heavy as any other: there every link keeps the paper's per-link coefficient (ThreadWidth), the net the
   hanging-sheet benchmark shares with its peers (docs/model.md section 2). */
static PetscReal ThreadLinkWidth(const PieceContext *pc, PetscInt i, PetscInt j, PetscBool warp)
{
  return pc->piece->mass_distribution == CLOTH_MASS_UNIFORM ? ThreadWidth(pc, i, j, warp) : ThreadOwnWidth(pc, i, j, warp);
}

static ClothLink *AddLink(ClothModel model, PetscInt a, PetscInt b, PetscReal k, PetscReal rest, PetscReal repel_length, PetscReal repel_k)
{
  ClothLink *link = &model->links[model->nlinks++];

  link->p[0]         = a;
  link->p[1]         = b;
  link->k            = k;
  link->rest         = rest;
  link->repel_length = repel_length;
  link->repel_k      = repel_k;
  link->knee_length  = 0;
  link->k_stiff      = k;
  return link;
}

/* An angle spring on the pattern nodes local[] (ClothAngleParticleCount(kind) of them), its rest angle
   from the flat pattern through the same arm weights as in ClothAngleEvaluate. */
static void AddAngle(ClothModel model, const PieceContext *pc, ClothAngleKind kind, const PetscInt local[], PetscReal k)
{
  ClothAngle *angle = &model->angles[model->nangles++];
  PetscReal   A[CLOTH_ANGLE_MAX_PARTICLES], B[CLOTH_ANGLE_MAX_PARTICLES], a[2] = {0, 0}, b[2] = {0, 0}, na, nb;

  ClothAngleArms(kind, A, B);
  for (PetscInt q = 0; q < ClothAngleParticleCount(kind); q++) {
    for (PetscInt c = 0; c < 2; c++) {
      a[c] += A[q] * pc->uv[2 * local[q] + c];
      b[c] += B[q] * pc->uv[2 * local[q] + c];
    }
    angle->p[q] = pc->offset + local[q];
  }
  na          = PetscSqrtReal(a[0] * a[0] + a[1] * a[1]);
  nb          = PetscSqrtReal(b[0] * b[0] + b[1] * b[1]);
  angle->kind = kind;
  angle->k    = k;
  angle->slip = 0;
  angle->cos0 = (a[0] * b[0] + a[1] * b[1]) / (na * nb);
  angle->sin0 = PetscAbsReal(a[0] * b[1] - a[1] * b[0]) / (na * nb);
}

/* The twist element of the cell with nodes local[0..3] (forces.h): its rest twist is zero, the pattern being flat. */
static void AddTwist(ClothModel model, const PieceContext *pc, const PetscInt local[4], PetscReal k)
{
  ClothAngle *twist = &model->angles[model->nangles++];

  for (PetscInt q = 0; q < 4; q++) twist->p[q] = pc->offset + local[q];
  twist->kind = CLOTH_ANGLE_TWIST;
  twist->k    = k;
  twist->slip = 0;
  twist->cos0 = 1;
  twist->sin0 = 0;
}

/* Stretch links to the 4 neighbours, and the skip-one bending links, along one thread direction. */
static void AddThreadInteractions(ClothModel model, const PieceContext *pc, PetscBool warp)
{
  const ScenePiece  *piece = pc->piece;
  const SceneFabric *fab   = pc->fabric;
  const PetscInt     di = warp ? 1 : 0, dj = warp ? 0 : 1;

  for (PetscInt j = 0; j < piece->nv; j++)
    for (PetscInt i = 0; i < piece->nu; i++) {
      const PetscInt a = PieceNode(pc, i, j);
      if (i + di < piece->nu && j + dj < piece->nv && PieceEdgeKept(pc, i, j, di, dj)) {
        const PetscInt  b     = PieceNode(pc, i + di, j + dj);
        const PetscReal rest  = FlatDistance(pc, a, b);
        const PetscReal width = 0.5 * (ThreadLinkWidth(pc, i, j, warp) + ThreadLinkWidth(pc, i + di, j + dj, warp));
        const PetscReal k     = FabricStretchLinkStiffness(fab, warp, rest, width);
        ClothLink      *link  = AddLink(model, pc->offset + a, pc->offset + b, k, rest, fab->repulsion * rest, fab->repulsion_stiffness * k);

        const PetscReal knee = warp ? fab->stretch_knee_warp : fab->stretch_knee_weft;

        if (knee > 0) { /* biphasic tensile curve (fabric.h) */
          link->knee_length = knee * rest;
          link->k_stiff     = FabricStretchLinkStiffStiffness(fab, warp, rest, width);
        }
      }
      if (i + 2 * di < piece->nu && j + 2 * dj < piece->nv && PieceEdgeKept(pc, i, j, di, dj) && PieceEdgeKept(pc, i + di, j + dj, di, dj)) {
        const PetscInt  m = PieceNode(pc, i + di, j + dj), b = PieceNode(pc, i + 2 * di, j + 2 * dj);
        const PetscReal width = ThreadLinkWidth(pc, i + di, j + dj, warp);
        if (fab->bend_model == CLOTH_BEND_LINK) {
          const PetscReal rest = FlatDistance(pc, a, b);
          AddLink(model, pc->offset + a, pc->offset + b, FabricBendLinkStiffness(fab, warp, rest, width), rest, 0, 0);
        } else {
          const PetscInt  local[3] = {a, m, b};
          const PetscReal segment  = 0.5 * (FlatDistance(pc, a, m) + FlatDistance(pc, m, b));
          const PetscReal own      = ThreadOwnWidth(pc, i + di, j + dj, warp);
          const PetscReal k        = FabricBendAngleStiffness(fab, warp, segment, own);
          const PetscReal friction = (warp ? fab->bend_hysteresis_warp : fab->bend_hysteresis_weft) * own;

          AddAngle(model, pc, CLOTH_ANGLE_CHAIN, local, k);
          if (friction > 0 && k > 0) { /* the Jenkins element of bending hysteresis (forces.h) */
            AddAngle(model, pc, CLOTH_ANGLE_CHAIN, local, CLOTH_HYSTERESIS_STIFFNESS * k);
            model->angles[model->nangles - 1].slip = friction / (CLOTH_HYSTERESIS_STIFFNESS * k);
          }
        }
      }
    }
}

/* Shear interactions of every grid cell, and the cell as an output quad. */
static PetscErrorCode AddCellInteractions(ClothModel model, const PieceContext *pc)
{
  const ScenePiece *piece = pc->piece;

  PetscFunctionBeginUser;
  for (PetscInt j = 0; j + 1 < piece->nv; j++)
    for (PetscInt i = 0; i + 1 < piece->nu; i++) {
      const PetscInt  c[4] = {PieceNode(pc, i, j), PieceNode(pc, i + 1, j), PieceNode(pc, i + 1, j + 1), PieceNode(pc, i, j + 1)};
      const PetscReal area = PatternCellArea(piece->nu, pc->uv, i, j);

      if (!PatternCellKept(piece, pc->uv, i, j)) continue;
      for (PetscInt k = 0; k < 4; k++) model->quads[4 * model->nquads + k] = pc->offset + c[k];
      model->nquads++;
      if (FabricTwistRigidity(pc->fabric) > 0) {
        const PetscReal lu = 0.5 * (FlatDistance(pc, c[0], c[1]) + FlatDistance(pc, c[3], c[2])), lv = 0.5 * (FlatDistance(pc, c[0], c[3]) + FlatDistance(pc, c[1], c[2]));
        AddTwist(model, pc, c, FabricTwistStiffness(pc->fabric, area, lu, lv));
      }
      if (pc->fabric->shear <= 0) continue;
      if (pc->fabric->shear_model == CLOTH_SHEAR_LINK) {
        for (PetscInt d = 0; d < 2; d++) {
          const PetscReal rest = FlatDistance(pc, c[d], c[d + 2]);
          AddLink(model, pc->offset + c[d], pc->offset + c[d + 2], FabricShearLinkStiffness(pc->fabric, rest, area), rest, 0, 0);
        }
      } else if (pc->fabric->shear_model == CLOTH_SHEAR_CELL) {
        const PetscReal k = FabricShearCellStiffness(pc->fabric, area);

        AddAngle(model, pc, CLOTH_ANGLE_CELL, c, k);
        if (pc->fabric->shear_hysteresis > 0) { /* the Jenkins element of shear hysteresis: gives way at HG A (forces.h) */
          AddAngle(model, pc, CLOTH_ANGLE_CELL, c, CLOTH_HYSTERESIS_STIFFNESS * k);
          model->angles[model->nangles - 1].slip = pc->fabric->shear_hysteresis * area / (CLOTH_HYSTERESIS_STIFFNESS * k);
        }
      } else {
        for (PetscInt k = 0; k < 4; k++) {
          const PetscInt local[3] = {c[k], c[(k + 1) % 4], c[(k + 3) % 4]};
          AddAngle(model, pc, CLOTH_ANGLE_CORNER, local, FabricShearAngleStiffness(pc->fabric, area));
        }
      }
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rolls a flat placement onto the cylinder around the piece's wrap axis that touches its plane: a point
   at distance s from the touching line (along the plane, across the axis) goes to angle s / r around the
   axis, its position along the axis kept, so lengths along and across the axis are preserved. */
static void WrapOntoCylinder(const ScenePiece *piece, PetscReal x[3])
{
  const PetscReal *a = piece->wrap_axis, *c = piece->wrap_point;
  PetscReal        normal[3], t[3], w[3], d = 0, r, along = 0, s = 0;

  normal[0] = piece->u_axis[1] * piece->v_axis[2] - piece->u_axis[2] * piece->v_axis[1];
  normal[1] = piece->u_axis[2] * piece->v_axis[0] - piece->u_axis[0] * piece->v_axis[2];
  normal[2] = piece->u_axis[0] * piece->v_axis[1] - piece->u_axis[1] * piece->v_axis[0];
  for (PetscInt k = 0; k < 3; k++) d += normal[k] * (piece->origin[k] - c[k]);
  r = PetscAbsReal(d);
  for (PetscInt k = 0; k < 3; k++) normal[k] *= (d > 0 ? 1.0 : -1.0); /* from the axis towards the plane */
  t[0] = a[1] * normal[2] - a[2] * normal[1];
  t[1] = a[2] * normal[0] - a[0] * normal[2];
  t[2] = a[0] * normal[1] - a[1] * normal[0];
  for (PetscInt k = 0; k < 3; k++) w[k] = x[k] - c[k];
  for (PetscInt k = 0; k < 3; k++) {
    along += w[k] * a[k];
    s += w[k] * t[k];
  }
  for (PetscInt k = 0; k < 3; k++) x[k] = c[k] + along * a[k] + r * (PetscCosReal(s / r) * normal[k] + PetscSinReal(s / r) * t[k]);
}

/* Rolls a flat placement onto the cone with apex A = wrap_point and axis a that touches its plane along the
   generator g0 (a projected onto the plane; the half-angle alpha is a's angle with the plane). A point at
   distance rho from A, at angle phi from g0 in the plane, goes to angle phi / sin(alpha) around the axis at
   the same distance rho from the apex: the cone's development, so all lengths are kept. */
static void WrapOntoCone(const ScenePiece *piece, PetscReal x[3])
{
  const PetscReal *a = piece->wrap_axis, *c = piece->wrap_point;
  PetscReal        normal[3], g0[3], e1[3], e2[3], w[3], an = 0, sa, ca, rho, phi, theta, norm = 0;

  Cross3(piece->u_axis, piece->v_axis, normal);
  for (PetscInt k = 0; k < 3; k++) an += a[k] * normal[k];
  for (PetscInt k = 0; k < 3; k++) g0[k] = a[k] - an * normal[k];
  for (PetscInt k = 0; k < 3; k++) norm += g0[k] * g0[k];
  norm = PetscSqrtReal(norm);
  for (PetscInt k = 0; k < 3; k++) g0[k] /= norm;
  ca = Dot3(a, g0);
  sa = PetscSqrtReal(PetscMax(0.0, 1 - ca * ca));
  for (PetscInt k = 0; k < 3; k++) e1[k] = (g0[k] - ca * a[k]) / sa; /* from the axis towards the touching line */
  Cross3(a, e1, e2);                                                 /* lies in the plane, across g0 */
  Sub3(x, c, w);
  rho   = PetscSqrtReal(Dot3(w, w));
  phi   = PetscAtan2Real(Dot3(w, e2), Dot3(w, g0));
  theta = phi / sa;
  for (PetscInt k = 0; k < 3; k++) x[k] = c[k] + rho * (ca * a[k] + sa * (PetscCosReal(theta) * e1[k] + PetscSinReal(theta) * e2[k]));
}

/* Particle positions (flat pattern placed in 3D), masses and pins of one piece. The nodes a cut (cut_disc) leaves
   outside every cell get no mass and no interaction and are held still: the particle numbering stays the grid's. */
static PetscErrorCode AddPieceParticles(ClothModel model, const PieceContext *pc)
{
  const ScenePiece *piece      = pc->piece;
  const PetscInt    n          = piece->nu * piece->nv;
  PetscReal         total_area = 0;
  PetscInt          nkept      = 0;

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < n; p++) {
    PetscReal *x = &model->position[3 * (pc->offset + p)];
    for (PetscInt c = 0; c < 3; c++) x[c] = piece->origin[c] + pc->uv[2 * p] * piece->u_axis[c] + pc->uv[2 * p + 1] * piece->v_axis[c];
    if (piece->wrapped && piece->wrap_cone)
      WrapOntoCone(piece, x);
    else if (piece->wrapped)
      WrapOntoCylinder(piece, x);
    model->mass[pc->offset + p] = 0;
  }
  for (PetscInt j = 0; j + 1 < piece->nv; j++)
    for (PetscInt i = 0; i + 1 < piece->nu; i++) {
      const PetscReal area = PatternCellArea(piece->nu, pc->uv, i, j);
      const PetscInt  c[4] = {PieceNode(pc, i, j), PieceNode(pc, i + 1, j), PieceNode(pc, i + 1, j + 1), PieceNode(pc, i, j + 1)};

      if (!PatternCellKept(piece, pc->uv, i, j)) continue;
      for (PetscInt k = 0; k < 4; k++) model->mass[pc->offset + c[k]] += 0.25 * area * pc->fabric->density;
      total_area += area;
    }
  for (PetscInt p = 0; p < n; p++) nkept += PatternNodeKept(piece, pc->uv, p % piece->nu, p / piece->nu) ? 1 : 0;
  for (PetscInt p = 0; p < n; p++) {
    const PetscBool kept = PatternNodeKept(piece, pc->uv, p % piece->nu, p / piece->nu);

    if (piece->mass_distribution == CLOTH_MASS_UNIFORM) model->mass[pc->offset + p] = kept ? pc->fabric->density * total_area / nkept : 0;
    model->damping[pc->offset + p] = pc->fabric->damping * model->mass[pc->offset + p];
    if (!kept) model->pinned[pc->offset + p] = PETSC_TRUE;
  }
  for (PetscInt k = 0; k < piece->npins; k++) model->pinned[pc->offset + PieceNode(pc, piece->pins[2 * k], piece->pins[2 * k + 1])] = PETSC_TRUE;
  for (PetscInt p = 0; p < n; p++) { /* pin regions in pattern coordinates: a support disc, a clamped table part */
    const PetscReal *u = &pc->uv[2 * p];

    if (piece->pin_disc[2] > 0 && PetscSqr(u[0] - piece->pin_disc[0]) + PetscSqr(u[1] - piece->pin_disc[1]) < PetscSqr(piece->pin_disc[2])) model->pinned[pc->offset + p] = PETSC_TRUE;
    if (piece->pin_box[2] > piece->pin_box[0] && u[0] >= piece->pin_box[0] && u[0] <= piece->pin_box[2] && u[1] >= piece->pin_box[1] && u[1] <= piece->pin_box[3]) model->pinned[pc->offset + p] = PETSC_TRUE;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Bending across a seam at one of its links: the two pieces continue each other straight across it. */
static void AddSeamBending(ClothModel model, Scene scene, const SeamBendSite *site)
{
  const SceneFabric *fab = &scene->fabrics[scene->pieces[site->dense_piece].fabric];
  const PetscReal   *x   = model->position;
  PetscReal          la = 0, lb = 0, width = 0;

  for (PetscInt c = 0; c < 3; c++) {
    la += PetscSqr(x[3 * site->node + c] - x[3 * site->inner + c]);
    lb += PetscSqr(x[3 * site->other_node + c] - x[3 * site->other_inner + c]);
    width += PetscSqr(x[3 * site->node + c] - x[3 * site->along + c]);
  }
  la    = PetscSqrtReal(la);
  lb    = PetscSqrtReal(lb);
  width = PetscSqrtReal(width);
  if (fab->bend_model == CLOTH_BEND_LINK) {
    AddLink(model, site->inner, site->other_inner, FabricBendLinkStiffness(fab, site->dense_warp, la + lb, width), la + lb, 0, 0);
  } else {
    ClothAngle *angle = &model->angles[model->nangles++];
    angle->p[0]       = site->inner;
    angle->p[1]       = site->node;
    angle->p[2]       = site->other_inner;
    angle->kind       = CLOTH_ANGLE_CHAIN;
    angle->k          = FabricBendAngleStiffness(fab, site->dense_warp, 0.5 * (la + lb), width);
    angle->cos0       = 1;
    angle->sin0       = 0;
    angle->slip       = 0;
  }
}

/* Seam links and the bending across seams; uvs holds every piece's flat coordinates. */
static PetscErrorCode AddSeams(ClothModel model, Scene scene, PetscReal *const uvs[])
{
  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < scene->nseams; s++) {
    const SceneSeam *seam = &scene->seams[s];
    SeamSide         a, b;
    SeamBendSite    *bend;
    PetscInt         n;

    PetscCall(SeamSideCreate(scene, seam, &seam->a, uvs[seam->a.piece], &a));
    PetscCall(SeamSideCreate(scene, seam, &seam->b, uvs[seam->b.piece], &b));
    PetscCall(PetscMalloc1(PetscMax(a.n, b.n), &bend));
    PetscCall(SeamBuildLinks(s, seam, &a, model->piece_offset[seam->a.piece], &b, model->piece_offset[seam->b.piece], &model->seamlinks[model->nseamlinks], bend, &n));
    model->nseamlinks += n;
    if (seam->bend)
      for (PetscInt k = 0; k < n; k++)
        if (bend[k].inner >= 0) AddSeamBending(model, scene, &bend[k]);
    PetscCall(PetscFree(bend));
    PetscCall(SeamSideDestroy(&a));
    PetscCall(SeamSideDestroy(&b));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothModelAllocate(Scene scene, ClothModel model)
{
  PetscInt maxlinks = 0, maxangles = 0, ncells = 0, maxseam = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(scene->npieces + 1, &model->piece_offset));
  model->npieces         = scene->npieces;
  model->piece_offset[0] = 0;
  for (PetscInt k = 0; k < scene->npieces; k++) {
    const PetscInt n           = scene->pieces[k].nu * scene->pieces[k].nv;
    model->piece_offset[k + 1] = model->piece_offset[k] + n;
    ncells += (scene->pieces[k].nu - 1) * (scene->pieces[k].nv - 1);
    maxlinks += 4 * n + 2 * n;              /* stretch + bending (both directions) + 2 shear per cell */
    maxangles += 4 * n + 2 * n + 2 * n + n; /* corner shear + bending + its friction elements + twist per cell */
  }
  for (PetscInt s = 0; s < scene->nseams; s++) {
    const ScenePiece *a = &scene->pieces[scene->seams[s].a.piece], *b = &scene->pieces[scene->seams[s].b.piece];
    maxseam += PetscMax(PetscMax(a->nu, a->nv), PetscMax(b->nu, b->nv));
  }
  maxlinks += maxseam; /* bending across seams, one per seam link */
  maxangles += maxseam;
  PetscCall(PetscMalloc1(maxseam + 1, &model->seamlinks));
  model->nparticles = model->piece_offset[scene->npieces];
  PetscCall(PetscCalloc4(3 * model->nparticles, &model->position, model->nparticles, &model->mass, model->nparticles, &model->damping, 4 * ncells, &model->quads));
  PetscCall(PetscCalloc1(model->nparticles, &model->pinned)); /* apart: kept by ClothModelReleaseParticleData */
  PetscCall(PetscMalloc2(maxlinks, &model->links, maxangles, &model->angles));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothModelCreate(Scene scene, ClothModel *model)
{
  ClothModel  m;
  PetscReal **uvs;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&m));
  PetscCall(ClothModelAllocate(scene, m));
  PetscCall(PetscCalloc1(scene->npieces, &uvs));
  for (PetscInt k = 0; k < scene->npieces; k++) {
    const ScenePiece *piece = &scene->pieces[k];
    PetscReal        *uv;
    PieceContext      pc;

    PetscCall(PetscMalloc1(2 * piece->nu * piece->nv, &uvs[k]));
    uv = uvs[k];
    PetscCall(PatternMeshPiece(piece, uv));
    pc.piece  = piece;
    pc.fabric = &scene->fabrics[piece->fabric];
    pc.uv     = uv;
    pc.offset = m->piece_offset[k];
    PetscCall(AddPieceParticles(m, &pc));
    AddThreadInteractions(m, &pc, PETSC_TRUE);
    AddThreadInteractions(m, &pc, PETSC_FALSE);
    PetscCall(AddCellInteractions(m, &pc));
  }
  PetscCall(AddSeams(m, scene, uvs)); /* after every piece: seams join pieces */
  for (PetscInt k = 0; k < scene->npieces; k++) PetscCall(PetscFree(uvs[k]));
  PetscCall(PetscFree(uvs));
  *model = m;
  for (PetscInt a = 0; a < m->nangles; a++) {
    m->nfriction += m->angles[a].slip > 0;
    m->nfriction_shear += m->angles[a].slip > 0 && m->angles[a].kind == CLOTH_ANGLE_CELL;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A uniform number in [-1, 1) from (seed, index) alone (splitmix64's finaliser): a PetscRandom
   stream would give each rank other numbers for the same particle. */
static PetscReal HashUniform(PetscInt seed, PetscInt index)
{
  uint64_t z = (uint64_t)seed * 0x9E3779B97F4A7C15ULL + (uint64_t)index + 1;

  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return 2.0 * (PetscReal)(z >> 11) / 9007199254740992.0 - 1.0; /* 53 bits / 2^53 */
}

/* The smooth imperfection field at x: the mean of CLOTH_PERTURBATION_MODES waves cos(2 pi d.x / l + phase),
   d a random unit vector, l in [L, 3L], drawn from (seed, mode) with indices no particle has (negative). */
static PetscReal SmoothField(PetscInt seed, PetscReal wavelength, const PetscReal x[3])
{
  PetscReal sum = 0;

  for (PetscInt m = 0; m < CLOTH_PERTURBATION_MODES; m++) {
    const PetscReal z = HashUniform(seed, -4 * m - 1), azimuth = PETSC_PI * HashUniform(seed, -4 * m - 2);
    const PetscReal l = wavelength * (2 + HashUniform(seed, -4 * m - 3)), phase = PETSC_PI * HashUniform(seed, -4 * m - 4);
    const PetscReal r = PetscSqrtReal(1 - z * z), d[3] = {r * PetscCosReal(azimuth), r * PetscSinReal(azimuth), z};

    sum += PetscCosReal(2 * PETSC_PI * Dot3(d, x) / l + phase);
  }
  return sum / CLOTH_PERTURBATION_MODES;
}

PetscErrorCode ClothModelPerturbPositions(ClothModel model, PetscReal amplitude, PetscReal wavelength, PetscInt seed)
{
  PetscReal *normal;

  PetscFunctionBeginUser;
  if (amplitude <= 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscCalloc1(3 * model->nparticles, &normal));
  for (PetscInt q = 0; q < model->nquads; q++) { /* area-weighted cell normals, summed at the corners */
    const PetscInt *c = &model->quads[4 * q];
    PetscReal       d0[3], d1[3], n[3];

    Sub3(&model->position[3 * c[2]], &model->position[3 * c[0]], d0);
    Sub3(&model->position[3 * c[3]], &model->position[3 * c[1]], d1);
    Cross3(d0, d1, n);
    for (PetscInt k = 0; k < 4; k++)
      for (PetscInt d = 0; d < 3; d++) normal[3 * c[k] + d] += n[d];
  }
  for (PetscInt i = 0; i < model->nparticles; i++) {
    const PetscReal len = PetscSqrtReal(Dot3(&normal[3 * i], &normal[3 * i]));
    const PetscReal h   = amplitude * (wavelength > 0 ? SmoothField(seed, wavelength, &model->position[3 * i]) : HashUniform(seed, i));

    if (model->pinned[i] || len == 0) continue;
    for (PetscInt d = 0; d < 3; d++) model->position[3 * i + d] += h * normal[3 * i + d] / len;
  }
  PetscCall(PetscFree(normal));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Appends the pairs of one interaction's particles to per-particle neighbour lists (counting pass when adj == NULL). */
static void VisitPairs(const PetscInt *p, PetscInt np, PetscInt *count, PetscInt *const *adj)
{
  for (PetscInt a = 0; a < np; a++)
    for (PetscInt b = 0; b < np; b++) {
      if (a == b || p[a] == p[b]) continue;
      if (adj) adj[p[a]][count[p[a]]] = p[b];
      count[p[a]]++;
    }
}

PetscErrorCode ClothModelGetAdjacency(ClothModel model, PetscInt **xadj_out, PetscInt **adjncy_out)
{
  const PetscInt n = model->nparticles;
  PetscInt      *count, *xadj, *adjncy, **rows;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(n, &count));
  for (PetscInt l = 0; l < model->nlinks; l++) VisitPairs(model->links[l].p, 2, count, NULL);
  for (PetscInt a = 0; a < model->nangles; a++) VisitPairs(model->angles[a].p, ClothAngleParticleCount(model->angles[a].kind), count, NULL);
  for (PetscInt s = 0; s < model->nseamlinks; s++) VisitPairs(model->seamlinks[s].p, model->seamlinks[s].np, count, NULL);
  PetscCall(PetscMalloc1(n + 1, &xadj));
  xadj[0] = 0;
  for (PetscInt i = 0; i < n; i++) xadj[i + 1] = xadj[i] + count[i];
  PetscCall(PetscMalloc1(xadj[n], &adjncy));
  PetscCall(PetscMalloc1(n, &rows));
  for (PetscInt i = 0; i < n; i++) {
    rows[i]  = &adjncy[xadj[i]];
    count[i] = 0;
  }
  for (PetscInt l = 0; l < model->nlinks; l++) VisitPairs(model->links[l].p, 2, count, rows);
  for (PetscInt a = 0; a < model->nangles; a++) VisitPairs(model->angles[a].p, ClothAngleParticleCount(model->angles[a].kind), count, rows);
  for (PetscInt s = 0; s < model->nseamlinks; s++) VisitPairs(model->seamlinks[s].p, model->seamlinks[s].np, count, rows);
  /* Sort and remove duplicates row by row, then compact. */
  {
    PetscInt w = 0;
    for (PetscInt i = 0; i < n; i++) {
      PetscInt len = count[i];
      PetscCall(PetscSortRemoveDupsInt(&len, rows[i]));
      for (PetscInt k = 0; k < len; k++) adjncy[w + k] = rows[i][k];
      xadj[i] = w;
      w += len;
    }
    xadj[n] = w;
  }
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(count));
  *xadj_out   = xadj;
  *adjncy_out = adjncy;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothModelReleaseInteractions(ClothModel model)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(model->links, model->angles));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothModelReleaseParticleData(ClothModel model)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(model->position, model->mass, model->damping, model->quads));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothModelDestroy(ClothModel *model)
{
  PetscFunctionBeginUser;
  if (!*model) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree4((*model)->position, (*model)->mass, (*model)->damping, (*model)->quads));
  PetscCall(PetscFree((*model)->pinned));
  PetscCall(PetscFree2((*model)->links, (*model)->angles));
  PetscCall(PetscFree((*model)->piece_offset));
  PetscCall(PetscFree((*model)->seamlinks));
  PetscCall(PetscFree(*model));
  PetscFunctionReturn(PETSC_SUCCESS);
}
