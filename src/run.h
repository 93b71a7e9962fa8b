/* ClothRun: one simulation run: run-level options (how: step, duration, output, checkpoints,
   restart) around a Cloth and its ClothIntegrator, and the time loop with progress output. */
#pragma once
#include "cloth.h"
#include "integrator.h"
#include "sewing.h"

typedef struct _n_ClothRun *ClothRun;

PetscErrorCode ClothRunCreate(MPI_Comm comm, Scene scene, ClothRun *run);
/* Reads every run-level option (see -help); scene values are the defaults. */
PetscErrorCode ClothRunSetFromOptions(ClothRun run);
/* Builds the cloth and integrator, restores a checkpoint given with -restart, opens the output. */
PetscErrorCode ClothRunSetUp(ClothRun run);
/* Runs the time loop to the end (or to a termination signal); always writes a final checkpoint. */
PetscErrorCode ClothRunSolve(ClothRun run);
PetscErrorCode ClothRunGetCloth(ClothRun run, Cloth *cloth);
/* The collision handler (borrowed; NULL when the scene has no bodies). */
PetscErrorCode ClothRunGetCollision(ClothRun run, ClothCollision *collision);
/* The fit maps of the current state, natural order, one value per particle (Vecs like ClothCreateStrainVec's):
   strain (ClothComputeStrain), stress in N/m (ClothComputeStress) and the bodies' contact pressure in N/m^2
   from the last step's contact response (ClothComputeContactPressure; zero without bodies). Collective. */
PetscErrorCode ClothRunComputeFitMaps(ClothRun run, Vec strain, Vec stress, Vec pressure);
PetscErrorCode ClothRunDestroy(ClothRun *run);
