/* Cloth: the per-particle fields of the fit maps, for output (see cloth.h).

   Strain: the largest relative elongation (l - l0) / l0 of the particle's stretch links (the links to its grid
   neighbours along warp and weft): where the fabric is pulled. Stress: the largest membrane stress of those
   links, the link's tension over the width of fabric it carries (N/m): where the fabric pulls. Each link is
   evaluated on the rank that evaluates its forces; a particle owned elsewhere gets the value through a MAX
   reduction of the ghosts. Pressure: the normal force a body exerts on the particle (collision.h) over the
   particle's fabric area (N/m^2): where the garment presses on the body. */
#include "cloth_impl.h"
#include "model.h"
#include "vec3.h"

typedef enum {
  CLOTH_STRETCH_STRAIN, /* (l - l0) / l0 */
  CLOTH_STRETCH_STRESS  /* tension / width, N/m */
} ClothStretchMeasure;

/* The piece of natural particle a. */
static PetscInt ClothPieceOf(const ClothLayout *layout, PetscInt a)
{
  const ClothModel m     = layout->model;
  PetscInt         piece = 0;

  while (piece + 1 < m->npieces && a >= m->piece_offset[piece + 1]) piece++;
  return piece;
}

/* Is the link between natural particles a and b a stretch link, i.e. do they sit at (i, j) and
   (i +- 1, j) or (i, j +- 1) of one piece? Bending links skip a node, shear links are diagonal and
   links between two pieces are seams, so none of those is a stretch link. along_u: it runs along i. */
