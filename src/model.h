/* ClothModel: the whole discrete fabric of a scene in natural (global particle) order: pieces in
   scene order, each row by row. Built identically on every rank from the scene; the distributed
   Cloth keeps only its own part of it. */
#pragma once
#include "scene.h"
#include "forces.h"
#include "seam.h"

typedef struct _n_ClothModel *ClothModel;
struct _n_ClothModel {
  PetscInt       nparticles;
  PetscReal     *position; /* 3 N: initial positions, m */
  PetscReal     *mass;     /* N: kg */
  PetscReal     *damping;  /* N: damping coefficient c_i (force -c_i v_i), kg/s */
  PetscBool     *pinned;   /* N */
  PetscInt       nlinks;
  ClothLink     *links; /* particle indices in natural order */
  PetscInt       nangles;
  ClothAngle    *angles;
  PetscInt       nfriction;       /* of which friction elements (slip > 0: bending and shear hysteresis) */
  PetscInt       nfriction_shear; /* of those, on the cell shear angle (shear hysteresis) */
  PetscInt       nquads;
  PetscInt      *quads; /* 4 per grid cell, counter-clockwise in the pattern plane */
  PetscInt       npieces;
  PetscInt      *piece_offset; /* npieces + 1: first particle of each piece */
  PetscInt       nseamlinks;
  ClothSeamLink *seamlinks; /* seam pairs (seam.h), in scene order of the seams */
};

PetscErrorCode ClothModelCreate(Scene scene, ClothModel *model);
/* Displaces every free particle along the fabric's normal there by a random amount within
   [-amplitude, amplitude] (m): the small imperfections of a real specimen, which decide how a
   symmetric start buckles. wavelength 0: independent and uniform per particle (depending on seed and the
   particle's natural index); wavelength L > 0: a smooth random field of the start position, the mean of
   CLOTH_PERTURBATION_MODES plane waves with random directions, phases and wavelengths in [L, 3L], so that
   the same specimen has the same imperfections at any resolution. Either way the start is the same on any
   number of ranks. Rest lengths and angles are not touched. */
#define CLOTH_PERTURBATION_MODES 16
PetscErrorCode ClothModelPerturbPositions(ClothModel model, PetscReal amplitude, PetscReal wavelength, PetscInt seed);
/* Adjacency in CSR form (no self loops): j is a neighbour of i when an interaction holds both. */
PetscErrorCode ClothModelGetAdjacency(ClothModel model, PetscInt **xadj, PetscInt **adjncy);
/* Frees the links and angle springs, keeping their counts: once every rank has its own share (ClothSetUp) a run no
   longer needs them, and they are the largest part of the model that every rank holds whole (about 280 bytes per
   particle of the hanging sheet: 5.85 links of 48 bytes). Their pointers become NULL. */
PetscErrorCode ClothModelReleaseInteractions(ClothModel model);
/* Frees the initial positions, masses, damping coefficients and quads, keeping their counts, the pins and the pieces:
   once the cloth holds its own share and its rest measures (ClothSetUp) and the output has the topology, only sewing
   and cloth-cloth contact read them again (about 56 bytes per particle of the whole fabric on every rank). Their
   pointers become NULL. */
PetscErrorCode ClothModelReleaseParticleData(ClothModel model);
PetscErrorCode ClothModelDestroy(ClothModel *model);
