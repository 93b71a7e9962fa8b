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

PetscErrorCode ClothProvenanceWrite(MPI_Comm comm, hid_t obj, Scene scene)
{
  char *options;
  hid_t file, group;

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeWriteString(obj, "code_version", CLOTHSIM_VERSION));
  PetscCall(ClothH5AttributeWriteString(obj, "git_revision", CLOTHSIM_GIT_REVISION));
  if (scene) PetscCall(ClothH5AttributeWriteString(obj, "scene_path", scene->path));
  ClothCallHDF5(file = H5Iget_file_id(obj));
  ClothCallHDF5(group = H5Gcreate2(file, CLOTH_PROVENANCE_GROUP, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  /* a 2.2 MB scene (a detailed DXF outline) or a long options file do not fit an attribute */
  if (scene) PetscCall(ClothH5WriteText(comm, group, "scene_text", scene->text ? scene->text : ""));
  PetscCall(PetscOptionsGetAll(NULL, &options)); /* the same on every rank: one command line */
  PetscCall(ClothH5WriteText(comm, group, "options", options));
  PetscCall(PetscFree(options));
  ClothCallHDF5(H5Gclose(group));
  ClothCallHDF5(H5Fclose(file)); /* the reference H5Iget_file_id took */
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothProvenanceSize(Scene scene, double *bytes)
{
  char *options;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetAll(NULL, &options));
  *bytes = (double)strlen(options) + (scene && scene->text ? (double)strlen(scene->text) : 0);
  PetscCall(PetscFree(options));
  PetscFunctionReturn(PETSC_SUCCESS);
}
