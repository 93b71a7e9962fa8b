/* Checkpoints: full state in one HDF5 file, written collectively, renamed into place when complete.

   Layout (docs/checkpoint.md): /state/position and /state/velocity, (N, 3) float64 in
   natural (global particle) order, plus any further per-particle field a restart needs (the implicit
   integrator's last velocity change, /state/implicit_dv, and bdf2's history, which the run declares; the state of
   the cloth's contributions, which each declares itself: cloth.h, checkpoint_fields); attributes on /state: step (int64), time
   (float64), and the rest of ClothCheckpointInfo. */
#pragma once
#include <stdint.h>
#include <petscvec.h>
#include "util.h"
#include "scene.h"

typedef struct {
  PetscInt64 step;                       /* steps taken */
  PetscReal  time;                       /* simulated time, s */
  PetscReal  dt;                         /* the nominal step in use when written, s (step halving is per step and leaves it unchanged) */
  PetscInt64 dt_start_step;              /* step and time at which dt came into use: time = dt_start_time + dt (step - dt_start_step), */
  PetscReal  dt_start_time;              /* so a restarted run computes exactly the times of an uninterrupted one */
  char       integrator[CLOTH_NAME_LEN]; /* name of the integrator */
  PetscReal  history_dt;                 /* the (sub-)step of the integrator's history (bdf2's last step; 0: none) */
  PetscInt64 scene_fingerprint;          /* Scene.fingerprint */
  char       scene_name[CLOTH_NAME_LEN];
  PetscInt64 nparticles;
  uint64_t   run_id; /* the run that wrote it (a restart continues its run); 0: none. Pruning removes only checkpoints of the writer's run */
  Scene      scene;  /* write: the scene, whose bytes go into the file (provenance.h); NULL: only the code version */
} ClothCheckpointInfo;

/* One per-particle dataset of a checkpoint: /state/<name>, shape (N, bs) float64 in natural order,
   bs the block size of vec (a natural-order Vec: PETSc's default contiguous layout). */
typedef struct {
  const char *name;
  Vec         vec;
  PetscBool   required; /* read: refuse a file without this dataset; otherwise vec is left untouched */
  PetscBool   found;    /* read: set to whether the file holds the dataset */
} ClothCheckpointField;

/* The field of this name among fields[0..nfields), or NULL. */
PetscErrorCode ClothCheckpointFieldFind(PetscInt nfields, const ClothCheckpointField fields[], const char name[], const ClothCheckpointField **field);
/* Writes DIR/checkpoint_NNNNNN.h5 (NNNNNN = info->step, six digits) through a temporary name, then
   renames it; keeps only the newest `keep` checkpoints of this run (info->run_id) in DIR when keep > 0, never
   touching another run's. fields must include
   "position" and "velocity"; each dataset carries a checksum of its bits. Returns the final path in
   path_out (may be NULL). Collective. */
PetscErrorCode ClothCheckpointWrite(MPI_Comm comm, const char dir[], const ClothCheckpointInfo *info, PetscInt nfields, const ClothCheckpointField fields[], PetscInt keep, char path_out[], size_t path_len);
/* The newest checkpoint_NNNNNN.h5 in dir (path "" when none) and how many there are. Collective. */
PetscErrorCode ClothCheckpointFindNewest(MPI_Comm comm, const char dir[], char path[], size_t len, PetscInt *count);
/* Reads a checkpoint into the fields' Vecs (natural order, already created with the right size).
   Refuses, with one clear message naming the file, a file that is missing, truncated or corrupt
   (unreadable, or a dataset whose checksum differs), has no end marker, lacks a required dataset,
   holds another particle count, or whose fingerprint differs from expect->scene_fingerprint (when
   expect is not NULL). Collective. */
PetscErrorCode ClothCheckpointRead(MPI_Comm comm, const char path[], const ClothCheckpointInfo *expect, ClothCheckpointInfo *info, PetscInt nfields, ClothCheckpointField fields[]);
