/* Small shared helpers: PETSc version compatibility and library error idioms. */
#pragma once
#include <petscsys.h>

/* PETSC_SUCCESS appeared in PETSc 3.19; Debian 12 ships 3.18. */
#ifndef PETSC_SUCCESS
  #define PETSC_SUCCESS 0
#endif

/* HDF5 reports failure with a negative return value (herr_t or hid_t). */
#define ClothCallHDF5(call) \
  do { \
    if ((call) < 0) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "HDF5 call failed: %s", #call); \
  } while (0)

/* Maximum length of names (pieces, fabrics, bodies) and paths kept in fixed buffers. */
#define CLOTH_NAME_LEN 64
#define CLOTH_PATH_LEN PETSC_MAX_PATH_LEN
