/* Partitioning of the particle graph across MPI ranks with METIS (k-way). */
#pragma once
#include <petscsys.h>
#include "util.h"

typedef enum {
  CLOTH_PARTITION_METIS, /* METIS_PartGraphKway on the interaction graph (default) */
  CLOTH_PARTITION_BLOCK  /* contiguous blocks of the natural order (for comparison) */
} ClothPartitionType;
extern const char *const ClothPartitionTypes[];

/* Assigns each of the n particles (graph in CSR form, natural order, no self loops) to one of
   nparts parts. Rank 0 partitions and broadcasts, so every rank gets the same part[]. Collective. */
PetscErrorCode ClothPartitionGraph(MPI_Comm comm, ClothPartitionType type, PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], PetscInt nparts, PetscInt part[]);
/* Number of graph edges whose ends lie in different parts (each edge counted once). */
PetscInt ClothPartitionEdgeCut(PetscInt n, const PetscInt xadj[], const PetscInt adjncy[], const PetscInt part[]);
