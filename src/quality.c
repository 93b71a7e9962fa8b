/* Garment quality at the end of a run (see quality.h). */
#include "quality.h"
#include "sewing.h"

/* Largest relative stretch of any stretch link at the current positions. */
static PetscErrorCode MaxLinkStrain(Cloth cloth, PetscReal *strain)
{
  Vec natural, x;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateStrainVec(cloth, &natural));
  PetscCall(ClothGetState(cloth, &x, NULL));
  PetscCall(ClothComputeStrain(cloth, x, natural));
  PetscCall(VecMax(natural, NULL, strain));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunWriteQuality(ClothRun run, const char path[], PetscReal wall_seconds)
{
  Cloth            cloth;
  ClothCollision   collision;
  ClothSewing      sewing;
  ClothSewingPhase phase;
  ClothEnergy      energy;
  Vec              x, v;
  PetscInt         inside = 0, sewn = 0, total = 0;
  PetscReal        gap = 0, strain;
  PetscMPIInt      size;
  FILE            *fp;

  PetscFunctionBeginUser;
  PetscCall(ClothRunGetCloth(run, &cloth));
  PetscCall(ClothRunGetCollision(run, &collision));
  PetscCall(ClothRunGetSewing(run, &sewing));
  if (sewing) PetscCall(ClothSewingGetStatus(sewing, &phase, &sewn, &total, &gap));
  if (collision) PetscCall(ClothCollisionCountInside(collision, &inside));
  PetscCall(MaxLinkStrain(cloth, &strain));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothComputeEnergy(cloth, x, v, &energy));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscFOpen(PETSC_COMM_WORLD, path, "w", &fp));
  PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "{\n  \"max_seam_gap_m\": %.6e,\n  \"sewn_pairs\": %" PetscInt_FMT ",\n  \"seam_pairs\": %" PetscInt_FMT ",\n", (double)gap, sewn, total));
  PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "  \"particles_inside_body\": %" PetscInt_FMT ",\n  \"max_link_strain\": %.6e,\n  \"kinetic_energy_j\": %.6e,\n", inside, (double)strain, (double)energy.kinetic));
  PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "  \"wall_s\": %.3f,\n  \"ranks\": %d\n}\n", (double)wall_seconds, (int)size));
  PetscCall(PetscFClose(PETSC_COMM_WORLD, fp));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Garment quality: widest seam gap %.2f mm (%" PetscInt_FMT "/%" PetscInt_FMT " pairs sewn), %" PetscInt_FMT " particles inside the body, max link strain %.4f, kinetic energy %.3e J -> %s\n", (double)(1e3 * gap), sewn, total, inside, (double)strain, (double)energy.kinetic, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}
