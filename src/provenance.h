/* Provenance: what made an output file, written as attributes of every HDF5 file clothsim writes (the XDMF
   series' .h5 and the checkpoints): the code version, the git revision at build time (not configure time:
   scripts/revision.cmake runs at every build), the scene file's path and bytes, and the options of the run. */
#pragma once
#include <hdf5.h>
#include "scene.h"

/* The git revision the binary was built from ("unknown" outside a git checkout). */
const char *ClothProvenanceRevision(void);
/* Writes code_version, git_revision, scene_path, scene_text (without a scene: not these two) and options as string
   attributes of obj (a file or a group, open collectively). Collective. */
PetscErrorCode ClothProvenanceWrite(hid_t obj, Scene scene);
