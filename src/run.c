/* ClothRun (see run.h). */
#include <signal.h>
#include "run.h"
#include "output.h"
#include "checkpoint.h"
#include "log.h"

struct _n_ClothRun {
  MPI_Comm        comm;
  Scene           scene;
  Cloth           cloth;
  ClothIntegrator integrator;
  ClothOutput     output;

  PetscReal       dt, t_final;
  PetscInt        steps;           /* total steps of the run (from -steps or t_final / dt) */
  PetscInt        step;            /* steps taken so far (continues from a restart) */
  PetscReal       time;
  char            output_dir[CLOTH_PATH_LEN];
  PetscInt        output_every, checkpoint_every, checkpoint_keep;
  char            restart[CLOTH_PATH_LEN];
  PetscReal       progress_seconds;
  PetscBool       monitor_energy;

  Vec             natural_position, natural_velocity;
  char            last_checkpoint[CLOTH_PATH_LEN];
  PetscInt        krylov_total, substeps_total;
};

/* Set by SIGTERM / SIGUSR1 (what batch schedulers send before a time limit). */
static volatile sig_atomic_t termination_requested = 0;

static void RequestTermination(int signum)
{
  (void)signum;
  termination_requested = 1;
}

static double WallTime(void)
{
  return MPI_Wtime();
}

