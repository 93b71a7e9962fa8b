/* Pattern meshing (see pattern.h). */
#include "pattern.h"

static PetscErrorCode PatternMeshRectangle(const ScenePiece *piece, PetscReal uv[])
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < piece->nv; j++)
    for (PetscInt i = 0; i < piece->nu; i++) {
      uv[2 * (j * piece->nu + i) + 0] = piece->size[0] * i / (piece->nu - 1);
      uv[2 * (j * piece->nu + i) + 1] = piece->size[1] * j / (piece->nv - 1);
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Signed area of cell (i, j) (corners (i,j), (i+1,j), (i+1,j+1), (i,j+1)) by the shoelace formula. */
static PetscReal CellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j)
{
  const PetscInt c[4] = {j * nu + i, j * nu + i + 1, (j + 1) * nu + i + 1, (j + 1) * nu + i};
  PetscReal      area = 0;

  for (PetscInt k = 0; k < 4; k++) {
    const PetscReal *p = &uv[2 * c[k]], *q = &uv[2 * c[(k + 1) % 4]];
    area += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * area;
}

static PetscErrorCode PatternCheckCells(const ScenePiece *piece, const PetscReal uv[])
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j + 1 < piece->nv; j++)
    for (PetscInt i = 0; i + 1 < piece->nu; i++)
      PetscCheck(CellArea(piece->nu, uv, i, j) > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "Piece '%s': grid cell (%" PetscInt_FMT ", %" PetscInt_FMT ") is folded or inverted (area %g m^2); check the boundaries' directions", piece->name, i, j, (double)CellArea(piece->nu, uv, i, j));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PatternMeshPiece(const ScenePiece *piece, PetscReal uv[])
{
  PetscFunctionBeginUser;
  PetscCall(PatternMeshRectangle(piece, uv));
  PetscCall(PatternCheckCells(piece, uv));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscReal PatternCellArea(PetscInt nu, const PetscReal uv[], PetscInt i, PetscInt j)
{
  return CellArea(nu, uv, i, j);
}
