/* ClothSelfContact, the broad phase of its search (see selfcontact_impl.h): the fabric cut into tiles of
   SELF_CONTACT_TILE x SELF_CONTACT_TILE grid cells, the pairs of tiles near each other found on a cell grid of their
   boxes, and for each such pair the pairs of primitives (particle-triangle, edge-edge) whose boxes come close, each
   handed to the narrow phase as it is found (nothing per pair of primitives is stored).

   Why tiles: the candidates must follow the geometry, not the speed. A primitive's own box swept over the step grows
   with its speed, and a search of every primitive against its spatial neighbours at every step pays for the whole
   area of every layer (its own flat neighbourhood, which the exclusion rule then throws away). A pair of tiles sweeps
   its boxes relative to its own mean motion (a sheet falling or sliding as a whole sweeps nothing), and neighbouring
   tiles of a layer that is flat or gently curved are proved to hold no allowed pair at all (TilesApart), so the work
   of a step follows the folds and the contacts, not the fabric's area or speed. The boxes reach only the search
   radius: a flat layer's own neighbours beyond the exclusion ring lie farther than that, so they cost box tests but
   no narrow-phase tests and no memory (pairs of primitives kept over steps would have to reach farther, by the
   motion they allow, and hold that flat neighbourhood: 177 pairs a particle at 513 x 513). Every test is
   conservative: the contacts are those of a search from scratch. */
#include "selfcontact_impl.h"
#include "log.h"
#include "vec3.h"

/* ------------------------------------------------------------------------------------------------ */
/* Static topology                                                                                  */

/* The tile of cell or particle (i, j) of piece k: the last row and column of particles belong to the last tile. */
static PetscInt TileOf(const ClothSelfContact sc, PetscInt k, PetscInt i, PetscInt j)
{
  const PetscInt *t = &sc->piece_tiles[SELF_CONTACT_PIECE_TILES * k]; /* first tile, tiles along i, along j, nu */

  return t[0] + PetscMin(j / SELF_CONTACT_TILE, t[2] - 1) * t[1] + PetscMin(i / SELF_CONTACT_TILE, t[1] - 1);
}

PetscInt SelfContactParticleTile(const ClothSelfContact sc, PetscInt g)
{
  return TileOf(sc, sc->piece_of[g], sc->grid_i[g], sc->grid_j[g]);
}

/* The tile of a primitive: that of the cell at its lowest (i, j). */
static PetscInt PrimitiveTile(const ClothSelfContact sc, const PetscInt v[], PetscInt nv)
{
  PetscInt i = sc->grid_i[v[0]], j = sc->grid_j[v[0]];

  for (PetscInt k = 1; k < nv; k++) i = PetscMin(i, sc->grid_i[v[k]]), j = PetscMin(j, sc->grid_j[v[k]]);
  return TileOf(sc, sc->piece_of[v[0]], i, j);
}

/* tile -> items (CSR) from each item's tile */
static PetscErrorCode TileIncidence(PetscInt ntiles, PetscInt nitems, const PetscInt tile[], PetscInt **start, PetscInt **of)
{
  PetscInt *fill;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(ntiles + 1, start));
  PetscCall(PetscCalloc1(ntiles + 1, &fill));
  for (PetscInt k = 0; k < nitems; k++) (*start)[tile[k] + 1]++;
  for (PetscInt t = 0; t < ntiles; t++) (*start)[t + 1] += (*start)[t];
  PetscCall(PetscMalloc1((*start)[ntiles] + 1, of));
  for (PetscInt k = 0; k < nitems; k++) (*of)[(*start)[tile[k]] + fill[tile[k]]++] = k;
  PetscCall(PetscFree(fill));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The tiles of every piece, their index rectangles and their cells in the pattern. */
