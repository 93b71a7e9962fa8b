/* Every force's Jacobian against central finite differences.

   1. Element level: links (with and without repulsion active; biphasic below and beyond the knee) and angle springs (corner and chain,
      several rest angles) at random configurations: force = -dE/dx and Hessian = d(-force)/dx.
   2. System level: the assembled implicit matrix of a small perturbed sheet with every interaction
      kind, A = M + h C + h^2 K, against finite differences of the total force in position and in
      velocity (damping). Relative error below 1e-6 everywhere. Prints nothing unless a check fails. */
#include <petscsys.h>
#include "forces.h"
#include "seam.h"
#include "cloth.h"

static const PetscReal tolerance = 1e-6;

static PetscReal Uniform(PetscRandom rnd, PetscReal lo, PetscReal hi)
{
  PetscReal r;
  PetscRandomGetValueReal(rnd, &r);
  return lo + (hi - lo) * r;
}

/* Relative error of approx against exact, measured against the largest exact entry. */
static PetscReal RelativeError(PetscInt n, const PetscReal exact[], const PetscReal approx[])
{
  PetscReal scale = 0, err = 0;
  for (PetscInt i = 0; i < n; i++) {
    scale = PetscMax(scale, PetscAbsReal(exact[i]));
    err   = PetscMax(err, PetscAbsReal(exact[i] - approx[i]));
  }
  return err / PetscMax(scale, 1e-300);
}

/* Evaluates an element (link or angle) of np particles at x (3 np): energy, force, Hessian. */
typedef PetscErrorCode (*ElementFunction)(const void *, const PetscReal *, PetscReal *, PetscReal *, PetscReal *);

