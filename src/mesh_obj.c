#define _POSIX_C_SOURCE 200809L /* strtok_r */
/* Wavefront OBJ reader (see mesh_obj.h). Rank 0 parses; input errors are turned into a message that is
   broadcast with the result, so that every rank raises the same error. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "mesh_obj.h"

#define MESH_OBJ_LINE_LEN 4096
/* Largest coordinate accepted, in file units: a million units is 1000 km in metres, 1 km in millimetres; beyond
   it (1e300) the collision grid and the distances overflow. */
#define MESH_OBJ_MAX_COORDINATE 1e6
/* A triangle whose area is below this fraction of its longest edge squared is degenerate (zero area). */
#define MESH_OBJ_DEGENERATE_AREA 1e-12
#define MESH_OBJ_MESSAGE_LEN (CLOTH_PATH_LEN + 512)

/* Growing arrays of the parse. */
typedef struct {
  PetscInt   nverts, cap_verts, ntris, cap_tris, npolygons;
  PetscReal *coords;
  PetscInt  *tris;
} MeshObjBuilder;

static PetscErrorCode BuilderAddVertex(MeshObjBuilder *b, const PetscReal x[3])
{
  PetscFunctionBeginUser;
  if (b->nverts == b->cap_verts) {
    b->cap_verts = PetscMax(1024, 2 * b->cap_verts);
    PetscCall(PetscRealloc(3 * sizeof(PetscReal) * (size_t)b->cap_verts, &b->coords));
  }
  for (PetscInt c = 0; c < 3; c++) b->coords[3 * b->nverts + c] = x[c];
  b->nverts++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode BuilderAddTriangle(MeshObjBuilder *b, PetscInt v0, PetscInt v1, PetscInt v2)
{
  PetscFunctionBeginUser;
  if (b->ntris == b->cap_tris) {
    b->cap_tris = PetscMax(1024, 2 * b->cap_tris);
    PetscCall(PetscRealloc(3 * sizeof(PetscInt) * (size_t)b->cap_tris, &b->tris));
  }
  b->tris[3 * b->ntris + 0] = v0;
  b->tris[3 * b->ntris + 1] = v1;
  b->tris[3 * b->ntris + 2] = v2;
  b->ntris++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Whether the rest of a line after its statement holds only blanks. */
static PetscBool IsBlank(const char *rest)
{
  while (*rest && isspace((unsigned char)*rest)) rest++;
  return *rest ? PETSC_FALSE : PETSC_TRUE;
}

/* 'v x y z [w]': *bad set to a message when the numbers are missing, malformed, out of range or followed by
   anything else. */
static PetscErrorCode ParseVertex(MeshObjBuilder *b, char *rest, char bad[], size_t len)
{
  PetscReal x[3];
  char     *end = rest;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < 3; c++) {
    char *start = end;
    errno       = 0;
    x[c]        = (PetscReal)strtod(start, &end);
    if (end == start || errno == ERANGE || PetscIsInfOrNanReal(x[c]) || PetscAbsReal(x[c]) > MESH_OBJ_MAX_COORDINATE) {
      PetscCall(PetscSNPrintf(bad, len, "expected a vertex 'v x y z' with 3 finite numbers of magnitude at most 1e6"));
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  if (!IsBlank(end)) { /* the optional weight w, then nothing */
    char *start = end;

    (void)strtod(start, &end);
    if (end == start || !IsBlank(end)) {
      PetscCall(PetscSNPrintf(bad, len, "expected a vertex 'v x y z' with 3 finite numbers of magnitude at most 1e6 (and an optional weight), got more after them"));
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  PetscCall(BuilderAddVertex(b, x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Twice the area of triangle (v0, v1, v2) over its longest edge squared: 0 for a degenerate triangle (repeated
   or collinear corners), about 0.87 for an equilateral one. */
static PetscReal TriangleShape(const PetscReal coords[], PetscInt v0, PetscInt v1, PetscInt v2)
{
  const PetscReal *a = &coords[3 * v0], *p = &coords[3 * v1], *q = &coords[3 * v2];
  PetscReal        e1[3], e2[3], e3[3], n[3], longest;

  for (PetscInt c = 0; c < 3; c++) {
    e1[c] = p[c] - a[c];
    e2[c] = q[c] - a[c];
    e3[c] = q[c] - p[c];
  }
  n[0]    = e1[1] * e2[2] - e1[2] * e2[1];
  n[1]    = e1[2] * e2[0] - e1[0] * e2[2];
  n[2]    = e1[0] * e2[1] - e1[1] * e2[0];
  longest = PetscMax(PetscMax(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]), e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2]);
  return longest > 0 ? PetscSqrtReal(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / longest : 0;
}

/* One face corner 'v', 'v/vt', 'v//vn' or 'v/vt/vn': the zero-based vertex index, or a message in bad. */
static PetscErrorCode ParseCorner(const MeshObjBuilder *b, const char *token, PetscInt *vertex, char bad[], size_t len)
{
  char *end;
  long  index;

  PetscFunctionBeginUser;
  errno = 0;
  index = strtol(token, &end, 10);
  if (end == token || errno == ERANGE || (*end && *end != '/')) {
    PetscCall(PetscSNPrintf(bad, len, "expected a face corner v, v/vt, v//vn or v/vt/vn with an integer vertex index, got '%s'", token));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (index < 0) index += (long)b->nverts + 1; /* relative: -1 is the last vertex read so far */
  if (index < 1 || index > (long)b->nverts) {
    PetscCall(PetscSNPrintf(bad, len, "face corner '%s' refers to vertex %ld, but %" PetscInt_FMT " vertices are defined before this line", token, index, b->nverts));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  *vertex = (PetscInt)index - 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 'f c1 c2 c3 ...': a polygon of at least 3 corners, split as a fan from its first corner. */
static PetscErrorCode ParseFace(MeshObjBuilder *b, char *rest, char bad[], size_t len)
{
  PetscInt first = -1, previous = -1, ncorners = 0;
  char    *save = NULL;

  PetscFunctionBeginUser;
  for (char *token = strtok_r(rest, " \t\r\n", &save); token; token = strtok_r(NULL, " \t\r\n", &save)) {
    PetscInt v = -1;

    PetscCall(ParseCorner(b, token, &v, bad, len));
    if (bad[0]) PetscFunctionReturn(PETSC_SUCCESS);
    if (ncorners == 0)
      first = v;
    else if (ncorners >= 2) {
      if (TriangleShape(b->coords, first, previous, v) <= MESH_OBJ_DEGENERATE_AREA) {
        PetscCall(PetscSNPrintf(bad, len, "expected a face of nonzero area, got corners %" PetscInt_FMT ", %" PetscInt_FMT ", %" PetscInt_FMT " (1-based vertices) that are repeated or on one line", first + 1, previous + 1, v + 1));
        PetscFunctionReturn(PETSC_SUCCESS);
      }
      PetscCall(BuilderAddTriangle(b, first, previous, v));
    }
    previous = v;
    ncorners++;
  }
  if (ncorners < 3) PetscCall(PetscSNPrintf(bad, len, "expected a face with at least 3 corners, got %" PetscInt_FMT, ncorners));
  b->npolygons++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Statements that carry nothing the collision mesh needs. */
static PetscBool IsIgnoredStatement(const char *keyword)
{
  static const char *const ignored[] = {"vt", "vn", "vp", "o", "g", "s", "usemtl", "mtllib", "l", NULL};

  for (PetscInt i = 0; ignored[i]; i++)
    if (!strcmp(keyword, ignored[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* One line; bad receives a message (without file and line) when the line is not valid OBJ for us. */
static PetscErrorCode ParseLine(MeshObjBuilder *b, char *line, char bad[], size_t len)
{
  char *save = NULL, *keyword, *rest;

  PetscFunctionBeginUser;
  keyword = strtok_r(line, " \t\r\n", &save);
  if (!keyword || keyword[0] == '#') PetscFunctionReturn(PETSC_SUCCESS);
  rest = save ? save : (char *)"";
  if (!strcmp(keyword, "v"))
    PetscCall(ParseVertex(b, rest, bad, len));
  else if (!strcmp(keyword, "f"))
    PetscCall(ParseFace(b, rest, bad, len));
  else if (!IsIgnoredStatement(keyword))
    PetscCall(PetscSNPrintf(bad, len, "unknown statement '%s': expected v, f (or vt, vn, vp, o, g, s, usemtl, mtllib, l, #, which are ignored)", keyword));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rank 0: parses the whole file; message is empty on success, else the complete error text. */
static PetscErrorCode ParseFileSerial(const char path[], MeshObjBuilder *b, char message[], size_t len)
{
  char  line[MESH_OBJ_LINE_LEN], bad[MESH_OBJ_MESSAGE_LEN] = "";
  long  lineno = 0;
  FILE *fp     = fopen(path, "r");

  PetscFunctionBeginUser;
  if (!fp) {
    PetscCall(PetscSNPrintf(message, len, "mesh %s: cannot open the file: %s", path, strerror(errno)));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  while (fgets(line, sizeof(line), fp)) {
    lineno++;
    if (!strchr(line, '\n') && !feof(fp)) {
      PetscCall(PetscSNPrintf(message, len, "mesh %s, line %ld: the line is longer than %d characters", path, lineno, MESH_OBJ_LINE_LEN - 2));
      break;
    }
    PetscCall(ParseLine(b, line, bad, sizeof(bad)));
    if (bad[0]) {
      PetscCall(PetscSNPrintf(message, len, "mesh %s, line %ld: %s", path, lineno, bad));
      break;
    }
  }
  if (!message[0] && ferror(fp)) PetscCall(PetscSNPrintf(message, len, "mesh %s: read error after line %ld", path, lineno));
  if (!message[0] && b->ntris == 0) PetscCall(PetscSNPrintf(message, len, "mesh %s: no faces found (expected 'f' lines with at least 3 corners)", path));
  fclose(fp);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MeshObjRead(MPI_Comm comm, const char path[], const char context[], MeshTriangles *mesh)
{
  MeshObjBuilder b                             = {0};
  char           message[MESH_OBJ_MESSAGE_LEN] = "";
  PetscMPIInt    rank;
  PetscInt       counts[3];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(mesh, sizeof(*mesh)));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) PetscCall(ParseFileSerial(path, &b, message, sizeof(message)));
  PetscCallMPI(MPI_Bcast(message, (PetscMPIInt)sizeof(message), MPI_CHAR, 0, comm));
  if (message[0]) {
    PetscCall(PetscFree(b.coords));
    PetscCall(PetscFree(b.tris));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "%s%s%s", context ? context : "", context ? ": " : "", message);
  }
  counts[0] = b.nverts;
  counts[1] = b.ntris;
  counts[2] = b.npolygons;
  PetscCallMPI(MPI_Bcast(counts, 3, MPIU_INT, 0, comm));
  mesh->nverts    = counts[0];
  mesh->ntris     = counts[1];
  mesh->npolygons = counts[2];
  PetscCall(PetscMalloc2(3 * mesh->nverts, &mesh->coords, 3 * mesh->ntris, &mesh->tris));
  if (rank == 0) {
    PetscCall(PetscArraycpy(mesh->coords, b.coords, 3 * mesh->nverts));
    PetscCall(PetscArraycpy(mesh->tris, b.tris, 3 * mesh->ntris));
  }
  PetscCall(PetscFree(b.coords));
  PetscCall(PetscFree(b.tris));
  PetscCallMPI(MPI_Bcast(mesh->coords, (PetscMPIInt)(3 * mesh->nverts), MPIU_REAL, 0, comm));
  PetscCallMPI(MPI_Bcast(mesh->tris, (PetscMPIInt)(3 * mesh->ntris), MPIU_INT, 0, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode MeshTrianglesFree(MeshTriangles *mesh)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(mesh->coords, mesh->tris));
  PetscCall(PetscMemzero(mesh, sizeof(*mesh)));
  PetscFunctionReturn(PETSC_SUCCESS);
}
