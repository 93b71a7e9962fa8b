/* Parallel HDF5 helpers shared by the output series (output.c) and the checkpoints (checkpoint.c).

   Files are opened with the MPI-IO driver on a communicator; every helper taking a file, group or
   dataset is collective on that communicator (all ranks call it with the same arguments), as parallel
   HDF5 requires for everything that touches metadata. Vectors are written as (rows, ncomp) float64
   datasets, each rank writing its ownership range as one hyperslab with a collective transfer, so the
   file holds the natural order whatever the number of ranks. */
#pragma once
#include <hdf5.h>
#include <petscvec.h>
#include "util.h"

/* Chooses the MPI-IO under HDF5 before the process's first file, and makes sure that it can open path. Open MPI
   chooses among its MPI-IO components at the first file open; clothsim takes ROMIO (OMPI_MCA_io=romio321 in this
   process's environment) unless OMPI_MCA_io is set. Open MPI 4's default, ompio, hangs every rank when a file
   opens on some ranks and not on others (measured: its directory deleted during the open, 1 run in 25 with a
   frame every step), where ROMIO agrees on the failure across the ranks; ompio also aborts the whole run
   ("buffer overflow detected") on a file name of more than 244 characters. Frames and checkpoints are written
   as fast with either (docs/performance.md). With OMPI_MCA_io forcing ompio, a longer path is refused naming
   the path and the way out. The run calls it for its longest names before its first file, and every open
   calls it again. With another MPI (whose MPI-IO is ROMIO) this does nothing. Collective. */
PetscErrorCode ClothH5PrepareMPIIO(MPI_Comm comm, const char path[]);
/* Creates (truncating) an HDF5 file for parallel access. */
PetscErrorCode ClothH5FileCreate(MPI_Comm comm, const char path[], hid_t *file);
/* Opens an existing file (flags: H5F_ACC_RDONLY or H5F_ACC_RDWR) without printing HDF5's error stack.
   *opened is PETSC_FALSE on every rank, and *file negative, when the file is not a readable HDF5 file
   (missing, truncated, not HDF5); the caller words the refusal. */
PetscErrorCode ClothH5FileOpen(MPI_Comm comm, const char path[], unsigned flags, hid_t *file, PetscBool *opened);
/* Closes a file opened by the two above (no-op for a negative id) and sets *file to -1. */
PetscErrorCode ClothH5FileClose(hid_t *file);

/* Whether the link (group, dataset) loc/name exists; name may be a relative path ("a/b"). */
PetscErrorCode ClothH5LinkExists(hid_t loc, const char name[], PetscBool *exists);
/* Deletes loc/name when it exists (its space is not reclaimed in the file; h5repack does that). */
PetscErrorCode ClothH5LinkDeleteIfExists(hid_t loc, const char name[]);

/* Writes a Vec of global size rows*ncomp as the float64 dataset loc/name of shape (rows, ncomp).
   The ownership range must hold whole rows (block size ncomp, or a layout made in multiples of it). */
PetscErrorCode ClothH5WriteVec(hid_t loc, const char name[], Vec v, PetscInt ncomp);
/* Reads loc/name, which must be (rows, ncomp) with rows*ncomp the global size of v, into v. */
PetscErrorCode ClothH5ReadVec(hid_t loc, const char name[], Vec v, PetscInt ncomp);
/* Writes a table (rows, cols) that every rank holds in full (topology, a static mesh): rank 0 writes
   it, the others take part in the collective call with an empty selection. */
PetscErrorCode ClothH5WriteIntTable(MPI_Comm comm, hid_t loc, const char name[], PetscInt rows, PetscInt cols, const PetscInt data[]);
PetscErrorCode ClothH5WriteRealTable(MPI_Comm comm, hid_t loc, const char name[], PetscInt rows, PetscInt cols, const PetscReal data[]);

/* Writes text (any length) as the scalar dataset loc/name of a fixed-length, null-terminated ASCII string (h5py:
   f[name][()] gives its bytes): rank 0 writes it, the others take part in the collective call. A dataset, not an
   attribute: an attribute lives in its object's header, which holds at most 64 kB (a longer one fails in H5Acreate2). */
PetscErrorCode ClothH5WriteText(MPI_Comm comm, hid_t loc, const char name[], const char text[]);

/* Scalar attributes on a group or dataset; a write replaces an attribute of the same name. Strings
   are stored as fixed-length, null-terminated ASCII; a read truncates to len - 1 characters. Only for values of
   bounded size (names, numbers, paths): text that may exceed 64 kB goes into a dataset (ClothH5WriteText). */
PetscErrorCode ClothH5AttributeExists(hid_t obj, const char name[], PetscBool *exists);
PetscErrorCode ClothH5AttributeWriteInt64(hid_t obj, const char name[], PetscInt64 value);
PetscErrorCode ClothH5AttributeWriteUInt64(hid_t obj, const char name[], uint64_t value);
PetscErrorCode ClothH5AttributeWriteReal(hid_t obj, const char name[], PetscReal value);
PetscErrorCode ClothH5AttributeWriteString(hid_t obj, const char name[], const char value[]);
PetscErrorCode ClothH5AttributeReadInt64(hid_t obj, const char name[], PetscInt64 *value);
PetscErrorCode ClothH5AttributeReadUInt64(hid_t obj, const char name[], uint64_t *value);
PetscErrorCode ClothH5AttributeReadReal(hid_t obj, const char name[], PetscReal *value);
PetscErrorCode ClothH5AttributeReadString(hid_t obj, const char name[], char value[], size_t len);
