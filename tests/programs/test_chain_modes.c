/* The first pendulum mode of a hanging chain (tests/data/hanging_chain.yaml: a ladder of 2 x N particles hanging from
   its top pair, its columns swinging together across its plane) against two exact answers:
   - the discrete chain: with the model's row masses m_r and link lengths l_r, the link above row r carries
     T_r = g sum_{s >= r} m_s and resists a transverse offset with T_r / l_r; the smallest eigenvalue of
     K y = omega^2 M y (inverse iteration on the tridiagonal M^-1/2 K M^-1/2) is omega_d^2, its vector the mode;
   - the continuous chain: omega_c = (j_01 / 2) sqrt(g / L), L the chain's length.
   The chain starts in that mode: every particle of row r moves across the ladder (z) at V phi_r / phi_bottom, with
   V = omega_d -amplitude (default 5 mm). It runs -periods periods (default 10) plus half a period of -dt (default
   1e-3 s) with -integrator. The bottom row's z gives the frequency (its zero crossings, interpolated linearly) and the
   amplitude (the parabola through the three samples around each positive peak); the amplitude kept is the peak
   -periods periods after the first over the first.
   Expectations, at least one (relative errors |omega - omega_x| / omega_x):
     -expect_frequency_error_discrete E, -expect_frequency_error_continuous E, -expect_amplitude_kept_min K,
     -expect_amplitude_kept_max K, and -expect_amplitude_scheme_error E: the amplitude kept within E of the scheme's own
     damping of a linear oscillator, |z(omega h)|^(periods 2 pi / (omega h)) with z the amplification factor of
     y'' = -omega^2 y: 1 / |1 - i omega h| (implicit: backward Euler), the principal root of
     (3/2 - i omega h) z^2 - 2 z + 1/2 = 0 (bdf2).
   Prints the measured values (the same on any number of ranks up to the solver's tolerance). */
#include <complex.h>
#include <petscvec.h>
#include "scene.h"
#include "cloth.h"
#include "integrator.h"
#include "test_support.h"

#define CHAIN_J01 2.404825557695773

