/* Scene (see scene.h): a YAML scene file -> struct _n_Scene, with validation; the format is in docs/scene_format.md
   and, key by key with its defaults, in scene_schema.c.

   How it reads: rank 0 reads the bytes and broadcasts them (scene_file.c), and every rank parses the same bytes with
   libyaml's document API (SceneParse), so every rank fails or succeeds alike. Each block has a table of its allowed
   keys (SceneTopKeys, SceneFabricKeys, ScenePieceKeys, SceneRunKeys, ...: scene_schema.c) checked before any value
   is read, and a reader that reads one key per line with a helper per kind of value (SceneKeyReal, SceneKeyRealList,
   SceneKeyInt, SceneKeyIntList, SceneKeyString, SceneKeyChoice, SceneKeyDirection: scene_reader.c): the fabrics in
   scene_fabric.c, the pieces in scene_piece.c, the other blocks in scene_blocks.c; a list of items (pieces:,
   bodies:, seams:) is read by one function, SceneReadList, with a reader per item. A new key is one entry in the
   table and one line in the reader; a new block is one table and one reader function, called by SceneReadDocument
   here, which also checks what spans blocks.

   Every error names the file, the line (libyaml's mark, 1-based), the key and the block, what was expected and
   what was found:  scene FILE, line L: key 'KEY' in fabric 'NAME': expected a positive number (kg/m^2), got '-1'

   This file: creating the scene (read, parse, fingerprint), the whole document's reading and its cross-checks,
   -grid (SceneSetGridSize), the view and destroy. */
#include <inttypes.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <petscviewer.h>
#include <yaml.h>
#include "scene_impl.h"
#include "fabric.h"

#define SCENE_FNV_OFFSET UINT64_C(0xcbf29ce484222325)
#define SCENE_FNV_PRIME UINT64_C(0x100000001b3)

/* The particles of all pieces, counted in 64 bits. */
static PetscInt64 SceneCountParticles(Scene scene)
{
  PetscInt64 n = 0;

  for (PetscInt p = 0; p < scene->npieces; p++) n += (PetscInt64)scene->pieces[p].nu * scene->pieces[p].nv;
  return n;
}

