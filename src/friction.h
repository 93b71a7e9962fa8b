/* The regularised Coulomb friction law of contacts in the implicit step, shared by the body contacts (collision_response.c,
   -collision_friction implicit) and the cloth-cloth contacts (selfcontact.c, -self_collision_friction); see
   docs/collisions.md, "Friction inside the implicit step". */
#pragma once
#include "util.h"

/* The friction force f on a contact with unit normal n, tangential (relative) velocity vt and normal force
   normal_force >= 0, and D = -df/dv_t (symmetric, positive semidefinite, tangential):
     f = -mu(u) N v_t / s,  u = |v_t|,  s = sqrt(u^2 + eps^2),  mu(u) = mu_k + (mu_s - mu_k) exp(-(u / v_s)^2)
   (v_s = 0: mu_k alone). drag_along: D along the motion is the drag mu N / s instead of the derivative (for contacts
   whose friction impulse over the step could reverse their slip). Not collective. */
PetscErrorCode ClothRegularisedFriction(PetscReal mu_s, PetscReal mu_k, PetscReal normal_force, PetscReal eps, PetscReal vs, PetscBool drag_along, const PetscReal n[3], const PetscReal vt[3], PetscReal f[3], PetscReal D[9]);

/* The normal force N = max(0, -F.n) that a force F (the particle's force without the contact's own) presses a
   particle with onto a contact whose normal n points from the contact into the particle: the load the contact carries
   at rest, the normal force of both the body friction and the friction between layers. Not collective. */
PetscErrorCode ClothFrictionNormalLoad(const PetscReal force[3], const PetscReal n[3], PetscReal *normal_force);
