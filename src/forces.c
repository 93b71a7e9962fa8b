/* Element kernels of the fabric model (see forces.h). */
#include "forces.h"
#include "log.h"
#include <petscblaslapack.h>
#include "vec3.h"

const char *const ClothStiffnessTypes[] = {"exact", "projected", "gauss_newton", "ClothStiffness", "CLOTH_STIFFNESS_", NULL};

/* Link potential phi(l) and its first two derivatives. */
static void LinkPotential(const ClothLink *link, PetscReal l, PetscReal *phi, PetscReal *dphi, PetscReal *d2phi)
{
  const PetscReal stretch = l - link->rest, knee = link->knee_length;

  if (knee > 0 && stretch > knee) { /* biphasic: the stiff branch continues the soft one's energy and force */
    const PetscReal beyond = stretch - knee;

    *phi   = 0.5 * link->k * knee * knee + link->k * knee * beyond + 0.5 * link->k_stiff * beyond * beyond;
    *dphi  = link->k * knee + link->k_stiff * beyond;
    *d2phi = link->k_stiff;
  } else {
    *phi   = 0.5 * link->k * stretch * stretch;
    *dphi  = link->k * stretch;
    *d2phi = link->k;
  }
  if (link->repel_length > 0 && l < link->repel_length) {
    const PetscReal gap = link->repel_length - l;
    *phi += 0.5 * link->repel_k * gap * gap;
    *dphi -= link->repel_k * gap;
    *d2phi += link->repel_k;
  }
}

