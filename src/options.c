/* Checks of run-time option values: see options.h. Messages with reals are formatted by snprintf: PETSc's
   printf writes %g of 1 and inf as "1." and "inf.". */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "options.h"
#include "clothsim_options.h" /* generated at build time: CLOTHSIM_OPTION_NAMES */

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

/* The options clothsim reads, from its sources (a few of them PETSc's, which it sets defaults of). */
static const char *const ClothOptionNames[] = {CLOTHSIM_OPTION_NAMES, NULL};
/* Prefixes of options that are PETSc's: its own, and those of PETSc objects clothsim gives a prefix of its own. */
static const char *const ClothOptionsOfPETSc[] = {"-ksp_", "-pc_",  "-mat_",    "-mg_",       "-log_",          "-options_",         "-snes_", "-ts_", "-vec_", "-dm_", "-sf_", "-is_", "-viewer_", "-draw_", "-malloc", "-memory_",
                                                  "-info", "-help", "-version", "-fallback_", "-implicit_mat_", "-cloth_partition_", NULL};
/* Beginnings that only clothsim's options have. */
static const char *const ClothOptionFamilies[] = {"-checkpoint_", "-cloth_", "-collision_", "-implicit_pc_", "-integrator_", "-output_", "-restart_", "-self_collision_", "-sewing_", NULL};

static PetscBool StartsWithAny(const char name[], const char *const prefixes[], const char **which)
{
  for (PetscInt i = 0; prefixes[i]; i++)
    if (!strncmp(name, prefixes[i], strlen(prefixes[i]))) {
      if (which) *which = prefixes[i];
      return PETSC_TRUE;
    }
  return PETSC_FALSE;
}

/* Edit distance of a and b (insertions, deletions, substitutions and swaps of neighbours, each 1), capped at 9. */
static int EditDistance(const char a[], const char b[])
{
  enum { LEN = 64 };
  int       d[LEN + 1][LEN + 1];
  const int m = (int)PetscMin(strlen(a), (size_t)LEN), n = (int)PetscMin(strlen(b), (size_t)LEN);

  for (int i = 0; i <= m; i++) d[i][0] = i;
  for (int j = 0; j <= n; j++) d[0][j] = j;
  for (int i = 1; i <= m; i++)
    for (int j = 1; j <= n; j++) {
      d[i][j] = PetscMin(PetscMin(d[i - 1][j] + 1, d[i][j - 1] + 1), d[i - 1][j - 1] + (a[i - 1] != b[j - 1]));
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = PetscMin(d[i][j], d[i - 2][j - 2] + 1);
    }
  return PetscMin(d[m][n], 9);
}

/* The clothsim option nearest to name, when near enough to be its misspelling: one edit for names of up to 4
   letters (-dt, -grid), two beyond; NULL otherwise or when name is one of them. */
static const char *NearestOption(const char name[])
{
  const char *nearest = NULL;
  int         best    = 10;

  for (PetscInt i = 0; ClothOptionNames[i]; i++) {
    const int distance = EditDistance(name, ClothOptionNames[i]);

    if (distance == 0) return NULL;
    if (StartsWithAny(ClothOptionNames[i], ClothOptionsOfPETSc, NULL)) continue; /* PETSc's: -ksp_atol is no -ksp_rtol */
    if (distance <= (strlen(ClothOptionNames[i]) <= 5 ? 1 : 2) && distance < best) {
      best    = distance;
      nearest = ClothOptionNames[i];
    }
  }
  return nearest;
}

/* "-output_dir, -output_every, ...": the clothsim options of a family. */
static void JoinFamily(const char family[], char buf[], size_t len)
{
  buf[0] = 0;
  for (PetscInt i = 0; ClothOptionNames[i]; i++) {
    if (strncmp(ClothOptionNames[i], family, strlen(family))) continue;
    if (buf[0]) strncat(buf, ", ", len - strlen(buf) - 1);
    strncat(buf, ClothOptionNames[i], len - strlen(buf) - 1);
  }
}

/* The refusal of one unused option, or "" when it does not look like clothsim's. */
static void DescribeUnknownOption(const char name[], const char value[], char message[], size_t len)
{
  const char *nearest, *family = NULL;
  char        members[1024];

  message[0] = 0;
  if (StartsWithAny(name, ClothOptionsOfPETSc, NULL)) return;
  for (PetscInt i = 0; ClothOptionNames[i]; i++)
    if (!strcmp(name, ClothOptionNames[i])) return; /* clothsim's, read later in the run or not at all in this one */
  if ((nearest = NearestOption(name)))
    snprintf(message, len, "option %s%s%s is not an option of clothsim: did you mean %s? (expected an option of clothsim or PETSc; see -help)", name, value ? " " : "", value ? value : "", nearest);
  else if (StartsWithAny(name, ClothOptionFamilies, &family)) {
    JoinFamily(family, members, sizeof(members));
    snprintf(message, len, "option %s%s%s is not an option of clothsim: expected one of its %s options: %s", name, value ? " " : "", value ? value : "", family, members);
  }
}

PetscErrorCode ClothOptionsCheckMisspelled(MPI_Comm comm)
{
  PetscInt n;
  char   **names, **values, message[2048] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt i = 0; i < n && !message[0]; i++) {
    char name[256];

    snprintf(name, sizeof(name), "-%s", names[i]); /* PETSc gives the names without their dash */
    DescribeUnknownOption(name, values[i], message, sizeof(message));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscCheck(!message[0], comm, PETSC_ERR_USER_INPUT, "%s", message);
  PetscFunctionReturn(PETSC_SUCCESS);
}