static PetscErrorCode LayOutTiles(ClothSelfContact sc, Scene scene, ClothModel m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(SELF_CONTACT_PIECE_TILES * m->npieces, &sc->piece_tiles));
  sc->ntiles = 0;
  for (PetscInt k = 0; k < m->npieces; k++) {
    const PetscInt nu = scene->pieces[k].nu, nv = scene->pieces[k].nv, tu = PetscMax(1, (nu - 1 + SELF_CONTACT_TILE - 1) / SELF_CONTACT_TILE), tv = PetscMax(1, (nv - 1 + SELF_CONTACT_TILE - 1) / SELF_CONTACT_TILE);
    PetscInt      *pt = &sc->piece_tiles[SELF_CONTACT_PIECE_TILES * k];

    pt[0] = sc->ntiles, pt[1] = tu, pt[2] = tv, pt[3] = nu;
    sc->ntiles += tu * tv;
  }
  PetscCall(PetscCalloc1(sc->ntiles, &sc->tiles));
  for (PetscInt k = 0; k < m->npieces; k++) {
    const PetscInt *pt = &sc->piece_tiles[SELF_CONTACT_PIECE_TILES * k];
    for (PetscInt tj = 0; tj < pt[2]; tj++)
      for (PetscInt ti = 0; ti < pt[1]; ti++) {
        SelfContactTile *t = &sc->tiles[pt[0] + tj * pt[1] + ti];

        t->piece = k, t->ti = ti, t->tj = tj;
        t->i0 = ti * SELF_CONTACT_TILE, t->j0 = tj * SELF_CONTACT_TILE;
        t->i1 = ti + 1 < pt[1] ? t->i0 + SELF_CONTACT_TILE : scene->pieces[k].nu - 1; /* last particle index */
        t->j1 = tj + 1 < pt[2] ? t->j0 + SELF_CONTACT_TILE : scene->pieces[k].nv - 1;
      }
  }
  for (PetscInt t = 0; t < sc->ntri; t += 2) sc->tiles[PrimitiveTile(sc, &sc->tri[3 * t], 3)].ncells++; /* two triangles a cell */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactBuildTiles(ClothSelfContact sc, Scene scene, ClothModel m)
{
  PetscInt *tile, n = PetscMax(PetscMax(m->nparticles, sc->ntri), sc->nedge);

  PetscFunctionBeginUser;
  PetscCall(LayOutTiles(sc, scene, m));
  PetscCall(PetscMalloc1(n + 1, &tile));
  for (PetscInt t = 0; t < sc->ntri; t++) tile[t] = PrimitiveTile(sc, &sc->tri[3 * t], 3);
  PetscCall(TileIncidence(sc->ntiles, sc->ntri, tile, &sc->tile_tri_start, &sc->tile_tri_of));
  for (PetscInt e = 0; e < sc->nedge; e++) tile[e] = PrimitiveTile(sc, &sc->edge[2 * e], 2);
  PetscCall(TileIncidence(sc->ntiles, sc->nedge, tile, &sc->tile_edge_start, &sc->tile_edge_of));
  for (PetscInt g = 0; g < m->nparticles; g++) tile[g] = SelfContactParticleTile(sc, g);
  PetscCall(TileIncidence(sc->ntiles, m->nparticles, tile, &sc->tile_particle_start, &sc->tile_particle_of));
  PetscCall(PetscFree(tile));
  PetscCall(PetscMalloc2(sc->ntiles, &sc->tile_present, sc->ntiles, &sc->tile_mark));
  n = 0;
  for (PetscInt t = 0; t < sc->ntiles; t++) n = PetscMax(n, PetscMax(sc->tile_tri_start[t + 1] - sc->tile_tri_start[t], sc->tile_edge_start[t + 1] - sc->tile_edge_start[t]));
  sc->scratch_room = n + 1;
  PetscCall(PetscMalloc3(4 * sc->scratch_room, &sc->scratch_ids, 24 * sc->scratch_room, &sc->scratch_ij, 24 * sc->scratch_room, &sc->scratch_boxes)); /* two tiles' triangles and edges */
  for (PetscInt t = 0; t < sc->ntiles; t++) sc->tile_present[t] = -1, sc->tile_mark[t] = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The natural indices of the particles of tile t's rectangle [i0, i1] x [j0, j1] (its own and those of its triangles
   and edges in the next tiles' first row and column), at most SELF_CONTACT_CLOSURE; returns their number. */
static PetscInt TileClosure(const ClothSelfContact sc, PetscInt t, PetscInt g[])
{
  const SelfContactTile *tile   = &sc->tiles[t];
  const PetscInt         offset = sc->layout.model->piece_offset[tile->piece], nu = sc->piece_tiles[SELF_CONTACT_PIECE_TILES * tile->piece + 3];
  PetscInt               n = 0;

  for (PetscInt j = tile->j0; j <= tile->j1; j++)
    for (PetscInt i = tile->i0; i <= tile->i1; i++) g[n++] = offset + j * nu + i;
  return n;
}

/* ------------------------------------------------------------------------------------------------ */
/* Tile states                                                                                      */

/* What a step knows of a present tile (one with a particle present here): whether its whole rectangle is here (every
   particle present, every cell in the pattern) and any of it is this rank's; its displacements' mean mdx. For a whole
   tile, for TilesApart: how far its map from grid indices to space is from affine (G, the mean of its triangles' gradients, 3 x 2, m per index, d/di then d/dj; eps, the largest Frobenius
   distance of a triangle's gradient from G), and its displacements' largest departure from their mean, dev. Its
   box (over the step, inflated) is kept apart, for the cell grid. */
typedef struct {
  PetscInt  tile;
  PetscBool whole, owned;
  PetscReal G[6], eps, mdx[3], dev;
} SelfContactTileState;

/* The gradient (3 x 2) of the affine map from grid indices to positions over triangle t (all present). */
static void TriangleGradient(ClothSelfContact sc, PetscInt t, PetscReal grad[6])
{
  const PetscInt  *v  = &sc->tri[3 * t];
  const PetscReal *x0 = &sc->x[3 * sc->contact_index[v[0]]], *x1 = &sc->x[3 * sc->contact_index[v[1]]], *x2 = &sc->x[3 * sc->contact_index[v[2]]];
  const PetscReal  a = sc->grid_i[v[1]] - sc->grid_i[v[0]], b = sc->grid_i[v[2]] - sc->grid_i[v[0]], c = sc->grid_j[v[1]] - sc->grid_j[v[0]], d = sc->grid_j[v[2]] - sc->grid_j[v[0]];
  const PetscReal  det = a * d - b * c; /* [e1 e2] = grad [[a b] [c d]] */

  for (PetscInt k = 0; k < 3; k++) {
    const PetscReal e1 = x1[k] - x0[k], e2 = x2[k] - x0[k];
    grad[k]     = (e1 * d - e2 * c) / det;
    grad[3 + k] = (e2 * a - e1 * b) / det;
  }
}

static PetscReal Distance6(const PetscReal a[6], const PetscReal b[6])
{
  PetscReal s = 0;
  for (PetscInt k = 0; k < 6; k++) s += PetscSqr(a[k] - b[k]);
  return PetscSqrtReal(s);
}

/* G and eps of a whole tile (TileState). */
static void TileShape(ClothSelfContact sc, PetscInt t, SelfContactTileState *s)
{
  const PetscInt t0 = sc->tile_tri_start[t], nt = sc->tile_tri_start[t + 1] - t0;
  PetscReal      grad[6];

  for (PetscInt k = 0; k < 6; k++) s->G[k] = 0;
  for (PetscInt q = 0; q < nt; q++) {
    TriangleGradient(sc, sc->tile_tri_of[t0 + q], grad);
    for (PetscInt k = 0; k < 6; k++) s->G[k] += grad[k] / nt;
  }
  s->eps = 0;
  for (PetscInt q = 0; q < nt; q++) {
    TriangleGradient(sc, sc->tile_tri_of[t0 + q], grad);
    s->eps = PetscMax(s->eps, Distance6(grad, s->G));
  }
}

/* The state and box (over the step, inflated by inflate) of present tile t. */
static void TileState(ClothSelfContact sc, PetscInt t, PetscReal inflate, SelfContactTileState *s, PetscReal box[6])
{
  const SelfContactTile *tile = &sc->tiles[t];
  PetscInt               g[SELF_CONTACT_CLOSURE], n = TileClosure(sc, t, g), present = 0, owned = 0;

  s->tile = t;
  for (PetscInt c = 0; c < 3; c++) box[c] = PETSC_MAX_REAL, box[3 + c] = -PETSC_MAX_REAL, s->mdx[c] = 0;
  for (PetscInt k = 0; k < n; k++) {
    const PetscInt i = sc->contact_index[g[k]];
    if (i < 0) continue;
    present++;
    owned += i < sc->layout.nlocal;
    for (PetscInt c = 0; c < 3; c++) {
      box[c]     = PetscMin(box[c], PetscMin(sc->x[3 * i + c], sc->x[3 * i + c] + sc->dx[3 * i + c]));
      box[3 + c] = PetscMax(box[3 + c], PetscMax(sc->x[3 * i + c], sc->x[3 * i + c] + sc->dx[3 * i + c]));
      s->mdx[c] += sc->dx[3 * i + c] / n;
    }
  }
  for (PetscInt c = 0; c < 3; c++) box[c] -= inflate, box[3 + c] += inflate;
  s->owned = owned > 0 ? PETSC_TRUE : PETSC_FALSE;
  s->whole = (present == n && tile->ncells == (tile->i1 - tile->i0) * (tile->j1 - tile->j0)) ? PETSC_TRUE : PETSC_FALSE;
  if (!s->whole) return;
  s->dev = 0;
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal *d    = &sc->dx[3 * sc->contact_index[g[k]]];
    const PetscReal  e[3] = {d[0] - s->mdx[0], d[1] - s->mdx[1], d[2] - s->mdx[2]};
    s->dev                = PetscMax(s->dev, PetscSqrtReal(Dot3(e, e)));
  }
  TileShape(sc, t, s);
}

