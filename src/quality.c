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

PetscErrorCode ClothQualityWrite(Cloth cloth, ClothCollision collision, ClothSewing sewing, uint64_t run_id, const char path[], PetscReal wall_seconds)
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
  PetscCall(PetscFOpen(comm, tmp, "w", &fp));
  PetscCall(PetscFPrintf(comm, fp, "{\n  \"max_seam_gap_m\": %.6e,\n  \"sewn_pairs\": %" PetscInt_FMT ",\n  \"seam_pairs\": %" PetscInt_FMT ",\n", (double)gap, sewn, total));
  PetscCall(PetscFPrintf(comm, fp, "  \"particles_inside_body\": %" PetscInt_FMT ",\n  \"max_link_strain\": %.6e,\n  \"kinetic_energy_j\": %.6e,\n", inside, (double)strain, (double)energy.kinetic));
  PetscCall(PetscFPrintf(comm, fp, "  \"wall_s\": %.3f,\n  \"ranks\": %d,\n", (double)wall_seconds, (int)size));
  PetscCall(PetscFPrintf(comm, fp, "  \"run_id\": \"%016llx\",\n", (unsigned long long)run_id)); /* a string: a JSON number is a double */
  PetscCall(WriteSeamLinks(cloth, fp));
  PetscCall(PetscFPrintf(comm, fp, "}\n"));
  PetscCall(ClothFileCommitText(comm, fp, tmp, path));
  PetscCall(PetscPrintf(comm, "Garment quality: widest seam gap %.2f mm (%" PetscInt_FMT "/%" PetscInt_FMT " pairs sewn), %" PetscInt_FMT " particles inside the body, max link strain %.4f, kinetic energy %.3e J -> %s\n",
                        (double)(1e3 * gap), sewn, total, inside, (double)strain, (double)energy.kinetic, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}
