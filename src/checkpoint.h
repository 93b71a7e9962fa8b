/* Checkpoints: full state in one HDF5 file, written collectively, renamed into place when complete.

   Layout (DESIGN.md): /state/position and /state/velocity, (N, 3) float64 in natural (global
   particle) order; attributes on /state: step (int64), time (float64), plus what a restart needs. */
#pragma once
#include <petscvec.h>
#include "util.h"

typedef struct {
  PetscInt64 step;                       /* steps taken */
  PetscReal  time;                       /* simulated time, s */
  PetscReal  dt;                         /* the step in use when written (after any reductions), s */
  char       integrator[CLOTH_NAME_LEN]; /* name of the integrator */
  PetscInt64 scene_fingerprint;          /* Scene.fingerprint */
  char       scene_name[CLOTH_NAME_LEN];
  PetscInt64 nparticles;
} ClothCheckpointInfo;

/* Writes DIR/checkpoint_NNNNNN.h5 (NNNNNN = info->step, six digits) through a temporary name, then
   renames it; keeps only the newest `keep` checkpoints in DIR when keep > 0. Returns the final path
   in path_out (may be NULL). Collective. */
PetscErrorCode ClothCheckpointWrite(MPI_Comm comm, const char dir[], const ClothCheckpointInfo *info, Vec position, Vec velocity, PetscInt keep, char path_out[], size_t path_len);
/* Reads a checkpoint into position/velocity (natural order, already created with the right size).
   Refuses, with one clear message naming the file, a file that is missing, truncated or corrupt, has
   no end marker, holds another particle count, or whose fingerprint differs from
   expect->scene_fingerprint (when expect is not NULL). Collective. */
PetscErrorCode ClothCheckpointRead(MPI_Comm comm, const char path[], const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, Vec position, Vec velocity);
