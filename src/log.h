/* Profiling: every PetscLogEvent and stage of clothsim, registered once, shown by -log_view. */
#pragma once
#include <petsclog.h>

typedef struct {
  PetscClassId  classid;
  PetscLogEvent setup, partition, forces, jacobian, solve, output, checkpoint;
  PetscLogEvent collision, collision_grid; /* contacts with bodies (detection + response); building the cell grids */
  PetscLogEvent self_collision;            /* cloth-cloth contact: exchange, search, repulsion, velocity filter */
  PetscLogEvent checkpoint_read;           /* reading and checking the checkpoint of -restart */
  PetscLogStage stage_setup, stage_steps;
  /* Phases of the set-up, nested in "Setup" (PETSc counts a nested stage's time in it alone, so the set-up total is
     "Setup" plus these); registered after "Time steps" so that it stays stage 2 for the scripts that read it. */
  PetscLogStage stage_scene;      /* reading and checking the scene file (every rank) */
  PetscLogStage stage_meshing;    /* the model: particles, links and angle springs of the pattern pieces (every rank, whole fabric) */
  PetscLogStage stage_graph;      /* the interaction graph in natural order (every rank, whole fabric) */
  PetscLogStage stage_partition;  /* splitting the graph across the ranks (-cloth_partition) */
  PetscLogStage stage_distribute; /* solver numbering, ghosts, each rank's interactions and vectors */
  PetscLogStage stage_bodies;     /* bodies: meshes read, their cell grids, particles pushed out of them */
  PetscLogStage stage_matrix;     /* the integrator: matrix preallocation and assembly pattern, solvers */
  PetscLogStage stage_output;     /* claiming -output_dir, opening the series, the first frame */
} ClothLogEvents;

extern ClothLogEvents ClothLog;

/* Registers the events and stages; safe to call more than once. */
PetscErrorCode ClothLogRegister(void);