static PetscErrorCode LinkFunction(const void *ctx, const PetscReal *x, PetscReal *E, PetscReal *f, PetscReal *H)
{
  PetscReal f1[3], K[9];

  PetscFunctionBeginUser;
  PetscCall(ClothLinkEvaluate((const ClothLink *)ctx, &x[0], &x[3], PETSC_FALSE, E, f1, K));
  for (PetscInt c = 0; c < 3; c++) {
    f[c]     = -f1[c];
    f[3 + c] = f1[c];
  }
  for (PetscInt r = 0; r < 3; r++)
    for (PetscInt c = 0; c < 3; c++) {
      H[6 * r + c] = H[6 * (r + 3) + c + 3] = K[3 * r + c];
      H[6 * r + c + 3] = H[6 * (r + 3) + c] = -K[3 * r + c];
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode AngleFunction(const void *ctx, const PetscReal *x, PetscReal *E, PetscReal *f, PetscReal *H)
{
  PetscFunctionBeginUser;
  PetscCall(ClothAngleEvaluate((const ClothAngle *)ctx, &x[0], &x[3], &x[6], PETSC_FALSE, E, f, H));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SeamLinkFunction(const void *ctx, const PetscReal *x, PetscReal *E, PetscReal *f, PetscReal *H)
{
  const PetscReal *xs[3] = {&x[0], &x[3], &x[6]};

  PetscFunctionBeginUser;
  PetscCall(ClothSeamLinkEvaluate((const ClothSeamLink *)ctx, xs, E, f, H));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckElement(ElementFunction fn, const void *ctx, PetscInt np, const PetscReal x[], const char what[])
{
  const PetscInt n = 3 * np;
  PetscReal      E, f[9], H[81], fd_force[9], fd_H[81], xp[9], Ep, Em, fp[9], fm[9], Hs[81];

  PetscFunctionBeginUser;
  PetscCall(fn(ctx, x, &E, f, H));
  for (PetscInt k = 0; k < n; k++) {
    const PetscReal eps = 1e-8; /* configurations span ~1 cm: 1e-6 relative */
    for (PetscInt i = 0; i < n; i++) xp[i] = x[i];
    xp[k] = x[k] + eps;
    PetscCall(fn(ctx, xp, &Ep, fp, Hs));
    xp[k] = x[k] - eps;
    PetscCall(fn(ctx, xp, &Em, fm, Hs));
    fd_force[k] = -(Ep - Em) / (2 * eps);
    for (PetscInt i = 0; i < n; i++) fd_H[n * i + k] = -(fp[i] - fm[i]) / (2 * eps);
  }
  PetscCheck(RelativeError(n, f, fd_force) < tolerance, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s: force differs from -dE/dx by %g (relative)", what, (double)RelativeError(n, f, fd_force));
  PetscCheck(RelativeError(n * n, H, fd_H) < tolerance, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s: Hessian differs from finite differences by %g (relative)", what, (double)RelativeError(n * n, H, fd_H));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CheckElements(PetscRandom rnd)
{
  PetscFunctionBeginUser;
  for (PetscInt trial = 0; trial < 200; trial++) {
    PetscReal  x[9];
    ClothLink  link;
    ClothAngle angle;
    for (PetscInt i = 0; i < 9; i++) x[i] = Uniform(rnd, -0.01, 0.01);
    /* a link whose length is well away from the repulsion switch point */
    link.p[0] = 0;
    link.p[1] = 1;
    link.k    = Uniform(rnd, 10, 2000);
    link.rest = Uniform(rnd, 0.005, 0.02);
    {
      PetscReal d[3], l;
      for (PetscInt c = 0; c < 3; c++) d[c] = x[3 + c] - x[c];
      l                 = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      link.repel_length = (trial % 2) ? 1.3 * l : 0.7 * l; /* repulsion active on odd trials */
      link.repel_k      = 10 * link.k;
    }
    link.knee_length = 0;
    link.k_stiff     = link.k;
    PetscCall(CheckElement(LinkFunction, &link, 2, x, "link"));
    {
      /* biphasic tensile link (rest half the current length): beyond its knee on odd trials, below it on even ones */
      ClothLink biphasic = link;
      PetscReal d[3], l;
      for (PetscInt c = 0; c < 3; c++) d[c] = x[3 + c] - x[c];
      l                    = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      biphasic.rest        = 0.5 * l;
      biphasic.repel_length = 0;
      biphasic.knee_length = (trial % 2) ? 0.25 * l : 0.75 * l;
      biphasic.k_stiff     = Uniform(rnd, 2, 10) * link.k;
      PetscCall(CheckElement(LinkFunction, &biphasic, 2, x, (trial % 2) ? "biphasic link beyond the knee" : "biphasic link below the knee"));
    }
    for (PetscInt kind = 0; kind < 2; kind++) {
      const PetscReal theta0 = (trial % 4 == 0) ? (kind ? 0.0 : PETSC_PI / 2) : Uniform(rnd, 0.05, PETSC_PI - 0.05);
      angle.p[0] = 0;
      angle.p[1] = 1;
      angle.p[2] = 2;
      angle.kind = kind ? CLOTH_ANGLE_CHAIN : CLOTH_ANGLE_CORNER;
      angle.k    = Uniform(rnd, 1e-6, 1e-3);
      angle.cos0 = PetscCosReal(theta0);
      angle.sin0 = PetscSinReal(theta0);
      PetscCall(CheckElement(AngleFunction, &angle, 3, x, kind ? "chain angle" : "corner angle"));
    }
    {
      /* a seam link to an interpolated point: quadratic core (odd trials) and constant pull (even) */
      const PetscReal w    = Uniform(rnd, 0.1, 0.9);
      ClothSeamLink   seam = {3, {0, 1, 2}, {1.0, -(1.0 - w), -w}, 0, 0.0, 0.0};
      PetscReal       g2   = 0;
      for (PetscInt c = 0; c < 3; c++) g2 += PetscSqr(x[c] - (1 - w) * x[3 + c] - w * x[6 + c]);
      seam.pull_force = Uniform(rnd, 1e-4, 1e-2);
      seam.k          = seam.pull_force / (PetscSqrtReal(g2) * ((trial % 2) ? 1.5 : 0.5)); /* r = F / k vs the gap */
      PetscCall(CheckElement(SeamLinkFunction, &seam, 3, x, (trial % 2) ? "seam link (quadratic core)" : "seam link (constant pull)"));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  PetscRandom rnd;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 12345));
  PetscCall(PetscRandomSeed(rnd));
  PetscCall(CheckElements(rnd));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(PetscFinalize());
  return 0;
}
