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
/* Adjacency in CSR form (no self loops): j is a neighbour of i when an interaction holds both. */
/* Displaces every free particle along the fabric's normal there by a uniform random amount in
   [-amplitude, amplitude] (m): the small imperfections of a real specimen, which decide how a
   symmetric start buckles. The numbers depend only on seed and the particle's natural index, so the
   start is the same on any number of ranks. Rest lengths and angles are not touched. */
PetscErrorCode ClothModelPerturbPositions(ClothModel model, PetscReal amplitude, PetscInt seed);
PetscErrorCode ClothModelGetAdjacency(ClothModel model, PetscInt **xadj, PetscInt **adjncy);
PetscErrorCode ClothModelDestroy(ClothModel *model);
