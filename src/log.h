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
} ClothLogEvents;

extern ClothLogEvents ClothLog;

/* Registers the events and stages; safe to call more than once. */
PetscErrorCode ClothLogRegister(void);
