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

/* A link as the cloth keeps it: its two particles and the index of its parameters (a ClothLink whose p is unused),
   which few links differ in (a piece's links share them by direction). 12 bytes instead of ClothLink's 56: at 5.85
   links per particle of a sheet, 257 bytes per particle less. */
typedef struct {
  PetscInt p[2];
  PetscInt param;
} ClothLinkRef;

/* The full link of a reference. */
static inline ClothLink ClothLinkExpand(const ClothLink params[], ClothLinkRef ref)
{
  ClothLink link = params[ref.param];
  link.p[0]      = ref.p[0];
  link.p[1]      = ref.p[1];
  return link;
}

typedef enum {
  CLOTH_ANGLE_CORNER, /* arms p0->p1 and p0->p2 (warp-weft angle at a cell corner: shear) */
  CLOTH_ANGLE_CHAIN,  /* arms p0->p1 and p1->p2 (consecutive segments of one thread: bending) */
  CLOTH_ANGLE_CELL,   /* p0..p3 a grid cell counter-clockwise from node (i, j): arms are the warp and weft
                         tangents at its centre, (x1 - x0 + x2 - x3)/2 and (x3 - x0 + x2 - x1)/2 (shear
                         measured in the tangent plane: a cell folded or twisted out of plane is not sheared) */
  CLOTH_ANGLE_TWIST   /* p0..p3 a grid cell as above; not an angle spring but the cell's twist element, energy
                         k T^2 with T = d . (a x b), d = x0 - x1 + x2 - x3 (the bilinear map's mixed derivative),
                         a = x2 - x0, b = x3 - x1 (the diagonals). T is zero for a flat cell and for a cell bent
                         along either thread, 2 kappa12 A^2 for a twist kappa12 of a cell of area A: the twisting
                         rigidity the thread-angle springs lack (they give a bend along the bias (B_warp + B_weft)/4).
                         k = Bt / (2 A^3) on a rectangle gives the continuum energy 2 Bt kappa12^2 per area
                         (FabricTwistStiffness, which also bounds it on skewed cells);
                         cos0, sin0 and slip are unused. */
} ClothAngleKind;

#define CLOTH_ANGLE_MAX_PARTICLES 4

/* An angle spring with energy k (1 - cos(theta - theta0)), theta the angle between the two arms,
   theta0 its rest value (stored as cos and sin). For small deviations this is 0.5 k (theta - theta0)^2.
   Each arm is a fixed linear combination of the particles' positions (ClothAngleArms). */
typedef struct {
  PetscInt       p[CLOTH_ANGLE_MAX_PARTICLES]; /* the first ClothAngleParticleCount(kind) are used */
  ClothAngleKind kind;
  PetscReal      k;          /* N m */
  PetscReal      cos0, sin0; /* rest angle */
  PetscReal      slip;       /* > 0: a friction element, its rest angle follows theta to within slip (rad); 0: elastic */
} ClothAngle;

/* Bending hysteresis (KES-FB2's loop M = B K +- HB): beside each elastic thread-bending spring, a spring of
   CLOTH_HYSTERESIS_STIFFNESS times its stiffness in series with a Coulomb slider that gives way at the
   friction moment HB (a Jenkins element). Stiff, so that the curvature before slipping, HB / (10 B), is
   small against a drape's; not so stiff that it dominates the implicit system. */
#define CLOTH_HYSTERESIS_STIFFNESS 10.0

/* Energy of a link; force on p[1] (the force on p[0] is its negative); the 3x3 block K such that the
   link's Hessian is [K -K; -K K]. With psd, K is clamped to its positive semidefinite part (the
   compressive transverse term is dropped), as the implicit system needs. Any output may be NULL. */
PetscErrorCode ClothLinkEvaluate(const ClothLink *link, const PetscReal x0[3], const PetscReal x1[3], PetscBool psd, PetscReal *energy, PetscReal force1[3], PetscReal K[9]);

