/* Profiling: every PetscLogEvent and stage of clothsim, registered once, shown by -log_view. */
#pragma once
#include <petsclog.h>

/* The phases of the set-up, each timed as a stage of its own (-log_view) and an event (its memory: -log_view_memory). */
typedef enum {
  CLOTH_SETUP_SCENE,      /* reading and checking the scene file (every rank) */
  CLOTH_SETUP_MESHING,    /* the model: particles, links and angle springs of the pattern pieces (every rank, whole fabric) */
  CLOTH_SETUP_GRAPH,      /* the interaction graph in natural order (every rank, whole fabric) */
  CLOTH_SETUP_PARTITION,  /* splitting the graph across the ranks (-cloth_partition) */
  CLOTH_SETUP_DISTRIBUTE, /* solver numbering, ghosts, each rank's interactions and vectors */
  CLOTH_SETUP_BODIES,     /* bodies: meshes read, their cell grids, particles pushed out of them */
  CLOTH_SETUP_MATRIX,     /* the integrator: matrix preallocation and assembly pattern, solvers */
  CLOTH_SETUP_OUTPUT,     /* claiming -output_dir, opening the series, the first frame */
  CLOTH_SETUP_PHASES
} ClothSetUpPhase;

typedef struct {
  PetscClassId  classid;
  PetscLogEvent setup, partition, forces, jacobian, solve, output, checkpoint;
  PetscLogEvent collision, collision_grid;  /* contacts with bodies (detection + response); building the cell grids */
  PetscLogEvent self_collision;             /* cloth-cloth contact: exchange, search, repulsion, velocity filter */
  PetscLogEvent self_build, self_filter;    /* nested in it: building the candidate list (exchange, cell grids); testing the candidates */
  PetscLogEvent self_coupling, self_forces; /* the contacts' couplings in a product of the implicit operator; repulsion and friction at an evaluation */
  PetscLogEvent self_impulses;              /* the velocity filter's Gauss-Seidel sweeps */
  PetscLogEvent project_psd;                /* one element stiffness projected by LAPACK (-cloth_stiffness projected): the count shows who still calls it */
  PetscLogEvent checkpoint_read;            /* reading and checking the checkpoint of -restart */
  PetscLogEvent block_ptap_symbolic;        /* the pattern-grid multigrid's finest Galerkin product, from the block matrix: */
  PetscLogEvent block_ptap_numeric;         /* its pattern (once per nonzero pattern of the matrix) and its values */
  PetscLogStage stage_setup, stage_steps;
  PetscLogStage stage_phase[CLOTH_SETUP_PHASES]; /* "Setup: NAME", nested in "Setup" (see ClothLogPhaseBegin) */
  PetscLogEvent event_phase[CLOTH_SETUP_PHASES]; /* "SetUpNAME": the same span, for -log_view_memory's columns */
} ClothLogEvents;

extern ClothLogEvents ClothLog;

/* Registers the events and stages; safe to call more than once. */
PetscErrorCode ClothLogRegister(void);
/* Pushes the phase's stage and begins its event; ClothLogPhaseEnd ends both. The stages are registered after "Time
   steps", which stays stage 2 for the scripts that read it; PETSc counts a nested stage's time in it alone, so the
   set-up's total is "Setup" plus its phases. */
PetscErrorCode ClothLogPhaseBegin(ClothSetUpPhase phase);
PetscErrorCode ClothLogPhaseEnd(ClothSetUpPhase phase);