/* The smallest singular value of the 3 x 2 matrix G (column-major). */
static PetscReal SmallestSingularValue(const PetscReal G[6])
{
  const PetscReal a = Dot3(G, G), b = Dot3(G, G + 3), d = Dot3(G + 3, G + 3), half = 0.5 * (a + d), root = PetscSqrtReal(PetscMax(0.0, 0.25 * PetscSqr(a - d) + b * b));

  return PetscSqrtReal(PetscMax(0.0, half - root));
}

/* The smallest distance in grid indices between two primitives (particle-triangle or edge-edge) of a grid triangulation
   that the exclusion ring R allows, i.e. whose particles are all more than R rings (Chebyshev) apart: R + 1 for
   R >= 1 (a particle and a triangle or edge beyond the ring's square), 1/sqrt 2 for R = 0 (a particle and the diagonal
   of the next cell, or two parallel diagonals); checked by enumeration over a 15 x 15 grid for R = 0 to 3. */
static PetscReal AllowedIndexDistance(PetscInt ring)
{
  return ring > 0 ? (PetscReal)(ring + 1) : 1 / PETSC_SQRT2;
}

/* Are tiles P and Q of one piece at most one tile apart? */
static PetscBool TileNeighbours(const SelfContactTile *P, const SelfContactTile *Q)
{
  return (P->piece == Q->piece && PetscAbsInt(P->ti - Q->ti) <= 1 && PetscAbsInt(P->tj - Q->tj) <= 1) ? PETSC_TRUE : PETSC_FALSE;
}