/* The stiffness an angle spring or twist element gives the implicit system.
   EXACT: the Hessian of its energy (indefinite away from rest: for tests and finite-difference checks).
   PROJECTED: the exact Hessian projected onto the positive semidefinite cone (an eigen-decomposition per element).
   GAUSS_NEWTON: the Gauss-Newton form J^T E'' J of the energy written as a function of a residual (the unit-arm
   difference for a straight-rest thread, the angle theta otherwise, T for the twist): positive semidefinite by
   construction, equal to the exact Hessian at rest, in closed form (no eigen-decomposition). */
typedef enum { CLOTH_STIFFNESS_EXACT, CLOTH_STIFFNESS_PROJECTED, CLOTH_STIFFNESS_GAUSS_NEWTON } ClothStiffness;

extern const char *const ClothStiffnessTypes[];

/* A positive semidefinite stiffness in factored form: sum over r < rank of lambda[r] q_r q_r^T, q_r the r-th row of
   q (3 np values, particle-major like the Hessian). The Gauss-Newton form of an angle spring has rank 1 to 3 (the
   arms' Jacobian), of a twist element rank 1, so K v, the constraint filter S K S and the element matrix cost
   O(rank n) or O(rank n^2) from the factors instead of O(n^2) to O(n^3) from the expanded matrix. */
#define CLOTH_STIFFNESS_MAX_RANK 3
typedef struct {
  PetscInt  rank;
  PetscReal lambda[CLOTH_STIFFNESS_MAX_RANK];
  PetscReal q[CLOTH_STIFFNESS_MAX_RANK][3 * CLOTH_ANGLE_MAX_PARTICLES];
} ClothFactoredStiffness;

/* H (n x n, row-major) = scale sum_r lambda_r q_r q_r^T, exactly symmetric. */
void ClothFactoredStiffnessExpand(const ClothFactoredStiffness *K, PetscInt n, PetscReal scale, PetscReal H[]);

/* Number of particles of an angle spring of this kind (3 or 4). */
PetscInt ClothAngleParticleCount(ClothAngleKind kind);
/* The arms of an angle spring as weights of its particles: arm a = sum_k A[k] x[p[k]], b = sum_k B[k] x[p[k]]
   (the same weights give the rest angle from the flat pattern). */
void ClothAngleArms(ClothAngleKind kind, PetscReal A[CLOTH_ANGLE_MAX_PARTICLES], PetscReal B[CLOTH_ANGLE_MAX_PARTICLES]);

/* Energy of an angle spring at positions x[k] of its np = ClothAngleParticleCount particles; forces on
   them (np x 3, row per particle); its 3np x 3np stiffness (row-major, particle-major) in the given form. Any output
   may be NULL. */
PetscErrorCode ClothAngleEvaluate(const ClothAngle *angle, const PetscReal *const x[], ClothStiffness form, PetscReal *energy, PetscReal force[], PetscReal H[]);
/* The same with the Gauss-Newton stiffness in factored form (K may be NULL: energy and forces only); equal to
   ClothAngleEvaluate's CLOTH_STIFFNESS_GAUSS_NEWTON H, which is this K expanded. */
PetscErrorCode ClothAngleEvaluateFactored(const ClothAngle *angle, const PetscReal *const x[], PetscReal *energy, PetscReal force[], ClothFactoredStiffness *K);

/* The slider of a friction element (slip > 0) at positions x[k]: where the arms' angle theta has moved more
   than slip from the rest angle, the rest angle follows to theta -+ slip, so that the moment
   k (theta - theta0) never exceeds k slip = the friction moment. theta is the unsigned angle between the
   arms, so a thread bent through straight keeps the slider's side: within slip of straight the friction
   moment may point the wrong way (at most one friction moment, over an angle of 2 slip). */
void ClothAngleSlide(ClothAngle *angle, const PetscReal *const x[]);

/* Projects a symmetric n x n matrix (row-major, n <= 12) onto the positive semidefinite cone in place. */
PetscErrorCode ClothProjectPSD(PetscInt n, PetscReal A[]);