/* Every rank's copy of a state-layout Vec in natural order (all, created on the first call). */
static PetscErrorCode GatherToAll(Cloth cloth, Vec solver, Vec natural, VecScatter *toall, Vec *all)
{
  PetscFunctionBeginUser;
  PetscCall(ClothScatterToNatural(cloth, solver, natural, SCATTER_FORWARD));
  if (!*toall) PetscCall(VecScatterCreateToAll(natural, toall, all));
  PetscCall(VecScatterBegin(*toall, natural, *all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(*toall, natural, *all, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The smallest eigenpair of the symmetric positive definite tridiagonal matrix (d[0..n), e[0..n-1)) by inverse
   iteration (LDL^T solves); y: its unit eigenvector. */
static PetscErrorCode SmallestEigenpair(PetscInt n, const PetscReal d[], const PetscReal e[], PetscReal *lambda, PetscReal y[])
{
  PetscReal *l, *piv, *z;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(n, &l, n, &piv, n, &z));
  piv[0] = d[0];
  for (PetscInt k = 1; k < n; k++) {
    l[k]   = e[k - 1] / piv[k - 1];
    piv[k] = d[k] - l[k] * e[k - 1];
    PetscCheck(piv[k] > 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Chain stiffness not positive definite at row %" PetscInt_FMT, k);
  }
  for (PetscInt k = 0; k < n; k++) y[k] = 1.0;
  for (PetscInt it = 0; it < 200; it++) {
    PetscReal norm = 0;

    for (PetscInt k = 0; k < n; k++) z[k] = y[k] - (k > 0 ? l[k] * z[k - 1] : 0.0); /* L z = y */
    for (PetscInt k = 0; k < n; k++) z[k] /= piv[k];                                /* D */
    for (PetscInt k = n - 2; k >= 0; k--) z[k] -= l[k + 1] * z[k + 1];              /* L^T */
    for (PetscInt k = 0; k < n; k++) norm += z[k] * z[k];
    for (PetscInt k = 0; k < n; k++) y[k] = z[k] / PetscSqrtReal(norm);
  }
  *lambda = 0;
  for (PetscInt k = 0; k < n; k++) *lambda += y[k] * (d[k] * y[k] + (k > 0 ? e[k - 1] * y[k - 1] : 0.0) + (k + 1 < n ? e[k] * y[k + 1] : 0.0));
  PetscCall(PetscFree3(l, piv, z));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The discrete chain's first mode from the start state: omega_d, the mode's shape phi[0..nv) per row (phi[0] = 0 at the
   pins, phi[nv - 1] = 1) and the chain's length. x, m: every particle's position and mass in natural order. */
static PetscErrorCode DiscreteChainMode(PetscInt nu, PetscInt nv, PetscReal g, const PetscScalar *x, const PetscScalar *m, PetscReal *omega, PetscReal phi[], PetscReal *length)
{
  PetscReal     *mass, *tension, *len, *d, *e, *y, lambda;
  const PetscInt n = nv - 1; /* rows below the pins */

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc4(nv + 1, &mass, nv + 1, &tension, nv, &len, nv, &y));
  PetscCall(PetscMalloc2(n, &d, n, &e));
  *length = 0;
  for (PetscInt r = 0; r < nv; r++)
    for (PetscInt i = 0; i < nu; i++) mass[r] += PetscRealPart(m[3 * (r * nu + i)]);
  for (PetscInt r = nv - 1; r >= 1; r--) tension[r] = tension[r + 1] + g * mass[r];
  for (PetscInt r = 1; r < nv; r++) { /* the distance between the rows' centres */
    PetscReal dist2 = 0;
    for (PetscInt c = 0; c < 3; c++) {
      PetscReal a = 0, b = 0;
      for (PetscInt i = 0; i < nu; i++) {
        a += PetscRealPart(x[3 * ((r - 1) * nu + i) + c]) / nu;
        b += PetscRealPart(x[3 * (r * nu + i) + c]) / nu;
      }
      dist2 += (b - a) * (b - a);
    }
    len[r] = PetscSqrtReal(dist2);
    *length += len[r];
  }
  for (PetscInt k = 0; k < n; k++) { /* unknown k is row k + 1 */
    const PetscInt r = k + 1;
    d[k]             = (tension[r] / len[r] + (r + 1 < nv ? tension[r + 1] / len[r + 1] : 0.0)) / mass[r];
    if (k + 1 < n) e[k] = -tension[r + 1] / len[r + 1] / PetscSqrtReal(mass[r] * mass[r + 1]);
  }
  PetscCall(SmallestEigenpair(n, d, e, &lambda, y));
  *omega = PetscSqrtReal(lambda);
  phi[0] = 0;
  for (PetscInt k = 0; k < n; k++) phi[k + 1] = y[k] / PetscSqrtReal(mass[k + 1]);
  for (PetscInt r = 0; r < nv - 1; r++) phi[r] /= phi[nv - 1];
  phi[nv - 1] = 1;
  PetscCall(PetscFree4(mass, tension, len, y));
  PetscCall(PetscFree2(d, e));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Brings the chain to its static equilibrium (it starts unstretched): backward-Euler steps of 0.05 s are nearly Newton steps
   on the stretch (M / h^2 is 1e-8 of the links' stiffness), each followed by v = 0. */
static PetscErrorCode SettleStatically(Cloth cloth)
{
  ClothIntegrator settle;
  Vec             v;
  PetscBool       ok;

  PetscFunctionBeginUser;
  PetscCall(ClothIntegratorCreate(cloth, &settle));
  PetscCall(ClothIntegratorSetType(settle, "implicit"));
  PetscCall(ClothGetState(cloth, NULL, &v));
  for (PetscInt k = 0; k < 3; k++) {
    PetscCall(ClothIntegratorStep(settle, 0.05, &ok, NULL));
    PetscCheck(ok, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "The static settling step failed");
    PetscCall(VecZeroEntries(v));
  }
  PetscCall(ClothIntegratorDestroy(&settle));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Sets every particle's z velocity to V phi[row] (rows of nu particles, natural order). */
static PetscErrorCode StartInMode(Cloth cloth, PetscInt nu, const PetscReal phi[], PetscReal V)
{
  Vec          natural, v;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, NULL, &v));
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(ClothScatterToNatural(cloth, v, natural, SCATTER_FORWARD));
  PetscCall(VecGetOwnershipRange(natural, &lo, &hi));
  PetscCall(VecGetArray(natural, &a));
  for (PetscInt k = lo; k < hi; k++)
    if (k % 3 == 2) a[k - lo] = V * phi[(k / 3) / nu];
  PetscCall(VecRestoreArray(natural, &a));
  PetscCall(ClothScatterToNatural(cloth, v, natural, SCATTER_REVERSE));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Frequency from the zero crossings of z[0..n] (sampled every dt) and the positive peaks (parabolic), those above 5 % of
   the first one's height. */
static void AnalyseSwing(PetscInt n, const PetscReal z[], PetscReal dt, PetscReal *omega, PetscInt *npeaks, PetscReal peaks[])
{
  PetscReal first = 0, last = 0;
  PetscInt  crossings = 0;

  *npeaks = 0;
  for (PetscInt k = 1; k < n; k++) {
    if ((z[k] <= 0 && z[k + 1] > 0) || (z[k] >= 0 && z[k + 1] < 0)) {
      const PetscReal t = (k + z[k] / (z[k] - z[k + 1])) * dt;
      if (!crossings) first = t;
      last = t;
      crossings++;
    }
    if (z[k] > 0 && z[k] > z[k - 1] && z[k] >= z[k + 1]) {
      const PetscReal curv = z[k - 1] - 2 * z[k] + z[k + 1], p = curv != 0 ? 0.5 * (z[k - 1] - z[k + 1]) / curv : 0.0;
      const PetscReal peak = z[k] - 0.25 * (z[k - 1] - z[k + 1]) * p;
      if (*npeaks == 0 || peak > 0.05 * peaks[0]) peaks[(*npeaks)++] = peak;
    }
  }
  *omega = crossings > 1 ? PETSC_PI * (crossings - 1) / (last - first) : 0.0;
}

/* The amplitude a linear oscillator of frequency omega keeps over the given periods with the integrator's scheme, or -1
   for a type this does not know. */
static PetscReal SchemeAmplitudeKept(const char *type, PetscReal omega, PetscReal h, PetscInt periods)
{
  const double theta = (double)(omega * h), steps = (double)periods * 2 * PETSC_PI / theta;
  PetscBool    be, bdf2;
  double       z = -1;

  if (PetscStrcmp(type, "implicit", &be) || PetscStrcmp(type, "bdf2", &bdf2)) return -1;
  if (be) z = 1 / sqrt(1 + theta * theta);
  if (bdf2) z = cabs((2 + csqrt(1 + 2 * I * theta)) / (3 - 2 * I * theta));
  return z < 0 ? -1 : (PetscReal)pow(z, steps);
}

int main(int argc, char **argv)
{
  Scene           scene;
  Cloth           cloth;
  ClothIntegrator integ;
  Vec             x, v, natural, all = NULL, work;
  VecScatter      toall = NULL;
  ClothEnergy     e;
  PetscReal       dt = 1e-3, amplitude = 5e-3, g, omega_d = 0, omega_c, omega, length, *phi, *z, *peaks, e_rest, e0, kept;
  PetscReal       err_d = -1, err_c = -1, kept_min = -1, kept_max = -1, err_scheme = -1, scheme;
  PetscInt        periods = 10, nu, nv, steps, npeaks;
  PetscBool       ok, set[5];
  const char     *type;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_frequency_error_discrete", &err_d, &set[0]));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_frequency_error_continuous", &err_c, &set[1]));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_amplitude_kept_min", &kept_min, &set[2]));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_amplitude_kept_max", &kept_max, &set[3]));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-expect_amplitude_scheme_error", &err_scheme, &set[4]));
  PetscCall(TestCheckExpectationsUsed());
  PetscCheck(set[0] || set[1] || set[2] || set[3] || set[4], PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Give at least one -expect_*: a run without an expectation checks nothing");
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-dt", &dt, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-amplitude", &amplitude, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-periods", &periods, NULL));
  PetscCall(TestClothFromOptions(&scene, &cloth));
  PetscCheck(scene->npieces == 1, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "The chain is one piece");
  nu = scene->pieces[0].nu;
  nv = scene->pieces[0].nv;
  g  = PetscSqrtReal(PetscSqr(scene->gravity[0]) + PetscSqr(scene->gravity[1]) + PetscSqr(scene->gravity[2]));
  PetscCall(ClothIntegratorCreate(cloth, &integ));
  PetscCall(ClothIntegratorSetFromOptions(integ));
  PetscCall(ClothIntegratorGetType(integ, &type));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(SettleStatically(cloth));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  e_rest = e.kinetic + e.gravity + e.elastic;
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  { /* the mode from the start state: masses and positions on every rank */
    const PetscReal *mass;
    PetscInt         nlocal;
    PetscScalar     *w;
    Vec              xall   = NULL;
    VecScatter       xtoall = NULL;

    PetscCall(ClothCreateStateVec(cloth, &work));
    PetscCall(ClothGetMasses(cloth, &mass, NULL));
    PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
    PetscCall(VecGetArray(work, &w));
    for (PetscInt i = 0; i < 3 * nlocal; i++) w[i] = mass[i / 3];
    PetscCall(VecRestoreArray(work, &w));
    PetscCall(GatherToAll(cloth, work, natural, &toall, &all));
    PetscCall(GatherToAll(cloth, x, natural, &xtoall, &xall));
    PetscCall(PetscMalloc1(nv, &phi));
    {
      const PetscScalar *ma, *xa;
      PetscCall(VecGetArrayRead(all, &ma));
      PetscCall(VecGetArrayRead(xall, &xa));
      PetscCall(DiscreteChainMode(nu, nv, g, xa, ma, &omega_d, phi, &length));
      PetscCall(VecRestoreArrayRead(xall, &xa));
      PetscCall(VecRestoreArrayRead(all, &ma));
    }
    PetscCall(VecScatterDestroy(&xtoall));
    PetscCall(VecDestroy(&xall));
    PetscCall(VecDestroy(&work));
  }
  omega_c = 0.5 * CHAIN_J01 * PetscSqrtReal(g / length);
  PetscCall(StartInMode(cloth, nu, phi, omega_d * amplitude));
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  e0    = e.kinetic + e.gravity + e.elastic;
  steps = (PetscInt)PetscCeilReal((periods + 0.5) * 2 * PETSC_PI / omega_d / dt);
  PetscCall(PetscMalloc2(steps + 1, &z, periods + 4, &peaks));
  for (PetscInt n = 0; n <= steps; n++) {
    const PetscScalar *a;

    if (n > 0) {
      PetscCall(ClothIntegratorStep(integ, dt, &ok, NULL));
      PetscCheck(ok, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Step %" PetscInt_FMT " failed", n);
    }
    PetscCall(GatherToAll(cloth, x, natural, &toall, &all));
    PetscCall(VecGetArrayRead(all, &a));
    z[n] = 0;
    for (PetscInt i = 0; i < nu; i++) z[n] += PetscRealPart(a[3 * ((nv - 1) * nu + i) + 2]) / nu;
    PetscCall(VecRestoreArrayRead(all, &a));
  }
  PetscCall(ClothComputeEnergy(cloth, x, v, &e));
  AnalyseSwing(steps, z, dt, &omega, &npeaks, peaks);
  PetscCheck(npeaks > periods, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "Found %" PetscInt_FMT " peaks of the swing, expected %" PetscInt_FMT, npeaks, periods + 1);
  kept   = peaks[periods] / peaks[0];
  scheme = SchemeAmplitudeKept(type, omega, dt, periods);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "%s, dt %g s, %" PetscInt_FMT " particles: omega %.7f rad/s; discrete chain %.7f (error %+.4f %%), continuous chain %.7f (error %+.4f %%); amplitude kept after %" PetscInt_FMT
                        " periods %.5f (the scheme's on a linear oscillator %.5f; first peak %.4e m); energy kept %.5f\n",
                        type, (double)dt, nu * nv, (double)omega, (double)omega_d, (double)(100 * (omega / omega_d - 1)), (double)omega_c, (double)(100 * (omega / omega_c - 1)), periods, (double)kept, (double)scheme, (double)peaks[0],
                        (double)((e.kinetic + e.gravity + e.elastic - e_rest) / (e0 - e_rest))));
  if (set[0]) PetscCheck(PetscAbsReal(omega / omega_d - 1) <= err_d, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "omega %.7f differs from the discrete chain's %.7f by more than %g", (double)omega, (double)omega_d, (double)err_d);
  if (set[1]) PetscCheck(PetscAbsReal(omega / omega_c - 1) <= err_c, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "omega %.7f differs from the continuous chain's %.7f by more than %g", (double)omega, (double)omega_c, (double)err_c);
  if (set[2]) PetscCheck(kept >= kept_min, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "amplitude kept %.5f below %g", (double)kept, (double)kept_min);
  if (set[3]) PetscCheck(kept <= kept_max, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "amplitude kept %.5f above %g", (double)kept, (double)kept_max);
  if (set[4]) {
    PetscCheck(scheme >= 0, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "-expect_amplitude_scheme_error: no amplification factor known for integrator %s", type);
    PetscCheck(PetscAbsReal(kept - scheme) <= err_scheme, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "amplitude kept %.5f differs from the scheme's %.5f by more than %g", (double)kept, (double)scheme, (double)err_scheme);
  }
  PetscCall(PetscFree2(z, peaks));
  PetscCall(PetscFree(phi));
  PetscCall(VecScatterDestroy(&toall));
  PetscCall(VecDestroy(&all));
  PetscCall(VecDestroy(&natural));
  PetscCall(ClothIntegratorDestroy(&integ));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(PetscFinalize());
  return 0;
}
