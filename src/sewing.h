/* ClothSewing: the phases of garment assembly (docs/model.md section 7).

   Phase "pull": gravity is off and every seam pair is pulled towards the midpoint between its two
   points (seam.h). A pair whose gap falls below the tolerance is sewn: from then on a stiff spring
   holds it. Phase "settle" starts when every pair is sewn (or after -sewing_max_time of pulling, with
   a warning naming the widest gap): gravity comes on and the garment settles on the body. Which pairs are
   sewn goes into checkpoints (the field seams_sewn, declared, written and read by the sewing's own
   ClothContribution, registered by ClothSewingCreate; the phase follows from it and the time). */
#pragma once
#include "cloth.h"

typedef enum { CLOTH_SEWING_PULL, CLOTH_SEWING_SETTLE } ClothSewingPhase;
extern const char *const ClothSewingPhases[];

typedef struct _n_ClothSewing *ClothSewing;

/* The cloth must be set up; destroy the sewing before the cloth. */
PetscErrorCode ClothSewingCreate(Cloth cloth, Scene scene, ClothSewing *sewing);
/* -sewing_max_time: seconds of pulling after which gravity comes on even with pairs still open. */
PetscErrorCode ClothSewingSetFromOptions(ClothSewing sewing);
/* Applies the current phase to the cloth (gravity, seam stiffnesses); call before the first step
   and after restoring a checkpoint. */
PetscErrorCode ClothSewingSetUp(ClothSewing sewing);
/* After a step at time t: sews the pairs that have closed and moves to the next phase when due. */
PetscErrorCode ClothSewingUpdate(ClothSewing sewing, PetscReal time);
/* The phase, sewn and total pair counts and the widest gap of all pairs (m). Collective. */
PetscErrorCode ClothSewingGetStatus(ClothSewing sewing, ClothSewingPhase *phase, PetscInt *sewn, PetscInt *total, PetscReal *max_gap);
/* Prints the n widest seam pairs at the current positions: gap, seam, and the piece and grid node
   (i, j) of each particle of the pair. Collective. */
PetscErrorCode ClothSewingViewWidest(ClothSewing sewing, PetscInt n);
/* The sewn state as one number per particle for checkpoints (natural order, block size 1): the sum of
   2^s over the seams s whose link at that node (the node a link starts from) is sewn. A node starts at
   most one link per seam, so this is exact for up to 52 seams. The phase is not stored: it follows from
   the sewn links and the time (ClothSewingUpdate moves on when all are sewn or the time is up). */
PetscErrorCode ClothSewingGetStateVec(ClothSewing sewing, Vec sewn);
/* Restores the sewn state written by ClothSewingGetStateVec at simulated time t. Collective. */
PetscErrorCode ClothSewingSetStateVec(ClothSewing sewing, Vec sewn, PetscReal time);
/* Cloth-cloth contact exclusion (selfcontact.h's ClothSelfContactExcludeFn, ctx the ClothSewing) on
   particles a and b (natural numbers). While the seams are pulled closed: particles within two grid
   rows of the same seam never repel each other (the pull, like gravity, is far weaker than the
   repulsion, and the layers must pass each other to close). Once all pairs are sewn: only the pairs a
   seam link joins, and two particles each joined to a third one (where two seams meet, as at the
   corners of the waist and the side seams); selfcontact.c excludes a pair of primitives when any of
   their particles are, so the points of a seam also skip the triangles and edges around the points
   they are sewn to, and every other contact, also one row from a seam, is repelled. Without the
   exclusion the contact thickness (and the impulses, which keep min_gap x thickness) would hold every
   seam open by that much. */
PetscErrorCode ClothSewingExcludeContact(void *ctx, PetscInt a, PetscInt b, PetscBool *excluded);
PetscErrorCode ClothSewingDestroy(ClothSewing *sewing);
