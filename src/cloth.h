/* Cloth: the fabric distributed over MPI ranks.

   Particles are partitioned (METIS) and renumbered so that each rank owns a contiguous range of the
   PETSc ("solver") numbering; files always use the natural order (pieces in scene order, row by
   row), reached through ClothScatterToNatural. Each interaction is evaluated on exactly one rank
   (the owner of its lowest-numbered particle); the particles it touches that other ranks own are
   ghosts, refreshed before and summed back after every evaluation. */
#pragma once
#include <petscmat.h>
#include "scene.h"
#include "model.h"
#include "partition.h"

typedef struct _n_Cloth *Cloth;

/* Energies of the whole fabric, J. */
typedef struct {
  PetscReal kinetic, gravity, elastic;
} ClothEnergy;

PetscErrorCode ClothCreate(MPI_Comm comm, Scene scene, Cloth *cloth);
/* Reads -cloth_partition metis|block and -cloth_view_partition. */
PetscErrorCode ClothSetFromOptions(Cloth cloth);
/* Builds the model, partitions and distributes it. Collective. */
PetscErrorCode ClothSetUp(Cloth cloth);
/* Prints particle counts and partition quality (edge cut, owned and ghost counts per rank, imbalance). */
PetscErrorCode ClothView(Cloth cloth, PetscViewer viewer);
PetscErrorCode ClothDestroy(Cloth *cloth);

/* The state: position and velocity, ghosted Vecs with block size 3 in solver numbering (borrowed). */
PetscErrorCode ClothGetState(Cloth cloth, Vec *position, Vec *velocity);
/* A new ghosted Vec with the state's layout (forces, work). */
PetscErrorCode ClothCreateStateVec(Cloth cloth, Vec *v);
PetscErrorCode ClothGetSizes(Cloth cloth, PetscInt *nlocal, PetscInt *nglobal);
/* Per owned particle: mass (kg) and whether it is held fixed. Borrowed arrays. */
PetscErrorCode ClothGetMasses(Cloth cloth, const PetscReal **mass, const PetscBool **fixed);

/* force = internal + gravity + damping forces at (position, velocity). position and velocity get
   their ghosts refreshed. Collective. */
PetscErrorCode ClothComputeForces(Cloth cloth, Vec position, Vec velocity, Vec force);
/* The linearised backward Euler system of MODEL.md section 5, filtered by the constraints:
   A = S (M + h C + h^2 K) S + (I - S) and rhs = S h (F - h K v), K the positive semidefinite part of
   the stiffness. A must come from ClothCreateMatrix. Collective. */
PetscErrorCode ClothAssembleImplicitSystem(Cloth cloth, PetscReal h, Vec position, Vec velocity, Mat A, Vec rhs);
/* With exact = true the implicit system uses the exact stiffness (possibly indefinite) instead of its
   positive semidefinite part; for Jacobian tests against finite differences. */
PetscErrorCode ClothSetExactStiffness(Cloth cloth, PetscBool exact);
/* A symmetric block (bs 3, BAIJ; -implicit_mat_type sbaij stores only the upper triangle) matrix with exactly the
   nonzero pattern of the interactions, preallocated. */
PetscErrorCode ClothCreateMatrix(Cloth cloth, Mat *A);
/* Zeroes the constrained components of a vector of per-particle 3-vectors (v <- S v). */
PetscErrorCode ClothApplyConstraints(Cloth cloth, Vec v);
PetscErrorCode ClothComputeEnergy(Cloth cloth, Vec position, Vec velocity, ClothEnergy *energy);

/* Natural-order Vecs (PETSc's default contiguous layout, block size 3) for files. */
PetscErrorCode ClothCreateNaturalVec(Cloth cloth, Vec *natural);
/* SCATTER_FORWARD: solver -> natural; SCATTER_REVERSE: natural -> solver. */
PetscErrorCode ClothScatterToNatural(Cloth cloth, Vec solver, Vec natural, ScatterMode mode);
/* The global model (every rank holds it; read-only): topology for output, counts. */
PetscErrorCode ClothGetModel(Cloth cloth, ClothModel *model);
