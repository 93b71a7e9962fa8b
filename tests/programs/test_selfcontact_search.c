/* The search of ClothSelfContact against brute force over every pair of primitives: the same point-triangle and
   edge-edge contacts, with the same distances, on any number of ranks.

   The scene's pieces are folded accordion-wise into -panels panels stacked -gap x thickness apart
   (the pieces one above the other), with a deterministic jitter of -jitter x thickness per
   coordinate, so that layers, fold lines and the two pieces all come within the thickness. Checks
   at least -min_contacts contacts of each kind. Prints the counts (independent of the rank count).
   With -check_motion, also the search as the layers move (CheckMotion): as one at a high speed, rigidly, and deformed
   a little and a lot, against brute force, with the pairs of primitives the broad phase keeps over steps. With
   -check_jacobian, also the repulsion's stiffness in the implicit system against central differences of the forces
   (-jacobian_eps, -jacobian_rtol). */
#include <petscvec.h>
#include "scene.h"
#include "cloth.h"
#include "selfcontact.h"
#include "test_support.h"

typedef struct {
  PetscInt  panels;
  PetscReal gap, jitter, thickness;
} Crumple;

/* A deterministic value in [-1, 1] from an index and a component (the same on every rank). */
static PetscReal Jitter(PetscInt g, PetscInt c)
{
  PetscInt64 h = (PetscInt64)g * 2654435761LL + (PetscInt64)c * 40503LL + 12345;

  h = (h ^ (h >> 13)) * 1274126177LL;
  h = h ^ (h >> 16);
  return (PetscReal)((h & 0xffff) / 32767.5 - 1.0);
}

