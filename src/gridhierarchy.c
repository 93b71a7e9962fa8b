/* ClothGridHierarchy (see gridhierarchy.h). */
#include "gridhierarchy.h"
#include "model.h"

struct _n_ClothGridHierarchy {
  MPI_Comm  comm;
  PetscInt  nlevels;
  PetscInt *nparticles; /* per level */
  Mat      *P;          /* P[l]: level l - 1 -> level l (P[0] unused) */
  PetscInt *grids;      /* per level and piece: nu, nv (for View) */
  PetscInt  npieces;
};

/* One level's grids while the hierarchy is built: the same on every rank. */
typedef struct {
  PetscInt   npieces;
  PetscInt  *nu, *nv;     /* per piece */
  PetscInt  *offset;      /* npieces + 1: the first particle of each piece in the level's natural numbering */
  PetscInt  *global;      /* natural -> global (solver) index */
  PetscInt  *ranges;      /* size + 1: rank r owns global indices [ranges[r], ranges[r + 1]) */
  PetscInt  *lines;       /* per piece nu then nv entries: where each grid line lies in the cloth's own grid (its index) */
  PetscInt  *line_offset; /* npieces + 1: the first entry of each piece in lines */
  PetscBool *pinned;      /* natural: held fixed (on a coarse level: sits on a pinned particle) */
} GridLevel;

