/* Profiling: every PetscLogEvent and stage of clothsim, registered once, shown by -log_view. */
#pragma once
#include <petsclog.h>

typedef struct {
  PetscClassId  classid;
  PetscLogEvent setup, partition, forces, jacobian, solve, output, checkpoint;
  PetscLogStage stage_setup, stage_steps;
} ClothLogEvents;

extern ClothLogEvents ClothLog;

/* Registers the events and stages; safe to call more than once. */
PetscErrorCode ClothLogRegister(void);
