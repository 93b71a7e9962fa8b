/* Garment quality at the end of a run (see quality.h). */
#include "quality.h"
#include "fileutil.h"

/* Prints the n particles with the largest strain (natural Vec), with their piece and grid node. */
static PetscErrorCode ViewMostStrained(Cloth cloth, Vec natural, PetscInt n)
{
  VecScatter         to_zero;
  Vec                all;
  const PetscScalar *s;
  PetscReal         *strain;
  PetscInt           size;
  PetscMPIInt        rank;
  MPI_Comm           comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(cloth, &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(VecScatterCreateToZero(natural, &to_zero, &all));
  PetscCall(VecScatterBegin(to_zero, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_zero, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscPrintf(comm, "Most strained particles (largest (l - l0) / l0 of their stretch links):\n"));
  if (rank == 0) {
    PetscCall(VecGetSize(all, &size));
    PetscCall(PetscMalloc1(size, &strain));
    PetscCall(VecGetArrayRead(all, &s));
    for (PetscInt g = 0; g < size; g++) strain[g] = PetscRealPart(s[g]);
    PetscCall(VecRestoreArrayRead(all, &s));
    for (PetscInt r = 0; r < PetscMin(n, size); r++) {
      PetscInt most = 0;
      char     name[2 * CLOTH_NAME_LEN];
      for (PetscInt g = 1; g < size; g++)
        if (strain[g] > strain[most]) most = g;
      PetscCall(ClothGetParticleName(cloth, most, name, sizeof(name)));
      PetscCall(PetscPrintf(PETSC_COMM_SELF, "  %.4f  %s\n", (double)strain[most], name));
      strain[most] = -PETSC_MAX_REAL;
    }
    PetscCall(PetscFree(strain));
  }
  PetscCall(VecScatterDestroy(&to_zero));
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Largest relative stretch of any stretch link at the current positions; the n most strained
   particles are printed. */
static PetscErrorCode MaxLinkStrain(Cloth cloth, PetscInt n, PetscReal *strain)
{
  Vec natural, x;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateStrainVec(cloth, &natural));
  PetscCall(ClothGetState(cloth, &x, NULL));
  PetscCall(ClothComputeStrain(cloth, x, natural));
  PetscCall(VecMax(natural, NULL, strain));
  if (n > 0) PetscCall(ViewMostStrained(cloth, natural, n));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* "seam_links": the particles (natural numbers) of every seam link, the node first, for the crossing
   count of postprocess/garment_quality.py (an edge and a triangle that meet at a sewn point are the seam
   itself, as two cells of one piece meet at a shared particle). Rank 0 writes. */
static PetscErrorCode WriteSeamLinks(Cloth cloth, FILE *fp)
{
  ClothModel model;
  MPI_Comm   comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(ClothGetComm(cloth, &comm));
  PetscCall(PetscFPrintf(comm, fp, "  \"seam_links\": ["));
  for (PetscInt l = 0; l < model->nseamlinks; l++) {
    const ClothSeamLink *link = &model->seamlinks[l];
    PetscCall(PetscFPrintf(comm, fp, "%s[%" PetscInt_FMT ", %" PetscInt_FMT, l ? ", " : "", link->p[0], link->p[1]));
    if (link->np == 3) PetscCall(PetscFPrintf(comm, fp, ", %" PetscInt_FMT, link->p[2]));
    PetscCall(PetscFPrintf(comm, fp, "]"));
  }
  PetscCall(PetscFPrintf(comm, fp, "]\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The q-quantile (0 <= q <= 1) of n sorted values, interpolated linearly between the nearest ranks (numpy's
   default); 0 for none. */
static PetscReal SortedQuantile(const PetscReal sorted[], PetscInt n, PetscReal q)
{
  PetscReal at;
  PetscInt  lo;

  if (n == 0) return 0;
  at = q * (PetscReal)(n - 1);
  lo = (PetscInt)PetscFloorReal(at);
  if (lo + 1 >= n) return sorted[n - 1];
  return sorted[lo] + (at - (PetscReal)lo) * (sorted[lo + 1] - sorted[lo]);
}

/* The maximum and 95th percentile of natural field values[first, last) as "name_max" and "name_p95" entries. */
static PetscErrorCode WriteFieldSummary(MPI_Comm comm, FILE *fp, const char name[], const PetscReal values[], PetscInt first, PetscInt last, const char *separator)
{
  PetscReal *sorted;
  PetscInt   n = last - first;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n, &sorted));
  PetscCall(PetscArraycpy(sorted, values + first, n));
  PetscCall(PetscSortReal(n, sorted));
  PetscCall(PetscFPrintf(comm, fp, "\"%s_max\": %.6e, \"%s_p95\": %.6e%s", name, (double)(n ? sorted[n - 1] : 0), name, (double)SortedQuantile(sorted, n, 0.95), separator));
  PetscCall(PetscFree(sorted));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A natural per-particle Vec gathered on rank 0 into values (allocated there; NULL elsewhere). */
static PetscErrorCode GatherToZero(Vec natural, PetscReal **values)
{
  VecScatter         to_zero;
  Vec                all;
  const PetscScalar *a;
  PetscInt           n;

  PetscFunctionBeginUser;
  *values = NULL;
  PetscCall(VecScatterCreateToZero(natural, &to_zero, &all));
  PetscCall(VecScatterBegin(to_zero, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_zero, natural, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetLocalSize(all, &n));
  if (n > 0) {
    PetscCall(PetscMalloc1(n, values));
    PetscCall(VecGetArrayRead(all, &a));
    for (PetscInt g = 0; g < n; g++) (*values)[g] = PetscRealPart(a[g]);
    PetscCall(VecRestoreArrayRead(all, &a));
  }
  PetscCall(VecScatterDestroy(&to_zero));
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* "fit_maps": per piece, in the scene's order, its particle count and the maximum and 95th percentile over its particles of the strain, the stress (N/m)
   and the contact pressure on the body (N/m^2; particles off the body count as 0). Rank 0 writes. */
static PetscErrorCode WriteFitMaps(Cloth cloth, Vec field[3], FILE *fp)
{
  static const char *const names[3] = {"strain", "stress_n_per_m", "pressure_pa"};
  ClothModel               model;
  Scene                    scene;
  PetscReal               *values[3];
  PetscMPIInt              rank;
  MPI_Comm                 comm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(cloth, &comm));
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(ClothGetScene(cloth, &scene));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt f = 0; f < 3; f++) PetscCall(GatherToZero(field[f], &values[f]));
  PetscCall(PetscFPrintf(comm, fp, "  \"fit_maps\": {\n"));
  if (rank == 0)
    for (PetscInt p = 0; p < model->npieces; p++) {
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "    \"%s\": {\"particles\": %" PetscInt_FMT ", ", scene->pieces[p].name, model->piece_offset[p + 1] - model->piece_offset[p]));
      for (PetscInt f = 0; f < 3; f++) PetscCall(WriteFieldSummary(PETSC_COMM_SELF, fp, names[f], values[f], model->piece_offset[p], model->piece_offset[p + 1], f < 2 ? ", " : ""));
      PetscCall(PetscFPrintf(PETSC_COMM_SELF, fp, "}%s\n", p + 1 < model->npieces ? "," : ""));
    }
  PetscCall(PetscFPrintf(comm, fp, "  },\n"));
  for (PetscInt f = 0; f < 3; f++) PetscCall(PetscFree(values[f]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothQualityWrite(Cloth cloth, ClothCollision collision, ClothSewing sewing, Vec fit_maps[3], uint64_t run_id, const char path[], PetscReal wall_seconds)
{
  ClothSewingPhase phase;
  ClothEnergy      energy;
  Vec              x, v;
  PetscInt         inside = 0, sewn = 0, total = 0, worst = 5;
  PetscReal        gap = 0, strain;
  PetscMPIInt      size;
  FILE            *fp;
  MPI_Comm         comm;
  char             tmp[CLOTH_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(ClothGetComm(cloth, &comm));
  PetscOptionsBegin(comm, NULL, "Garment quality (written at the end of a run with seams)", "ClothQualityWrite");
  PetscCall(PetscOptionsInt("-quality_worst", "Print this many of the widest seam pairs and of the most strained particles, with their pieces and grid nodes", "ClothQualityWrite", worst, &worst, NULL));
  PetscOptionsEnd();
  if (sewing) PetscCall(ClothSewingGetStatus(sewing, &phase, &sewn, &total, &gap));
  if (sewing) PetscCall(ClothSewingViewWidest(sewing, worst));
  if (collision) PetscCall(ClothCollisionCountInside(collision, &inside));
  PetscCall(MaxLinkStrain(cloth, worst, &strain));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothComputeEnergy(cloth, x, v, &energy));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path)); /* renamed when complete: a full disk leaves no half file */
  PetscCall(ClothFileOpenText(comm, tmp, &fp));
  PetscCall(PetscFPrintf(comm, fp, "{\n  \"max_seam_gap_m\": %.6e,\n  \"sewn_pairs\": %" PetscInt_FMT ",\n  \"seam_pairs\": %" PetscInt_FMT ",\n", (double)gap, sewn, total));
  PetscCall(PetscFPrintf(comm, fp, "  \"particles_inside_body\": %" PetscInt_FMT ",\n  \"max_link_strain\": %.6e,\n  \"kinetic_energy_j\": %.6e,\n", inside, (double)strain, (double)energy.kinetic));
  PetscCall(PetscFPrintf(comm, fp, "  \"wall_s\": %.3f,\n  \"ranks\": %d,\n", (double)wall_seconds, (int)size));
  PetscCall(PetscFPrintf(comm, fp, "  \"run_id\": \"%016llx\",\n", (unsigned long long)run_id)); /* a string: a JSON number is a double */
  if (fit_maps) PetscCall(WriteFitMaps(cloth, fit_maps, fp));
  PetscCall(WriteSeamLinks(cloth, fp));
  PetscCall(PetscFPrintf(comm, fp, "}\n"));
  PetscCall(ClothFileCommitText(comm, fp, tmp, path));
  PetscCall(PetscPrintf(comm, "Garment quality: widest seam gap %.2f mm (%" PetscInt_FMT "/%" PetscInt_FMT " pairs sewn), %" PetscInt_FMT " particles inside the body, max link strain %.4f, kinetic energy %.3e J -> %s\n", (double)(1e3 * gap), sewn,
                        total, inside, (double)strain, (double)energy.kinetic, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}