/* Can no pair of primitives of the neighbouring tiles P and Q that the exclusion ring allows come within rho during
   the step? Their grid rectangle U (P alone, P and Q side by side, or the 2 x 2 block of diagonal neighbours) is
   convex, so for points x, y at grid indices a, b the map from indices to space with |grad - G| <= eps on every
   triangle of U gives |x - y| >= (sigma_min(G) - eps) |a - b|; the exclusion puts |a - b| >= AllowedIndexDistance(R)
   (R the ring) between any two allowed primitives; over the step their
   separation changes by at most twice the largest departure of a displacement from U's mean, dev. A flat or gently
   curved layer moving as one thus has no pair of primitives to test. False when U is not whole here. */
static PetscBool TilesApart(ClothSelfContact sc, const SelfContactTileState *state, const SelfContactTile *P, const SelfContactTile *Q, PetscReal rho)
{
  const PetscInt              piece = P->piece, ring = sc->ring[piece], *pt = &sc->piece_tiles[SELF_CONTACT_PIECE_TILES * piece];
  const PetscInt              ti0 = PetscMin(P->ti, Q->ti), ti1 = PetscMax(P->ti, Q->ti), tj0 = PetscMin(P->tj, Q->tj), tj1 = PetscMax(P->tj, Q->tj);
  const SelfContactTile      *low = &sc->tiles[pt[0] + tj0 * pt[1] + ti0], *high = &sc->tiles[pt[0] + tj1 * pt[1] + ti1];
  const SelfContactTileState *u[4];
  PetscInt                    nu   = 0;
  PetscReal                   G[6] = {0, 0, 0, 0, 0, 0}, mdx[3] = {0, 0, 0}, eps = 0, dev = 0;

  if (!sc->same_piece || PetscMax(high->i1 - low->i0, high->j1 - low->j0) <= ring) return PETSC_TRUE; /* every pair excluded */
  for (PetscInt tj = tj0; tj <= tj1; tj++)
    for (PetscInt ti = ti0; ti <= ti1; ti++) {
      const PetscInt k = sc->tile_present[pt[0] + tj * pt[1] + ti];
      if (k < 0 || !state[k].whole) return PETSC_FALSE;
      u[nu++] = &state[k];
    }
  for (PetscInt k = 0; k < nu; k++)
    for (PetscInt c = 0; c < 6; c++) G[c] += u[k]->G[c] / nu;
  for (PetscInt k = 0; k < nu; k++)
    for (PetscInt c = 0; c < 3; c++) mdx[c] += u[k]->mdx[c] / nu;
  for (PetscInt k = 0; k < nu; k++) {
    const PetscReal e[3] = {u[k]->mdx[0] - mdx[0], u[k]->mdx[1] - mdx[1], u[k]->mdx[2] - mdx[2]};
    eps                  = PetscMax(eps, u[k]->eps + Distance6(u[k]->G, G));
    dev                  = PetscMax(dev, u[k]->dev + PetscSqrtReal(Dot3(e, e)));
  }
  return (SmallestSingularValue(G) - eps) * AllowedIndexDistance(ring) >= rho + 2 * dev ? PETSC_TRUE : PETSC_FALSE;
}

/* ------------------------------------------------------------------------------------------------ */
/* Pairs of primitives of a pair of tiles                                                           */

/* The box of the natural particles v[0..nv) over the step (from the positions at its start to those after its
   displacements less the common one u; NULL: none), inflated by inflate. Whether two primitives come within a
   distance during the step depends only on their relative motion: boxes swept with the displacements less a common one
   meet whenever the primitives come close, and a layer that slides as a whole sweeps nothing. */