static PetscErrorCode ClothIsStretchLink(const ClothLayout *layout, PetscInt a, PetscInt b, PetscBool *stretch, PetscBool *along_u)
{
  const ClothModel m     = layout->model;
  const PetscInt   piece = ClothPieceOf(layout, a);
  PetscInt         nu, la, lb, di, dj;

  PetscFunctionBeginUser;
  *stretch = PETSC_FALSE;
  if (b < m->piece_offset[piece] || b >= m->piece_offset[piece + 1]) PetscFunctionReturn(PETSC_SUCCESS);
  nu       = layout->scene->pieces[piece].nu;
  la       = a - m->piece_offset[piece];
  lb       = b - m->piece_offset[piece];
  di       = PetscAbsInt(la % nu - lb % nu);
  dj       = PetscAbsInt(la / nu - lb / nu);
  *stretch = (PetscBool)(di + dj == 1);
  *along_u = (PetscBool)(di == 1);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The width of fabric a thread carries at natural particle a, across the direction along_u, at the initial positions:
   half the distance to each neighbour across (half a spacing on a piece's edge), or for a `mass: uniform` net the mean
   distance (the one neighbour's on the edge). model.c's ThreadLinkWidth sets the stretch links' stiffness E w / l0 from
   the same width (there from the flat pattern: the two differ by the chord-to-arc ratio on a piece wrapped round an
   arm, under 1 % at 20 particles round), so that the stress of a link is E times its strain also on a piece's edge. */
static PetscReal ClothThreadWidth(const ClothLayout *layout, PetscInt a, PetscBool along_u)
{
  const ClothModel m     = layout->model;
  const PetscInt   piece = ClothPieceOf(layout, a);
  const PetscInt   nu = layout->scene->pieces[piece].nu, nv = layout->scene->pieces[piece].nv;
  const PetscInt   la = a - m->piece_offset[piece], i = la % nu, j = la / nu;
  const PetscInt   stride = along_u ? nu : 1, index = along_u ? j : i, count = along_u ? nv : nu;
  const PetscBool  uniform = layout->scene->pieces[piece].mass_distribution == CLOTH_MASS_UNIFORM ? PETSC_TRUE : PETSC_FALSE;
  PetscReal        sum     = 0;
  PetscInt         n       = 0;

  for (PetscInt s = -1; s <= 1; s += 2) {
    PetscReal d[3];

    if (index + s < 0 || index + s >= count) continue;
    Sub3(&m->position[3 * (a + s * stride)], &m->position[3 * a], d);
    sum += PetscSqrtReal(Dot3(d, d));
    n++;
  }
  if (!n) return 0;
  return uniform ? sum / n : 0.5 * sum;
}

/* The measure of one stretch link at positions xa, xb; wa, wb: the thread widths across it at its ends. */
static PetscErrorCode ClothStretchLinkValue(const ClothLink *link, PetscReal wa, PetscReal wb, const PetscReal xa[3], const PetscReal xb[3], ClothStretchMeasure measure, PetscReal *value)
{
  PetscReal d[3], f[3], l, width;

  PetscFunctionBeginUser;
  Sub3(xb, xa, d);
  l = PetscSqrtReal(Dot3(d, d));
  if (measure == CLOTH_STRETCH_STRAIN) {
    *value = (l - link->rest) / link->rest;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  width  = 0.5 * (wa + wb);
  *value = 0;
  if (l == 0 || width == 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothLinkEvaluate(link, xa, xb, PETSC_FALSE, NULL, f, NULL));
  *value = -Dot3(f, d) / (l * width); /* the force on b along b - a is minus the tension */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Per local particle (owned and ghosts), 3 entries each: the largest measure of this rank's stretch links at
   it, in all three entries; -PETSC_MAX_REAL where this rank has none. width: the cloth's thread_width. */
static PetscErrorCode ClothStretchLocal(const ClothLayout *layout, const PetscReal width[], const PetscScalar x[], ClothStretchMeasure measure, PetscScalar s[])
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < 3 * (layout->nlocal + layout->nghost); i++) s[i] = -PETSC_MAX_REAL;
  for (PetscInt l = 0; l < layout->nlinks; l++) {
    const ClothLink  expanded = ClothLinkExpand(layout->link_params, layout->links[l]);
    const ClothLink *link     = &expanded;
    const PetscInt   a = link->p[0], b = link->p[1];
    PetscBool        stretch, along_u;
    PetscReal        xa[3], xb[3], value;

    PetscCall(ClothIsStretchLink(layout, layout->natural_of_local[a], layout->natural_of_local[b], &stretch, &along_u));
    if (!stretch) continue;
    for (PetscInt c = 0; c < 3; c++) {
      xa[c] = PetscRealPart(x[3 * a + c]);
      xb[c] = PetscRealPart(x[3 * b + c]);
    }
    PetscCall(ClothStretchLinkValue(link, width[2 * a + (along_u ? 0 : 1)], width[2 * b + (along_u ? 0 : 1)], xa, xb, measure, &value));
    for (PetscInt c = 0; c < 3; c++) {
      s[3 * a + c] = PetscMax(PetscRealPart(s[3 * a + c]), value);
      s[3 * b + c] = PetscMax(PetscRealPart(s[3 * b + c]), value);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothCreateStrainVec(Cloth cloth, Vec *strain)
{
  PetscInt    n;
  PetscBool   setup;
  ClothLayout layout;
  Vec         natural;

  PetscFunctionBeginUser;
  PetscCall(ClothIsSetUp(cloth, &setup));
  PetscCheck(setup, PETSC_COMM_SELF, PETSC_ERR_ORDER, "Call ClothSetUp before ClothCreateStrainVec");
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCall(ClothCreateNaturalVec(cloth, &natural)); /* one value per particle of its layout */
  PetscCall(VecGetLocalSize(natural, &n));
  PetscCall(VecDestroy(&natural));
  PetscCall(VecCreateMPI(layout.comm, n / 3, layout.nglobal, strain));
  PetscCall(PetscObjectSetName((PetscObject)*strain, "strain"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The stretch-link field of the measure, natural order, one value per particle. */
static PetscErrorCode ClothComputeStretchField(Cloth cloth, Vec position, ClothStretchMeasure measure, Vec field)
{
  Vec                work, work_local;
  const PetscScalar *x;
  PetscScalar       *s;
  Vec                position_local;
  ClothLayout        layout;

  PetscFunctionBeginUser;
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCall(VecGhostUpdateBegin(position, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGhostUpdateEnd(position, INSERT_VALUES, SCATTER_FORWARD));
  work = cloth->work_force; /* scratch of the force evaluations, free between them: no vector of the state's size more at output */
  PetscCall(VecGhostGetLocalForm(position, &position_local));
  PetscCall(VecGhostGetLocalForm(work, &work_local));
  PetscCall(VecGetArrayRead(position_local, &x));
  PetscCall(VecGetArrayWrite(work_local, &s));
  PetscCall(ClothStretchLocal(&layout, cloth->thread_width, x, measure, s));
  PetscCall(VecRestoreArrayWrite(work_local, &s));
  PetscCall(VecRestoreArrayRead(position_local, &x));
  PetscCall(VecGhostRestoreLocalForm(work, &work_local));
  PetscCall(VecGhostRestoreLocalForm(position, &position_local));
  PetscCall(VecGhostUpdateBegin(work, MAX_VALUES, SCATTER_REVERSE));
  PetscCall(VecGhostUpdateEnd(work, MAX_VALUES, SCATTER_REVERSE));
  /* a particle without stretch links (a piece of one node) is unstrained */
  PetscCall(VecGetArray(work, &s));
  for (PetscInt i = 0; i < 3 * layout.nlocal; i++)
    if (PetscRealPart(s[i]) == -PETSC_MAX_REAL) s[i] = 0;
  PetscCall(VecRestoreArray(work, &s));
  PetscCall(ClothScatterParticleValuesToNatural(cloth, work, field));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeStrain(Cloth cloth, Vec position, Vec strain)
{
  PetscFunctionBeginUser;
  PetscCall(ClothComputeStretchField(cloth, position, CLOTH_STRETCH_STRAIN, strain));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeStress(Cloth cloth, Vec position, Vec stress)
{
  PetscFunctionBeginUser;
  PetscCall(ClothComputeStretchField(cloth, position, CLOTH_STRETCH_STRESS, stress));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothComputeContactPressure(Cloth cloth, const PetscReal normal_force[], Vec pressure)
{
  Vec          work = cloth->work_force; /* as in ClothComputeStretchField */
  PetscScalar *p;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayWrite(work, &p));
  for (PetscInt i = 0; i < cloth->nlocal; i++) {
    const PetscReal a     = cloth->area[i];
    const PetscReal value = normal_force && a > 0 ? normal_force[i] / a : 0;
    for (PetscInt c = 0; c < 3; c++) p[3 * i + c] = value;
  }
  PetscCall(VecRestoreArrayWrite(work, &p));
  PetscCall(ClothScatterParticleValuesToNatural(cloth, work, pressure));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Every owned particle's area: a quarter of each grid cell it is a corner of, at the initial positions. */
static void ClothComputeParticleAreas(Cloth cloth, PetscMPIInt rank)
{
  const ClothModel m = cloth->model;

  for (PetscInt i = 0; i < cloth->nlocal; i++) cloth->area[i] = 0;
  for (PetscInt q = 0; q < m->nquads; q++) {
    const PetscInt *c = &m->quads[4 * q];
    PetscReal       d1[3], d2[3], n[3], quarter;

    if (cloth->part[c[0]] != rank && cloth->part[c[1]] != rank && cloth->part[c[2]] != rank && cloth->part[c[3]] != rank) continue;
    Sub3(&m->position[3 * c[2]], &m->position[3 * c[0]], d1);
    Sub3(&m->position[3 * c[3]], &m->position[3 * c[1]], d2);
    Cross3(d1, d2, n);
    quarter = 0.125 * PetscSqrtReal(Dot3(n, n)); /* a quad's area is half its diagonals' cross product */
    for (PetscInt k = 0; k < 4; k++)
      if (cloth->part[c[k]] == rank) cloth->area[cloth->solver_of_natural[c[k]] - cloth->rstart] += quarter;
  }
}

PetscErrorCode ClothComputeRestMeasures(Cloth cloth)
{
  const PetscInt nl = cloth->nlocal + cloth->nghost;
  ClothLayout    layout;
  PetscMPIInt    rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(cloth->comm, &rank));
  PetscCall(ClothGetLayout(cloth, &layout));
  PetscCall(PetscMalloc2(2 * nl, &cloth->thread_width, cloth->nlocal, &cloth->area));
  for (PetscInt i = 0; i < nl; i++)
    for (PetscInt d = 0; d < 2; d++) cloth->thread_width[2 * i + d] = ClothThreadWidth(&layout, cloth->natural_of_local[i], d == 0 ? PETSC_TRUE : PETSC_FALSE);
  ClothComputeParticleAreas(cloth, rank);
  PetscFunctionReturn(PETSC_SUCCESS);
}
