/* Provenance: what made an output file, written into every HDF5 file clothsim writes (the XDMF series' .h5 and the
   checkpoints): the code version, the git revision at build time (not configure time: scripts/revision.cmake runs at
   every build) and the scene file's path, as attributes, and the scene file's bytes and the options of the run, as
   datasets of the group /provenance (text of any length: an attribute holds at most 64 kB). */
#pragma once
#include <hdf5.h>
#include "scene.h"

/* The group of the text datasets, at the root of every file. */
#define CLOTH_PROVENANCE_GROUP "/provenance"

/* The git revision the binary was built from ("unknown" outside a git checkout). */
const char *ClothProvenanceRevision(void);
/* Writes code_version, git_revision and scene_path (without a scene: not this one) as string attributes of obj (a file
   or a group, open collectively on comm), and the datasets /provenance/scene_text (without a scene: not this one) and
   /provenance/options in obj's file. Collective on comm. */
PetscErrorCode ClothProvenanceWrite(MPI_Comm comm, hid_t obj, Scene scene);
/* Bytes the provenance adds to a file (its texts), for the free-space check before a write. */
PetscErrorCode ClothProvenanceSize(Scene scene, double *bytes);
