/* Checks of run-time option values where they are read: every real finite and in its physical range,
   every count within what the code can hold. Collective on comm (every rank reads the same options). */
#pragma once
#include <petscsys.h>
#include "util.h"

/* Errors unless value is finite and min <= value <= max (min < value when min_open). The message names
   the option, the value, the unit (may be NULL) and the range, e.g. "-dt inf: expected a finite number
   > 0 s". max PETSC_MAX_REAL: no upper bound. */
PetscErrorCode ClothOptionsCheckReal(MPI_Comm comm, const char option[], PetscReal value, PetscReal min, PetscBool min_open, PetscReal max, const char unit[]);
/* Errors unless min <= value <= max (max PETSC_MAX_INT: no upper bound), naming the option. */
PetscErrorCode ClothOptionsCheckInt(MPI_Comm comm, const char option[], PetscInt value, PetscInt min, PetscInt max);
/* Errors unless the text of an integer option, read as a 64-bit integer, is within [min, max]: PETSc's parser
   of a PetscInt wraps values beyond 32 bits without a word (-steps 3000000000 became -1294967296, and
   5000000000 a run of 705032704 steps). Call before PetscOptionsInt reads it. An option not given, or whose
   text is not an integer, is left to PETSc's parser. Collective on comm. */
PetscErrorCode ClothOptionsCheckIntText(MPI_Comm comm, const char option[], PetscInt min, PetscInt max);
/* Errors unless the value of string option `option`, when given, has at most max characters; why says what the
   limit is (may be NULL). PETSc's PetscOptionsString copies into a buffer of fixed size and cuts a longer value
   without a word: a 5000-character -output_dir became a 4095-character directory, which then failed in HDF5's
   open (MPI_ERR_BAD_FILE, exit 76). Call before the option is read. Collective on comm. */
PetscErrorCode ClothOptionsCheckStringLength(MPI_Comm comm, const char option[], size_t max, const char why[]);
/* Refuses an option nobody has read so far that looks like a misspelled or unknown clothsim option, before the run
   (at the end of it, the unused options are only listed: a long job ran without its checkpoints when
   -checkpont_every 5 was given). It looks like one when it is within a small edit distance of an option clothsim
   reads (the names of the sources' PetscOptions calls, gathered at build time: scripts/option_names.cmake), or when
   it starts like a family of them (-checkpoint_, -collision_, -output_, ...); the message names the nearest option.
   PETSc's own options (-ksp_*, -pc_*, -log_*, -mg_*, ...), those of PETSc objects with clothsim's prefixes
   (-fallback_*, -implicit_mat_*, -cloth_partition_*) and options read later in the run by PETSc are left alone: they
   are either used by the end or listed then. Collective on comm (every rank holds the same options). */
PetscErrorCode ClothOptionsCheckMisspelled(MPI_Comm comm);
