/* ClothRun (see run.h). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <time.h>
#include <unistd.h>
#include "run.h"
#include "output.h"
#include "checkpoint.h"
#include "selfcontact.h"
#include "sewing.h"
#include "quality.h"
#include "log.h"
#include "options.h"
#include "fileutil.h"
#include "h5util.h"
#include "watchdog.h"

struct _n_ClothRun {
  MPI_Comm         comm;
  Scene            scene;
  Cloth            cloth;
  ClothIntegrator  integrator;
  ClothCollision   collision; /* NULL when the scene has no bodies */
  ClothOutput      output;
  ClothSelfContact self_contact; /* cloth-cloth collisions; attached to the cloth only when enabled */
  ClothSewing      sewing;       /* garment assembly phases; NULL when the scene has no seams */

  PetscReal dt, t_final;
  PetscInt  steps; /* total steps of the run (from -steps or t_final / dt) */
  PetscInt  step;  /* steps taken so far (continues from a restart) */
  PetscReal time;
  PetscInt  dt_start_step;     /* step and time at which dt came into use (0, 0 unless a restart */
  PetscReal dt_start_time;     /* changed dt): time = dt_start_time + dt (step - dt_start_step) */
  PetscBool dt_set;            /* -dt given: it overrides the step of a restart's checkpoint */
  PetscBool steps_set;         /* -steps given (for messages: what set the end of the run) */
  PetscBool t_final_set;       /* -t_final given */
  PetscBool restart_any_scene; /* -restart_any_scene: accept a checkpoint of another scene (same particle count) */
  PetscBool output_overwrite;  /* -output_overwrite: a new run may replace the results in output_dir */
  int       output_lock;       /* rank 0: the lock on output_dir (fileutil.h); -1 elsewhere */
  uint64_t  run_id;            /* this run's identity in its checkpoints; a restart continues its checkpoint's */
  char      output_dir[CLOTH_PATH_LEN];
  PetscInt  output_every, checkpoint_every, checkpoint_keep;
  PetscReal xdmf_seconds; /* -output_xdmf_seconds */
  char      restart[CLOTH_PATH_LEN];
  PetscReal progress_seconds;
  PetscBool monitor_energy;
  PetscBool help;         /* -help: set up (listing every option), then stop without claiming the output or stepping */
  PetscReal gravity_ramp; /* s over which gravity rises from 0 to full (0: full from the start) */

  Vec      natural_position, natural_velocity, natural_dv; /* natural_dv: the implicit warm start */
  Vec      natural_strain;                                 /* one value per particle, for frames */
  Vec      natural_body_contact, natural_self_contact;     /* contact fields of frames (output.h); zero when off */
  Vec      natural_stress, natural_pressure;               /* fit maps of frames (output.h) */
  char     last_checkpoint[CLOTH_PATH_LEN];
  PetscInt krylov_total, substeps_total;

  Vec       natural_history[2]; /* bdf2's history (rate, velocity) for checkpoints; NULL until a checkpoint needs them */
  PetscReal history_dt;         /* read from the restart's checkpoint: the step of its history (0: none) */
};

/* The signal received, SIGTERM or SIGUSR1 (what batch schedulers send before a time limit); 0: none. */
static volatile sig_atomic_t termination_requested = 0;

static void RequestTermination(int signum)
{
  termination_requested = signum;
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
  /* From here on (replacing PETSc's handlers, which abort) a termination signal, even during set-up,
     stops the run after its next step with a checkpoint. */
  signal(SIGTERM, RequestTermination);
  signal(SIGUSR1, RequestTermination);
  PetscCall(PetscNew(&r));
  r->comm             = comm;
  r->scene            = scene;
  r->dt               = scene->run.dt > 0 ? scene->run.dt : 1.0 / 240.0;
  r->t_final          = scene->run.t_final > 0 ? scene->run.t_final : 1.0;
  r->steps            = scene->run.steps;
  r->output_every     = scene->run.output_every > 0 ? scene->run.output_every : 10;
  r->xdmf_seconds     = CLOTH_OUTPUT_XDMF_SECONDS;
  r->checkpoint_every = scene->run.checkpoint_every;
  r->checkpoint_keep  = 2;
  r->output_lock      = -1;
  r->progress_seconds = 2.0;
  PetscCall(PetscSNPrintf(r->output_dir, sizeof(r->output_dir), "output/%s", scene->name));
  PetscCall(ClothCreate(comm, scene, &r->cloth));
  PetscCall(ClothSetViewPartitionSummary(r->cloth, PETSC_TRUE)); /* users of a parallel run see how it was split */
  PetscCall(ClothIntegratorCreate(r->cloth, &r->integrator));
  PetscCall(ClothSelfContactCreate(r->cloth, &r->self_contact));
  if (scene->nbodies) {
    PetscCall(ClothCollisionCreate(r->cloth, scene, &r->collision));
    PetscCall(ClothIntegratorSetCollision(r->integrator, r->collision));
  }
  if (scene->run.integrator[0]) PetscCall(ClothIntegratorSetType(r->integrator, scene->run.integrator));
  *run = r;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The longest -output_dir: a path has at most CLOTH_PATH_LEN - 1 characters (PATH_MAX, 4096 with its NUL, on Linux),
   and 128 of them stay for "/" and the longest name a run writes in the directory (NAME.xdmf's temporary file, NAME
   of up to 63 characters; .checkpoint_NNNNNNNNNN.h5.tmp). */
#define CLOTH_RUN_OUTPUT_NAME_ROOM 128

/* Memory a particle costs, measured: the hanging sheet's peak memory grows by 2.4 kB per particle from 65 x 65 to
   257 x 257 (implicit integrator, 1 rank); contacts and self-collision add to it, so this is a lower bound. */
#define CLOTH_RUN_BYTES_PER_PARTICLE 2400.0

/* Refuses a scene whose particles cannot fit in the memory of the nodes before anything is allocated for them,
   naming the grids and the memory: without it, a huge grid ends in the allocator, a message that names neither.
   Each node needs its ranks' share; the node that lacks memory the most decides, for all ranks alike. */
static PetscErrorCode ClothRunCheckMemory(ClothRun run)
{
  MPI_Comm    node;
  PetscMPIInt size, node_ranks;
  PetscInt    n;
  double      need, have, shortfall;
  char        grids[256] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(run->comm, &size));
  PetscCallMPI(MPI_Comm_split_type(run->comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &node_ranks));
  PetscCallMPI(MPI_Comm_free(&node));
  PetscCall(SceneGetParticleCount(run->scene, &n));
  need      = CLOTH_RUN_BYTES_PER_PARTICLE * (double)n / size * node_ranks;
  have      = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
  shortfall = have > 0 ? need / have : 0; /* 0: the memory size is unknown here */
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &shortfall, 1, MPI_DOUBLE, MPI_MAX, run->comm));
  if (shortfall <= 1) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt p = 0; p < run->scene->npieces && p < 4; p++) {
    char piece[96];

    PetscCall(PetscSNPrintf(piece, sizeof(piece), "%s'%s' %" PetscInt_FMT " x %" PetscInt_FMT, p ? ", " : "", run->scene->pieces[p].name, run->scene->pieces[p].nu, run->scene->pieces[p].nv));
    PetscCall(PetscStrlcat(grids, piece, sizeof(grids)));
  }
  if (run->scene->npieces > 4) PetscCall(PetscStrlcat(grids, ", ...", sizeof(grids)));
  SETERRQ(run->comm, PETSC_ERR_USER_INPUT,
          "scene %s: the grids (%s) give %" PetscInt_FMT " particles, which need about %.3g GB of memory on a node (%.1f kB per particle, %d of %d ranks on it), %.3g times the %.3g GB it has: expected fewer particles or more nodes", run->scene->path,
          grids, n, need / 1e9, CLOTH_RUN_BYTES_PER_PARTICLE / 1e3, node_ranks, size, shortfall, have / 1e9);
}