PetscErrorCode SceneCheckParticleCount(Scene scene, const char cause[])
{
  const PetscInt64 n = SceneCountParticles(scene);

  PetscFunctionBeginUser;
  PetscCheck(n <= SCENE_MAX_PARTICLES, scene->comm, PETSC_ERR_USER_INPUT, "scene %s%s%s: the pieces have %" PetscInt64_FMT " particles in all: expected at most %" PetscInt64_FMT " (3 coordinates each, indexed by a %d-bit PetscInt)", scene->path,
             cause[0] ? ", " : "", cause, n, SCENE_MAX_PARTICLES, (int)(8 * sizeof(PetscInt)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneGetLargestSpacing(Scene scene, PetscReal *spacing)
{
  PetscFunctionBeginUser;
  *spacing = 0;
  for (PetscInt p = 0; p < scene->npieces; p++) *spacing = PetscMax(*spacing, ScenePieceLargestSpacing(&scene->pieces[p]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* Document and file                                                                                            */

/* A piece cut to a disc (cut_disc) keeps its whole grid of particles, those outside held still without mass; seams
   (sides of the grid) and cloth-cloth contact (the grid's triangles) do not know the cut, so they are refused. */
static PetscErrorCode SceneCheckCutPieces(SceneReader *r, Scene scene)
{
  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < scene->npieces; p++) {
    if (!(scene->pieces[p].cut_disc[2] > 0)) continue;
    PetscCheck(!scene->self_collision.enabled, r->comm, PETSC_ERR_USER_INPUT, "scene %s: piece '%s': expected no cut_disc with self_collision enabled (the contact search does not know the cut), got both", r->path, scene->pieces[p].name);
    for (PetscInt s = 0; s < scene->nseams; s++)
      PetscCheck(scene->seams[s].a.piece != p && scene->seams[s].b.piece != p, r->comm, PETSC_ERR_USER_INPUT, "scene %s: seam '%s': expected no seam on piece '%s', which is cut to a disc (cut_disc), got one", r->path, scene->seams[s].name,
                 scene->pieces[p].name);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneReadDocument(SceneReader *r, Scene scene)
{
  yaml_node_t *root = yaml_document_get_root_node(r->doc), *name;
  char         keys[SCENE_TEXT_LEN];

  PetscFunctionBeginUser;
  PetscCall(SceneJoinNames(SceneTopKeys, -1, keys, sizeof(keys)));
  PetscCheck(root, r->comm, PETSC_ERR_USER_INPUT, "scene %s, line 1: the file is empty: expected a map with keys among %s", r->path, keys);
  PetscCall(SceneExpectMap(r, root, NULL, SceneTopKeys, NULL));
  PetscCall(SceneKeyName(r, root, "name", PETSC_FALSE, scene->name, sizeof(scene->name), &name));
  PetscCheck(name || SceneNameIsSafe(scene->name), r->comm, PETSC_ERR_USER_INPUT, "scene %s: the scene is named '%s' after its file, which names the output files: expected a key 'name' (" SCENE_NAME_RULE ") or a file name of such characters",
             r->path, scene->name);
  PetscCall(SceneKeyRealList(r, root, "gravity", PETSC_FALSE, 3, SCENE_REAL_ANY, "m/s^2", scene->gravity));
  PetscCall(SceneReadFabrics(r, root, scene));
  PetscCall(SceneReadPieces(r, root, scene));
  PetscCall(SceneReadRun(r, root, &scene->run));
  PetscCall(SceneReadBodies(r, root, scene));
  PetscCall(SceneReadSelfCollision(r, root, scene));
  PetscCall(SceneReadSeams(r, root, scene));
  PetscCall(SceneReadSewing(r, root, &scene->sewing));
  PetscCall(SceneCheckCutPieces(r, scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Parses the bytes (the same on every rank) and reads the document into scene. */
static PetscErrorCode SceneParse(MPI_Comm comm, const char bytes[], size_t len, Scene scene)
{
  yaml_parser_t   parser;
  yaml_document_t doc, extra;
  SceneReader     reader = {comm, scene->path, &doc, "", SceneRealBounds};
  PetscErrorCode  ierr;
  PetscBool       more;

  PetscFunctionBeginUser;
  PetscCall(SceneCheckNesting(comm, scene->path, bytes, len, SCENE_MAX_DEPTH)); /* before the loader, which would take hours */
  PetscCheck(yaml_parser_initialize(&parser), comm, PETSC_ERR_MEM, "libyaml could not create a parser");
  yaml_parser_set_input_string(&parser, (const unsigned char *)bytes, len);
  if (!yaml_parser_load(&parser, &doc)) {
    ierr = SceneFailSyntax(comm, scene->path, &parser);
    yaml_parser_delete(&parser);
    PetscCall(ierr);
  }
  if (!yaml_parser_load(&parser, &extra)) {
    ierr = SceneFailSyntax(comm, scene->path, &parser);
    yaml_document_delete(&doc);
    yaml_parser_delete(&parser);
    PetscCall(ierr);
  }
  more = yaml_document_get_root_node(&extra) ? PETSC_TRUE : PETSC_FALSE;
  yaml_document_delete(&extra);
  /* Read, then free libyaml's memory whatever happened; the error (if any) is raised after. */
  ierr = more ? PETSC_SUCCESS : SceneReadDocument(&reader, scene);
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  PetscCheck(!more, comm, PETSC_ERR_USER_INPUT, "scene %s: the file holds more than one YAML document: expected exactly one", scene->path);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* FNV-1a, 64 bits, continued from hash over n bytes. */
static PetscErrorCode SceneHashBytes(uint64_t *hash, const unsigned char bytes[], size_t n)
{
  PetscFunctionBeginUser;
  for (size_t i = 0; i < n; i++) *hash = (*hash ^ bytes[i]) * SCENE_FNV_PRIME;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneCreateFromFile(MPI_Comm comm, const char path[], Scene *scene)
{
  Scene          s;
  char          *bytes;
  size_t         len;
  uint64_t       hash = SCENE_FNV_OFFSET;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  *scene = NULL;
  PetscCheck(strlen(path) < CLOTH_PATH_LEN, comm, PETSC_ERR_ARG_SIZ, "scene %s: the path is too long: expected less than %d characters", path, CLOTH_PATH_LEN);
  PetscCall(SceneReadBytes(comm, path, &bytes, &len));
  PetscCall(PetscNew(&s));
  s->comm = comm;
  PetscCall(SceneSetDefaults(s, path));
  PetscCall(SceneHashBytes(&hash, (const unsigned char *)bytes, len));
  s->file_fingerprint = s->fingerprint = (PetscInt64)hash;
  ierr                                 = SceneParse(comm, bytes, len, s);
  if (!ierr) {
    PetscCall(PetscMalloc1(len + 1, &s->text));
    PetscCall(PetscArraycpy(s->text, bytes, len));
    s->text[len] = 0;
  }
  PetscCall(PetscFree(bytes));
  if (ierr) PetscCall(SceneDestroy(&s));
  PetscCall(ierr);
  *scene = s;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneSetGridSize(Scene scene, PetscInt n)
{
  ScenePiece   *piece;
  uint64_t      hash = (uint64_t)scene->file_fingerprint;
  unsigned char nbytes[8];
  char          cause[64];

  PetscFunctionBeginUser;
  PetscCheck(scene->single_grid, scene->comm, PETSC_ERR_USER_INPUT, "scene %s: -grid %" PetscInt_FMT ": expected a scene of one rectangular piece, got %" PetscInt_FMT " pieces", scene->path, n, scene->npieces);
  PetscCheck(n >= 2, scene->comm, PETSC_ERR_USER_INPUT, "scene %s: -grid %" PetscInt_FMT ": expected an integer >= 2", scene->path, n);
  piece     = &scene->pieces[0];
  piece->nu = piece->nv = n;
  PetscCall(PetscSNPrintf(cause, sizeof(cause), "-grid %" PetscInt_FMT, n));
  PetscCall(SceneCheckParticleCount(scene, cause));
  PetscCall(ScenePieceResolvePins(scene->comm, scene->path, piece));
  for (int b = 0; b < 8; b++) nbytes[b] = (unsigned char)(((uint64_t)n >> (8 * b)) & 0xff); /* little-endian on every host */
  if (n != piece->grid_given[0] || n != piece->grid_given[1]) PetscCall(SceneHashBytes(&hash, nbytes, sizeof(nbytes)));
  scene->fingerprint = (PetscInt64)hash;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------------------------------------------------------ */
/* View and destroy                                                                                             */

/* Appends ", <fmt...>" (without the comma when buf is empty) to a list being built in buf. */
static PetscErrorCode SceneAppendItem(char buf[], size_t len, const char fmt[], ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
static PetscErrorCode SceneAppendItem(char buf[], size_t len, const char fmt[], ...)
{
  char    item[SCENE_TEXT_LEN];
  va_list args;

  PetscFunctionBeginUser;
  va_start(args, fmt);
  vsnprintf(item, sizeof(item), fmt, args);
  va_end(args);
  if (buf[0]) PetscCall(PetscStrlcat(buf, ", ", len));
  PetscCall(PetscStrlcat(buf, item, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneFabricView(const SceneFabric *f, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (f->preset[0]) PetscCall(SceneAppendItem(list, sizeof(list), "preset %s", f->preset));
  PetscCall(SceneAppendItem(list, sizeof(list), "density %g kg/m^2", (double)f->density));
  PetscCall(SceneAppendItem(list, sizeof(list), "stretch %g/%g N/m (warp/weft)", (double)f->stretch_warp, (double)f->stretch_weft));
  if (f->stretch_knee_warp > 0 || f->stretch_knee_weft > 0)
    PetscCall(SceneAppendItem(list, sizeof(list), "beyond strain %g/%g: %g/%g N/m", (double)f->stretch_knee_warp, (double)f->stretch_knee_weft, (double)f->stretch_stiff_warp, (double)f->stretch_stiff_weft));
  PetscCall(SceneAppendItem(list, sizeof(list), "shear %g N/m (%s)", (double)f->shear, ClothShearModels[f->shear_model]));
  if (f->shear_hysteresis > 0) PetscCall(SceneAppendItem(list, sizeof(list), "shear friction HG %g N/m", (double)f->shear_hysteresis));
  PetscCall(SceneAppendItem(list, sizeof(list), "bend %g/%g %s (warp/weft, %s)", (double)f->bend_warp, (double)f->bend_weft, f->bend_model == CLOTH_BEND_LINK ? "N/m" : "N m", ClothBendModels[f->bend_model]));
  if (f->bend_bias > 0) PetscCall(SceneAppendItem(list, sizeof(list), "bias bend %g N m (twisting rigidity %g N m)", (double)f->bend_bias, (double)FabricTwistRigidity(f)));
  if (f->bend_hysteresis_warp > 0 || f->bend_hysteresis_weft > 0) PetscCall(SceneAppendItem(list, sizeof(list), "bending friction HB %g/%g N m/m (warp/weft)", (double)f->bend_hysteresis_warp, (double)f->bend_hysteresis_weft));
  PetscCall(SceneAppendItem(list, sizeof(list), "damping %g 1/s", (double)f->damping));
  if (f->repulsion > 0)
    PetscCall(SceneAppendItem(list, sizeof(list), "repulsion below %g of the rest length (stiffness x %g)", (double)f->repulsion, (double)f->repulsion_stiffness));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "repulsion off"));
  PetscCall(PetscViewerASCIIPrintf(viewer, "fabric '%s': %s\n", f->name, list));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ScenePieceView(Scene scene, const ScenePiece *p, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "", frame[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  PetscCall(SceneAppendItem(list, sizeof(list), "fabric '%s'", scene->fabrics[p->fabric].name));
  PetscCall(SceneAppendItem(list, sizeof(list), "grid %" PetscInt_FMT " x %" PetscInt_FMT " = %" PetscInt_FMT " particles", p->nu, p->nv, p->nu * p->nv));
  if (p->has_boundaries)
    PetscCall(SceneAppendItem(list, sizeof(list), "outline from 4 boundaries (%" PetscInt_FMT "/%" PetscInt_FMT "/%" PetscInt_FMT "/%" PetscInt_FMT " vertices)", p->boundary_npoints[0], p->boundary_npoints[1], p->boundary_npoints[2],
                              p->boundary_npoints[3]));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "size %g x %g m", (double)p->size[0], (double)p->size[1]));
  PetscCall(SceneAppendItem(list, sizeof(list), "mass %s", ClothMassDistributions[p->mass_distribution]));
  PetscCall(SceneAppendItem(list, sizeof(list), "%" PetscInt_FMT " pin%s", p->npins, p->npins == 1 ? "" : "s"));
  if (p->pin_disc[2] > 0) PetscCall(SceneAppendItem(list, sizeof(list), "pinned within %g m of (%g, %g)", (double)p->pin_disc[2], (double)p->pin_disc[0], (double)p->pin_disc[1]));
  if (p->pin_box[2] > p->pin_box[0]) PetscCall(SceneAppendItem(list, sizeof(list), "pinned in [%g, %g] x [%g, %g]", (double)p->pin_box[0], (double)p->pin_box[2], (double)p->pin_box[1], (double)p->pin_box[3]));
  if (p->cut_disc[2] > 0) PetscCall(SceneAppendItem(list, sizeof(list), "cut to the cells within %g m of (%g, %g)", (double)p->cut_disc[2], (double)p->cut_disc[0], (double)p->cut_disc[1]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "origin (%g, %g, %g) m", (double)p->origin[0], (double)p->origin[1], (double)p->origin[2]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "u_axis (%g, %g, %g)", (double)p->u_axis[0], (double)p->u_axis[1], (double)p->u_axis[2]));
  PetscCall(SceneAppendItem(frame, sizeof(frame), "v_axis (%g, %g, %g)", (double)p->v_axis[0], (double)p->v_axis[1], (double)p->v_axis[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "piece '%s': %s\n", p->name, list));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", frame));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneRunView(const SceneRunDefaults *run, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (run->integrator[0]) PetscCall(SceneAppendItem(list, sizeof(list), "integrator %s", run->integrator));
  if (run->dt > 0) PetscCall(SceneAppendItem(list, sizeof(list), "dt %g s", (double)run->dt));
  if (run->t_final > 0) PetscCall(SceneAppendItem(list, sizeof(list), "t_final %g s", (double)run->t_final));
  if (run->steps > 0) PetscCall(SceneAppendItem(list, sizeof(list), "steps %" PetscInt_FMT, run->steps));
  if (run->output_every > 0) PetscCall(SceneAppendItem(list, sizeof(list), "output_every %" PetscInt_FMT, run->output_every));
  if (run->checkpoint_every > 0) PetscCall(SceneAppendItem(list, sizeof(list), "checkpoint_every %" PetscInt_FMT, run->checkpoint_every));
  PetscCall(PetscViewerASCIIPrintf(viewer, "run defaults (options override them): %s\n", list[0] ? list : "none"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode SceneBodyView(const SceneBody *b, PetscViewer viewer)
{
  char list[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (b->type == SCENE_BODY_SPHERE)
    PetscCall(SceneAppendItem(list, sizeof(list), "sphere, center (%g, %g, %g) m, radius %g m", (double)b->center[0], (double)b->center[1], (double)b->center[2], (double)b->radius));
  else if (b->type == SCENE_BODY_PLANE)
    PetscCall(SceneAppendItem(list, sizeof(list), "plane through (%g, %g, %g) m, normal (%g, %g, %g)", (double)b->point[0], (double)b->point[1], (double)b->point[2], (double)b->normal[0], (double)b->normal[1], (double)b->normal[2]));
  else
    PetscCall(SceneAppendItem(list, sizeof(list), "mesh %s, scale %g, rotation (%g, %g, %g) deg, translation (%g, %g, %g) m", b->file, (double)b->scale, (double)b->rotation[0], (double)b->rotation[1], (double)b->rotation[2],
                              (double)b->translation[0], (double)b->translation[1], (double)b->translation[2]));
  PetscCall(SceneAppendItem(list, sizeof(list), "friction %g/%g (static/kinetic), thickness %g m", (double)b->friction_static, (double)b->friction_kinetic, (double)b->thickness));
  PetscCall(PetscViewerASCIIPrintf(viewer, "body '%s': %s\n", b->name, list));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneGetParticleCount(Scene scene, PetscInt *n)
{
  PetscFunctionBeginUser;
  *n = (PetscInt)SceneCountParticles(scene); /* fits: checked when the grids were set */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneView(Scene scene, PetscViewer viewer)
{
  PetscBool iascii;
  PetscInt  particles;
  char      gravity[SCENE_TEXT_LEN] = "";

  PetscFunctionBeginUser;
  if (!viewer) PetscCall(PetscViewerASCIIGetStdout(scene->comm, &viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (!iascii) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(SceneGetParticleCount(scene, &particles));
  PetscCall(PetscViewerASCIIPrintf(viewer, "Scene '%s' from %s (fingerprint %016" PRIx64 "): %" PetscInt_FMT " piece%s, %" PetscInt_FMT " particles\n", scene->name, scene->path, (uint64_t)scene->fingerprint, scene->npieces,
                                   scene->npieces == 1 ? "" : "s", particles));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(SceneAppendItem(gravity, sizeof(gravity), "gravity (%g, %g, %g) m/s^2", (double)scene->gravity[0], (double)scene->gravity[1], (double)scene->gravity[2]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", gravity));
  for (PetscInt f = 0; f < scene->nfabrics; f++) PetscCall(SceneFabricView(&scene->fabrics[f], viewer));
  for (PetscInt p = 0; p < scene->npieces; p++) PetscCall(ScenePieceView(scene, &scene->pieces[p], viewer));
  PetscCall(SceneRunView(&scene->run, viewer));
  for (PetscInt b = 0; b < scene->nbodies; b++) PetscCall(SceneBodyView(&scene->bodies[b], viewer));
  if (scene->self_collision.enabled)
    PetscCall(PetscViewerASCIIPrintf(viewer, "self-collision: thickness %g m, stiffness %g N/m, %" PetscInt_FMT " ring(s) excluded%s\n", (double)scene->self_collision.thickness, (double)scene->self_collision.stiffness,
                                     scene->self_collision.exclude_ring, scene->self_collision.same_piece ? "" : ", pieces do not collide with themselves"));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode SceneDestroy(Scene *scene)
{
  PetscFunctionBeginUser;
  if (!scene || !*scene) PetscFunctionReturn(PETSC_SUCCESS);
  for (PetscInt p = 0; p < (*scene)->npieces && (*scene)->pieces; p++) {
    PetscCall(PetscFree((*scene)->pieces[p].pins));
    PetscCall(PetscFree((*scene)->pieces[p].pins_given));
    for (PetscInt b = 0; b < 4; b++) PetscCall(PetscFree((*scene)->pieces[p].boundary_points[b]));
  }
  PetscCall(PetscFree((*scene)->pieces));
  PetscCall(PetscFree((*scene)->text));
  PetscCall(PetscFree((*scene)->fabrics));
  PetscCall(PetscFree((*scene)->bodies));
  PetscCall(PetscFree((*scene)->seams));
  PetscCall(PetscFree(*scene));
  PetscFunctionReturn(PETSC_SUCCESS);
}
