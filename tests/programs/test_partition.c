/* The distributed cloth against a brute-force serial evaluation of the whole model.

   Options: -scene FILE [-grid N]. On any number of ranks, checks that
   - every interaction is evaluated exactly once: the links and angle springs the ranks evaluate
     (ClothGetInteractionCounts) sum to the model's totals;
   - seam links (scenes with seams) get stiffnesses, half of them as sewn springs and half pulling, so
     that they take part in the comparison below (without a sewing object they would carry nothing);
   - at a perturbed state (the same, particle by particle, on every rank count), the forces of
     ClothComputeForces, brought to natural order, equal the sum over every interaction of the model
     evaluated serially on each rank, plus gravity and damping, to 1e-12 relative to the largest
     force (they differ only in summation order: a missed or doubly counted interaction, a wrong
     ghost or a wrong natural <-> solver map shows up as an O(1) error);
   - the elastic energy of ClothComputeEnergy equals the serial sum to 1e-12 relative.
   Prints nothing unless a check fails. */
#include <petscvec.h>
#include "scene.h"
#include "cloth.h"
#include "seam_links.h"
#include "test_support.h"

/* A smooth, rank-independent perturbation of particle k's component c (natural order). */
static PetscReal Perturbation(PetscInt k, PetscInt c, PetscReal amplitude)
{
  return amplitude * PetscSinReal(0.37 * (PetscReal)k + 1.1 * (PetscReal)c + 0.5 * (PetscReal)(c * c));
}