void SelfContactSweptBox(ClothSelfContact sc, const PetscInt v[], PetscInt nv, PetscReal inflate, const PetscReal u[3], PetscReal box[6])
{
  const PetscReal none[3] = {0, 0, 0};

  if (!u) u = none;
  for (PetscInt c = 0; c < 3; c++) box[c] = PETSC_MAX_REAL, box[3 + c] = -PETSC_MAX_REAL;
  for (PetscInt k = 0; k < nv; k++) {
    const PetscInt   i = sc->contact_index[v[k]];
    const PetscReal *x = &sc->x[3 * i], *d = &sc->dx[3 * i];
    for (PetscInt c = 0; c < 3; c++) {
      box[c]     = PetscMin(box[c], PetscMin(x[c], x[c] + d[c] - u[c]));
      box[3 + c] = PetscMax(box[3 + c], PetscMax(x[c], x[c] + d[c] - u[c]));
    }
  }
  for (PetscInt c = 0; c < 3; c++) box[c] -= inflate, box[3 + c] += inflate;
}

static inline PetscBool BoxesOverlap(const PetscReal a[6], const PetscReal b[6])
{
  return (a[3] < b[0] || b[3] < a[0] || a[4] < b[1] || b[4] < a[1] || a[5] < b[2] || b[5] < a[2]) ? PETSC_FALSE : PETSC_TRUE;
}

#define SELF_CONTACT_TILE_CELLS (SELF_CONTACT_TILE * SELF_CONTACT_TILE)

/* A tile's primitives of one kind present here, grouped by the tile's cells (a primitive's cell: that at its lowest
   (i, j)), with their boxes over the step, inflated, and each cell's box (the union of its primitives'; inverted when it
   has none), so that a pair of tiles compares cells first and primitives only within cells that come close. */
typedef struct {
  PetscInt   n, nv, start[SELF_CONTACT_TILE_CELLS + 1];
  PetscInt  *ids, *ij; /* ij: the grid position (i, j) of each of a primitive's nv particles, for the exclusion ring */
  PetscReal *boxes;
  PetscReal  cell[6 * SELF_CONTACT_TILE_CELLS];
} TilePrimitives;

/* Are two particles of one piece at grid positions a[0..na) and b[0..nb) ((i, j) each) within ring rings of each other
   (SelfContactRingExcluded, read from positions gathered beside the primitives)? */