static PetscErrorCode GridLevelAllocate(PetscInt npieces, PetscMPIInt size, GridLevel *level)
{
  PetscFunctionBeginUser;
  level->npieces = npieces;
  level->global  = NULL;
  level->lines   = NULL;
  level->pinned  = NULL;
  PetscCall(PetscMalloc5(npieces, &level->nu, npieces, &level->nv, npieces + 1, &level->offset, size + 1, &level->ranges, npieces + 1, &level->line_offset));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* After nu and nv are set: room for the grid lines. */
static PetscErrorCode GridLevelAllocateLines(GridLevel *level)
{
  PetscFunctionBeginUser;
  level->line_offset[0] = 0;
  for (PetscInt p = 0; p < level->npieces; p++) level->line_offset[p + 1] = level->line_offset[p] + level->nu[p] + level->nv[p];
  PetscCall(PetscMalloc1(level->line_offset[level->npieces], &level->lines));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode GridLevelFree(GridLevel *level)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree5(level->nu, level->nv, level->offset, level->ranges, level->line_offset));
  PetscCall(PetscFree(level->global));
  PetscCall(PetscFree(level->lines));
  PetscCall(PetscFree(level->pinned));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The cloth itself as the finest level. */
static PetscErrorCode GridLevelFromCloth(Cloth cloth, GridLevel *level)
{
  ClothLayout layout;
  PetscMPIInt size;
  PetscInt    p;

  PetscFunctionBeginUser;
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCallMPI(MPI_Comm_size(layout.comm, &size));
  PetscCall(GridLevelAllocate(layout.model->npieces, size, level));
  for (p = 0; p < level->npieces; p++) {
    level->nu[p] = layout.scene->pieces[p].nu;
    level->nv[p] = layout.scene->pieces[p].nv;
  }
  PetscCall(PetscArraycpy(level->offset, layout.model->piece_offset, level->npieces + 1));
  PetscCall(GridLevelAllocateLines(level));
  for (p = 0; p < level->npieces; p++) {
    PetscInt *u = level->lines + level->line_offset[p], *v = u + level->nu[p];
    for (PetscInt i = 0; i < level->nu[p]; i++) u[i] = i;
    for (PetscInt j = 0; j < level->nv[p]; j++) v[j] = j;
  }
  PetscCall(PetscMalloc1(layout.nglobal, &level->global));
  PetscCall(PetscArraycpy(level->global, layout.solver_of_natural, layout.nglobal));
  PetscCall(PetscMalloc1(layout.nglobal, &level->pinned));
  PetscCall(PetscArraycpy(level->pinned, layout.model->pinned, layout.nglobal));
  level->ranges[0] = 0;
  PetscCallMPI(MPI_Allgather(&layout.nlocal, 1, MPIU_INT, level->ranges + 1, 1, MPIU_INT, layout.comm));
  for (PetscMPIInt r = 0; r < size; r++) level->ranges[r + 1] += level->ranges[r];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Along one direction of n grid points, coarsening by the ratio r keeps the indices 0, r, 2r, ... and the last one. */
static PetscInt CoarseCount(PetscInt n, PetscInt r)
{
  return (n - 1) / r + 1 + ((n - 1) % r ? 1 : 0);
}

/* The fine index of coarse index ic. */
static PetscInt FineIndexOf(PetscInt ic, PetscInt n, PetscInt r)
{
  return PetscMin(r * ic, n - 1);
}

/* Linear interpolation along one direction: fine index i of n points, whose grid lines lie at line[] in the cloth's
   grid, from at most two coarse indices (r = 1: the direction is not coarsened). Linear in the cloth's grid index, so
   that a field linear in it is reproduced on every level, the shorter last interval of a level included. */
static PetscInt Weights1D(PetscInt i, PetscInt n, PetscInt r, const PetscInt line[], PetscInt index[2], PetscReal weight[2])
{
  PetscInt f0, f1;

  if (i % r == 0 || i == n - 1) {
    index[0]  = i == n - 1 ? CoarseCount(n, r) - 1 : i / r;
    weight[0] = 1;
    return 1;
  }
  index[0]  = i / r;
  index[1]  = index[0] + 1;
  f0        = FineIndexOf(index[0], n, r);
  f1        = FineIndexOf(index[1], n, r);
  weight[1] = (PetscReal)(line[i] - line[f0]) / (PetscReal)(line[f1] - line[f0]);
  weight[0] = 1 - weight[1];
  return 2;
}

/* The ratio a direction of n points is coarsened by: r while that leaves at least 2 points and removes some, else 1. */
static PetscInt RatioFor(PetscInt n, PetscInt r)
{
  return n >= 3 ? r : 1;
}

/* The next coarser level of fine: grids, natural -> global numbering (a coarse particle is owned by the owner of the
   fine particle it sits on, numbered in the order of those fine particles' global indices) and ranges. */
static PetscErrorCode GridLevelCoarsen(const GridLevel *fine, PetscInt ratio, PetscMPIInt size, GridLevel *coarse)
{
  PetscInt    nfine = fine->offset[fine->npieces], ncoarse, *coarse_at, count = 0;
  PetscMPIInt r = 0;

  PetscFunctionBeginUser;
  PetscCall(GridLevelAllocate(fine->npieces, size, coarse));
  coarse->offset[0] = 0;
  for (PetscInt p = 0; p < fine->npieces; p++) {
    coarse->nu[p]         = CoarseCount(fine->nu[p], RatioFor(fine->nu[p], ratio));
    coarse->nv[p]         = CoarseCount(fine->nv[p], RatioFor(fine->nv[p], ratio));
    coarse->offset[p + 1] = coarse->offset[p] + coarse->nu[p] * coarse->nv[p];
  }
  ncoarse = coarse->offset[fine->npieces];
  PetscCall(GridLevelAllocateLines(coarse));
  for (PetscInt p = 0; p < fine->npieces; p++) {
    const PetscInt *u = fine->lines + fine->line_offset[p], *v = u + fine->nu[p];
    PetscInt       *uc = coarse->lines + coarse->line_offset[p], *vc = uc + coarse->nu[p];
    for (PetscInt ic = 0; ic < coarse->nu[p]; ic++) uc[ic] = u[FineIndexOf(ic, fine->nu[p], RatioFor(fine->nu[p], ratio))];
    for (PetscInt jc = 0; jc < coarse->nv[p]; jc++) vc[jc] = v[FineIndexOf(jc, fine->nv[p], RatioFor(fine->nv[p], ratio))];
  }
  PetscCall(PetscMalloc1(ncoarse, &coarse->global));
  PetscCall(PetscMalloc1(ncoarse, &coarse->pinned));
  PetscCall(PetscMalloc1(nfine, &coarse_at)); /* fine global index -> coarse natural index, or -1 */
  for (PetscInt g = 0; g < nfine; g++) coarse_at[g] = -1;
  for (PetscInt p = 0; p < fine->npieces; p++) {
    const PetscInt ru = RatioFor(fine->nu[p], ratio), rv = RatioFor(fine->nv[p], ratio);
    for (PetscInt jc = 0; jc < coarse->nv[p]; jc++)
      for (PetscInt ic = 0; ic < coarse->nu[p]; ic++) {
        const PetscInt n                                            = fine->offset[p] + FineIndexOf(jc, fine->nv[p], rv) * fine->nu[p] + FineIndexOf(ic, fine->nu[p], ru);
        coarse_at[fine->global[n]]                                  = coarse->offset[p] + jc * coarse->nu[p] + ic;
        coarse->pinned[coarse->offset[p] + jc * coarse->nu[p] + ic] = fine->pinned[n];
      }
  }
  for (PetscInt g = 0; g < nfine; g++) {
    while (r <= size && fine->ranges[r] == g) coarse->ranges[r++] = count;
    if (coarse_at[g] >= 0) coarse->global[coarse_at[g]] = count++;
  }
  while (r <= size) coarse->ranges[r++] = count;
  PetscCall(PetscFree(coarse_at));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The bilinear interpolation weights of fine particle (p, i, j): up to 4 coarse natural indices and weights. Pinned
   particles are held by their constraint (their rows of the system are the mass alone), so the coarse space vanishes on
   them, as a finite-element coarse space vanishes on a Dirichlet boundary: a pinned particle is interpolated only from
   a coarse particle on itself, and a free one leaves out the pinned coarse particles (without renormalising). Mixing
   the two kinds made the coarse levels useless next to pins (measured: 115 iterations a step on a sheet pinned along
   an edge, against 6 without the pins). */
static PetscInt CellWeights(const GridLevel *fine, const GridLevel *coarse, PetscInt ratio, PetscInt p, PetscInt i, PetscInt j, PetscInt index[4], PetscReal weight[4])
{
  const PetscInt *u = fine->lines + fine->line_offset[p], *v = u + fine->nu[p];
  const PetscBool pinned = fine->pinned[fine->offset[p] + j * fine->nu[p] + i];
  PetscInt        iu[2], iv[2], nu, nv, k = 0;
  PetscReal       wu[2], wv[2];

  nu = Weights1D(i, fine->nu[p], RatioFor(fine->nu[p], ratio), u, iu, wu);
  nv = Weights1D(j, fine->nv[p], RatioFor(fine->nv[p], ratio), v, iv, wv);
  if (pinned && nu * nv > 1) return 0; /* not a coarse particle itself */
  for (PetscInt b = 0; b < nv; b++)
    for (PetscInt a = 0; a < nu; a++) {
      index[k]  = coarse->offset[p] + iv[b] * coarse->nu[p] + iu[a];
      weight[k] = wu[a] * wv[b];
      if (pinned || !coarse->pinned[index[k]]) k++;
    }
  return k;
}

/* P: rows the fine level's owned particles, columns the coarse level's. With maij, as MAIJ: the scalar weights kept
   once and applied to the three components alike (a third of AIJ's indices and values: at ratio 4 about 100 bytes
   per fine particle less); else AIJ with block size 3, which MatPtAP takes for the coarser levels (PETSc 3.18's
   MPIAIJ x MPIMAIJ product is only its slow all-at-once one). */
static PetscErrorCode BuildInterpolation(MPI_Comm comm, const GridLevel *fine, const GridLevel *coarse, PetscInt ratio, PetscBool maij, Mat *P)
{
  const PetscInt dof = maij ? 1 : 3;
  PetscMPIInt    rank;
  PetscInt       rstart, rend, cstart, cend, *dnnz, *onnz, index[4], k;
  PetscReal      weight[4];
  Mat            Q;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  rstart = fine->ranges[rank], rend = fine->ranges[rank + 1];
  cstart = coarse->ranges[rank], cend = coarse->ranges[rank + 1];
  PetscCall(PetscCalloc2(dof * (rend - rstart), &dnnz, dof * (rend - rstart), &onnz));
  for (PetscInt pass = 0; pass < 2; pass++) { /* count, then set */
    if (pass == 1) {
      PetscCall(MatCreateAIJ(comm, dof * (rend - rstart), dof * (cend - cstart), PETSC_DETERMINE, PETSC_DETERMINE, 0, dnnz, 0, onnz, &Q));
      PetscCall(MatSetBlockSizes(Q, dof, dof));
      PetscCall(MatSetOption(Q, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
    }
    for (PetscInt p = 0; p < fine->npieces; p++)
      for (PetscInt j = 0; j < fine->nv[p]; j++)
        for (PetscInt i = 0; i < fine->nu[p]; i++) {
          const PetscInt g = fine->global[fine->offset[p] + j * fine->nu[p] + i];
          if (g < rstart || g >= rend) continue;
          k = CellWeights(fine, coarse, ratio, p, i, j, index, weight);
          for (PetscInt a = 0; a < k; a++) {
            const PetscInt gc = coarse->global[index[a]];
            for (PetscInt c = 0; c < dof; c++) {
              const PetscInt row = dof * g + c, col = dof * gc + c;
              if (pass == 0) {
                if (gc >= cstart && gc < cend)
                  dnnz[row - dof * rstart]++;
                else
                  onnz[row - dof * rstart]++;
              } else
                PetscCall(MatSetValue(Q, row, col, weight[a], INSERT_VALUES));
            }
          }
        }
  }
  PetscCall(PetscFree2(dnnz, onnz));
  PetscCall(MatAssemblyBegin(Q, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(Q, MAT_FINAL_ASSEMBLY));
  if (maij) {
    PetscCall(MatCreateMAIJ(Q, 3, P));
    PetscCall(MatDestroy(&Q));
  } else
    *P = Q;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyCreate(Cloth cloth, PetscInt ratio, PetscInt max_levels, PetscInt coarse_particles, PetscBool all_maij, ClothGridHierarchy *gh)
{
  ClothGridHierarchy h;
  GridLevel          fine, coarse;
  PetscMPIInt        size;
  Mat                P[CLOTH_GRID_MAX_LEVELS];
  PetscInt           n[CLOTH_GRID_MAX_LEVELS], nfine_levels = 1;
  MPI_Comm           comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(cloth, &comm));
  PetscCheck(ratio >= 2, comm, PETSC_ERR_USER_INPUT, "Grid multigrid coarsening ratio %" PetscInt_FMT ": expected 2 or more", ratio);
  PetscCheck(max_levels >= 1 && max_levels <= CLOTH_GRID_MAX_LEVELS, comm, PETSC_ERR_USER_INPUT, "Grid multigrid levels %" PetscInt_FMT ": expected 1 to %d", max_levels, CLOTH_GRID_MAX_LEVELS);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscNew(&h));
  h->comm = comm;
  PetscCall(GridLevelFromCloth(cloth, &fine));
  h->npieces = fine.npieces;
  /* from the finest down; stored finest first, reversed into PCMG's order below */
  n[0] = fine.offset[fine.npieces];
  PetscCall(PetscMalloc1(2 * fine.npieces * max_levels, &h->grids));
  for (PetscInt p = 0; p < fine.npieces; p++) h->grids[2 * p] = fine.nu[p], h->grids[2 * p + 1] = fine.nv[p];
  while (nfine_levels < max_levels && n[nfine_levels - 1] > coarse_particles) {
    PetscCall(GridLevelCoarsen(&fine, ratio, size, &coarse));
    if (coarse.offset[coarse.npieces] == n[nfine_levels - 1]) { /* no piece can be coarsened further */
      PetscCall(GridLevelFree(&coarse));
      break;
    }
    PetscCall(BuildInterpolation(comm, &fine, &coarse, ratio, all_maij || nfine_levels == 1 ? PETSC_TRUE : PETSC_FALSE, &P[nfine_levels]));
    n[nfine_levels] = coarse.offset[coarse.npieces];
    for (PetscInt p = 0; p < fine.npieces; p++) {
      h->grids[2 * (nfine_levels * fine.npieces + p)]     = coarse.nu[p];
      h->grids[2 * (nfine_levels * fine.npieces + p) + 1] = coarse.nv[p];
    }
    nfine_levels++;
    PetscCall(GridLevelFree(&fine));
    fine = coarse;
  }
  PetscCall(GridLevelFree(&fine));
  h->nlevels = nfine_levels;
  PetscCall(PetscMalloc1(h->nlevels, &h->nparticles));
  PetscCall(PetscCalloc1(h->nlevels, &h->P));
  for (PetscInt l = 0; l < h->nlevels; l++) h->nparticles[l] = n[h->nlevels - 1 - l];
  for (PetscInt l = 1; l < h->nlevels; l++) h->P[l] = P[h->nlevels - l]; /* P[k] (k-th coarsening) maps to level nlevels-k */
  *gh = h;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyGetLevels(ClothGridHierarchy gh, PetscInt *nlevels)
{
  PetscFunctionBeginUser;
  *nlevels = gh->nlevels;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyGetInterpolation(ClothGridHierarchy gh, PetscInt level, Mat *P)
{
  PetscFunctionBeginUser;
  PetscCheck(level >= 1 && level < gh->nlevels, gh->comm, PETSC_ERR_ARG_OUTOFRANGE, "Level %" PetscInt_FMT " has no interpolation: expected 1 to %" PetscInt_FMT, level, gh->nlevels - 1);
  *P = gh->P[level];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyGetLevelSize(ClothGridHierarchy gh, PetscInt level, PetscInt *nparticles)
{
  PetscFunctionBeginUser;
  PetscCheck(level >= 0 && level < gh->nlevels, gh->comm, PETSC_ERR_ARG_OUTOFRANGE, "Level %" PetscInt_FMT ": expected 0 to %" PetscInt_FMT, level, gh->nlevels - 1);
  *nparticles = gh->nparticles[level];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyView(ClothGridHierarchy gh, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Pattern-grid multigrid: %" PetscInt_FMT " levels\n", gh->nlevels));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  for (PetscInt l = gh->nlevels - 1; l >= 0; l--) {
    const PetscInt *g = gh->grids + 2 * (gh->nlevels - 1 - l) * gh->npieces;
    PetscCall(PetscViewerASCIIPrintf(viewer, "level %" PetscInt_FMT ": %" PetscInt_FMT " particles, first piece %" PetscInt_FMT " x %" PetscInt_FMT "\n", l, gh->nparticles[l], g[0], g[1]));
  }
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothGridHierarchyDestroy(ClothGridHierarchy *gh)
{
  PetscFunctionBeginUser;
  if (!*gh) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt l = 1; l < (*gh)->nlevels; l++) PetscCall(MatDestroy(&(*gh)->P[l]));
  PetscCall(PetscFree((*gh)->P));
  PetscCall(PetscFree((*gh)->nparticles));
  PetscCall(PetscFree((*gh)->grids));
  PetscCall(PetscFree(*gh));
  PetscFunctionReturn(PETSC_SUCCESS);
}
