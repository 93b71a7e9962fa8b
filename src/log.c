/* The events and stages of clothsim (see log.h). */
#include "log.h"
#include "util.h"

ClothLogEvents ClothLog;

static PetscBool registered = PETSC_FALSE;

static const char *const phase_names[CLOTH_SETUP_PHASES] = {"scene", "meshing", "graph", "partition", "distribute", "bodies", "matrix", "output"};

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
  PetscCall(PetscLogEventRegister("ClothSelfBuild", ClothLog.classid, &ClothLog.self_build));
  PetscCall(PetscLogEventRegister("ClothSelfFilter", ClothLog.classid, &ClothLog.self_filter));
  PetscCall(PetscLogEventRegister("ClothSelfCoupling", ClothLog.classid, &ClothLog.self_coupling));
  PetscCall(PetscLogEventRegister("ClothSelfForces", ClothLog.classid, &ClothLog.self_forces));
  PetscCall(PetscLogEventRegister("ClothSelfImpulses", ClothLog.classid, &ClothLog.self_impulses));
  PetscCall(PetscLogEventRegister("ClothProjectPSD", ClothLog.classid, &ClothLog.project_psd));
  PetscCall(PetscLogEventRegister("ClothCheckpointRead", ClothLog.classid, &ClothLog.checkpoint_read));
  PetscCall(PetscLogEventRegister("ClothBlockPtAPSym", ClothLog.classid, &ClothLog.block_ptap_symbolic));
  PetscCall(PetscLogEventRegister("ClothBlockPtAPNum", ClothLog.classid, &ClothLog.block_ptap_numeric));
  PetscCall(PetscLogStageRegister("Setup", &ClothLog.stage_setup));
  PetscCall(PetscLogStageRegister("Time steps", &ClothLog.stage_steps));
  for (PetscInt p = 0; p < CLOTH_SETUP_PHASES; p++) {
    char stage[64], event[64];

    PetscCall(PetscSNPrintf(stage, sizeof(stage), "Setup: %s", phase_names[p]));
    PetscCall(PetscSNPrintf(event, sizeof(event), "SetUp_%s", phase_names[p]));
    PetscCall(PetscLogStageRegister(stage, &ClothLog.stage_phase[p]));
    PetscCall(PetscLogEventRegister(event, ClothLog.classid, &ClothLog.event_phase[p]));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothLogPhaseBegin(ClothSetUpPhase phase)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(ClothLog.stage_phase[phase]));
  PetscCall(PetscLogEventBegin(ClothLog.event_phase[phase], 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothLogPhaseEnd(ClothSetUpPhase phase)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventEnd(ClothLog.event_phase[phase], 0, 0, 0, 0));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(PETSC_SUCCESS);
}