PetscErrorCode ClothRunSetFromOptions(ClothRun run)
{
  PetscReal io_timeout = CLOTH_IO_TIMEOUT_DEFAULT;
  PetscInt  grid       = 0;
  PetscBool set_grid;
  char      why[128];

  PetscFunctionBeginUser;
  /* counts beyond a PetscInt, which PETSc's parser would wrap */
  PetscCall(ClothOptionsCheckIntText(run->comm, "-steps", 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckIntText(run->comm, "-output_every", 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckIntText(run->comm, "-checkpoint_every", 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckIntText(run->comm, "-checkpoint_keep", 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckIntText(run->comm, "-grid", 2, PETSC_MAX_INT));
  /* paths beyond the buffers, which PETSc would cut */
  PetscCall(PetscSNPrintf(why, sizeof(why), "the names of the files in it need %d more of the %d characters a path may have", CLOTH_RUN_OUTPUT_NAME_ROOM, CLOTH_PATH_LEN - 1));
  PetscCall(ClothOptionsCheckStringLength(run->comm, "-output_dir", CLOTH_PATH_LEN - 1 - CLOTH_RUN_OUTPUT_NAME_ROOM, why));
  PetscCall(ClothOptionsCheckStringLength(run->comm, "-restart", CLOTH_PATH_LEN - 1, NULL));
  PetscOptionsBegin(run->comm, NULL, "Run (how the scene is simulated)", "ClothRun");
  PetscCall(PetscOptionsInt("-grid", "Particles per side of a scene made of one rectangular piece", "SceneSetGridSize", grid, &grid, &set_grid));
  PetscCall(PetscOptionsReal("-dt", "Time step, s (default on -restart: the checkpoint's)", "ClothRunSolve", run->dt, &run->dt, &run->dt_set));
  PetscCall(PetscOptionsReal("-t_final", "Simulated time to reach, s", "ClothRunSolve", run->t_final, &run->t_final, &run->t_final_set));
  PetscCall(PetscOptionsInt("-steps", "Number of steps (instead of -t_final)", "ClothRunSolve", run->steps, &run->steps, &run->steps_set));
  PetscCall(PetscOptionsString("-output_dir", "Directory for the XDMF series and checkpoints", "ClothRunSetUp", run->output_dir, run->output_dir, sizeof(run->output_dir), NULL));
  PetscCall(PetscOptionsBool("-output_overwrite", "A new run may replace the results already in -output_dir (otherwise refused; -restart continues them)", "ClothRunSetUp", run->output_overwrite, &run->output_overwrite, NULL));
  PetscCall(PetscOptionsInt("-output_every", "Write an XDMF frame every K steps (0: only the first and last)", "ClothRunSolve", run->output_every, &run->output_every, NULL));
  PetscCall(PetscOptionsReal("-output_xdmf_seconds", "Wall seconds between rewrites of NAME.xdmf, the frames' list (0: after every frame); also rewritten at every checkpoint and at the end; each frame's data reach NAME.h5 at once",
                             "ClothOutputSetXdmfInterval", run->xdmf_seconds, &run->xdmf_seconds, NULL));
  PetscCall(PetscOptionsInt("-checkpoint_every", "Write a checkpoint every K steps (0: only at the end)", "ClothRunSolve", run->checkpoint_every, &run->checkpoint_every, NULL));
  PetscCall(PetscOptionsInt("-checkpoint_keep", "Keep only the newest N checkpoints of this run (0: keep all)", "ClothCheckpointWrite", run->checkpoint_keep, &run->checkpoint_keep, NULL));
  PetscCall(PetscOptionsString("-restart", "Continue from this checkpoint (any number of ranks)", "ClothRunSetUp", run->restart, run->restart, sizeof(run->restart), NULL));
  PetscCall(PetscOptionsBool("-restart_any_scene", "Continue from a checkpoint of another scene (one edited on purpose) with the same particle count", "ClothRunSetUp", run->restart_any_scene, &run->restart_any_scene, NULL));
  PetscCall(PetscOptionsReal("-progress_seconds", "Wall seconds between progress lines (0: every step)", "ClothRunSolve", run->progress_seconds, &run->progress_seconds, NULL));
  PetscCall(PetscOptionsReal("-gravity_ramp", "Seconds over which gravity rises linearly from 0 to its full value (0: full from the start)", "ClothRunSolve", run->gravity_ramp, &run->gravity_ramp, NULL));
  PetscCall(PetscOptionsReal("-io_timeout", "Seconds a frame or checkpoint write may take before the run is stopped (exit status 3) as hung (0: no limit)", "ClothWatchdogArm", io_timeout, &io_timeout, NULL));
  PetscCall(PetscOptionsBool("-monitor_energy", "Print kinetic, gravitational and elastic energy with every frame", "ClothRunSolve", run->monitor_energy, &run->monitor_energy, NULL));
  PetscOptionsEnd();
  PetscCall(PetscOptionsHasHelp(NULL, &run->help));
  PetscCall(ClothOptionsCheckReal(run->comm, "-dt", run->dt, 0, PETSC_TRUE, PETSC_MAX_REAL, "s"));
  PetscCall(ClothOptionsCheckReal(run->comm, "-gravity_ramp", run->gravity_ramp, 0, PETSC_FALSE, PETSC_MAX_REAL, "s"));
  PetscCall(ClothOptionsCheckReal(run->comm, "-progress_seconds", run->progress_seconds, 0, PETSC_FALSE, PETSC_MAX_REAL, "s"));
  PetscCall(ClothOptionsCheckReal(run->comm, "-io_timeout", io_timeout, 0, PETSC_FALSE, 1e8, "s"));
  PetscCall(ClothOptionsCheckReal(run->comm, "-output_xdmf_seconds", run->xdmf_seconds, 0, PETSC_FALSE, 1e8, "s"));
  PetscCall(ClothWatchdogSetTimeout(io_timeout));
  PetscCheck(!(run->gravity_ramp > 0 && run->scene->nseams > 0), run->comm, PETSC_ERR_USER_INPUT, "-gravity_ramp cannot be used with seams: the sewing phases switch gravity themselves");
  PetscCall(ClothOptionsCheckInt(run->comm, "-steps", run->steps, 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckInt(run->comm, "-output_every", run->output_every, 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckInt(run->comm, "-checkpoint_every", run->checkpoint_every, 0, PETSC_MAX_INT));
  PetscCall(ClothOptionsCheckInt(run->comm, "-checkpoint_keep", run->checkpoint_keep, 0, PETSC_MAX_INT));
  PetscCheck(run->output_dir[0], run->comm, PETSC_ERR_USER_INPUT, "option -output_dir '': expected a directory name (default output/%s)", run->scene->name);
  if (set_grid) {
    PetscCall(ClothOptionsCheckInt(run->comm, "-grid", grid, 2, PETSC_MAX_INT));
    PetscCall(SceneSetGridSize(run->scene, grid));
  }
  if (run->t_final_set && !run->steps_set) run->steps = 0;
  if (run->steps == 0) PetscCall(ClothOptionsCheckReal(run->comm, "-t_final", run->t_final, 0, PETSC_TRUE, PETSC_MAX_REAL, "s"));
  PetscCall(ClothRunCheckMemory(run));
  PetscCall(ClothSetFromOptions(run->cloth));
  PetscCall(ClothIntegratorSetFromOptions(run->integrator));
  PetscCall(ClothSelfContactSetFromOptions(run->self_contact));
  if (run->collision) PetscCall(ClothCollisionSetFromOptions(run->collision));
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
  info->dt_start_step     = run->dt_start_step;
  info->dt_start_time     = run->dt_start_time;
  info->scene_fingerprint = run->scene->fingerprint;
  info->nparticles        = nglobal;
  info->run_id            = run->run_id;
  info->scene             = run->scene;
  PetscCall(PetscStrncpy(info->integrator, type, sizeof(info->integrator)));
  PetscCall(PetscStrncpy(info->scene_name, run->scene->name, sizeof(info->scene_name)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* bdf2's history in checkpoints (integrator.h, ClothIntegratorGetHistory): a restart without it would take its first
   step as backward Euler where the uninterrupted run takes BDF2. write: gathers it for the next checkpoint (its fields
   are left out when there is none) and returns its step in *history_dt; !write (a restart, before the integrator is set
   up): only creates the natural Vecs the checkpoint's fields are read into. */
static PetscErrorCode ClothRunHistoryCheckpoint(ClothRun run, PetscBool write, PetscReal *history_dt)
{
  Vec rate = NULL, velocity = NULL;

  PetscFunctionBeginUser;
  if (history_dt) *history_dt = 0;
  if (write) PetscCall(ClothIntegratorGetHistory(run->integrator, &rate, &velocity, history_dt));
  if (write && (!rate || *history_dt == 0)) {
    for (PetscInt k = 0; k < 2; k++) PetscCall(VecDestroy(&run->natural_history[k]));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (PetscInt k = 0; k < 2; k++)
    if (!run->natural_history[k]) PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_history[k]));
  if (write) {
    PetscCall(ClothScatterToNatural(run->cloth, rate, run->natural_history[0], SCATTER_FORWARD));
    PetscCall(ClothScatterToNatural(run->cloth, velocity, run->natural_history[1], SCATTER_FORWARD));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The checkpoint fields (natural order). The run's own: position, velocity, the implicit integrator's warm start
   (without which a restarted run's first Krylov solves would start from zero and differ from an uninterrupted run's
   at the solver tolerance; left out with with_dv false) and, last, bdf2's history when the run keeps one
   (ClothRunHistoryCheckpoint). Between them the state of the cloth's contributions, which each declares itself
   (cloth.h, checkpoint_fields: hysteresis sliders, held body contacts, sewn seams), so that the run needs no change
   for a new one: *ncontributed fields from fields[*first] on, lent (give them back with
   ClothRestoreCheckpointFields). */
#define CLOTH_RUN_OWN_FIELDS 5
#define CLOTH_RUN_FIELDS_CAPACITY (CLOTH_RUN_OWN_FIELDS + CLOTH_MAX_CONTRIBUTIONS * CLOTH_CONTRIBUTION_MAX_FIELDS)
static PetscErrorCode ClothRunCheckpointFields(ClothRun run, PetscBool write, PetscBool with_dv, ClothCheckpointField fields[CLOTH_RUN_FIELDS_CAPACITY], PetscInt *nfields, PetscInt *first, PetscInt *ncontributed)
{
  PetscInt n = 0;

  PetscFunctionBeginUser;
  fields[n++] = (ClothCheckpointField){"position", run->natural_position, PETSC_TRUE, PETSC_FALSE};
  fields[n++] = (ClothCheckpointField){"velocity", run->natural_velocity, PETSC_TRUE, PETSC_FALSE};
  if (with_dv) fields[n++] = (ClothCheckpointField){"implicit_dv", run->natural_dv, PETSC_FALSE, PETSC_FALSE};
  *first = n;
  PetscCall(ClothGetCheckpointFields(run->cloth, write, CLOTH_RUN_FIELDS_CAPACITY - n - 2, &fields[n], ncontributed));
  n += *ncontributed;
  if (run->natural_history[0]) {
    fields[n++] = (ClothCheckpointField){"bdf2_history_rate", run->natural_history[0], PETSC_FALSE, PETSC_FALSE};
    fields[n++] = (ClothCheckpointField){"bdf2_history_velocity", run->natural_history[1], PETSC_FALSE, PETSC_FALSE};
  }
  *nfields = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether the file read held the field of this name. */
static PetscErrorCode ClothRunCheckpointFieldFound(PetscInt nfields, const ClothCheckpointField fields[], const char name[], PetscBool *found)
{
  const ClothCheckpointField *field;

  PetscFunctionBeginUser;
  PetscCall(ClothCheckpointFieldFind(nfields, fields, name, &field));
  *found = field && field->found ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The step and integrator of a restart: the checkpoint's, unless -dt / -integrator say otherwise, in
   which case the continued run cannot be the same as an uninterrupted one, and the user is told. */
static PetscErrorCode ClothRunAdoptCheckpointSettings(ClothRun run, const ClothCheckpointInfo *info)
{
  const char *type;
  PetscBool   integrator_set, same_type;

  PetscFunctionBeginUser;
  if (!run->dt_set) run->dt = info->dt;
  if (run->dt == info->dt) {
    run->dt_start_step = (PetscInt)info->dt_start_step;
    run->dt_start_time = info->dt_start_time;
  } else {
    run->dt_start_step = run->step;
    run->dt_start_time = run->time;
    PetscCall(PetscFPrintf(run->comm, PETSC_STDERR, "WARNING: -dt %g differs from the step %g of checkpoint %s: the run continues with -dt from t = %.6f s\n", (double)run->dt, (double)info->dt, run->restart, (double)run->time));
  }
  PetscCall(PetscOptionsHasName(NULL, NULL, "-integrator", &integrator_set));
  PetscCall(ClothIntegratorGetType(run->integrator, &type));
  PetscCall(PetscStrcmp(type, info->integrator, &same_type));
  if (!same_type && !integrator_set)
    PetscCall(ClothIntegratorSetType(run->integrator, info->integrator));
  else if (!same_type)
    PetscCall(PetscFPrintf(run->comm, PETSC_STDERR, "WARNING: -integrator %s differs from the integrator %s of checkpoint %s: the run continues with %s, so it will not match an uninterrupted run\n", type, info->integrator, run->restart, type));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads the checkpoint of -restart: the state and the run's position in time. The integrator is not
   set up yet, so that it can take the checkpoint's type; its warm start follows in ClothRunRestoreWarmStart. */
static PetscErrorCode ClothRunRestore(ClothRun run)
{
  ClothCheckpointInfo  expect, info;
  ClothCheckpointField fields[CLOTH_RUN_FIELDS_CAPACITY];
  PetscInt             nfields, first, ncontributed;
  PetscBool            dv_found = PETSC_FALSE, rate_found = PETSC_FALSE, velocity_found = PETSC_FALSE;
  Vec                  x, v;

  PetscFunctionBeginUser;
  PetscCall(ClothRunFillCheckpointInfo(run, &expect));
  PetscCall(ClothRunHistoryCheckpoint(run, PETSC_FALSE, NULL));
  PetscCall(ClothRunCheckpointFields(run, PETSC_FALSE, PETSC_TRUE, fields, &nfields, &first, &ncontributed));
  PetscCall(PetscLogEventBegin(ClothLog.checkpoint_read, 0, 0, 0, 0));
  PetscCall(ClothCheckpointRead(run->comm, run->restart, run->restart_any_scene ? NULL : &expect, &info, nfields, fields));
  if (info.scene_fingerprint != expect.scene_fingerprint)
    PetscCall(PetscFPrintf(run->comm, PETSC_STDERR, "WARNING: checkpoint %s was written for scene '%s' of another fingerprint; continuing with this scene '%s' (-restart_any_scene)\n", run->restart, info.scene_name, run->scene->name));
  PetscCall(PetscLogEventEnd(ClothLog.checkpoint_read, 0, 0, 0, 0));
  PetscCall(ClothGetState(run->cloth, &x, &v));
  PetscCall(ClothScatterToNatural(run->cloth, x, run->natural_position, SCATTER_REVERSE));
  PetscCall(ClothScatterToNatural(run->cloth, v, run->natural_velocity, SCATTER_REVERSE));
  PetscCall(ClothRunCheckpointFieldFound(nfields, fields, "implicit_dv", &dv_found));
  if (!dv_found) PetscCall(VecZeroEntries(run->natural_dv));                             /* written by another integrator: no warm start */
  PetscCall(ClothLoadCheckpointFields(run->cloth, &info, ncontributed, &fields[first])); /* contacts, seams, sliders */
  PetscCall(ClothRestoreCheckpointFields(run->cloth, ncontributed, &fields[first]));
  run->step = (PetscInt)info.step;
  run->time = info.time;
  if (info.run_id) run->run_id = info.run_id; /* the same run continues: its pruning covers its earlier checkpoints */
  PetscCall(ClothRunCheckpointFieldFound(nfields, fields, "bdf2_history_rate", &rate_found));
  PetscCall(ClothRunCheckpointFieldFound(nfields, fields, "bdf2_history_velocity", &velocity_found));
  run->history_dt = rate_found && velocity_found ? info.history_dt : 0;
  PetscCall(ClothRunAdoptCheckpointSettings(run, &info));
  PetscCall(PetscPrintf(run->comm, "Restarting from %s: step %" PetscInt_FMT ", t = %.6f s, dt = %g s (written by integrator %s, %s)\n", run->restart, run->step, (double)run->time, (double)info.dt, info.integrator,
                        dv_found ? "with its warm start" : "without a warm start"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The implicit integrator's warm start from the checkpoint (zero when the checkpoint had none), and bdf2's history. */
static PetscErrorCode ClothRunRestoreWarmStart(ClothRun run)
{
  Vec dv;

  PetscFunctionBeginUser;
  PetscCall(ClothIntegratorGetWarmStart(run->integrator, &dv));
  if (dv) PetscCall(ClothScatterToNatural(run->cloth, dv, run->natural_dv, SCATTER_REVERSE));
  { /* and bdf2's history, when both the checkpoint and the integrator have one */
    Vec rate, velocity;

    PetscCall(ClothIntegratorGetHistory(run->integrator, &rate, &velocity, NULL));
    if (rate && run->history_dt > 0) {
      PetscCall(ClothScatterToNatural(run->cloth, rate, run->natural_history[0], SCATTER_REVERSE));
      PetscCall(ClothScatterToNatural(run->cloth, velocity, run->natural_history[1], SCATTER_REVERSE));
      PetscCall(ClothIntegratorSetHistoryStep(run->integrator, run->history_dt));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The last step of the run: -steps, or -t_final reached with the step in use (counted from where that
   step came into use, so that a restart with another -dt still ends at t_final). Counted in double: a
   count beyond PetscInt (-t_final 1e9 with a small step) is refused, as is a new run of no step at all
   (-dt longer than -t_final), which would otherwise end at once with exit status 0 like a finished run. */
static PetscErrorCode ClothRunStepsFromFinalTime(ClothRun run)
{
  double last;
  char   message[256] = "";

  PetscFunctionBeginUser;
  last = (double)run->dt_start_step + floor((double)(run->t_final - run->dt_start_time) / (double)run->dt + 0.5);
  /* snprintf, not PETSc's printf, whose %g writes 1e9 as "1e+09." */
  if (last > (double)PETSC_MAX_INT)
    snprintf(message, sizeof(message), "-t_final %g s with -dt %g s needs %.4g steps: expected at most %d steps (a larger -dt, a shorter -t_final, or a restart chain)", (double)run->t_final, (double)run->dt, last - (double)run->step,
             (int)PETSC_MAX_INT);
  else if (last < 1 && !run->restart[0])
    snprintf(message, sizeof(message), "-t_final %g s with -dt %g s is less than half a step: expected -dt <= -t_final (at least one step)", (double)run->t_final, (double)run->dt);
  PetscCheck(!message[0], run->comm, PETSC_ERR_USER_INPUT, "%s", message);
  run->steps = (PetscInt)PetscMax(last, -1.0); /* -1: before any checkpoint, refused by ClothRunCheckEnd */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What set the end of the run, for messages: "-steps 10", "-t_final 0.1 s", "the scene's run: t_final 1 s". */
static PetscErrorCode ClothRunDescribeEnd(ClothRun run, char buf[], size_t len)
{
  const PetscBool by_steps = run->steps_set || (!run->t_final_set && run->scene->run.steps > 0);

  PetscFunctionBeginUser;
  if (by_steps)
    snprintf(buf, len, "%s %" PetscInt_FMT, run->steps_set ? "-steps" : "the scene's run: steps", run->steps);
  else
    snprintf(buf, len, "%s %g s", run->t_final_set ? "-t_final" : run->scene->run.t_final > 0 ? "the scene's run: t_final" : "the default -t_final", (double)run->t_final);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A restart ends at or after its checkpoint: one told to end before it (-t_final or -steps of an earlier point)
   used to print "Done: 0 steps", exit 0 and rewrite the checkpoint, like a finished run. And the run's step and its
   simulated time stay within the scene's bounds of dt and t_final (-dt 1e9 -steps 3 ran). */
static PetscErrorCode ClothRunCheckEnd(ClothRun run)
{
  const double end = (double)run->dt_start_time + (double)run->dt * (double)(run->steps - run->dt_start_step);
  char         what[128], message[CLOTH_PATH_LEN + 512] = "";

  PetscFunctionBeginUser;
  if (run->dt_set) PetscCall(ClothOptionsCheckReal(run->comm, "-dt", run->dt, 0, PETSC_TRUE, SCENE_MAX_DT, "s (a cloth time step of more than 10 s is a unit mistake)"));
  PetscCall(ClothRunDescribeEnd(run, what, sizeof(what)));
  /* snprintf, not PETSc's printf, whose %g writes 1 as "1." */
  if (run->steps < run->step)
    snprintf(message, sizeof(message),
             "%s ends the run at step %" PetscInt_FMT " (t = %g s), before step %" PetscInt_FMT
             " (t = %g s) of checkpoint %s: expected an end at or after the checkpoint's (-steps counts every step of the run, the checkpoint's too: -steps >= %" PetscInt_FMT "; or -t_final >= %g s)",
             what, PetscMax(run->steps, 0), PetscMax(end, 0.0), run->step, (double)run->time, run->restart, run->step, (double)run->time);
  else if (end > SCENE_MAX_T_FINAL * (1 + 1e-12))
    snprintf(message, sizeof(message), "%s with a step of %g s ends the run at t = %g s: expected at most %g s of simulated time (more than 11 days)", what, (double)run->dt, end, SCENE_MAX_T_FINAL);
  PetscCheck(!message[0], run->comm, PETSC_ERR_USER_INPUT, "%s", message);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunResolveSteps(ClothRun run)
{
  PetscFunctionBeginUser;
  if (run->steps == 0) PetscCall(ClothRunStepsFromFinalTime(run));
  PetscCall(ClothRunCheckEnd(run));
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
  topo.run_id     = run->run_id;
  topo.scene      = run->scene;
  PetscCall(ClothOutputCreate(run->comm, run->output_dir, run->scene->name, &topo, run->restart[0] ? run->time : -1.0, &run->output));
  PetscCall(ClothOutputSetXdmfInterval(run->output, run->xdmf_seconds));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The mesh bodies (the mannequin) go into the XDMF series beside the fabric, in metres as simulated. */
static PetscErrorCode ClothRunAddBodyMeshes(ClothRun run)
{
  PetscInt    nbodies;
  const Body *bodies;

  PetscFunctionBeginUser;
  if (!run->collision) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothCollisionGetBodies(run->collision, &nbodies, &bodies));
  for (PetscInt b = 0; b < nbodies; b++) {
    const SceneBody     *d;
    const MeshTriangles *mesh;

    PetscCall(BodyGetDescription(bodies[b], &d));
    if (d->type != SCENE_BODY_MESH) continue;
    PetscCall(BodyGetMesh(bodies[b], &mesh, NULL, NULL, NULL));
    PetscCall(ClothOutputAddStaticMesh(run->output, d->name, mesh->nverts, mesh->coords, mesh->ntris, mesh->tris));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A new identity for this run's checkpoints: rank 0's clock and pid, mixed, never 0. */
static PetscErrorCode ClothRunNewId(ClothRun run)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(run->comm, &rank));
  if (rank == 0) {
    uint64_t x = ((uint64_t)time(NULL) << 32) ^ ((uint64_t)getpid() << 12) ^ (uint64_t)(1e6 * MPI_Wtime());

    x           = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x           = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    run->run_id = (x ^ (x >> 31)) | 1;
  }
  PetscCallMPI(MPI_Bcast(&run->run_id, 1, MPI_UINT64_T, 0, run->comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Makes output_dir this run's: a lock against a second live run in it, and, for a new run, no results of an
   earlier one (a series, checkpoints) that it would overwrite or mix with, unless -output_overwrite. */
static PetscErrorCode ClothRunClaimOutput(ClothRun run)
{
  char      holder[CLOTH_NAME_LEN + 16], path[CLOTH_PATH_LEN], newest[CLOTH_PATH_LEN];
  PetscInt  ncheckpoints;
  PetscBool series, xdmf;

  PetscFunctionBeginUser;
  PetscCall(ClothFileMakeDirectory(run->comm, run->output_dir));
  PetscCall(PetscSNPrintf(holder, sizeof(holder), "scene %s", run->scene->name));
  PetscCall(ClothFileLockDirectory(run->comm, run->output_dir, holder, &run->output_lock));
  /* the longest names the run will open, checked before its first file (which fixes Open MPI's MPI-IO component,
     h5util.h) rather than at its first checkpoint, after the computing */
  if (run->restart[0]) PetscCall(ClothH5PrepareMPIIO(run->comm, run->restart));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/.checkpoint_%06d.h5.tmp", run->output_dir, 0));
  PetscCall(ClothH5PrepareMPIIO(run->comm, path));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s.h5", run->output_dir, run->scene->name));
  PetscCall(ClothH5PrepareMPIIO(run->comm, path));
  PetscCall(ClothRunNewId(run));
  if (run->restart[0]) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s.h5", run->output_dir, run->scene->name));
  PetscCall(ClothFileExists(run->comm, path, &series));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s.xdmf", run->output_dir, run->scene->name));
  PetscCall(ClothFileExists(run->comm, path, &xdmf));
  PetscCall(ClothCheckpointFindNewest(run->comm, run->output_dir, newest, sizeof(newest), &ncheckpoints));
  if (run->output_overwrite) { /* the series is replaced; checkpoints are another run's, kept (and never pruned by this one) */
    if (ncheckpoints)
      PetscCall(
          PetscFPrintf(run->comm, PETSC_STDERR, "WARNING: -output_overwrite: the %" PetscInt_FMT " checkpoint(s) of an earlier run in %s stay (the newest %s); this run's are told apart by their run_id\n", ncheckpoints, run->output_dir, newest));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCheck(!series && !xdmf && !ncheckpoints, run->comm, PETSC_ERR_USER_INPUT,
             "output directory %s already holds results (%s%s%" PetscInt_FMT " checkpoint(s)%s%s): continue them with -restart %s, replace them with -output_overwrite, or choose another -output_dir", run->output_dir,
             series || xdmf ? run->scene->name : "", series || xdmf ? " series, " : "", ncheckpoints, ncheckpoints ? ", the newest " : "", newest, ncheckpoints ? newest : "CHECKPOINT");
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Each rank now holds its own links and angle springs: the whole model's copies on every rank go (issue 25: memory
   that every rank holds for the whole fabric). */
static PetscErrorCode ClothRunReleaseModelInteractions(ClothRun run)
{
  ClothModel model;

  PetscFunctionBeginUser;
  PetscCall(ClothGetModel(run->cloth, &model));
  PetscCall(ClothModelReleaseInteractions(model));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Once the output has the fabric's topology, the whole model's initial positions, masses, damping and quads go too
   (the cloth keeps its own share and rest measures), unless sewing or cloth-cloth contact reads them later. */
static PetscErrorCode ClothRunReleaseModelParticleData(ClothRun run)
{
  ClothModel       model;
  ClothSelfContact attached;

  PetscFunctionBeginUser;
  PetscCall(ClothGetSelfContact(run->cloth, &attached));
  if (run->sewing || attached) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothGetModel(run->cloth, &model));
  PetscCall(ClothModelReleaseParticleData(model));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunSetUp(ClothRun run)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(ClothLog.stage_setup));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_OUTPUT));
  if (!run->help) PetscCall(ClothRunClaimOutput(run));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_OUTPUT));
  PetscCall(ClothSetUp(run->cloth));
  PetscCall(ClothRunReleaseModelInteractions(run));
  if (run->collision) { /* reads meshes, pushes out particles that start inside */
    PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_BODIES));
    PetscCall(ClothCollisionSetUp(run->collision));
    PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_BODIES));
  }
  {
    PetscBool self_collision;
    PetscCall(ClothSelfContactGetEnabled(run->self_contact, &self_collision));
    if (self_collision) { /* before the integrator creates the matrix, which holds the contacts' blocks */
      ClothContribution repulsion;

      PetscCall(ClothSelfContactSetUp(run->self_contact));
      PetscCall(ClothSetSelfContact(run->cloth, run->self_contact));
      PetscCall(ClothSelfContactGetContribution(run->self_contact, &repulsion));
      PetscCall(ClothAddContribution(run->cloth, &repulsion));
    }
  }
  PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_position));
  PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_velocity));
  PetscCall(ClothCreateNaturalVec(run->cloth, &run->natural_dv));
  PetscCall(ClothCreateStrainVec(run->cloth, &run->natural_strain));
  PetscCall(VecDuplicate(run->natural_strain, &run->natural_body_contact)); /* one value per particle */
  PetscCall(VecDuplicate(run->natural_strain, &run->natural_self_contact));
  PetscCall(VecDuplicate(run->natural_strain, &run->natural_stress));
  PetscCall(VecDuplicate(run->natural_strain, &run->natural_pressure));
  PetscCall(VecZeroEntries(run->natural_body_contact));
  PetscCall(VecZeroEntries(run->natural_self_contact));
  if (run->scene->nseams > 0) {
    PetscCall(ClothSewingCreate(run->cloth, run->scene, &run->sewing));
    PetscCall(ClothSewingSetFromOptions(run->sewing));
    PetscCall(ClothSewingSetUp(run->sewing));
    if (run->self_contact) PetscCall(ClothSelfContactSetExclusion(run->self_contact, ClothSewingExcludeContact, run->sewing));
  }
  PetscCall(PetscObjectSetName((PetscObject)run->natural_position, "position"));
  PetscCall(PetscObjectSetName((PetscObject)run->natural_velocity, "velocity"));
  if (run->restart[0]) PetscCall(ClothRunRestore(run));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_MATRIX));
  PetscCall(ClothIntegratorSetUp(run->integrator));
  PetscCall(ClothReleaseGraph(run->cloth)); /* the matrix exists, and its pattern never changes (contacts' couplings are applied apart) */
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_MATRIX));
  if (run->restart[0]) PetscCall(ClothRunRestoreWarmStart(run));
  PetscCall(ClothRunResolveSteps(run));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_OUTPUT));
  if (!run->help) PetscCall(ClothRunOpenOutput(run));
  if (!run->help) PetscCall(ClothRunAddBodyMeshes(run));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_OUTPUT));
  PetscCall(ClothRunReleaseModelParticleData(run));
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

/* The contacts of the last step in a frame: with bodies and with self-collision; zeros without. */
static PetscErrorCode ClothRunGatherContacts(ClothRun run, ClothOutputFrame *frame)
{
  PetscBool self_collision;

  PetscFunctionBeginUser;
  frame->body_contact  = run->natural_body_contact;
  frame->self_contact  = run->natural_self_contact;
  frame->body_contacts = frame->self_contacts = frame->self_contact_particles = 0;
  if (run->collision) PetscCall(ClothCollisionGetContactField(run->collision, run->natural_body_contact, &frame->body_contacts));
  PetscCall(ClothSelfContactGetEnabled(run->self_contact, &self_collision));
  if (self_collision) PetscCall(ClothSelfContactGetContactField(run->self_contact, run->natural_self_contact, &frame->self_contacts, &frame->self_contact_particles));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunComputeFitMaps(ClothRun run, Vec strain, Vec stress, Vec pressure)
{
  const PetscReal *normal_force = NULL;
  Vec              x;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(run->cloth, &x, NULL));
  PetscCall(ClothComputeStrain(run->cloth, x, strain));
  PetscCall(ClothComputeStress(run->cloth, x, stress));
  if (run->collision) PetscCall(ClothCollisionGetNormalForces(run->collision, &normal_force));
  PetscCall(ClothComputeContactPressure(run->cloth, normal_force, pressure));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The fit maps of a frame: strain, stress and the pressure on the bodies (zero without bodies). */
static PetscErrorCode ClothRunGatherFitMaps(ClothRun run, ClothOutputFrame *frame)
{
  PetscFunctionBeginUser;
  PetscCall(ClothRunComputeFitMaps(run, run->natural_strain, run->natural_stress, run->natural_pressure));
  frame->strain   = run->natural_strain;
  frame->stress   = run->natural_stress;
  frame->pressure = run->natural_pressure;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunWriteCheckpoint(ClothRun run);

/* A series that vanished during the run (its directory deleted or moved) cannot take the frame: the state is
   saved in a checkpoint first (which recreates the directory), then the run stops saying where it is. */
static PetscErrorCode ClothRunCheckSeries(ClothRun run)
{
  PetscBool   exists;
  const char *path;

  PetscFunctionBeginUser;
  PetscCall(ClothOutputSeriesExists(run->output, &exists, &path));
  if (exists) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothRunWriteCheckpoint(run));
  SETERRQ(run->comm, PETSC_ERR_FILE_OPEN, "Output series %s is gone (was its directory deleted or moved during the run?): the state at step %" PetscInt_FMT " is saved in %s; continue with -restart %s", path, run->step, run->last_checkpoint,
          run->last_checkpoint);
}

static PetscErrorCode ClothRunWriteFrame(ClothRun run)
{
  ClothOutputFrame frame;

  PetscFunctionBeginUser;
  PetscCall(ClothRunCheckSeries(run));
  PetscCall(PetscLogEventBegin(ClothLog.output, 0, 0, 0, 0));
  PetscCall(ClothRunGatherNatural(run));
  frame.velocity = run->natural_velocity;
  PetscCall(ClothRunGatherFitMaps(run, &frame));
  PetscCall(ClothRunGatherContacts(run, &frame));
  PetscCall(ClothOutputWriteFrame(run->output, run->step, run->time, run->natural_position, &frame));
  PetscCall(PetscLogEventEnd(ClothLog.output, 0, 0, 0, 0));
  if (run->monitor_energy) {
    ClothEnergy e;
    Vec         x, v;
    PetscCall(ClothGetState(run->cloth, &x, &v));
    PetscCall(ClothComputeEnergy(run->cloth, x, v, &e));
    PetscCall(
        PetscPrintf(run->comm, "  energy at step %" PetscInt_FMT ": kinetic %.9e J, gravity %.9e J, elastic %.9e J, total %.9e J\n", run->step, (double)e.kinetic, (double)e.gravity, (double)e.elastic, (double)(e.kinetic + e.gravity + e.elastic)));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunWriteCheckpoint(ClothRun run)
{
  ClothCheckpointInfo  info;
  ClothCheckpointField fields[CLOTH_RUN_FIELDS_CAPACITY];
  PetscInt             nfields, first, ncontributed;
  Vec                  dv;
  PetscReal            history_dt;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ClothLog.checkpoint, 0, 0, 0, 0));
  PetscCall(ClothRunGatherNatural(run));
  PetscCall(ClothIntegratorGetWarmStart(run->integrator, &dv));
  if (dv) PetscCall(ClothScatterToNatural(run->cloth, dv, run->natural_dv, SCATTER_FORWARD));
  PetscCall(ClothRunHistoryCheckpoint(run, PETSC_TRUE, &history_dt));
  PetscCall(ClothRunCheckpointFields(run, PETSC_TRUE, dv ? PETSC_TRUE : PETSC_FALSE, fields, &nfields, &first, &ncontributed));
  PetscCall(ClothRunFillCheckpointInfo(run, &info));
  info.history_dt = history_dt;
  PetscCall(ClothCheckpointWrite(run->comm, run->output_dir, &info, nfields, fields, run->checkpoint_keep, run->last_checkpoint, sizeof(run->last_checkpoint)));
  PetscCall(ClothRestoreCheckpointFields(run->cloth, ncontributed, &fields[first]));
  PetscCall(ClothIntegratorRequestPreconditionerRebuild(run->integrator)); /* as a restart from this checkpoint */
  PetscCall(PetscLogEventEnd(ClothLog.checkpoint, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ClothRunProgress(ClothRun run, PetscInt first_step, double start, const ClothStepStats *stats)
{
  const double wall = WallTime() - start, per_step = wall / (double)(run->step - first_step);
  char         sewing[128] = "";

  PetscFunctionBeginUser;
  if (run->sewing) {
    ClothSewingPhase phase;
    PetscInt         sewn, total;
    PetscReal        gap;
    PetscCall(ClothSewingGetStatus(run->sewing, &phase, &sewn, &total, &gap));
    PetscCall(PetscSNPrintf(sewing, sizeof(sewing), "  sewing: %s, %" PetscInt_FMT "/%" PetscInt_FMT " sewn, widest gap %.1f mm", ClothSewingPhases[phase], sewn, total, (double)(1e3 * gap)));
  }
  PetscCall(PetscPrintf(run->comm, "step %6" PetscInt_FMT "/%" PetscInt_FMT "  t = %.5f s  wall %.2f s  KSP its %" PetscInt_FMT "%s  ETA %.1f s%s\n", run->step, run->steps, (double)run->time, wall, stats->krylov_iterations,
                        stats->substeps > 1 ? " (step reduced)" : "", per_step * (double)(run->steps - run->step), sewing));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Has any rank received a termination signal? Collective. */
static PetscErrorCode TerminationRequested(MPI_Comm comm, PetscBool *requested)
{
  int local = termination_requested, global;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, comm));
  *requested = global ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The frame of the starting state, when the series has no frame yet: a new run, or a restart into
   another output directory. A restart that continues its series does not add one: the frame at the
   restart step is already there when it was an output step, and must not be when it was not, so that
   the series is the same as an uninterrupted run's. */
static PetscErrorCode ClothRunWriteFirstFrame(ClothRun run)
{
  PetscInt nframes;

  PetscFunctionBeginUser;
  PetscCall(ClothOutputGetFrames(run->output, &nframes, NULL, NULL));
  if (nframes == 0) PetscCall(ClothRunWriteFrame(run));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunSolve(ClothRun run)
{
  const PetscInt first_step = run->step;
  const double   start      = WallTime();
  double         last_print = start;
  PetscBool      ok = PETSC_TRUE, stop = PETSC_FALSE;
  int            print;
  ClothStepStats stats = {0, 0, run->dt};
  PetscInt       fallbacks;
  const char    *failure = "";

  PetscFunctionBeginUser;
  if (run->help) {
    PetscCall(PetscPrintf(run->comm, "-help: the options of this run are listed above (the multigrid levels' own -mg_levels_* options appear at the first solve); nothing was run or written\n"));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscPrintf(run->comm, "Running %s: %" PetscInt_FMT " steps of %g s from step %" PetscInt_FMT "; output in %s\n", run->scene->name, run->steps, (double)run->dt, run->step, run->output_dir));
  PetscCall(ClothLogPhaseBegin(CLOTH_SETUP_OUTPUT));
  PetscCall(ClothRunWriteFirstFrame(run));
  PetscCall(ClothLogPhaseEnd(CLOTH_SETUP_OUTPUT));
  PetscCall(PetscLogStagePush(ClothLog.stage_steps));
  while (run->step < run->steps && !stop) {
    /* the scale at the end of the step, where implicit Euler evaluates the forces; a function of time alone,
       so a restart continues the same ramp */
    if (run->gravity_ramp > 0) PetscCall(ClothSetGravityScale(run->cloth, PetscMin(1.0, (run->time + run->dt) / run->gravity_ramp)));
    PetscCall(ClothIntegratorStep(run->integrator, run->dt, &ok, &stats));
    if (!ok) break;
    run->step++;
    run->time = run->dt_start_time + run->dt * (PetscReal)(run->step - run->dt_start_step);
    run->krylov_total += stats.krylov_iterations;
    run->substeps_total += stats.substeps;
    if (run->sewing) PetscCall(ClothSewingUpdate(run->sewing, run->time));
    if ((run->output_every > 0 && run->step % run->output_every == 0) || run->step == run->steps) PetscCall(ClothRunWriteFrame(run));
    if (run->checkpoint_every > 0 && run->step % run->checkpoint_every == 0 && run->step < run->steps) {
      PetscCall(ClothOutputFlush(run->output)); /* the .xdmf lists every frame up to the checkpoint */
      PetscCall(ClothRunWriteCheckpoint(run));
    }
    /* rank 0's clock decides for all: the progress line is collective (the sewing status), and the
       ranks' clocks differ (under load, by more than a step: mismatched collectives, MPI_ERR_TRUNCATE) */
    print = run->progress_seconds <= 0 || WallTime() - last_print >= run->progress_seconds || run->step == run->steps;
    PetscCallMPI(MPI_Bcast(&print, 1, MPI_INT, 0, run->comm));
    if (print) {
      PetscCall(ClothRunProgress(run, first_step, start, &stats));
      last_print = WallTime();
    }
    PetscCall(TerminationRequested(run->comm, &stop));
  }
  PetscCall(PetscLogStagePop());
  PetscCall(ClothOutputFlush(run->output));
  PetscCall(ClothRunWriteCheckpoint(run));
  if (!ok) PetscCall(ClothIntegratorGetFailure(run->integrator, &failure));
  PetscCheck(ok, run->comm, PETSC_ERR_NOT_CONVERGED, "Step %" PetscInt_FMT " failed even with the step halved down to %g s (%s); the last good state (step %" PetscInt_FMT ") is in %s", run->step + 1, (double)stats.smallest_dt, failure, run->step,
             run->last_checkpoint);
  if (stop)
    PetscCall(PetscPrintf(run->comm, "Stopped by %s at step %" PetscInt_FMT " of %" PetscInt_FMT " (t = %g s) after finishing the step; the state is in %s: continue with -restart %s\n", termination_requested == SIGUSR1 ? "SIGUSR1" : "SIGTERM",
                          run->step, run->steps, (double)run->time, run->last_checkpoint, run->last_checkpoint));
  if (run->sewing) { /* a garment: measure how well it is assembled */
    char path[CLOTH_PATH_LEN];
    PetscCall(PetscSNPrintf(path, sizeof(path), "%s/quality.json", run->output_dir));
    Vec fit_maps[3];

    PetscCall(ClothCreateStrainVec(run->cloth, &fit_maps[0]));
    PetscCall(VecDuplicate(fit_maps[0], &fit_maps[1]));
    PetscCall(VecDuplicate(fit_maps[0], &fit_maps[2]));
    PetscCall(ClothRunComputeFitMaps(run, fit_maps[0], fit_maps[1], fit_maps[2]));
    PetscCall(ClothQualityWrite(run->cloth, run->collision, run->sewing, fit_maps, run->run_id, path, WallTime() - start));
    for (PetscInt f = 0; f < 3; f++) PetscCall(VecDestroy(&fit_maps[f]));
  }
  PetscCall(ClothIntegratorViewSystem(run->integrator, PETSC_VIEWER_STDOUT_(run->comm)));
  PetscCall(ClothIntegratorGetPCFallbacks(run->integrator, &fallbacks));
  if (fallbacks) PetscCall(PetscPrintf(run->comm, "Preconditioner breakdowns: %" PetscInt_FMT " solves redone by the fallback solver (-fallback_ksp_type, -fallback_pc_type)\n", fallbacks));
  PetscCall(PetscPrintf(run->comm, "Done: %" PetscInt_FMT " steps (%" PetscInt_FMT " sub-steps), %" PetscInt_FMT " Krylov iterations, %.2f s wall. Results: %s/%s.xdmf (open in ParaView), checkpoint %s\n", run->step - first_step, run->substeps_total,
                        run->krylov_total, WallTime() - start, run->output_dir, run->scene->name, run->last_checkpoint));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunGetCollision(ClothRun run, ClothCollision *collision)
{
  PetscFunctionBeginUser;
  *collision = run->collision;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunGetCloth(ClothRun run, Cloth *cloth)
{
  PetscFunctionBeginUser;
  *cloth = run->cloth;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothRunDestroy(ClothRun *run)
{
  ClothRun r = *run;

  PetscFunctionBeginUser;
  if (!r) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothOutputDestroy(&r->output));
  PetscCall(ClothFileUnlockDirectory(&r->output_lock));
  PetscCall(ClothIntegratorDestroy(&r->integrator));
  PetscCall(ClothCollisionDestroy(&r->collision));
  PetscCall(ClothSewingDestroy(&r->sewing));
  PetscCall(ClothDestroy(&r->cloth));
  PetscCall(ClothSelfContactDestroy(&r->self_contact)); /* after the cloth, which borrows it */
  PetscCall(VecDestroy(&r->natural_position));
  PetscCall(VecDestroy(&r->natural_velocity));
  PetscCall(VecDestroy(&r->natural_dv));
  for (PetscInt k = 0; k < 2; k++) PetscCall(VecDestroy(&r->natural_history[k]));
  PetscCall(VecDestroy(&r->natural_strain));
  PetscCall(VecDestroy(&r->natural_body_contact));
  PetscCall(VecDestroy(&r->natural_self_contact));
  PetscCall(VecDestroy(&r->natural_stress));
  PetscCall(VecDestroy(&r->natural_pressure));
  PetscCall(PetscFree(*run));
  PetscFunctionReturn(PETSC_SUCCESS);
}
