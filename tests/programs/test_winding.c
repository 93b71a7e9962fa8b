/* The inside test's tree (src/winding.c) against the exact sum over all triangles, on the mannequin (the main job's
   body, 26,756 triangles, open at the neck, wrists and ankles):
   - 5,000 seeded random points in its bounding box widened by 10 % on each side;
   - points 1 mm and 0.1 mm off every 20th triangle's centroid along its normal, in and out (the cloth lies that close);
   every estimate must lie within its error bound of the exact sum, every point be classified as the exact sum
   classifies it, and the tree decide alone (without the exact sum) for at least 99 % of each set. Prints the counts.
   Usage: test_winding -mesh OBJ -scale S */
#include <petscsys.h>
#include "body.h"
#include "winding.h"
#include "vec3.h"
#include "test_support.h"

#define NRANDOM 5000

typedef struct {
  PetscInt  points, inside, exact, wrong, beyond; /* beyond: estimates farther from the exact sum than their bound */
  PetscReal worst;                                /* largest |estimate - exact| / bound */
} Tally;

static PetscErrorCode Classify(Body body, WindingTree tree, const PetscReal x[3], Tally *tally)
{
  const MeshTriangles *m;
  PetscBool            inside, exact;
  PetscReal            w, bound, w_exact;

  PetscFunctionBeginUser;
  PetscCall(BodyGetMesh(body, &m, NULL, NULL, NULL));
  PetscCall(WindingTreeIsInside(tree, x, &inside, &exact));
  PetscCall(WindingTreeEstimate(tree, x, &w, &bound));
  w_exact = WindingNumberExact(m->ntris, m->tris, m->coords, x);
  tally->points++;
  tally->inside += inside;
  tally->exact += exact;
  if (inside != (w_exact > 0.5 ? PETSC_TRUE : PETSC_FALSE)) tally->wrong++;
  if (PetscAbsReal(w - w_exact) > bound + 1e-12) tally->beyond++;
  if (bound > 0) tally->worst = PetscMax(tally->worst, PetscAbsReal(w - w_exact) / bound);
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  SceneBody            d = {0};
  Body                 body;
  WindingTree          tree;
  const MeshTriangles *m;
  const PetscReal     *normal;
  PetscReal            lo[3], hi[3];
  PetscRandom          rnd;
  Tally                random = {0}, near = {0};
  PetscBool            set;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscStrncpy(d.name, "mannequin", sizeof(d.name)));
  d.type  = SCENE_BODY_MESH;
  d.scale = 1;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-mesh", d.file, sizeof(d.file), &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "Usage: test_winding -mesh OBJ -scale S");
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-scale", &d.scale, NULL));
  PetscCall(BodyCreate(PETSC_COMM_SELF, &d, "test_winding", &body));
  PetscCall(BodyGetMesh(body, &m, &normal, lo, hi));
  PetscCall(WindingTreeCreate(m->ntris, m->tris, m->coords, &tree));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &rnd));
  PetscCall(PetscRandomSetSeed(rnd, 20261126));
  PetscCall(PetscRandomSeed(rnd));
  for (PetscInt i = 0; i < NRANDOM; i++) {
    PetscReal x[3], u;
    for (PetscInt k = 0; k < 3; k++) {
      PetscCall(PetscRandomGetValueReal(rnd, &u));
      x[k] = lo[k] - 0.1 * (hi[k] - lo[k]) + 1.2 * u * (hi[k] - lo[k]);
    }
    PetscCall(Classify(body, tree, x, &random));
  }
  for (PetscInt t = 0; t < m->ntris; t += 20) {
    const PetscReal offsets[4] = {1e-3, -1e-3, 1e-4, -1e-4};
    if (Dot3(&normal[3 * t], &normal[3 * t]) == 0) continue;
    for (PetscInt o = 0; o < 4; o++) {
      PetscReal x[3];
      for (PetscInt k = 0; k < 3; k++) x[k] = (m->coords[3 * m->tris[3 * t] + k] + m->coords[3 * m->tris[3 * t + 1] + k] + m->coords[3 * m->tris[3 * t + 2] + k]) / 3 + offsets[o] * normal[3 * t + k];
      PetscCall(Classify(body, tree, x, &near));
    }
  }
  for (PetscInt s = 0; s < 2; s++) {
    const Tally *c = s ? &near : &random;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "%s: %" PetscInt_FMT ", %" PetscInt_FMT " inside, %" PetscInt_FMT " decided by the exact sum, %" PetscInt_FMT " misclassified, %" PetscInt_FMT " estimates beyond their bound (worst error %.3g of the bound)\n",
                          s ? "points 1 and 0.1 mm off the surface" : "random points", c->points, c->inside, c->exact, c->wrong, c->beyond, (double)c->worst));
    PetscCheck(c->wrong == 0 && c->beyond == 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the tree misclassified %" PetscInt_FMT " points, %" PetscInt_FMT " estimates beyond their bound", c->wrong, c->beyond);
    PetscCheck(c->exact <= c->points / 100, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the exact sum decided %" PetscInt_FMT " of %" PetscInt_FMT " points (at most 1 %% expected)", c->exact, c->points);
  }
  PetscCheck(random.inside > 0 && near.inside > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "no point inside: the test checks nothing");
  PetscCall(PetscRandomDestroy(&rnd));
  PetscCall(WindingTreeDestroy(&tree));
  PetscCall(BodyDestroy(&body));
  PetscCall(PetscFinalize());
  return 0;
}
