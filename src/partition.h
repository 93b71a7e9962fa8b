/* Partitioning of the particle graph across MPI ranks: METIS (k-way) on rank 0 by default, or PETSc's parallel
   MatPartitioning (PT-Scotch, ParMETIS) on the graph distributed by blocks of rows. */
#pragma once
#include <petscsys.h>
#include "util.h"

typedef enum {
  CLOTH_PARTITION_METIS,    /* METIS_PartGraphKway on the interaction graph (default) */
  CLOTH_PARTITION_BLOCK,    /* contiguous blocks of the natural order (for comparison) */
  CLOTH_PARTITION_PTSCOTCH, /* PETSc MatPartitioning "ptscotch", every rank partitioning its block of rows */
  CLOTH_PARTITION_PARMETIS  /* PETSc MatPartitioning "parmetis" (only when PETSc was built with it) */
} ClothPartitionType;
extern const char *const ClothPartitionTypes[];

/* Assigns each of the n particles (graph in CSR form, natural order, no self loops) to one of
   nparts parts. metis and block: rank 0 partitions and broadcasts; ptscotch and parmetis: all ranks partition
   together and gather. Every rank gets the same part[], checked to put every particle in a part and leave no part
   empty. Collective. */
PetscErrorCode ClothPartitionGraph(MPI_Comm comm, ClothPartitionType type, PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[]);
/* Number of graph edges whose ends lie in different parts (each edge counted once). */
PetscInt ClothPartitionEdgeCut(PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], const PetscInt part[]);