static inline PetscBool WithinRing(const PetscInt a[], PetscInt na, const PetscInt b[], PetscInt nb, PetscInt ring)
{
  for (PetscInt k = 0; k < na; k++)
    for (PetscInt l = 0; l < nb; l++)
      if (PetscAbsInt(a[2 * k] - b[2 * l]) <= ring && PetscAbsInt(a[2 * k + 1] - b[2 * l + 1]) <= ring) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* The cell, within tile t, of the primitive with particles v[0..nv). */
static PetscInt CellInTile(ClothSelfContact sc, const SelfContactTile *tile, const PetscInt v[], PetscInt nv)
{
  PetscInt i = sc->grid_i[v[0]], j = sc->grid_j[v[0]];

  for (PetscInt k = 1; k < nv; k++) i = PetscMin(i, sc->grid_i[v[k]]), j = PetscMin(j, sc->grid_j[v[k]]);
  return (PetscMin(i, tile->i1 - 1) - tile->i0) + (PetscMin(j, tile->j1 - 1) - tile->j0) * (tile->i1 - tile->i0);
}

/* The cell in tile t of the primitive with particles v[0..nv), or -1 when one of them is not present here. */
static PetscInt PresentPrimitiveCell(ClothSelfContact sc, const SelfContactTile *tile, const PetscInt v[], PetscInt nv)
{
  for (PetscInt k = 0; k < nv; k++)
    if (sc->contact_index[v[k]] < 0) return -1;
  return CellInTile(sc, tile, v, nv);
}

/* The present primitives (nv particles each, prim[], listed for tile t by start/of) of tile t into tp, their ids and
   boxes (swept with the displacements less u, inflated by inflate) in the room at ids, ij and boxes. */
static void GatherTilePrimitives(ClothSelfContact sc, PetscInt t, PetscInt nv, const PetscInt prim[], const PetscInt start[], const PetscInt of[], PetscReal inflate, const PetscReal u[3], PetscInt ids[], PetscInt ij[], PetscReal boxes[],
                                 TilePrimitives *tp)
{
  const SelfContactTile *tile  = &sc->tiles[t];
  const PetscInt         ncell = (tile->i1 - tile->i0) * (tile->j1 - tile->j0);
  PetscInt               fill[SELF_CONTACT_TILE_CELLS];

  tp->ids = ids, tp->ij = ij, tp->boxes = boxes, tp->nv = nv;
  for (PetscInt c = 0; c <= ncell; c++) tp->start[c] = 0;
  for (PetscInt q = start[t]; q < start[t + 1]; q++) {
    const PetscInt c = PresentPrimitiveCell(sc, tile, &prim[nv * of[q]], nv);
    if (c >= 0) tp->start[c + 1]++;
  }
  for (PetscInt c = 0; c < ncell; c++) tp->start[c + 1] += tp->start[c], fill[c] = tp->start[c];
  tp->n = tp->start[ncell];
  for (PetscInt q = start[t]; q < start[t + 1]; q++) {
    const PetscInt c = PresentPrimitiveCell(sc, tile, &prim[nv * of[q]], nv);
    if (c < 0) continue;
    ids[fill[c]] = of[q];
    for (PetscInt k = 0; k < nv; k++) ij[2 * (nv * fill[c] + k)] = sc->grid_i[prim[nv * of[q] + k]], ij[2 * (nv * fill[c] + k) + 1] = sc->grid_j[prim[nv * of[q] + k]];
    SelfContactSweptBox(sc, &prim[nv * of[q]], nv, inflate, u, &boxes[6 * fill[c]]);
    fill[c]++;
  }
  for (PetscInt c = 0; c < ncell; c++) {
    PetscReal *cb = &tp->cell[6 * c];
    for (PetscInt k = 0; k < 3; k++) cb[k] = PETSC_MAX_REAL, cb[3 + k] = -PETSC_MAX_REAL;
    for (PetscInt q = tp->start[c]; q < tp->start[c + 1]; q++)
      for (PetscInt k = 0; k < 3; k++) cb[k] = PetscMin(cb[k], boxes[6 * q + k]), cb[3 + k] = PetscMax(cb[3 + k], boxes[6 * q + 3 + k]);
  }
}

/* The exclusion ring between tiles P and Q: their piece's when both are of it, -1 (none) otherwise (every pair of one
   piece is excluded with same_piece off, which VisitTilePairs has handled). */
static PetscInt TilesRing(ClothSelfContact sc, PetscInt P, PetscInt Q)
{
  return sc->tiles[P].piece == sc->tiles[Q].piece ? sc->ring[sc->tiles[P].piece] : -1;
}

/* Particle-triangle pairs of the owned particles of tile P against the triangles tq of tile Q (boxes swept less u) to
   the narrow phase within rho. */
static PetscErrorCode PairPointsWithTriangles(ClothSelfContact sc, PetscInt P, PetscInt Q, const PetscReal u[3], const TilePrimitives *tq, PetscReal rho)
{
  const SelfContactTile *tile  = &sc->tiles[Q];
  const PetscInt         ncell = (tile->i1 - tile->i0) * (tile->j1 - tile->j0), ring = TilesRing(sc, P, Q);

  PetscFunctionBeginUser;
  for (PetscInt q = sc->tile_particle_start[P]; q < sc->tile_particle_start[P + 1]; q++) {
    const PetscInt g = sc->tile_particle_of[q], i = sc->contact_index[g], ij[2] = {sc->grid_i[g], sc->grid_j[g]};
    PetscReal      box[6];

    if (i < 0 || i >= sc->layout.nlocal) continue;
    SelfContactSweptBox(sc, &g, 1, 0.0, u, box);
    for (PetscInt c = 0; c < ncell; c++) {
      if (!BoxesOverlap(box, &tq->cell[6 * c])) continue;
      for (PetscInt k = tq->start[c]; k < tq->start[c + 1]; k++)
        if (!WithinRing(ij, 1, &tq->ij[6 * k], 3, ring) && BoxesOverlap(box, &tq->boxes[6 * k])) PetscCall(SelfContactTestPair(sc, CLOTH_CONTACT_POINT_TRIANGLE, g, tq->ids[k], rho));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Edge-edge pairs of the edges of cells a (of ep) and b (of eq) that this rank handles (the same cell of the same tile:
   each pair once), to the narrow phase within rho; ring: the exclusion ring between their tiles. */
static PetscErrorCode PairCellEdges(ClothSelfContact sc, const TilePrimitives *ep, PetscInt a, const TilePrimitives *eq, PetscInt b, PetscBool same, PetscInt ring, PetscReal rho)
{
  PetscFunctionBeginUser;
  for (PetscInt k1 = ep->start[a]; k1 < ep->start[a + 1]; k1++) {
    const PetscInt e1 = ep->ids[k1];
    for (PetscInt k2 = same ? k1 + 1 : eq->start[b]; k2 < eq->start[b + 1]; k2++) {
      const PetscInt e2 = eq->ids[k2], first = PetscMin(e1, e2), second = PetscMax(e1, e2);
      PetscInt       p[4];

      if (WithinRing(&ep->ij[4 * k1], 2, &eq->ij[4 * k2], 2, ring) || !BoxesOverlap(&ep->boxes[6 * k1], &eq->boxes[6 * k2])) continue;
      p[0] = sc->edge[2 * first], p[1] = sc->edge[2 * first + 1], p[2] = sc->edge[2 * second], p[3] = sc->edge[2 * second + 1];
      if (SelfContactHandlesEdgePair(sc, e1, e2, p)) PetscCall(SelfContactTestPair(sc, CLOTH_CONTACT_EDGE_EDGE, first, second, rho));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Edge-edge pairs of tiles P and Q (edges ep, eq; the same tile: each pair once), cell pairs whose boxes overlap. */
static PetscErrorCode PairEdges(ClothSelfContact sc, PetscInt P, PetscInt Q, const TilePrimitives *ep, const TilePrimitives *eq, PetscReal rho)
{
  const PetscInt np = (sc->tiles[P].i1 - sc->tiles[P].i0) * (sc->tiles[P].j1 - sc->tiles[P].j0), nq = (sc->tiles[Q].i1 - sc->tiles[Q].i0) * (sc->tiles[Q].j1 - sc->tiles[Q].j0), ring = TilesRing(sc, P, Q);

  PetscFunctionBeginUser;
  for (PetscInt a = 0; a < np; a++)
    for (PetscInt b = P == Q ? a : 0; b < nq; b++)
      if (BoxesOverlap(&ep->cell[6 * a], &eq->cell[6 * b])) PetscCall(PairCellEdges(sc, ep, a, eq, b, (P == Q && a == b) ? PETSC_TRUE : PETSC_FALSE, ring, rho));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The present triangles and edges of tile t, their boxes swept relative to u, into the scratch slots slot (triangles)
   and slot + 1 (edges). */
static void GatherTile(ClothSelfContact sc, PetscInt t, PetscReal rho, const PetscReal u[3], PetscInt slot, TilePrimitives *tri, TilePrimitives *edge)
{
  const PetscInt room = sc->scratch_room;

  GatherTilePrimitives(sc, t, 3, sc->tri, sc->tile_tri_start, sc->tile_tri_of, rho, u, sc->scratch_ids + slot * room, sc->scratch_ij + 6 * slot * room, sc->scratch_boxes + 6 * slot * room, tri);
  slot++;
  GatherTilePrimitives(sc, t, 2, sc->edge, sc->tile_edge_start, sc->tile_edge_of, 0.5 * rho, u, sc->scratch_ids + slot * room, sc->scratch_ij + 6 * slot * room, sc->scratch_boxes + 6 * slot * room, edge);
}

/* Gives the narrow phase (SelfContactTestPair within rho) every pair of primitives of tiles P and Q (each pair once)
   that this rank handles, that the exclusion ring allows and whose boxes over the step relative to u, inflated so
   that together they reach rho, overlap. P's triangles and edges are given, gathered relative to u (GatherTile, slots
   0 and 1: P's own mean displacement, so that a tile gathers its primitives once for all its neighbours); Q's are
   gathered here relative to the same u. Any displacement common to both tiles serves: only their relative motion
   counts. */
static PetscErrorCode PairTiles(ClothSelfContact sc, PetscInt P, PetscInt Q, const PetscReal u[3], const TilePrimitives *ptri, const TilePrimitives *pedge, PetscReal rho)
{
  TilePrimitives qtri, qedge;

  PetscFunctionBeginUser;
  if (Q == P) {
    PetscCall(PairPointsWithTriangles(sc, P, P, u, ptri, rho));
    PetscCall(PairEdges(sc, P, P, pedge, pedge, rho));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  GatherTile(sc, Q, rho, u, 2, &qtri, &qedge);
  PetscCall(PairPointsWithTriangles(sc, P, Q, u, &qtri, rho));
  PetscCall(PairPointsWithTriangles(sc, Q, P, u, ptri, rho));
  PetscCall(PairEdges(sc, P, Q, pedge, &qedge, rho));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The present tiles (sc->tile_present: tile -> its index in *state, or -1), their states and boxes. */
static PetscErrorCode PresentTiles(ClothSelfContact sc, PetscReal rho, PetscInt *n, SelfContactTileState **state, PetscReal **boxes)
{
  const PetscInt nparticles = sc->layout.nlocal + sc->nremote;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < sc->npresent_tiles; k++) sc->tile_present[sc->present_tiles[k]] = -1;
  sc->npresent_tiles = 0;
  for (PetscInt k = 0; k < nparticles; k++) {
    const PetscInt t = SelfContactParticleTile(sc, sc->natural_of[k]);
    if (sc->tile_present[t] >= 0) continue;
    if (sc->npresent_tiles == sc->maxpresent_tiles) PetscCall(SelfContactGrowArray(sizeof(PetscInt), sc->npresent_tiles, &sc->maxpresent_tiles, 64, &sc->present_tiles));
    sc->tile_present[t]                     = sc->npresent_tiles;
    sc->present_tiles[sc->npresent_tiles++] = t;
  }
  *n = sc->npresent_tiles;
  PetscCall(PetscMalloc2(*n + 1, state, 6 * *n + 6, boxes));
  for (PetscInt k = 0; k < *n; k++) TileState(sc, sc->present_tiles[k], 0.5 * rho, &(*state)[k], &(*boxes)[6 * k]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The pairs of present tiles whose boxes overlap, found on a cell grid of the boxes, each given to PairTiles unless
   neither holds anything of this rank's or TilesApart proves it holds nothing. */
static PetscErrorCode VisitTilePairs(ClothSelfContact sc, const SelfContactTileState *state, const PetscReal *boxes, PetscInt n, const PetscReal region[6], PetscReal rho)
{
  PetscInt        ncell[3], lo[3], hi[3];
  const PetscInt *start, *item;
  PetscReal       cell = 0;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++)
    for (PetscInt c = 0; c < 3; c++) cell = PetscMax(cell, boxes[6 * k + 3 + c] - boxes[6 * k + c]);
  if (n == 0 || !(cell > 0)) PetscFunctionReturn(PETSC_SUCCESS);
  /* cells as large as the largest box: each box touches at most two along each axis */
  PetscCall(CellGridBuild(sc->tile_grid, region, region + 3, cell, 8 * n + 64, n, boxes, boxes + 3, 6));
  CellGridGetCells(sc->tile_grid, ncell, &start, &item);
  for (PetscInt a = 0; a < n; a++) {
    const SelfContactTile *P        = &sc->tiles[state[a].tile];
    PetscBool              gathered = PETSC_FALSE; /* a's primitives, relative to its mean displacement */
    TilePrimitives         ptri, pedge;

    CellGridGetCellRange(sc->tile_grid, &boxes[6 * a], &boxes[6 * a + 3], lo, hi);
    sc->visit++;
    for (PetscInt i = lo[0]; i <= hi[0]; i++)
      for (PetscInt j = lo[1]; j <= hi[1]; j++)
        for (PetscInt l = lo[2]; l <= hi[2]; l++) {
          const PetscInt c = CellGridCellIndex(ncell, i, j, l);
          for (PetscInt q = start[c]; q < start[c + 1]; q++) {
            const PetscInt         b = item[q];
            const SelfContactTile *Q = &sc->tiles[state[b].tile];

            if (b < a || sc->tile_mark[b] == sc->visit) continue;
            sc->tile_mark[b] = sc->visit;
            if ((!state[a].owned && !state[b].owned) || !BoxesOverlap(&boxes[6 * a], &boxes[6 * b])) continue;
            if (!sc->same_piece && P->piece == Q->piece) continue; /* one piece never collides with itself */
            sc->tile_pairs++;
            if (TileNeighbours(P, Q) && TilesApart(sc, state, P, Q, rho)) {
              sc->tile_pairs_apart++;
              continue;
            }
            if (!gathered) GatherTile(sc, state[a].tile, rho, state[a].mdx, 0, &ptri, &pedge);
            gathered = PETSC_TRUE;
            PetscCall(PairTiles(sc, state[a].tile, state[b].tile, state[a].mdx, &ptri, &pedge, rho));
          }
        }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactPairPrimitives(ClothSelfContact sc, const PetscReal region[6], PetscReal rho)
{
  SelfContactTileState *state;
  PetscReal            *boxes;
  PetscInt              n = 0;

  PetscFunctionBeginUser;
  PetscCall(PresentTiles(sc, rho, &n, &state, &boxes));
  PetscCall(VisitTilePairs(sc, state, boxes, n, region, rho));
  PetscCall(PetscFree2(state, boxes));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SelfContactDestroyTiles(ClothSelfContact sc)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(sc->piece_tiles));
  PetscCall(PetscFree(sc->tiles));
  PetscCall(PetscFree(sc->tile_tri_start));
  PetscCall(PetscFree(sc->tile_tri_of));
  PetscCall(PetscFree(sc->tile_edge_start));
  PetscCall(PetscFree(sc->tile_edge_of));
  PetscCall(PetscFree(sc->tile_particle_start));
  PetscCall(PetscFree(sc->tile_particle_of));
  PetscCall(PetscFree2(sc->tile_present, sc->tile_mark));
  PetscCall(PetscFree(sc->present_tiles));
  PetscCall(PetscFree3(sc->scratch_ids, sc->scratch_ij, sc->scratch_boxes));
  PetscCall(CellGridDestroy(&sc->tile_grid));
  PetscFunctionReturn(PETSC_SUCCESS);
}
