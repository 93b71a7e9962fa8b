/* Checks of run-time option values: see options.h. Messages with reals are formatted by snprintf: PETSc's
   printf writes %g of 1 and inf as "1." and "inf.". */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "options.h"

PetscErrorCode ClothOptionsCheckReal(MPI_Comm comm, const char option[], PetscReal value, PetscReal min, PetscBool min_open, PetscReal max, const char unit[])
{
  char      message[256], upper[64] = "";
  PetscBool ok = (PetscIsInfOrNanReal(value) || value < min || (min_open && value == min) || value > max) ? PETSC_FALSE : PETSC_TRUE;

  PetscFunctionBeginUser;
  if (ok) PetscFunctionReturn(PETSC_SUCCESS);
  if (max < PETSC_MAX_REAL) snprintf(upper, sizeof(upper), " and <= %g", (double)max);
  snprintf(message, sizeof(message), "option %s %g: expected a finite number %s %g%s%s%s", option, (double)value, min_open ? ">" : ">=", (double)min, upper, unit ? " " : "", unit ? unit : "");
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s", message);
}

PetscErrorCode ClothOptionsCheckInt(MPI_Comm comm, const char option[], PetscInt value, PetscInt min, PetscInt max)
{
  char upper[64] = "";

  PetscFunctionBeginUser;
  if (value >= min && value <= max) PetscFunctionReturn(PETSC_SUCCESS);
  if (max < PETSC_MAX_INT) PetscCall(PetscSNPrintf(upper, sizeof(upper), " and <= %" PetscInt_FMT, max));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "option %s %" PetscInt_FMT ": expected an integer >= %" PetscInt_FMT "%s", option, value, min, upper);
}

PetscErrorCode ClothOptionsCheckIntText(MPI_Comm comm, const char option[], PetscInt min, PetscInt max)
{
  char      text[64], *end;
  PetscBool set;
  long long value;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, option, text, sizeof(text), &set));
  if (!set || !text[0]) PetscFunctionReturn(PETSC_SUCCESS);
  errno = 0;
  value = strtoll(text, &end, 10);
  if (*end) PetscFunctionReturn(PETSC_SUCCESS); /* not an integer: PETSc's parser names it */
  PetscCheck(errno != ERANGE && value >= (long long)min && value <= (long long)max, comm, PETSC_ERR_USER_INPUT, "option %s %s: expected an integer >= %" PetscInt_FMT " and <= %" PetscInt_FMT "%s", option, text, min, max,
             max == PETSC_MAX_INT ? " (the largest count a PetscInt of this build holds)" : "");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOptionsCheckStringLength(MPI_Comm comm, const char option[], size_t max, const char why[])
{
  const char *value = NULL;
  PetscBool   set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsFindPair(NULL, NULL, option, &value, &set));
  if (!set || !value) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCheck(strlen(value) <= max, comm, PETSC_ERR_USER_INPUT, "option %s %.48s... (%zu characters): expected a path of at most %zu characters%s%s%s", option, value, strlen(value), max, why ? " (" : "", why ? why : "", why ? ")" : "");
  PetscFunctionReturn(PETSC_SUCCESS);
}
