/* Provenance (see provenance.h). */
#include "provenance.h"
#include "h5util.h"
#include "clothsim_revision.h" /* generated at build time: CLOTHSIM_GIT_REVISION */

#ifndef CLOTHSIM_VERSION
#define CLOTHSIM_VERSION "unknown"
#endif

const char *ClothProvenanceRevision(void)
{
  return CLOTHSIM_GIT_REVISION;
}

PetscErrorCode ClothProvenanceWrite(hid_t obj, Scene scene)
{
  char *options;

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeWriteString(obj, "code_version", CLOTHSIM_VERSION));
  PetscCall(ClothH5AttributeWriteString(obj, "git_revision", CLOTHSIM_GIT_REVISION));
  if (scene) {
    PetscCall(ClothH5AttributeWriteString(obj, "scene_path", scene->path));
    PetscCall(ClothH5AttributeWriteString(obj, "scene_text", scene->text ? scene->text : ""));
  }
  PetscCall(PetscOptionsGetAll(NULL, &options)); /* the same on every rank: one command line */
  PetscCall(ClothH5AttributeWriteString(obj, "options", options));
  PetscCall(PetscFree(options));
  PetscFunctionReturn(PETSC_SUCCESS);
}
