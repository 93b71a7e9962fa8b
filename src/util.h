/* Small shared helpers: PETSc version compatibility and library error idioms. */
#pragma once
#include <errno.h>
#include <string.h>
#include <petscsys.h>

/* PETSC_SUCCESS appeared in PETSc 3.19; Debian 12 ships 3.18. */
#ifndef PETSC_SUCCESS
#define PETSC_SUCCESS 0
#endif

/* HDF5 reports failure with a negative return value (herr_t or hid_t). The OS error of the call, if any, is in
   the message; a full disk or quota (ENOSPC, EDQUOT) is a file error (exit status 3, errors.h), not a bug. */
#define ClothCallHDF5(call)                                                                                                                                                                                                                              \
  do {                                                                                                                                                                                                                                                   \
    errno = 0;                                                                                                                                                                                                                                           \
    if ((call) < 0) {                                                                                                                                                                                                                                    \
      const int os_error_ = errno;                                                                                                                                                                                                                       \
      SETERRQ(PETSC_COMM_SELF, os_error_ == ENOSPC || os_error_ == EDQUOT ? PETSC_ERR_FILE_WRITE : PETSC_ERR_LIB, "HDF5 call failed: %s%s%s%s", #call, os_error_ ? " (" : "", os_error_ ? strerror(os_error_) : "", os_error_ ? ")" : "");               \
    }                                                                                                                                                                                                                                                    \
  } while (0)

/* Maximum length of names (pieces, fabrics, bodies) and paths kept in fixed buffers. */
#define CLOTH_NAME_LEN 64
#define CLOTH_PATH_LEN PETSC_MAX_PATH_LEN