PetscErrorCode ClothLinkEvaluate(const ClothLink *link, const PetscReal x0[3], const PetscReal x1[3], PetscBool psd, PetscReal *energy, PetscReal force1[3], PetscReal K[9])
{
  PetscReal d[3], l, phi, dphi, d2phi, axial, transverse;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < 3; c++) d[c] = x1[c] - x0[c];
  l = PetscSqrtReal(Dot3(d, d));
  PetscCheck(l > 0, PETSC_COMM_SELF, PETSC_ERR_FP, "Link between particles %" PetscInt_FMT " and %" PetscInt_FMT " has zero length", link->p[0], link->p[1]);
  for (PetscInt c = 0; c < 3; c++) d[c] /= l;
  LinkPotential(link, l, &phi, &dphi, &d2phi);
  if (energy) *energy = phi;
  if (force1)
    for (PetscInt c = 0; c < 3; c++) force1[c] = -dphi * d[c];
  if (K) {
    /* Hessian of phi(|x1 - x0|) w.r.t. x1: phi'' d d^T + (phi'/l)(I - d d^T). */
    axial      = d2phi;
    transverse = dphi / l;
    if (psd) {
      axial      = PetscMax(axial, 0.0);
      transverse = PetscMax(transverse, 0.0);
    }
    for (PetscInt r = 0; r < 3; r++)
      for (PetscInt c = 0; c < 3; c++) K[3 * r + c] = (axial - transverse) * d[r] * d[c] + (r == c ? transverse : 0.0);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscInt ClothAngleParticleCount(ClothAngleKind kind)
{
  return (kind == CLOTH_ANGLE_CELL || kind == CLOTH_ANGLE_TWIST) ? 4 : 3;
}

void ClothAngleArms(ClothAngleKind kind, PetscReal A[CLOTH_ANGLE_MAX_PARTICLES], PetscReal B[CLOTH_ANGLE_MAX_PARTICLES])
{
  static const PetscReal arms[4][2][CLOTH_ANGLE_MAX_PARTICLES] = {
      {{-1, 1, 0, 0}, {-1, 0, 1, 0}},                   /* corner */
      {{-1, 1, 0, 0}, {0, -1, 1, 0}},                   /* chain */
      {{-0.5, 0.5, 0.5, -0.5}, {-0.5, -0.5, 0.5, 0.5}}, /* cell: d/du and d/dv of the bilinear map at the centre */
      {{-1, 0, 1, 0}, {0, -1, 0, 1}}                    /* twist: the cell's diagonals (TwistEvaluate) */
  };

  for (PetscInt k = 0; k < CLOTH_ANGLE_MAX_PARTICLES; k++) {
    A[k] = arms[kind][0][k];
    B[k] = arms[kind][1][k];
  }
}

/* c = a.b / (|a||b|), its gradient g = (dc/da, dc/db) and Hessian Hc (6x6, row-major; NULL: not wanted, as for forces
   alone and the Gauss-Newton stiffness, which needs only g). */
static void NormalizedDot(const PetscReal a[3], const PetscReal b[3], PetscReal *c, PetscReal g[6], PetscReal Hc[36])
{
  const PetscReal na2 = Dot3(a, a), nb2 = Dot3(b, b), na = PetscSqrtReal(na2), nb = PetscSqrtReal(nb2);
  const PetscReal d = Dot3(a, b), inv = 1.0 / (na * nb);

  *c = d * inv;
  for (PetscInt i = 0; i < 3; i++) {
    g[i]     = (b[i] - d * a[i] / na2) * inv;
    g[3 + i] = (a[i] - d * b[i] / nb2) * inv;
  }
  if (!Hc) return;
  for (PetscInt i = 0; i < 3; i++) {
    for (PetscInt j = 0; j < 3; j++) {
      const PetscReal delta = (i == j) ? 1.0 : 0.0;
      /* d2c/da_i da_j */
      Hc[6 * i + j] = (-(b[i] * a[j] + a[i] * b[j]) - d * delta + 3.0 * d * a[i] * a[j] / na2) * inv / na2;
      /* d2c/db_i db_j */
      Hc[6 * (3 + i) + 3 + j] = (-(a[i] * b[j] + b[i] * a[j]) - d * delta + 3.0 * d * b[i] * b[j] / nb2) * inv / nb2;
      /* d2c/da_i db_j */
      Hc[6 * i + 3 + j]   = (delta - a[i] * a[j] / na2 - b[i] * b[j] / nb2 + d * a[i] * b[j] / (na2 * nb2)) * inv;
      Hc[6 * (3 + j) + i] = Hc[6 * i + 3 + j];
    }
  }
}

/* The arms a, b of an angle spring at its particles' positions x[k] (weights from ClothAngleArms). */
static void AngleArmVectors(const ClothAngle *angle, const PetscReal *const x[], PetscReal A[CLOTH_ANGLE_MAX_PARTICLES], PetscReal B[CLOTH_ANGLE_MAX_PARTICLES], PetscReal a[3], PetscReal b[3])
{
  ClothAngleArms(angle->kind, A, B);
  for (PetscInt i = 0; i < 3; i++) a[i] = b[i] = 0;
  for (PetscInt k = 0; k < ClothAngleParticleCount(angle->kind); k++)
    for (PetscInt i = 0; i < 3; i++) {
      a[i] += A[k] * x[k][i];
      b[i] += B[k] * x[k][i];
    }
}

/* S[p][q] = sum_m eps_pqm v_m, the antisymmetric matrix of the trilinear form det[., ., v]. */
static void LeviCivitaContract(const PetscReal v[3], PetscReal S[3][3])
{
  S[0][0] = S[1][1] = S[2][2] = 0;
  S[0][1]                     = v[2];
  S[1][0]                     = -v[2];
  S[0][2]                     = -v[1];
  S[2][0]                     = v[1];
  S[1][2]                     = v[0];
  S[2][1]                     = -v[0];
}

/* The twist element (CLOTH_ANGLE_TWIST): E = k T^2, T = det[d, a, b] with d, a, b fixed combinations of the four
   positions (weights D, Aw, Bw). T is trilinear, so its gradient and Hessian are exact and short:
   dT/dx_k = D_k a x b + Aw_k b x d + Bw_k d x a, and the (k p, l q) second derivative is
   S_b[p][q] (D_k Aw_l - Aw_k D_l) + S_a[p][q] (Bw_k D_l - D_k Bw_l) + S_d[p][q] (Aw_k Bw_l - Bw_k Aw_l). */
static PetscErrorCode TwistEvaluate(const ClothAngle *twist, const PetscReal *const x[], ClothStiffness form, PetscReal *energy, PetscReal force[], PetscReal H[], ClothFactoredStiffness *F)
{
  static const PetscReal D[4] = {1, -1, 1, -1};
  PetscReal              Aw[CLOTH_ANGLE_MAX_PARTICLES], Bw[CLOTH_ANGLE_MAX_PARTICLES], a[3], b[3], d[3] = {0, 0, 0}, axb[3], bxd[3], dxa[3], T, grad[12];

  PetscFunctionBeginUser;
  AngleArmVectors(twist, x, Aw, Bw, a, b);
  for (PetscInt k = 0; k < 4; k++)
    for (PetscInt i = 0; i < 3; i++) d[i] += D[k] * x[k][i];
  Cross3(a, b, axb);
  Cross3(b, d, bxd);
  Cross3(d, a, dxa);
  T = Dot3(d, axb);
  for (PetscInt k = 0; k < 4; k++)
    for (PetscInt i = 0; i < 3; i++) grad[3 * k + i] = D[k] * axb[i] + Aw[k] * bxd[i] + Bw[k] * dxa[i];
  if (energy) *energy = twist->k * T * T;
  if (force)
    for (PetscInt i = 0; i < 12; i++) force[i] = -2 * twist->k * T * grad[i];
  if (F) { /* Gauss-Newton: 2 k grad T grad T^T, drops the term in T, zero at rest */
    F->rank      = 1;
    F->lambda[0] = 2 * twist->k;
    for (PetscInt i = 0; i < 12; i++) F->q[0][i] = grad[i];
  }
  if (H) {
    PetscReal Sa[3][3], Sb[3][3], Sd[3][3];

    LeviCivitaContract(a, Sa);
    LeviCivitaContract(b, Sb);
    LeviCivitaContract(d, Sd);
    for (PetscInt k = 0; k < 4; k++)
      for (PetscInt l = 0; l < 4; l++)
        for (PetscInt p = 0; p < 3; p++)
          for (PetscInt q = 0; q < 3; q++) {
            const PetscReal HT              = Sb[p][q] * (D[k] * Aw[l] - Aw[k] * D[l]) + Sa[p][q] * (Bw[k] * D[l] - D[k] * Bw[l]) + Sd[p][q] * (Aw[k] * Bw[l] - Bw[k] * Aw[l]);
            H[12 * (3 * k + p) + 3 * l + q] = 2 * twist->k * (grad[3 * k + p] * grad[3 * l + q] + T * HT);
          }
    if (form == CLOTH_STIFFNESS_PROJECTED) PetscCall(ClothProjectPSD(12, H));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gauss-Newton stiffness of an angle spring with respect to its arms (a, b), as factors: sum_r lambda_r u_r u_r^T
   (u_r of 6 values). For a straight rest (theta0 = 0) the energy is k (1 - c) = (k/2) |a/|a| - b/|b||^2, whose
   residual's Jacobian J = [P_a/|a|, -P_b/|b|] (P the projector normal to an arm) gives k J^T J: both bending
   directions, no singularity at a straight thread; its three rows are the factors (P_a P_a = P_a).
   Otherwise E = k (1 - cos(theta - theta0)) as a function of theta gives k max(cos(theta - theta0), 0) grad theta
   grad theta^T with grad theta = -grad c / sin theta, in the arms' plane; when the spring is bent beyond its rest
   angle, the positive out-of-plane curvature of theta, (dE/dtheta / sin theta) u u^T with u = (n/|a|, -n/|b|), n the
   plane's unit normal, is kept too: as theta0 -> 0 it becomes the straight form's out-of-plane part, so the
   stiffness does not jump when a slider moves a rest angle off zero. */
static void AngleGaussNewton(const ClothAngle *angle, const PetscReal a[3], const PetscReal b[3], PetscReal c, PetscReal s, const PetscReal g[6], PetscReal sin_floor, PetscInt *rank, PetscReal lambda[CLOTH_STIFFNESS_MAX_RANK],
                             PetscReal u[CLOTH_STIFFNESS_MAX_RANK][6])
{
  if (angle->sin0 == 0 && angle->cos0 > 0) {
    const PetscReal la = PetscSqrtReal(Dot3(a, a)), lb = PetscSqrtReal(Dot3(b, b));

    *rank = 3;
    for (PetscInt m = 0; m < 3; m++) {
      lambda[m] = angle->k * angle->cos0;
      for (PetscInt i = 0; i < 3; i++) {
        u[m][i]     = (((m == i) ? 1.0 : 0.0) - a[m] * a[i] / (la * la)) / la;
        u[m][3 + i] = -(((m == i) ? 1.0 : 0.0) - b[m] * b[i] / (lb * lb)) / lb;
      }
    }
  } else {
    const PetscReal sc = PetscMax(s, sin_floor), w = angle->k * PetscMax(c * angle->cos0 + s * angle->sin0, 0.0) / (sc * sc);
    const PetscReal torque = angle->k * (s * angle->cos0 - c * angle->sin0); /* dE/dtheta = k sin(theta - theta0) */

    *rank     = 1;
    lambda[0] = w;
    for (PetscInt r = 0; r < 6; r++) u[0][r] = g[r];
    if (torque > 0 && s >= sin_floor) { /* bent beyond rest: out of the arms' plane theta grows as (1/theta) u u^T */
      const PetscReal la = PetscSqrtReal(Dot3(a, a)), lb = PetscSqrtReal(Dot3(b, b));
      PetscReal       n[3];

      Cross3(a, b, n);
      *rank     = 2;
      lambda[1] = torque / s;
      for (PetscInt i = 0; i < 3; i++) {
        u[1][i]     = n[i] / (la * la * lb * s); /* unit normal / |a| */
        u[1][3 + i] = -n[i] / (la * lb * lb * s);
      }
    }
  }
}

/* H = sum_m p_m p_m^T with p_m = sqrt(scale lambda_m) q_m: exactly symmetric, and each row a short loop of RANK
   products that the compiler unrolls and vectorises. */
#define FACTORED_EXPAND(RANK)                                                                                                                                                                                                                            \
  do {                                                                                                                                                                                                                                                   \
    for (PetscInt r = 0; r < n; r++)                                                                                                                                                                                                                     \
      for (PetscInt c = 0; c < n; c++) {                                                                                                                                                                                                                 \
        PetscReal sum = 0;                                                                                                                                                                                                                               \
        for (PetscInt m = 0; m < (RANK); m++) sum += p[m][r] * p[m][c];                                                                                                                                                                                  \
        H[n * r + c] = sum;                                                                                                                                                                                                                              \
      }                                                                                                                                                                                                                                                  \
  } while (0)

void ClothFactoredStiffnessExpand(const ClothFactoredStiffness *K, PetscInt n, PetscReal scale, PetscReal H[])
{
  PetscReal p[CLOTH_STIFFNESS_MAX_RANK][3 * CLOTH_ANGLE_MAX_PARTICLES];

  for (PetscInt m = 0; m < K->rank; m++) {
    const PetscReal w = PetscSqrtReal(scale * K->lambda[m]); /* lambda >= 0: the form is positive semidefinite */
    for (PetscInt c = 0; c < n; c++) p[m][c] = w * K->q[m][c];
  }
  switch (K->rank) {
  case 1:
    FACTORED_EXPAND(1);
    break;
  case 2:
    FACTORED_EXPAND(2);
    break;
  case 3:
    FACTORED_EXPAND(3);
    break;
  default:
    FACTORED_EXPAND(K->rank);
  }
}
#undef FACTORED_EXPAND

/* An angle spring's energy, forces, and stiffness: the exact or projected Hessian in H, or the Gauss-Newton form's
   factors in F (the arms' factors carried to the particles by the arm weights). */
static PetscErrorCode AngleEvaluate(const ClothAngle *angle, const PetscReal *const x[], ClothStiffness form, PetscReal *energy, PetscReal force[], PetscReal H[], ClothFactoredStiffness *F)
{
  const PetscInt np = ClothAngleParticleCount(angle->kind), n = 3 * np;
  PetscReal      A[CLOTH_ANGLE_MAX_PARTICLES], B[CLOTH_ANGLE_MAX_PARTICLES], a[3], b[3], c, s, g[6], Hc[36];
  PetscReal      dEdc, d2Edc2;
  /* Below this sine the cone of (theta - theta0) at theta = 0 is cut off (only matters when sin0 > 0). */
  const PetscReal sin_floor = 1e-6;

  PetscFunctionBeginUser;
  if (angle->kind == CLOTH_ANGLE_TWIST) {
    PetscCall(TwistEvaluate(angle, x, form, energy, force, H, F));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  AngleArmVectors(angle, x, A, B, a, b);
  NormalizedDot(a, b, &c, g, H ? Hc : NULL);
  s = PetscSqrtReal(PetscMax(1.0 - c * c, 0.0));
  /* E = k (1 - c c0 - s s0) with s = sqrt(1 - c^2) */
  if (energy) *energy = angle->k * (1.0 - c * angle->cos0 - s * angle->sin0);
  if (angle->sin0 != 0.0) {
    const PetscReal sc = PetscMax(s, sin_floor);
    dEdc               = -angle->k * (angle->cos0 - angle->sin0 * c / sc);
    d2Edc2             = angle->k * angle->sin0 / (sc * sc * sc);
  } else {
    dEdc   = -angle->k * angle->cos0;
    d2Edc2 = 0.0;
  }
  if (force) {
    for (PetscInt k = 0; k < np; k++)
      for (PetscInt i = 0; i < 3; i++) force[3 * k + i] = -dEdc * (A[k] * g[i] + B[k] * g[3 + i]);
  }
  if (F) {
    PetscReal u[CLOTH_STIFFNESS_MAX_RANK][6];

    AngleGaussNewton(angle, a, b, c, s, g, sin_floor, &F->rank, F->lambda, u);
    for (PetscInt m = 0; m < F->rank; m++)
      for (PetscInt k = 0; k < np; k++)
        for (PetscInt i = 0; i < 3; i++) F->q[m][3 * k + i] = A[k] * u[m][i] + B[k] * u[m][3 + i];
  }
  if (H) {
    PetscReal He[36]; /* stiffness w.r.t. (a, b) */
    for (PetscInt r = 0; r < 6; r++)
      for (PetscInt q = 0; q < 6; q++) He[6 * r + q] = d2Edc2 * g[r] * g[q] + dEdc * Hc[6 * r + q];
    for (PetscInt k = 0; k < np; k++)
      for (PetscInt l = 0; l < np; l++)
        for (PetscInt i = 0; i < 3; i++)
          for (PetscInt j = 0; j < 3; j++) H[n * (3 * k + i) + 3 * l + j] = A[k] * A[l] * He[6 * i + j] + A[k] * B[l] * He[6 * i + 3 + j] + B[k] * A[l] * He[6 * (3 + i) + j] + B[k] * B[l] * He[6 * (3 + i) + 3 + j];
    if (form == CLOTH_STIFFNESS_PROJECTED) PetscCall(ClothProjectPSD(n, H));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothAngleEvaluate(const ClothAngle *angle, const PetscReal *const x[], ClothStiffness form, PetscReal *energy, PetscReal force[], PetscReal H[])
{
  PetscFunctionBeginUser;
  if (H && form == CLOTH_STIFFNESS_GAUSS_NEWTON) {
    ClothFactoredStiffness F;

    PetscCall(AngleEvaluate(angle, x, form, energy, force, NULL, &F));
    ClothFactoredStiffnessExpand(&F, 3 * ClothAngleParticleCount(angle->kind), 1.0, H);
  } else
    PetscCall(AngleEvaluate(angle, x, form, energy, force, H, NULL));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothAngleEvaluateFactored(const ClothAngle *angle, const PetscReal *const x[], PetscReal *energy, PetscReal force[], ClothFactoredStiffness *K)
{
  PetscFunctionBeginUser;
  PetscCall(AngleEvaluate(angle, x, CLOTH_STIFFNESS_GAUSS_NEWTON, energy, force, NULL, K));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void ClothAngleSlide(ClothAngle *angle, const PetscReal *const x[])
{
  PetscReal A[CLOTH_ANGLE_MAX_PARTICLES], B[CLOTH_ANGLE_MAX_PARTICLES], a[3], b[3], axb[3], theta, rest;

  if (angle->slip <= 0) return;
  AngleArmVectors(angle, x, A, B, a, b);
  Cross3(a, b, axb);
  theta = PetscAtan2Real(PetscSqrtReal(Dot3(axb, axb)), Dot3(a, b));
  rest  = PetscAtan2Real(angle->sin0, angle->cos0);
  if (theta - rest > angle->slip)
    rest = theta - angle->slip;
  else if (rest - theta > angle->slip)
    rest = theta + angle->slip;
  else
    return; /* sticking */
  angle->cos0 = PetscCosReal(rest);
  angle->sin0 = PetscSinReal(rest);
}

PetscErrorCode ClothProjectPSD(PetscInt n, PetscReal A[])
{
  PetscBLASInt bn, lwork = 12 * 12 * 3, info;
  PetscReal    V[144], w[12], work[12 * 12 * 3];

  PetscFunctionBeginUser;
  PetscCheck(n <= 12, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "ClothProjectPSD handles n <= 12, got %" PetscInt_FMT, n);
  PetscCall(PetscBLASIntCast(n, &bn));
  PetscCall(ClothLogRegister());
  PetscCall(PetscLogEventBegin(ClothLog.project_psd, 0, 0, 0, 0));
  for (PetscInt i = 0; i < n * n; i++) V[i] = A[i];
  /* Row-major symmetric == column-major symmetric, so LAPACK sees the same matrix. */
  PetscCallBLAS("LAPACKsyev", LAPACKsyev_("V", "U", &bn, V, &bn, w, work, &lwork, &info));
  PetscCheck(info == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "LAPACK syev failed with info %d", (int)info);
  if (w[0] < 0) { /* eigenvalues ascending: w[0] >= 0 is PSD already */
    for (PetscInt i = 0; i < n * n; i++) A[i] = 0;
    for (PetscInt e = 0; e < n; e++) {
      const PetscReal *v = &V[e * n]; /* column e of the column-major eigenvector matrix */
      if (w[e] <= 0) continue;
      for (PetscInt i = 0; i < n; i++)
        for (PetscInt j = 0; j < n; j++) A[i * n + j] += w[e] * v[i] * v[j];
    }
  }
  PetscCall(PetscLogEventEnd(ClothLog.project_psd, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