PetscErrorCode ClothRunCreate(MPI_Comm comm, Scene scene, ClothRun *run)
{
  ClothRun r;

  PetscFunctionBeginUser;
  PetscCall(ClothLogRegister());
  PetscCall(PetscNew(&r));
  r->comm             = comm;
  r->scene            = scene;
  r->dt               = scene->run.dt > 0 ? scene->run.dt : 1.0 / 240.0;
  r->t_final          = scene->run.t_final > 0 ? scene->run.t_final : 1.0;
  r->steps            = scene->run.steps;
  r->output_every     = scene->run.output_every > 0 ? scene->run.output_every : 10;
  r->checkpoint_every = scene->run.checkpoint_every;
  r->checkpoint_keep  = 2;
  r->progress_seconds = 2.0;
  PetscCall(PetscSNPrintf(r->output_dir, sizeof(r->output_dir), "output/%s", scene->name));
  PetscCall(ClothCreate(comm, scene, &r->cloth));
  PetscCall(ClothIntegratorCreate(r->cloth, &r->integrator));
  if (scene->run.integrator[0]) PetscCall(ClothIntegratorSetType(r->integrator, scene->run.integrator));
  *run = r;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunSetFromOptions(ClothRun run)
{
  PetscInt  grid = 0;
  PetscBool set_steps, set_tfinal, set_grid;

  PetscFunctionBeginUser;
  PetscOptionsBegin(run->comm, NULL, "Run (how the scene is simulated)", "ClothRun");
  PetscCall(PetscOptionsInt("-grid", "Particles per side of a scene made of one rectangular piece", "SceneSetGridSize", grid, &grid, &set_grid));
  PetscCall(PetscOptionsReal("-dt", "Time step, s", "ClothRunSolve", run->dt, &run->dt, NULL));
  PetscCall(PetscOptionsReal("-t_final", "Simulated time to reach, s", "ClothRunSolve", run->t_final, &run->t_final, &set_tfinal));
  PetscCall(PetscOptionsInt("-steps", "Number of steps (instead of -t_final)", "ClothRunSolve", run->steps, &run->steps, &set_steps));
  PetscCall(PetscOptionsString("-output_dir", "Directory for the XDMF series and checkpoints", "ClothRunSetUp", run->output_dir, run->output_dir, sizeof(run->output_dir), NULL));
  PetscCall(PetscOptionsInt("-output_every", "Write an XDMF frame every K steps (0: only the first and last)", "ClothRunSolve", run->output_every, &run->output_every, NULL));
  PetscCall(PetscOptionsInt("-checkpoint_every", "Write a checkpoint every K steps (0: only at the end)", "ClothRunSolve", run->checkpoint_every, &run->checkpoint_every, NULL));
  PetscCall(PetscOptionsInt("-checkpoint_keep", "Keep only the newest N checkpoints (0: keep all)", "ClothCheckpointWrite", run->checkpoint_keep, &run->checkpoint_keep, NULL));
  PetscCall(PetscOptionsString("-restart", "Continue from this checkpoint (any number of ranks)", "ClothRunSetUp", run->restart, run->restart, sizeof(run->restart), NULL));
  PetscCall(PetscOptionsReal("-progress_seconds", "Wall seconds between progress lines (0: every step)", "ClothRunSolve", run->progress_seconds, &run->progress_seconds, NULL));
  PetscCall(PetscOptionsBool("-monitor_energy", "Print kinetic, gravitational and elastic energy with every frame", "ClothRunSolve", run->monitor_energy, &run->monitor_energy, NULL));
  PetscOptionsEnd();
  PetscCheck(run->dt > 0, run->comm, PETSC_ERR_USER_INPUT, "-dt must be positive, got %g", (double)run->dt);
  PetscCheck(run->steps >= 0 && run->output_every >= 0 && run->checkpoint_every >= 0, run->comm, PETSC_ERR_USER_INPUT, "-steps, -output_every and -checkpoint_every must not be negative");
  if (set_grid) {
    PetscCheck(grid >= 2, run->comm, PETSC_ERR_USER_INPUT, "-grid must be at least 2, got %" PetscInt_FMT, grid);
    PetscCall(SceneSetGridSize(run->scene, grid));
  }
  if (set_tfinal && !set_steps) run->steps = 0;
  if (run->steps == 0) {
    PetscCheck(run->t_final > 0, run->comm, PETSC_ERR_USER_INPUT, "-t_final must be positive, got %g", (double)run->t_final);
    run->steps = (PetscInt)PetscFloorReal(run->t_final / run->dt + 0.5);
  }
  PetscCall(ClothSetFromOptions(run->cloth));
  PetscCall(ClothIntegratorSetFromOptions(run->integrator));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunFillCheckpointInfo(ClothRun run, ClothCheckpointInfo *info)
{
  const char *type;
  PetscInt    nglobal;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(info, sizeof(*info)));
  PetscCall(ClothIntegratorGetType(run->integrator, &type));
  PetscCall(ClothGetSizes(run->cloth, NULL, &nglobal));
  info->step              = run->step;
  info->time              = run->time;
  info->dt                = run->dt;
  info->scene_fingerprint = run->scene->fingerprint;
  info->nparticles        = nglobal;
  PetscCall(PetscStrncpy(info->integrator, type, sizeof(info->integrator)));
  PetscCall(PetscStrncpy(info->scene_name, run->scene->name, sizeof(info->scene_name)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunRestore(ClothRun run)
{
  ClothCheckpointInfo expect, info;
  Vec                 x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothRunFillCheckpointInfo(run, &expect));
  PetscCall(ClothCheckpointRead(run->comm, run->restart, &expect, &info, run->natural_position, run->natural_velocity));
  PetscCall(ClothGetState(run->cloth, &x, &v));
  PetscCall(ClothScatterToNatural(run->cloth, x, run->natural_position, SCATTER_REVERSE));
  PetscCall(ClothScatterToNatural(run->cloth, v, run->natural_velocity, SCATTER_REVERSE));
  run->step = (PetscInt)info.step;
  run->time = info.time;
  PetscCall(PetscPrintf(run->comm, "Restarting from %s: step %" PetscInt_FMT ", t = %.6f s (written by integrator %s)\n", run->restart, run->step, (double)run->time, info.integrator));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunOpenOutput(ClothRun run)
{
  ClothModel          model;
  ClothOutputTopology topo;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(run->cloth, &model));
  topo.nparticles = model->nparticles;
  topo.nquads     = model->nquads;
  topo.quads      = model->quads;
  PetscCall(ClothOutputCreate(run->comm, run->output_dir, run->scene->name, &topo, run->restart[0] ? run->time : -1.0, &run->output));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunSetUp(ClothRun run)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(ClothLog.stage_setup));
  PetscCall(ClothSetUp(run->cloth));
  PetscCall(ClothIntegratorSetUp(run->integrator));
  PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_position));
  PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_velocity));
  PetscCall(PetscObjectSetName((PetscObject)run->natural_position, "position"));
  PetscCall(PetscObjectSetName((PetscObject)run->natural_velocity, "velocity"));
  if (run->restart[0]) PetscCall(ClothRunRestore(run));
  PetscCall(ClothRunOpenOutput(run));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunGatherNatural(ClothRun run)
{
  Vec x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(run->cloth, &x, &v));
  PetscCall(ClothScatterToNatural(run->cloth, x, run->natural_position, SCATTER_FORWARD));
  PetscCall(ClothScatterToNatural(run->cloth, v, run->natural_velocity, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunWriteFrame(ClothRun run)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.output, 0, 0, 0, 0));
  PetscCall(ClothRunGatherNatural(run));
  PetscCall(ClothOutputWriteFrame(run->output, run->step, run->time, run->natural_position, run->natural_velocity));
  PetscCall(PetscLogEventEnd(ClothLog.output, 0, 0, 0, 0));
  if (run->monitor_energy) {
    ClothEnergy e;
    Vec         x, v;
    PetscCall(ClothGetState(run->cloth, &x, &v));
    PetscCall(ClothComputeEnergy(run->cloth, x, v, &e));
    PetscCall(PetscPrintf(run->comm, "  energy at step %" PetscInt_FMT ": kinetic %.9e J, gravity %.9e J, elastic %.9e J, total %.9e J\n", run->step, (double)e.kinetic, (double)e.gravity, (double)e.elastic, (double)(e.kinetic + e.gravity + e.elastic)));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunWriteCheckpoint(ClothRun run)
{
  ClothCheckpointInfo info;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.checkpoint, 0, 0, 0, 0));
  PetscCall(ClothRunGatherNatural(run));
  PetscCall(ClothRunFillCheckpointInfo(run, &info));
  PetscCall(ClothCheckpointWrite(run->comm, run->output_dir, &info, run->natural_position, run->natural_velocity, run->checkpoint_keep, run->last_checkpoint, sizeof(run->last_checkpoint)));
  PetscCall(PetscLogEventEnd(ClothLog.checkpoint, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunProgress(ClothRun run, PetscInt first_step, double start, const ClothStepStats *stats)
{
  const double wall = WallTime() - start, per_step = wall / (double)(run->step - first_step);

  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(run->comm, "step %6" PetscInt_FMT "/%" PetscInt_FMT "  t = %.5f s  wall %.2f s  KSP its %" PetscInt_FMT "%s  ETA %.1f s\n", run->step, run->steps, (double)run->time, wall, stats->krylov_iterations, stats->substeps > 1 ? " (step reduced)" : "", per_step * (double)(run->steps - run->step)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Has any rank received a termination signal? Collective. */
static PetscErrorCode TerminationRequested(MPI_Comm comm, PetscBool *requested)
{
  int local = termination_requested ? 1 : 0, global;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm));
  *requested = global ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunSolve(ClothRun run)
{
  const PetscInt first_step = run->step;
  const double   start      = WallTime();
  double         last_print = start;
  PetscBool      ok = PETSC_TRUE, stop = PETSC_FALSE;
  ClothStepStats stats = {0, 0, run->dt};

  PetscFunctionBeginUser;
  signal(SIGTERM, RequestTermination);
  signal(SIGUSR1, RequestTermination);
  PetscCall(PetscPrintf(run->comm, "Running %s: %" PetscInt_FMT " steps of %g s from step %" PetscInt_FMT "; output in %s\n", run->scene->name, run->steps, (double)run->dt, run->step, run->output_dir));
  if (!run->restart[0]) PetscCall(ClothRunWriteFrame(run));
  PetscCall(PetscLogStagePush(ClothLog.stage_steps));
  while (run->step < run->steps && !stop) {
    PetscCall(ClothIntegratorStep(run->integrator, run->dt, &ok, &stats));
    if (!ok) break;
    run->step++;
    run->time = run->dt * run->step;
    run->krylov_total += stats.krylov_iterations;
    run->substeps_total += stats.substeps;
    if ((run->output_every > 0 && run->step % run->output_every == 0) || run->step == run->steps) PetscCall(ClothRunWriteFrame(run));
    if (run->checkpoint_every > 0 && run->step % run->checkpoint_every == 0 && run->step < run->steps) PetscCall(ClothRunWriteCheckpoint(run));
    if (run->progress_seconds <= 0 || WallTime() - last_print >= run->progress_seconds || run->step == run->steps) {
      PetscCall(ClothRunProgress(run, first_step, start, &stats));
      last_print = WallTime();
    }
    PetscCall(TerminationRequested(run->comm, &stop));
  }
  PetscCall(PetscLogStagePop());
  PetscCall(ClothRunWriteCheckpoint(run));
  PetscCheck(ok, run->comm, PETSC_ERR_NOT_CONVERGED, "Step %" PetscInt_FMT " failed (Krylov solver diverged or the state became non-finite) even after halving the step down to %g s; the last good state (step %" PetscInt_FMT ") is in %s", run->step + 1, (double)stats.smallest_dt, run->step, run->last_checkpoint);
  if (stop) PetscCall(PetscPrintf(run->comm, "Stopped by a termination signal at step %" PetscInt_FMT "; checkpoint %s\n", run->step, run->last_checkpoint));
  PetscCall(PetscPrintf(run->comm, "Done: %" PetscInt_FMT " steps (%" PetscInt_FMT " sub-steps), %" PetscInt_FMT " Krylov iterations, %.2f s wall. Results: %s/%s.xdmf (open in ParaView), checkpoint %s\n", run->step - first_step, run->substeps_total, run->krylov_total, WallTime() - start, run->output_dir, run->scene->name, run->last_checkpoint));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunGetCloth(ClothRun run, Cloth *cloth)
{
  PetscFunctionBeginUser;
  *cloth = run->cloth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunGetStep(ClothRun run, PetscInt *step, PetscReal *time)
{
  PetscFunctionBeginUser;
  if (step) *step = run->step;
  if (time) *time = run->time;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunDestroy(ClothRun *run)
{
  ClothRun r = *run;

  PetscFunctionBeginUser;
  if (!r) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothOutputDestroy(&r->output));
  PetscCall(ClothIntegratorDestroy(&r->integrator));
  PetscCall(ClothDestroy(&r->cloth));
  PetscCall(VecDestroy(&r->natural_position));
  PetscCall(VecDestroy(&r->natural_velocity));
  PetscCall(PetscFree(*run));
  PetscFunctionReturn(PETSC_SUCCESS);
}