/* Sets the state to the model's initial positions plus a perturbation, and a velocity field. */
static PetscErrorCode SetPerturbedState(Cloth cloth, ClothModel model)
{
  Vec          x, v, natural;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(VecGetOwnershipRange(natural, &lo, &hi));
  PetscCall(VecGetArray(natural, &a));
  for (PetscInt i = lo; i < hi; i++) a[i - lo] = model->position[i] + Perturbation(i / 3, i % 3, 2e-3);
  PetscCall(VecRestoreArray(natural, &a));
  PetscCall(ClothScatterToNatural(cloth, x, natural, SCATTER_REVERSE));
  PetscCall(VecGetArray(natural, &a));
  for (PetscInt i = lo; i < hi; i++) a[i - lo] = Perturbation(i / 3, i % 3 + 3, 0.3);
  PetscCall(VecRestoreArray(natural, &a));
  PetscCall(ClothScatterToNatural(cloth, v, natural, SCATTER_REVERSE));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gathers a natural-order Vec whole onto every rank (the caller frees *all). */
static PetscErrorCode GatherNatural(Cloth cloth, Vec solver, PetscReal **all)
{
  Vec                natural, seq;
  VecScatter         to_all;
  const PetscScalar *a;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(ClothScatterToNatural(cloth, solver, natural, SCATTER_FORWARD));
  PetscCall(VecScatterCreateToAll(natural, &to_all, &seq));
  PetscCall(VecScatterBegin(to_all, natural, seq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(to_all, natural, seq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetSize(seq, &n));
  PetscCall(PetscMalloc1(n, all));
  PetscCall(VecGetArrayRead(seq, &a));
  PetscCall(PetscArraycpy(*all, a, n));
  PetscCall(VecRestoreArrayRead(seq, &a));
  PetscCall(VecScatterDestroy(&to_all));
  PetscCall(VecDestroy(&seq));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gives every seam link a force, the same on every rank count: even-numbered ones are sewn springs
   (pull_force 0), odd ones pull with a constant force that softens within 1 cm (seam.h), as the sewing
   phases would set them. The model's links (the serial reference) and this rank's copies agree. */
static PetscErrorCode SetSeamStiffnesses(Cloth cloth, ClothModel model)
{
  ClothSeamLink  *links;
  const PetscInt *model_index;
  PetscInt        n;

  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < model->nseamlinks; s++) {
    ClothSeamLink *link = &model->seamlinks[s];

    link->pull_force = s % 2 ? 0.01 * (1 + 0.1 * (PetscReal)(s % 7)) : 0;
    link->k          = s % 2 ? link->pull_force / 0.01 : 500 + 10 * (PetscReal)(s % 5);
  }
  PetscCall(ClothSeamLinksGetLocal(cloth, &n, &links, &model_index));
  for (PetscInt l = 0; l < n; l++) {
    links[l].pull_force = model->seamlinks[model_index[l]].pull_force;
    links[l].k          = model->seamlinks[model_index[l]].k;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Forces (3 N, natural order) and elastic energy of the whole model at (x, v), evaluated serially. */
static PetscErrorCode SerialForces(ClothModel model, const PetscReal gravity[3], const PetscReal x[], const PetscReal v[], PetscReal f[], PetscReal *energy)
{
  PetscFunctionBeginUser;
  *energy = 0;
  for (PetscInt i = 0; i < model->nparticles; i++)
    for (PetscInt c = 0; c < 3; c++) f[3 * i + c] = model->mass[i] * gravity[c] - model->damping[i] * v[3 * i + c];
  for (PetscInt l = 0; l < model->nlinks; l++) {
    const ClothLink *link = &model->links[l];
    PetscReal        e, f1[3];
    PetscCall(ClothLinkEvaluate(link, &x[3 * link->p[0]], &x[3 * link->p[1]], PETSC_TRUE, &e, f1, NULL));
    for (PetscInt c = 0; c < 3; c++) {
      f[3 * link->p[0] + c] -= f1[c];
      f[3 * link->p[1] + c] += f1[c];
    }
    *energy += e;
  }
  for (PetscInt a = 0; a < model->nangles; a++) {
    const ClothAngle *angle = &model->angles[a];
    const PetscInt    np    = ClothAngleParticleCount(angle->kind);
    const PetscReal  *xs[CLOTH_ANGLE_MAX_PARTICLES];
    PetscReal         e, fa[3 * CLOTH_ANGLE_MAX_PARTICLES];
    for (PetscInt k = 0; k < np; k++) xs[k] = &x[3 * angle->p[k]];
    PetscCall(ClothAngleEvaluate(angle, xs, CLOTH_STIFFNESS_GAUSS_NEWTON, &e, fa, NULL));
    for (PetscInt k = 0; k < np; k++)
      for (PetscInt c = 0; c < 3; c++) f[3 * angle->p[k] + c] += fa[3 * k + c];
    *energy += e;
  }
  for (PetscInt s = 0; s < model->nseamlinks; s++) {
    const ClothSeamLink *link = &model->seamlinks[s];
    const PetscReal     *xs[CLOTH_SEAM_LINK_MAX_PARTICLES];
    PetscReal            e, fs[3 * CLOTH_SEAM_LINK_MAX_PARTICLES];
    for (PetscInt k = 0; k < link->np; k++) xs[k] = &x[3 * link->p[k]];
    PetscCall(ClothSeamLinkEvaluate(link, xs, &e, fs, NULL));
    for (PetscInt k = 0; k < link->np; k++)
      for (PetscInt c = 0; c < 3; c++) f[3 * link->p[k] + c] += fs[3 * k + c];
    *energy += e;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckInteractionCounts(Cloth cloth, ClothModel model)
{
  PetscInt local[2], total[2];

  PetscFunctionBeginUser;
  PetscCall(ClothGetInteractionCounts(cloth, &local[0], &local[1]));
  PetscCallMPI(MPI_Allreduce(local, total, 2, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscCheck(total[0] == model->nlinks, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "The ranks evaluate %" PetscInt_FMT " links in all, the model has %" PetscInt_FMT, total[0], model->nlinks);
  PetscCheck(total[1] == model->nangles, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "The ranks evaluate %" PetscInt_FMT " angle springs in all, the model has %" PetscInt_FMT, total[1], model->nangles);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckAgainstSerial(Cloth cloth, Scene scene, ClothModel model)
{
  const PetscReal rtol = 1e-12;
  const PetscInt  n    = 3 * model->nparticles;
  Vec             x, v, force;
  PetscReal      *xa, *va, *fa, *reference, energy, worst = 0, scale = 0;
  ClothEnergy     e;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(ClothCreateStateVec(cloth, &force));
  PetscCall(ClothComputeForces(cloth, x, v, force));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  PetscCall(GatherNatural(cloth, x, &xa));
  PetscCall(GatherNatural(cloth, v, &va));
  PetscCall(GatherNatural(cloth, force, &fa));
  PetscCall(PetscMalloc1(n, &reference));
  PetscCall(SerialForces(model, scene->gravity, xa, va, reference, &energy));
  for (PetscInt i = 0; i < n; i++) {
    worst = PetscMax(worst, PetscAbsReal(fa[i] - reference[i]));
    scale = PetscMax(scale, PetscAbsReal(reference[i]));
  }
  PetscCheck(worst <= rtol * scale, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Distributed forces differ from the serial evaluation by %g N (largest force %g N, tolerance %g relative)", (double)worst, (double)scale, (double)rtol);
  PetscCheck(PetscAbsReal(e.elastic - energy) <= rtol * PetscAbsReal(energy), PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Distributed elastic energy %.17g J differs from the serial sum %.17g J (tolerance %g relative)", (double)e.elastic, (double)energy,
             (double)rtol);
  PetscCheck(energy > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "The perturbation should strain the fabric, yet the elastic energy is %g J", (double)energy);
  PetscCall(PetscFree(reference));
  PetscCall(PetscFree(xa));
  PetscCall(PetscFree(va));
  PetscCall(PetscFree(fa));
  PetscCall(VecDestroy(&force));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  Scene      scene;
  Cloth      cloth;
  ClothModel model;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(CheckInteractionCounts(cloth, model));
  PetscCall(SetSeamStiffnesses(cloth, model));
  PetscCall(SetPerturbedState(cloth, model));
  PetscCall(CheckAgainstSerial(cloth, scene, model));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
