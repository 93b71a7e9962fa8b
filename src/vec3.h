/* Small 3-vector helpers shared by the geometric kernels (forces, bodies, collisions, self-contact). */
#pragma once
#include <petscsys.h>

static inline PetscReal Dot3(const PetscReal a[3], const PetscReal b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void Sub3(const PetscReal a[3], const PetscReal b[3], PetscReal d[3])
{
  for (PetscInt c = 0; c < 3; c++) d[c] = a[c] - b[c];
}

static inline void Cross3(const PetscReal a[3], const PetscReal b[3], PetscReal c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
