/* Every force's Jacobian against central finite differences.

   1. Element level: links (with and without repulsion active; biphasic below and beyond the knee) and angle springs (corner, chain
      and cell, several rest angles) and the twist element at random configurations (cells: randomly distorted squares): force = -dE/dx and Hessian = d(-force)/dx.
   2. System level: the assembled implicit matrix of a small perturbed sheet with every interaction
      kind, A = M + h C + h^2 K, against finite differences of the total force in position and in
      velocity (damping). Relative error below 1e-6 everywhere. Prints nothing unless a check fails.
   3. What the cell shear spring measures (CheckCellShearMeasure), and the twist element (CheckTwistMeasure).
   4. The Gauss-Newton stiffness of angle springs and twist elements (CheckGaussNewton): equal to the exact Hessian at
      rest (relative 1e-9), positive semidefinite everywhere (unchanged by the LAPACK projection to 1e-12), and within
      1e-2 of the projected Hessian after a displacement of 1e-4 of the element's size. */
#include <petscsys.h>
#include "forces.h"
#include "seam.h"
#include "cloth.h"
#include "test_support.h"

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
  const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES] = {&x[0], &x[3], &x[6], &x[9]};

  PetscFunctionBeginUser;
  PetscCall(ClothAngleEvaluate((const ClothAngle *)ctx, xs, CLOTH_STIFFNESS_EXACT, E, f, H));
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
  PetscReal      E, f[12], H[144], fd_force[12], fd_H[144], xp[12], Ep, Em, fp[12], fm[12], Hs[144];

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
    PetscReal  x[12];
    ClothLink  link;
    ClothAngle angle;
    for (PetscInt i = 0; i < 12; i++) x[i] = Uniform(rnd, -0.01, 0.01);
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
      l                     = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      biphasic.rest         = 0.5 * l;
      biphasic.repel_length = 0;
      biphasic.knee_length  = (trial % 2) ? 0.25 * l : 0.75 * l;
      biphasic.k_stiff      = Uniform(rnd, 2, 10) * link.k;
      PetscCall(CheckElement(LinkFunction, &biphasic, 2, x, (trial % 2) ? "biphasic link beyond the knee" : "biphasic link below the knee"));
    }
    for (PetscInt kind = CLOTH_ANGLE_CORNER; kind <= CLOTH_ANGLE_TWIST; kind++) {
      const char *const names[] = {"corner angle", "chain angle", "cell angle", "cell twist"};
      const PetscReal   theta0  = (trial % 4 == 0) ? (kind == CLOTH_ANGLE_CHAIN ? 0.0 : PETSC_PI / 2) : Uniform(rnd, 0.05, PETSC_PI - 0.05);
      for (PetscInt k = 0; k < CLOTH_ANGLE_MAX_PARTICLES; k++) angle.p[k] = k;
      angle.kind = (ClothAngleKind)kind;
      angle.k    = Uniform(rnd, 1e-6, 1e-3);
      angle.cos0 = PetscCosReal(theta0);
      angle.sin0 = PetscSinReal(theta0);
      if (ClothAngleParticleCount(angle.kind) == 4) { /* a cell: a 1 cm square, each corner moved by up to 4 mm in 3D */
        const PetscReal corner[4][2] = {{0, 0}, {0.01, 0}, {0.01, 0.01}, {0, 0.01}};
        PetscReal       xc[12];
        for (PetscInt q = 0; q < 4; q++)
          for (PetscInt c = 0; c < 3; c++) xc[3 * q + c] = (c < 2 ? corner[q][c] : 0.0) + 0.4 * x[3 * q + c];
        PetscCall(CheckElement(AngleFunction, &angle, 4, xc, names[kind]));
      } else
        PetscCall(CheckElement(AngleFunction, &angle, 3, x, names[kind]));
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

/* The slider of a friction element (ClothAngleSlide) along a loading path of a chain bent in its plane, slip 0.05 rad:
   bent to 0.03 it sticks (rest 0); to 0.3 it slides (rest 0.25, so the moment k (theta - rest) is the friction
   moment k slip); back to 0.22 it sticks again (rest 0.25); back to 0.1 it slides the other way (rest 0.15). */
static PetscErrorCode CheckFrictionSlide(void)
{
  ClothAngle      angle   = {{0, 1, 2, 0}, CLOTH_ANGLE_CHAIN, 2.0, 1.0, 0.0, 0.05};
  const PetscReal path[4] = {0.03, 0.3, 0.22, 0.1}, rest[4] = {0, 0.25, 0.25, 0.15};

  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < 4; s++) {
    const PetscReal  x[9]  = {-1, 0, 0, 0, 0, 0, PetscCosReal(path[s]), PetscSinReal(path[s]), 0};
    const PetscReal *xs[3] = {&x[0], &x[3], &x[6]};
    PetscReal        got;

    ClothAngleSlide(&angle, xs);
    got = PetscAtan2Real(angle.sin0, angle.cos0);
    PetscCheck(PetscAbsReal(got - rest[s]) < 1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Friction slider bent to %g rad: rest angle %.15g, expected %g", (double)path[s], (double)got, (double)rest[s]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Total shear energy of one square cell (side h, rest angle 90 degrees, G A = 1) at corners x (counter-clockwise
   from (0, 0)): one cell spring, or the four corner springs of G A / 4 each. */
static PetscErrorCode CellShearEnergy(const PetscReal x[12], PetscBool cell, PetscReal *energy)
{
  ClothAngle angle = {{0, 1, 2, 3}, CLOTH_ANGLE_CELL, 1.0, 0.0, 1.0, 0.0};
  PetscReal  e;

  PetscFunctionBeginUser;
  *energy = 0;
  if (cell) {
    const PetscReal *xs[4] = {&x[0], &x[3], &x[6], &x[9]};
    PetscCall(ClothAngleEvaluate(&angle, xs, CLOTH_STIFFNESS_EXACT, energy, NULL, NULL));
  } else {
    angle.kind = CLOTH_ANGLE_CORNER;
    angle.k    = 0.25;
    for (PetscInt k = 0; k < 4; k++) { /* corner k, arms to its two neighbours (as model.c) */
      const PetscReal *xs[3] = {&x[3 * k], &x[3 * ((k + 1) % 4)], &x[3 * ((k + 3) % 4)]};
      PetscCall(ClothAngleEvaluate(&angle, xs, CLOTH_STIFFNESS_EXACT, &e, NULL, NULL));
      *energy += e;
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What the cell shear spring measures, against the corner springs, on a 1 cm square cell:
   - in-plane shear by gamma = 0.01: both give 0.5 G A gamma^2 (relative 1e-4: k (1 - cos) against the quadratic);
   - the cell folded out of plane with all four sides and both diagonals kept equal (corners 1 and 3 lifted by
     0.3 h: a twist, which is also how a fold across a cell's diagonal is taken up without stretching its
     edges): the threads stay at 90 degrees in the tangent plane, so the cell spring gives 0 (below 1e-12), while
     the corner springs, which measure the 3D angle between the cell's edges, charge it (>= 1e-3 G A). */
static PetscErrorCode CheckCellShearMeasure(void)
{
  const PetscReal h = 0.01, gamma = 0.01, z = 0.3 * h;
  const PetscReal sheared[12] = {0, 0, 0, h, 0, 0, h + h * PetscTanReal(gamma), h, 0, h * PetscTanReal(gamma), h, 0};
  const PetscReal twisted[12] = {0, 0, 0, h, 0, z, h, h, 0, 0, h, z};
  PetscReal       e_cell, e_corner;

  PetscFunctionBeginUser;
  PetscCall(CellShearEnergy(sheared, PETSC_TRUE, &e_cell));
  PetscCall(CellShearEnergy(sheared, PETSC_FALSE, &e_corner));
  PetscCheck(PetscAbsReal(e_cell / (0.5 * gamma * gamma) - 1) < 1e-4 && PetscAbsReal(e_corner / (0.5 * gamma * gamma) - 1) < 1e-4, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "in-plane shear 0.01: energies %g (cell) and %g (corners), expected 0.5 G A gamma^2 = %g", (double)e_cell, (double)e_corner, (double)(0.5 * gamma * gamma));
  PetscCall(CellShearEnergy(twisted, PETSC_TRUE, &e_cell));
  PetscCall(CellShearEnergy(twisted, PETSC_FALSE, &e_corner));
  PetscCheck(e_cell < 1e-12 && e_corner > 1e-3, PETSC_COMM_SELF, PETSC_ERR_PLIB, "unsheared twisted cell: energies %g (cell, expected 0) and %g (corners, expected > 1e-3)", (double)e_cell, (double)e_corner);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* What the twist element measures, on a square cell of side h = 1 cm with k = Bt / (2 A^3) (FabricTwistStiffness),
   its corners lifted onto a surface z(x, y) (exact: T is a polynomial of the corners):
   - bent along either thread (z = kappa x^2 / 2, z = kappa y^2 / 2): 0, the thread springs' business;
   - twisted (z = kappa x y, kappa12 = kappa): 2 Bt kappa^2 A, the continuum 2 Bt kappa12^2 per area;
   - bent along the bias (z = kappa (x + y)^2 / 4, kappa12 = kappa / 2): 0.5 Bt kappa^2 A, so the bias rigidity
     gains Bt. Relative 1e-12. */
static PetscErrorCode CheckTwistMeasure(void)
{
  const PetscReal h = 0.01, A = h * h, Bt = 3e-6, kappa = 20;
  const PetscReal corner[4][2] = {{0, 0}, {h, 0}, {h, h}, {0, h}};
  const PetscReal expected[4]  = {0, 0, 2 * Bt * kappa * kappa * A, 0.5 * Bt * kappa * kappa * A};
  const char     *names[4]     = {"bent along u", "bent along v", "twisted", "bent along the bias"};
  ClothAngle      twist        = {{0, 1, 2, 3}, CLOTH_ANGLE_TWIST, Bt / (2 * A * A * A), 1.0, 0.0, 0.0};

  PetscFunctionBeginUser;
  for (PetscInt shape = 0; shape < 4; shape++) {
    PetscReal        x[12], E;
    const PetscReal *xs[4] = {&x[0], &x[3], &x[6], &x[9]};

    for (PetscInt q = 0; q < 4; q++) {
      const PetscReal u = corner[q][0], v = corner[q][1];
      const PetscReal z[4] = {0.5 * kappa * u * u, 0.5 * kappa * v * v, kappa * u * v, 0.25 * kappa * (u + v) * (u + v)};
      x[3 * q]             = u;
      x[3 * q + 1]         = v;
      x[3 * q + 2]         = z[shape];
    }
    PetscCall(ClothAngleEvaluate(&twist, xs, CLOTH_STIFFNESS_EXACT, &E, NULL, NULL));
    PetscCheck(PetscAbsReal(E - expected[shape]) <= 1e-12 * 2 * Bt * kappa * kappa * A, PETSC_COMM_SELF, PETSC_ERR_PLIB, "twist element, cell %s: energy %g, expected %g", names[shape], (double)E, (double)expected[shape]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Stiffness of an angle spring or twist element at x in the given form (n = 3 np). */
static PetscErrorCode AngleStiffness(const ClothAngle *angle, const PetscReal x[12], ClothStiffness form, PetscReal H[144])
{
  const PetscReal *xs[CLOTH_ANGLE_MAX_PARTICLES] = {&x[0], &x[3], &x[6], &x[9]};

  PetscFunctionBeginUser;
  PetscCall(ClothAngleEvaluate(angle, xs, form, NULL, NULL, H));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Sets an angle spring's rest angle to its angle at x (a twist element is at rest on a flat cell: z = 0 there). */
static void SetRestAngle(ClothAngle *angle, const PetscReal x[12])
{
  PetscReal A[CLOTH_ANGLE_MAX_PARTICLES], B[CLOTH_ANGLE_MAX_PARTICLES], a[3] = {0, 0, 0}, b[3] = {0, 0, 0}, axb[3], theta;

  ClothAngleArms(angle->kind, A, B);
  for (PetscInt k = 0; k < ClothAngleParticleCount(angle->kind); k++)
    for (PetscInt i = 0; i < 3; i++) {
      a[i] += A[k] * x[3 * k + i];
      b[i] += B[k] * x[3 * k + i];
    }
  axb[0]      = a[1] * b[2] - a[2] * b[1];
  axb[1]      = a[2] * b[0] - a[0] * b[2];
  axb[2]      = a[0] * b[1] - a[1] * b[0];
  theta       = PetscAtan2Real(PetscSqrtReal(axb[0] * axb[0] + axb[1] * axb[1] + axb[2] * axb[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
  angle->cos0 = PetscCosReal(theta);
  angle->sin0 = PetscSinReal(theta);
}

static PetscErrorCode CheckGaussNewton(PetscRandom rnd)
{
  const char *const names[] = {"corner angle", "chain angle", "cell angle", "cell twist", "straight chain"};

  PetscFunctionBeginUser;
  for (PetscInt trial = 0; trial < 200; trial++)
    for (PetscInt variant = 0; variant < 5; variant++) {
      const PetscInt kind  = variant == 4 ? CLOTH_ANGLE_CHAIN : variant;
      ClothAngle     angle = {{0, 1, 2, 3}, (ClothAngleKind)kind, Uniform(rnd, 1e-6, 1e-3), 1.0, 0.0, 0.0};
      const PetscInt n     = 3 * ClothAngleParticleCount(angle.kind);
      PetscReal      x[12], xd[12], H[144], Hgn[144], Hp[144], err;

      if (variant == 4) { /* three particles on a line: a straight thread at rest */
        PetscReal       u[3], len = 0;
        const PetscReal ratio = Uniform(rnd, 0.5, 1.5); /* of the second segment to the first */
        for (PetscInt i = 0; i < 3; i++) u[i] = Uniform(rnd, -1, 1);
        for (PetscInt i = 0; i < 3; i++) len += u[i] * u[i];
        for (PetscInt i = 0; i < 3; i++) {
          x[i]     = Uniform(rnd, -0.01, 0.01);
          x[3 + i] = x[i] + 0.01 * u[i] / PetscSqrtReal(len);
          x[6 + i] = x[3 + i] + ratio * 0.01 * u[i] / PetscSqrtReal(len);
        }
      } else if (n == 12) { /* a cell: a distorted 1 cm square, flat (z = 0) so that the twist element is at rest */
        const PetscReal corner[4][2] = {{0, 0}, {0.01, 0}, {0.01, 0.01}, {0, 0.01}};
        for (PetscInt q = 0; q < 4; q++)
          for (PetscInt c = 0; c < 3; c++) x[3 * q + c] = c < 2 ? corner[q][c] + Uniform(rnd, -0.003, 0.003) : 0.0;
      } else
        for (PetscInt i = 0; i < 9; i++) x[i] = Uniform(rnd, -0.01, 0.01);
      if (kind != CLOTH_ANGLE_TWIST && variant != 4) SetRestAngle(&angle, x);
      PetscCall(AngleStiffness(&angle, x, CLOTH_STIFFNESS_EXACT, H));
      PetscCall(AngleStiffness(&angle, x, CLOTH_STIFFNESS_GAUSS_NEWTON, Hgn));
      err = RelativeError(n * n, H, Hgn);
      PetscCheck(err < 1e-9, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s at rest: Gauss-Newton stiffness differs from the exact Hessian by %g (relative)", names[variant], (double)err);
      for (PetscInt scale = 0; scale < 2; scale++) { /* a small and a large displacement */
        const PetscReal amplitude = scale ? 0.004 : 1e-6;
        for (PetscInt i = 0; i < n; i++) xd[i] = x[i] + Uniform(rnd, -amplitude, amplitude);
        PetscCall(AngleStiffness(&angle, xd, CLOTH_STIFFNESS_GAUSS_NEWTON, Hgn));
        for (PetscInt i = 0; i < n * n; i++) Hp[i] = Hgn[i];
        PetscCall(ClothProjectPSD(n, Hp));
        err = RelativeError(n * n, Hgn, Hp);
        PetscCheck(err < 1e-12, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s displaced by %g m: Gauss-Newton stiffness is not positive semidefinite (projection changes it by %g)", names[variant], (double)amplitude, (double)err);
        if (scale) continue;
        PetscCall(AngleStiffness(&angle, xd, CLOTH_STIFFNESS_PROJECTED, Hp));
        err = RelativeError(n * n, Hp, Hgn);
        PetscCheck(err < 1e-2, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%s near rest: Gauss-Newton stiffness differs from the projected Hessian by %g (relative)", names[variant], (double)err);
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
  PetscCall(CheckCellShearMeasure());
  PetscCall(CheckTwistMeasure());
  PetscCall(CheckFrictionSlide());
  PetscCall(CheckGaussNewton(rnd));
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
