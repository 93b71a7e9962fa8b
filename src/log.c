/* The events and stages of clothsim (see log.h). */
#include "log.h"
#include "util.h"

ClothLogEvents ClothLog;

static PetscBool registered = PETSC_FALSE;

PetscErrorCode ClothLogRegister(void)
{
  PetscFunctionBeginUser;
  if (registered) PetscFunctionReturn(PETSC_SUCCESS);
  registered = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("Cloth", &ClothLog.classid));
  PetscCall(PetscLogEventRegister("ClothSetUp", ClothLog.classid, &ClothLog.setup));
  PetscCall(PetscLogEventRegister("ClothPartition", ClothLog.classid, &ClothLog.partition));
  PetscCall(PetscLogEventRegister("ClothForces", ClothLog.classid, &ClothLog.forces));
  PetscCall(PetscLogEventRegister("ClothJacobian", ClothLog.classid, &ClothLog.jacobian));
  PetscCall(PetscLogEventRegister("ClothSolve", ClothLog.classid, &ClothLog.solve));
  PetscCall(PetscLogEventRegister("ClothOutput", ClothLog.classid, &ClothLog.output));
  PetscCall(PetscLogEventRegister("ClothCheckpoint", ClothLog.classid, &ClothLog.checkpoint));
  PetscCall(PetscLogEventRegister("ClothCollision", ClothLog.classid, &ClothLog.collision));
  PetscCall(PetscLogEventRegister("ClothCollisionGrid", ClothLog.classid, &ClothLog.collision_grid));
  PetscCall(PetscLogEventRegister("ClothSelfCollision", ClothLog.classid, &ClothLog.self_collision));
  PetscCall(PetscLogEventRegister("ClothCheckpointRead", ClothLog.classid, &ClothLog.checkpoint_read));
  PetscCall(PetscLogStageRegister("Setup", &ClothLog.stage_setup));
  PetscCall(PetscLogStageRegister("Time steps", &ClothLog.stage_steps));
  PetscCall(PetscLogStageRegister("Setup: scene", &ClothLog.stage_scene));
  PetscCall(PetscLogStageRegister("Setup: meshing", &ClothLog.stage_meshing));
  PetscCall(PetscLogStageRegister("Setup: graph", &ClothLog.stage_graph));
  PetscCall(PetscLogStageRegister("Setup: partition", &ClothLog.stage_partition));
  PetscCall(PetscLogStageRegister("Setup: distribute", &ClothLog.stage_distribute));
  PetscCall(PetscLogStageRegister("Setup: bodies", &ClothLog.stage_bodies));
  PetscCall(PetscLogStageRegister("Setup: matrix", &ClothLog.stage_matrix));
  PetscCall(PetscLogStageRegister("Setup: output", &ClothLog.stage_output));
  PetscFunctionReturn(PETSC_SUCCESS);
}
