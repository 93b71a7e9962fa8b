/* ClothOutput: the XDMF + HDF5 time series that ParaView opens (DIR/NAME.xdmf + DIR/NAME.h5).

   Vectors passed in are in the *natural* (global particle) order (docs/model.md section 1): pieces in scene order,
   each piece row by row, with PETSc's default contiguous layout and block size 3, so that every rank
   writes one contiguous hyperslab. */
#pragma once
#include <stdint.h>
#include <petscvec.h>
#include "util.h"
#include "scene.h"

typedef struct _n_ClothOutput *ClothOutput;

/* Fabric topology: nquads quadrilaterals, 4 global particle indices each, counter-clockwise.
   Every rank passes the same full array (it is small next to the state). */
typedef struct {
  PetscInt        nparticles;
  PetscInt        nquads;
  const PetscInt *quads;
  uint64_t        run_id; /* the run writing the series (root attribute run_id); 0: none, no check */
  Scene           scene;  /* its bytes, the code version and the options go into a new series (provenance.h); NULL: none */
} ClothOutputTopology;

/* Opens the series. If restart_time >= 0 the existing series is kept up to and including that time
   and later frames are dropped (a restarted run then appends with no duplicated or missing times), unless it
   was written by another run (its run_id differs from topology->run_id), which is refused; otherwise any
   previous series under that name is replaced. Collective. */
PetscErrorCode ClothOutputCreate(MPI_Comm comm, const char dir[], const char name[], const ClothOutputTopology *topology, PetscReal restart_time, ClothOutput *out);
/* What a frame holds besides the positions. The Vecs are in natural order; the counts are totals over
   all ranks (every rank passes the same values). A run without bodies or without self-collision passes
   zero fields and counts, so that every series has the same layout. */
typedef struct {
  Vec      velocity;               /* 3 per particle */
  Vec      strain;                 /* 1 per particle: ClothComputeStrain */
  Vec      body_contact;           /* 1 per particle: ClothCollisionGetContactField (0 free, 1 in contact, 2 held) */
  Vec      self_contact;           /* 1 per particle: ClothSelfContactGetContactField (contacts it is part of) */
  Vec      stress;                 /* 1 per particle: ClothComputeStress (N/m) */
  Vec      pressure;               /* 1 per particle: ClothComputeContactPressure (N/m^2) */
  PetscInt body_contacts;          /* particles in contact with a body */
  PetscInt self_contacts;          /* cloth-cloth contacts (point-triangle and edge-edge pairs) */
  PetscInt self_contact_particles; /* particles in one or more cloth-cloth contacts */
} ClothOutputFrame;

/* Appends one frame at (step, time): positions (natural order, 3 per particle), the fields of frame as
   datasets (and XDMF attributes of the fabric) and its counts as attributes of the frame's group;
   rewrites the .xdmf (always complete: through a temporary file) when -output_xdmf_seconds have passed since its
   last rewrite. Collective. */
PetscErrorCode ClothOutputWriteFrame(ClothOutput out, PetscInt step, PetscReal time, Vec position, const ClothOutputFrame *frame);
/* The default wall time between rewrites of the .xdmf (-output_xdmf_seconds). The .xdmf lists every frame and is
   rewritten whole (through a temporary file and fsync, so that ParaView never reads half of it): rewriting it after
   every frame cost time quadratic in the frames, 2.0 of the main job's 2.4 s of output at 251 frames
   (docs/performance.md). */
#define CLOTH_OUTPUT_XDMF_SECONDS 10.0
/* Rewrite the .xdmf at most every seconds of wall time (0: after every frame); >= 0. Not collective (every rank
   passes the same value). */
PetscErrorCode ClothOutputSetXdmfInterval(ClothOutput out, PetscReal seconds);
/* Rewrites the .xdmf if it does not list every frame written yet (at a checkpoint, at the end; ClothOutputDestroy
   does it too). Collective. */
PetscErrorCode ClothOutputFlush(ClothOutput out);
/* Adds a mesh that does not move (the mannequin): nverts points (coords: 3 per point) and ntris
   triangles (tris: 3 point indices each, 0-based), written once to NAME.h5:/static/<name>/{points,
   triangles} and shown as a grid <name> beside "fabric" in every frame of the .xdmf. Every rank passes
   the same full arrays. Calling it again with the same name replaces that mesh; after a restart call it
   again (the .xdmf lists the meshes added since ClothOutputCreate). Collective. */
PetscErrorCode ClothOutputAddStaticMesh(ClothOutput out, const char name[], PetscInt nverts, const PetscReal coords[], PetscInt ntris, const PetscInt tris[]);
/* Whether the series file NAME.h5 is still there (a directory deleted during a run takes it away) and its path
   (may be NULL). Collective. */
PetscErrorCode ClothOutputSeriesExists(ClothOutput out, PetscBool *exists, const char **path);
/* The frames in the series, in step order, including those kept from before a restart. The arrays
   belong to out and stay valid until the next frame is written; any output may be NULL. Not collective. */
PetscErrorCode ClothOutputGetFrames(ClothOutput out, PetscInt *nframes, const PetscInt64 *steps[], const PetscReal *times[]);
PetscErrorCode ClothOutputDestroy(ClothOutput *out);
