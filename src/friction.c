/* The regularised Coulomb friction law (see friction.h). */
#include "friction.h"
#include "vec3.h"

/* D = -df/dv_t = mu N / s (P - t t^T) + max(0, mu N eps^2 / s^3 + N mu'(u) u / s) t t^T (P = I - n n^T, t = v_t / u):
   across the motion the force turns with v_t, along it it changes only with the regularisation and the
   static-to-kinetic drop. The drop (mu' < 0) would make D indefinite and the system lose the positive definiteness CG
   needs, so its part of D is left out (clamped at 0): the drop then acts explicitly. drag_along: along the motion too
   D = mu N / s, the friction as a drag with the coefficient of the step's start: it over-brakes a sliding contact
   slightly but cannot carry it through v_t = 0 into a reversal within the step. */
PetscErrorCode ClothRegularisedFriction(PetscReal mu_s, PetscReal mu_k, PetscReal normal_force, PetscReal eps, PetscReal vs, PetscBool drag_along, const PetscReal n[3], const PetscReal vt[3], PetscReal f[3], PetscReal D[9])
{
  const PetscReal u = PetscSqrtReal(Dot3(vt, vt)), s = PetscSqrtReal(u * u + eps * eps);
  const PetscReal decay  = vs > 0 ? PetscExpReal(-PetscSqr(u / vs)) : 0.0;
  const PetscReal mu     = mu_k + (mu_s - mu_k) * decay;
  const PetscReal dmu    = vs > 0 ? -(mu_s - mu_k) * 2 * u / (vs * vs) * decay : 0.0;
  const PetscReal across = mu * normal_force / s;
  const PetscReal along  = drag_along ? across : PetscMax(0.0, mu * normal_force * eps * eps / (s * s * s) + normal_force * dmu * u / s);
  PetscReal       t[3]   = {0, 0, 0};

  PetscFunctionBeginUser;
  if (u > 0)
    for (PetscInt k = 0; k < 3; k++) t[k] = vt[k] / u;
  for (PetscInt k = 0; k < 3; k++) f[k] = -across * vt[k];
  for (PetscInt r = 0; r < 3; r++)
    for (PetscInt c = 0; c < 3; c++) D[3 * r + c] = across * ((r == c ? 1.0 : 0.0) - n[r] * n[c] - t[r] * t[c]) + along * t[r] * t[c];
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFrictionNormalLoad(const PetscReal force[3], const PetscReal n[3], PetscReal *normal_force)
{
  PetscFunctionBeginUser;
  *normal_force = PetscMax(0.0, -Dot3(force, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}
