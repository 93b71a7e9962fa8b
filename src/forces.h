/* Element kernels of the fabric model: energy, gradient and Hessian of one interaction.

   Every interaction is derived from an energy, so forces (minus the gradient) and the stiffness
   (the Hessian, K = -dF/dr) are consistent, as the implicit integrator needs. */
#pragma once
#include <petscsys.h>
#include "util.h"

/* A link between two particles (stretch, shear diagonal, skip-one bending link). Its energy is
   0.5 k (l - rest)^2, plus, when repel_length > 0, 0.5 repel_k (repel_length - l)^2 for
   l < repel_length (the paper's short-range repulsion that keeps particles apart). When
   knee_length > 0 the curve is biphasic: beyond an extension s = l - rest > knee_length the
   energy continues as 0.5 k knee^2 + k knee (s - knee) + 0.5 k_stiff (s - knee)^2 (force
   continuous, stiffness k below the knee, k_stiff above). */
typedef struct {
  PetscInt  p[2];         /* particle indices (local numbering once distributed) */
  PetscReal k;            /* stiffness, N/m */
  PetscReal rest;         /* rest length, m */
  PetscReal repel_length; /* 0 = no repulsion */
  PetscReal repel_k;      /* N/m */
  PetscReal knee_length;  /* extension where a biphasic link stiffens, m (0 = linear) */
  PetscReal k_stiff;      /* stiffness beyond the knee, N/m */
} ClothLink;

typedef enum {
  CLOTH_ANGLE_CORNER, /* arms p0->p1 and p0->p2 (warp-weft angle at a cell corner: shear) */
  CLOTH_ANGLE_CHAIN   /* arms p0->p1 and p1->p2 (consecutive segments of one thread: bending) */
} ClothAngleKind;

/* An angle spring with energy k (1 - cos(theta - theta0)), theta the angle between the two arms,
   theta0 its rest value (stored as cos and sin). For small deviations this is 0.5 k (theta - theta0)^2. */
typedef struct {
  PetscInt       p[3];
  ClothAngleKind kind;
  PetscReal      k;          /* N m */
  PetscReal      cos0, sin0; /* rest angle */
} ClothAngle;

/* Energy of a link; force on p[1] (the force on p[0] is its negative); the 3x3 block K such that the
   link's Hessian is [K -K; -K K]. With psd, K is clamped to its positive semidefinite part (the
   compressive transverse term is dropped), as the implicit system needs. Any output may be NULL. */
PetscErrorCode ClothLinkEvaluate(const ClothLink *link, const PetscReal x0[3], const PetscReal x1[3], PetscBool psd, PetscReal *energy, PetscReal force1[3], PetscReal K[9]);

/* Energy of an angle spring; forces on its three particles (3x3, row per particle); its 9x9
   Hessian (row-major, particle-major). With psd, the Hessian is projected onto the positive
   semidefinite cone (eigenvalues clamped at 0). Any output may be NULL. */
PetscErrorCode ClothAngleEvaluate(const ClothAngle *angle, const PetscReal x0[3], const PetscReal x1[3], const PetscReal x2[3], PetscBool psd, PetscReal *energy, PetscReal force[9], PetscReal H[81]);

/* Projects a symmetric n x n matrix (row-major, n <= 12) onto the positive semidefinite cone in place. */
PetscErrorCode ClothProjectPSD(PetscInt n, PetscReal A[]);