/* Natural-order positions of the folded pieces. */
static PetscErrorCode CrumpledPositions(Scene scene, ClothModel model, const Crumple *cr, PetscReal x[])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < model->npieces; k++) {
    const ScenePiece *piece = &scene->pieces[k];
    for (PetscInt g = model->piece_offset[k]; g < model->piece_offset[k + 1]; g++) {
      const PetscInt  local = g - model->piece_offset[k], i = local % piece->nu, j = local / piece->nu;
      const PetscReal s = (PetscReal)i / (piece->nu - 1), t = (PetscReal)j / (piece->nv - 1);
      const PetscReal width = piece->size[0] / cr->panels;
      PetscInt        panel = PetscMin((PetscInt)(s * cr->panels), cr->panels - 1);
      const PetscReal f     = s * cr->panels - panel;

      x[3 * g + 0] = (panel % 2 == 0 ? f : 1 - f) * width;
      x[3 * g + 1] = (panel + k * cr->panels) * cr->gap * cr->thickness;
      x[3 * g + 2] = t * piece->size[1];
      for (PetscInt c = 0; c < 3; c++) x[3 * g + c] += cr->jitter * cr->thickness * Jitter(g, c);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Natural-order values (3 per particle) into a state vector of the cloth. */
static PetscErrorCode SetStateVec(Cloth cloth, const PetscReal values[], Vec state)
{
  Vec          natural;
  PetscScalar *a;
  PetscInt     lo, hi;

  PetscFunctionBeginUser;
  PetscCall(ClothCreateNaturalVec(cloth, &natural));
  PetscCall(VecGetOwnershipRange(natural, &lo, &hi));
  PetscCall(VecGetArray(natural, &a));
  for (PetscInt k = lo; k < hi; k++) a[k - lo] = values[k];
  PetscCall(VecRestoreArray(natural, &a));
  PetscCall(ClothScatterToNatural(cloth, state, natural, SCATTER_REVERSE));
  PetscCall(VecDestroy(&natural));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Positions x and velocities v (NULL: at rest), natural order. */
static PetscErrorCode SetState(Cloth cloth, const PetscReal x[], const PetscReal v[])
{
  Vec position, velocity;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &position, &velocity));
  PetscCall(SetStateVec(cloth, x, position));
  if (v) PetscCall(SetStateVec(cloth, v, velocity));
  else PetscCall(VecZeroEntries(velocity));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static int CompareContacts(const void *pa, const void *pb)
{
  const ClothContact *a = (const ClothContact *)pa, *b = (const ClothContact *)pb;

  if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
  for (PetscInt k = 0; k < 4; k++)
    if (a->p[k] != b->p[k]) return a->p[k] < b->p[k] ? -1 : 1;
  return 0;
}

/* Every rank's contacts on every rank (sorted). */
static PetscErrorCode GatherContacts(MPI_Comm comm, PetscInt n, const ClothContact local[], PetscInt *total, ClothContact **all)
{
  PetscMPIInt size, nbytes = (PetscMPIInt)(n * sizeof(ClothContact)), *counts, *displs;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Allgather(&nbytes, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  *total = displs[size] / (PetscMPIInt)sizeof(ClothContact);
  PetscCall(PetscMalloc1(*total + 1, all));
  PetscCallMPI(MPI_Allgatherv(local, nbytes, MPI_BYTE, *all, counts, displs, MPI_BYTE, comm));
  qsort(*all, (size_t)*total, sizeof(ClothContact), CompareContacts);
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode CountKinds(PetscInt n, const ClothContact c[], PetscInt count[2])
{
  PetscFunctionBeginUser;
  count[0] = count[1] = 0;
  for (PetscInt k = 0; k < n; k++) count[c[k].kind]++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The search at natural-order positions x (set as the cloth's state) against brute force: the same contacts, with the
   same distances (1e-14 m), at least min_contacts of each kind. With velocities v, the search of a step of h
   (ClothSelfContactUpdate: contacts that come within the thickness, radius) against brute force with displacements
   h v; without, at rest within radius (ClothSelfContactFind). Returns every rank's contacts (sorted). Collective. */
static PetscErrorCode CompareWithBruteForce(Cloth cloth, ClothSelfContact sc, const PetscReal x[], const PetscReal v[], PetscReal h, PetscReal radius, PetscInt min_contacts, PetscInt *nall, ClothContact **all)
{
  PetscInt            n, nbrute, kinds[2], np;
  const ClothContact *found;
  ClothContact       *brute;
  PetscReal          *dx = NULL;

  PetscFunctionBeginUser;
  PetscCall(SetState(cloth, x, v));
  if (v) {
    PetscCall(ClothGetSizes(cloth, NULL, &np));
    PetscCall(PetscMalloc1(3 * np, &dx));
    for (PetscInt k = 0; k < 3 * np; k++) dx[k] = h * v[k];
    PetscCall(ClothSelfContactUpdate(sc, h));
  } else PetscCall(ClothSelfContactFind(sc, radius));
  PetscCall(ClothSelfContactGetContacts(sc, &n, &found));
  PetscCall(GatherContacts(PETSC_COMM_WORLD, n, found, nall, all));
  PetscCall(ClothSelfContactFindBruteForce(sc, x, dx, radius, &nbrute, &brute));
  PetscCall(PetscFree(dx));
  qsort(brute, (size_t)nbrute, sizeof(ClothContact), CompareContacts);
  PetscCall(CountKinds(nbrute, brute, kinds));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "brute force: %" PetscInt_FMT " point-triangle, %" PetscInt_FMT " edge-edge contacts within %g m\n", kinds[0], kinds[1], (double)radius));
  PetscCheck(kinds[0] >= min_contacts && kinds[1] >= min_contacts, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the crumpled configuration has too few contacts to test anything (%" PetscInt_FMT ", %" PetscInt_FMT ")", kinds[0], kinds[1]);
  PetscCall(CountKinds(*nall, *all, kinds));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "search:      %" PetscInt_FMT " point-triangle, %" PetscInt_FMT " edge-edge contacts\n", kinds[0], kinds[1]));
  PetscCheck(*nall == nbrute, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the search found %" PetscInt_FMT " contacts, brute force %" PetscInt_FMT, *nall, nbrute);
  for (PetscInt k = 0; k < *nall; k++) {
    const ClothContact *a = &(*all)[k], *b = &brute[k];
    PetscCheck(CompareContacts(a, b) == 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB,
               "contact %" PetscInt_FMT " differs: search (%d: %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT "), brute force (%d: %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT ")", k, (int)a->kind,
               a->p[0], a->p[1], a->p[2], a->p[3], (int)b->kind, b->p[0], b->p[1], b->p[2], b->p[3]);
    PetscCheck(PetscAbsReal(a->distance - b->distance) <= 1e-14, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "contact %" PetscInt_FMT ": distance %.17g (search) and %.17g (brute force)", k, (double)a->distance, (double)b->distance);
  }
  PetscCall(PetscFree(brute));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The number of contacts of all[0..n) that start[0..nstart) lacks. */
static PetscInt NewContacts(PetscInt n, const ClothContact all[], PetscInt nstart, const ClothContact start[])
{
  PetscInt fresh = 0;

  for (PetscInt k = 0; k < n; k++)
    if (!bsearch(&all[k], start, (size_t)nstart, sizeof(ClothContact), CompareContacts)) fresh++;
  return fresh;
}

/* One search of CheckMotion against brute force: the contacts, and of this search (since the statistics before) the
   pairs of primitives the broad phase gave the narrow phase. */
static PetscErrorCode CompareMoved(Cloth cloth, ClothSelfContact sc, const char *what, const PetscReal x[], const PetscReal v[], PetscReal h, PetscReal radius, PetscInt nstart, const ClothContact start[], PetscInt64 *pairs, PetscInt *fresh)
{
  ClothSelfContactStatistics before, after;
  PetscInt                   nall;
  ClothContact              *all;

  PetscFunctionBeginUser;
  PetscCall(ClothSelfContactGetStatistics(sc, &before));
  PetscCall(CompareWithBruteForce(cloth, sc, x, v, h, radius, 1, &nall, &all));
  PetscCall(ClothSelfContactGetStatistics(sc, &after));
  *pairs = after.primitive_pairs - before.primitive_pairs;
  *fresh = NewContacts(nall, all, nstart, start);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: %" PetscInt_FMT " contacts, %" PetscInt_FMT " of them new; %" PetscInt64_FMT " pairs of primitives\n", what, nall, *fresh, *pairs));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The search as the layers move, each against brute force (exactly the same contacts), after the search at rest
   (start, with pairs0 pairs of primitives):
   - the whole fabric at 10 m/s, a step of 1/240 s (4 cm): the same contacts and the same pairs of primitives as at
     rest, since only relative motion counts;
   - moved rigidly (turned 30 degrees about an oblique axis, shifted by 25 thicknesses): the contacts are the same but
     where rounding passes a particle's nearest point to the other of two equal triangles;
   - then the upper piece moved as one 0.75 thickness closer to the lower: new contacts;
   - then every particle moved 0.75 thickness in its own direction: new contacts. Collective. */
static PetscErrorCode CheckMotion(Cloth cloth, ClothSelfContact sc, ClothModel model, const PetscReal x[], PetscReal radius, PetscInt nstart, const ClothContact start[], PetscInt64 pairs0)
{
  const PetscInt  np = model->nparticles;
  const PetscReal h = 1.0 / 240, angle = PETSC_PI / 6, axis[3] = {0.2672612419124244, 0.5345224838248488, 0.8017837257372732}, shift = 0.75 * radius;
  PetscReal      *y, *v, *z, R[9];
  PetscInt64      pairs;
  PetscInt        fresh;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(3 * np, &y, 3 * np, &v, 3 * np, &z));
  for (PetscInt g = 0; g < np; g++) v[3 * g] = 3, v[3 * g + 1] = -10, v[3 * g + 2] = 1;
  PetscCall(CompareMoved(cloth, sc, "all at 10 m/s", x, v, h, radius, nstart, start, &pairs, &fresh));
  PetscCheck(fresh == 0 && pairs == pairs0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "moving as one changed the search: %" PetscInt_FMT " new contacts, %" PetscInt64_FMT " pairs of primitives against %" PetscInt64_FMT " at rest", fresh, pairs, pairs0);
  /* Rodrigues: R = cos I + sin [axis]x + (1 - cos) axis axis^T */
  for (PetscInt r = 0; r < 3; r++)
    for (PetscInt c = 0; c < 3; c++) R[3 * r + c] = (r == c ? PetscCosReal(angle) : 0) + (1 - PetscCosReal(angle)) * axis[r] * axis[c];
  R[1] -= PetscSinReal(angle) * axis[2], R[2] += PetscSinReal(angle) * axis[1], R[3] += PetscSinReal(angle) * axis[2];
  R[5] -= PetscSinReal(angle) * axis[0], R[6] -= PetscSinReal(angle) * axis[1], R[7] += PetscSinReal(angle) * axis[0];
  for (PetscInt g = 0; g < np; g++)
    for (PetscInt r = 0; r < 3; r++) y[3 * g + r] = R[3 * r] * x[3 * g] + R[3 * r + 1] * x[3 * g + 1] + R[3 * r + 2] * x[3 * g + 2] + 25 * radius;
  PetscCall(CompareMoved(cloth, sc, "moved rigidly", y, NULL, h, radius, nstart, start, &pairs, &fresh));
  /* the upper piece (moved as one) closer to the lower one */
  for (PetscInt g = 0; g < np; g++)
    for (PetscInt c = 0; c < 3; c++) z[3 * g + c] = y[3 * g + c] - (g >= model->piece_offset[1] ? shift * R[3 * c + 1] : 0);
  PetscCall(CompareMoved(cloth, sc, "upper piece 0.75 thickness closer", z, NULL, h, radius, nstart, start, &pairs, &fresh));
  PetscCheck(fresh > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "upper piece 0.75 thickness closer: no new contacts");
  /* every particle in its own direction */
  for (PetscInt g = 0; g < np; g++) {
    PetscReal d[3], norm;
    for (PetscInt c = 0; c < 3; c++) d[c] = Jitter(g + 7 * np, c);
    norm = PetscSqrtReal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (PetscInt c = 0; c < 3; c++) z[3 * g + c] = y[3 * g + c] + shift * d[c] / norm;
  }
  PetscCall(CompareMoved(cloth, sc, "deformed by 0.75 thickness", z, NULL, h, radius, nstart, start, &pairs, &fresh));
  PetscCheck(fresh > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "deformed by 0.75 thickness: no new contacts");
  PetscCall(PetscFree3(y, v, z));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* -(F(x + eps d) - F(x - eps d)) / (2 eps) with the cloth's current contacts held fixed. */
static PetscErrorCode ForceDerivative(Cloth cloth, Vec d, PetscReal eps, Vec df)
{
  Vec x, v, fm;

  PetscFunctionBeginUser;
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(VecDuplicate(x, &fm));
  PetscCall(VecAXPY(x, eps, d));
  PetscCall(ClothComputeForces(cloth, x, v, df));
  PetscCall(VecAXPY(x, -2 * eps, d));
  PetscCall(ClothComputeForces(cloth, x, v, fm));
  PetscCall(VecAXPY(x, eps, d));
  PetscCall(VecAXPY(df, -1.0, fm));
  PetscCall(VecScale(df, -1.0 / (2 * eps)));
  PetscCall(VecDestroy(&fm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The implicit system with the repulsion against finite differences: with h = 1, no damping and the
   exact stiffness, its operator (the assembled matrix and the contacts' couplings applied without it,
   ClothCreateImplicitOperator) is M + K, so (op - M) d must equal -dF/dx d along a random direction d, with the
   contacts and their weights of the search held fixed (the stiffness is exact for that energy). Also
   checks that the contacts contribute (against the same derivative with self-contact detached). */
static PetscErrorCode CheckJacobian(Cloth cloth, ClothSelfContact sc, PetscReal eps, PetscReal rtol)
{
  ClothContribution  repulsion;
  Mat                A, op;
  Vec                x, v, d, Ad, df, df0, rhs;
  PetscRandom        rnd;
  const PetscReal   *mass;
  PetscScalar       *a;
  const PetscScalar *dd;
  PetscInt           nlocal;
  PetscReal          norm, err, share;

  PetscFunctionBeginUser;
  PetscCall(ClothSetExactStiffness(cloth, PETSC_TRUE));
  PetscCall(ClothSelfContactGetContribution(sc, &repulsion));
  PetscCall(ClothSetSelfContact(cloth, sc));
  PetscCall(ClothAddContribution(cloth, &repulsion));
  PetscCall(ClothSelfContactUpdate(sc, 1.0)); /* zero velocity: contacts within the thickness */
  PetscCall(ClothCreateMatrix(cloth, MATBAIJ, &A));
  PetscCall(ClothCreateImplicitOperator(cloth, A, &op));
  PetscCall(ClothGetState(cloth, &x, &v));
  PetscCall(VecDuplicate(x, &d));
  PetscCall(VecDuplicate(x, &Ad));
  PetscCall(VecDuplicate(x, &df));
  PetscCall(VecDuplicate(x, &df0));
  PetscCall(VecDuplicate(x, &rhs));
  PetscCall(ClothAssembleImplicitSystem(cloth, 1.0, x, v, A, rhs));
  PetscCall(PetscRandomCreate(PETSC_COMM_WORLD, &rnd));
  PetscCall(PetscRandomSetInterval(rnd, -1.0, 1.0));
  PetscCall(VecSetRandom(d, rnd));
  PetscCall(MatMult(op, d, Ad));
  PetscCall(ClothGetMasses(cloth, &mass, NULL));
  PetscCall(ClothGetSizes(cloth, &nlocal, NULL));
  PetscCall(VecGetArray(Ad, &a));
  PetscCall(VecGetArrayRead(d, &dd));
  for (PetscInt i = 0; i < nlocal; i++)
    for (PetscInt c = 0; c < 3; c++) a[3 * i + c] -= mass[i] * dd[3 * i + c];
  PetscCall(VecRestoreArrayRead(d, &dd));
  PetscCall(VecRestoreArray(Ad, &a));
  PetscCall(ForceDerivative(cloth, d, eps, df));
  PetscCall(ClothRemoveContribution(cloth, sc)); /* the same derivative without the repulsion */
  PetscCall(ForceDerivative(cloth, d, eps, df0));
  PetscCall(ClothAddContribution(cloth, &repulsion));
  PetscCall(VecNorm(df, NORM_INFINITY, &norm));
  PetscCall(VecAXPY(df0, -1.0, df));
  PetscCall(VecNorm(df0, NORM_INFINITY, &share));
  PetscCall(VecAXPY(Ad, -1.0, df));
  PetscCall(VecNorm(Ad, NORM_INFINITY, &err));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "stiffness along a random direction: |K d| %.3e, of it from contacts %.3e, error against central differences %.3e (relative %.1e)\n", (double)norm, (double)share, (double)err, (double)(err / norm)));
  PetscCheck(share > 1e-3 * norm, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the contacts hardly contribute (%g of %g): the check would test nothing", (double)share, (double)norm);
  PetscCheck(err <= rtol * norm, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the assembled stiffness differs from finite differences by %g relative (tolerance %g)", (double)(err / norm), (double)rtol);
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(VecDestroy(&d));
  PetscCall(VecDestroy(&Ad));
  PetscCall(VecDestroy(&df));
  PetscCall(VecDestroy(&df0));
  PetscCall(VecDestroy(&rhs));
  PetscCall(MatDestroy(&op));
  PetscCall(MatDestroy(&A));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char             path[PETSC_MAX_PATH_LEN];
  Scene            scene;
  Cloth            cloth;
  ClothModel       model;
  ClothSelfContact sc;
  Crumple          cr = {4, 0.6, 0.3, 0};
  PetscReal       *x;
  PetscInt         nall = 0, min_contacts = 100;
  ClothContact    *all;
  PetscBool        flg, check_jacobian = PETSC_FALSE, check_motion = PETSC_FALSE;
  PetscReal        eps = 1e-7, rtol = 1e-5;
  ClothSelfContactStatistics rest;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-check_jacobian", &check_jacobian, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-check_motion", &check_motion, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-jacobian_eps", &eps, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-jacobian_rtol", &rtol, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", path, sizeof(path), &flg));
  PetscCheck(flg, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "give -scene");
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-panels", &cr.panels, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-gap", &cr.gap, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-jitter", &cr.jitter, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-min_contacts", &min_contacts, NULL));
  PetscCall(SceneCreateFromFile(PETSC_COMM_WORLD, path, &scene));
  PetscCall(ClothCreate(PETSC_COMM_WORLD, scene, &cloth));
  PetscCall(ClothSetFromOptions(cloth));
  PetscCall(ClothSetUp(cloth));
  PetscCall(ClothSelfContactCreate(cloth, &sc));
  PetscCall(ClothSelfContactSetFromOptions(sc));
  PetscCall(ClothSelfContactSetUp(sc));
  cr.thickness = scene->self_collision.thickness;
  PetscCall(ClothGetModel(cloth, &model));
  PetscCall(PetscMalloc1(3 * model->nparticles, &x));
  PetscCall(CrumpledPositions(scene, model, &cr, x));

  PetscCall(CompareWithBruteForce(cloth, sc, x, NULL, 0, cr.thickness, min_contacts, &nall, &all));
  PetscCall(ClothSelfContactGetStatistics(sc, &rest));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "identical contact sets\n"));
  if (check_motion) PetscCall(CheckMotion(cloth, sc, model, x, cr.thickness, nall, all, rest.primitive_pairs));
  if (check_jacobian) PetscCall(CheckJacobian(cloth, sc, eps, rtol));
  PetscCall(PetscFree(all));
  PetscCall(PetscFree(x));
  PetscCall(ClothSelfContactDestroy(&sc));
  PetscCall(ClothDestroy(&cloth));
  PetscCall(SceneDestroy(&scene));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
