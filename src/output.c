/* The XDMF + HDF5 time series: see output.h.

   NAME.h5 layout:
     /topology/quads              (nquads, 4) int: the fabric's quadrilaterals, global particle indices
     /frames/NNNNNN/              one group per frame, NNNNNN = step (six digits or more);
                                  attributes step (int64), time (float64) and the frame's counts
                                  (int64, see OutputWriteFrameCounts): body_contacts,
                                  self_contacts, self_contact_particles
       position                   (N, 3) float64, natural order
       velocity                   (N, 3) float64
       strain                     (N, 1) float64: largest relative elongation of the particle's
                                  stretch links (any further per-node field: see OutputNodeFields)
       body_contact               (N, 1) float64: 0 free, 1 in contact with a body, 2 held on it
       self_contact               (N, 1) float64: cloth-cloth contacts the particle is part of
       stress                     (N, 1) float64: largest membrane stress of its stretch links, N/m
       pressure                   (N, 1) float64: the bodies' normal force on it over its fabric area, N/m^2
     /static/<mesh>/points        (nverts, 3) float64: meshes that do not move (ClothOutputAddStaticMesh)
     /static/<mesh>/triangles     (ntris, 3) int
   NAME.xdmf (Xdmf 3) references these with paths relative to its own folder, so the folder can move.
   The h5 file is opened for each frame and closed again, so that it is complete between frames. */
#include <errno.h>
#include <string.h>
#include "output.h"
#include "fileutil.h"
#include "h5util.h"
#include "provenance.h"
#include "errors.h"
#include "watchdog.h"

/* Per-node fields written in every frame besides the positions, as XDMF Attributes of the fabric.
   To add one: add its entry here, its Vec to ClothOutputFrame and that Vec at the same index to the
   fields of ClothOutputWriteFrame (ncomp 1 is a Scalar, 3 a Vector). */
typedef struct {
  const char *name;
  PetscInt    ncomp;
} OutputNodeField;
static const OutputNodeField OutputNodeFields[] = {{"velocity", 3}, {"strain", 1}, {"body_contact", 1}, {"self_contact", 1}, {"stress", 1}, {"pressure", 1}};
#define OUTPUT_NFIELDS ((PetscInt)PETSC_STATIC_ARRAY_LENGTH(OutputNodeFields))

typedef struct {
  char     name[CLOTH_NAME_LEN];
  PetscInt nverts, ntris;
} OutputStaticMesh;

struct _n_ClothOutput {
  MPI_Comm          comm;
  char              name[CLOTH_NAME_LEN];
  char              h5name[CLOTH_PATH_LEN];   /* NAME.h5, as the .xdmf refers to it */
  char              h5path[CLOTH_PATH_LEN];   /* DIR/NAME.h5 */
  char              xdmfpath[CLOTH_PATH_LEN]; /* DIR/NAME.xdmf */
  PetscInt          nparticles, nquads;
  PetscInt          nframes, maxframes; /* frames sorted by step */
  PetscInt64       *steps;
  PetscReal        *times;
  PetscInt          nstatic;
  OutputStaticMesh *statics;
  uint64_t          run_id;          /* the run writing the series, named in a comment of the .xdmf (0: none) */
  PetscReal         xdmf_seconds;    /* -output_xdmf_seconds: wall time between two rewrites of the .xdmf */
  double            xdmf_written_at; /* rank 0's MPI_Wtime() at the last rewrite */
  PetscInt          xdmf_frames;     /* frames the .xdmf on disk lists */
};

typedef char OutputGroupName[CLOTH_NAME_LEN];

/* Frames with a time above restart_time by more than this (relative) are dropped on restart. */
#define OUTPUT_RESTART_TIME_TOLERANCE 1e-12

static PetscErrorCode OutputFrameGroupName(PetscInt64 step, char name[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(name, len, "%06" PetscInt64_FMT, step));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Enters (step, time) in the sorted frame list, replacing the time of a frame with the same step. */
static PetscErrorCode OutputRecordFrame(ClothOutput out, PetscInt64 step, PetscReal time)
{
  PetscInt i = out->nframes;

  PetscFunctionBeginUser;
  while (i > 0 && out->steps[i - 1] >= step) i--;
  if (i < out->nframes && out->steps[i] == step) {
    out->times[i] = time;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (out->nframes == out->maxframes) {
    out->maxframes = 2 * out->maxframes + 16;
    PetscCall(PetscRealloc((size_t)out->maxframes * sizeof(*out->steps), &out->steps));
    PetscCall(PetscRealloc((size_t)out->maxframes * sizeof(*out->times), &out->times));
  }
  PetscCall(PetscArraymove(out->steps + i + 1, out->steps + i, out->nframes - i));
  PetscCall(PetscArraymove(out->times + i + 1, out->times + i, out->nframes - i));
  out->steps[i] = step;
  out->times[i] = time;
  out->nframes++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Opens loc/name, creating the group when it is missing. */
static PetscErrorCode OutputGroupOpenOrCreate(hid_t loc, const char name[], hid_t *group)
{
  PetscBool exists = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(ClothH5LinkExists(loc, name, &exists));
  if (exists)
    ClothCallHDF5(*group = H5Gopen2(loc, name, H5P_DEFAULT));
  else
    ClothCallHDF5(*group = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputSeriesExists(ClothOutput out, PetscBool *exists, const char **path)
{
  PetscFunctionBeginUser;
  PetscCall(ClothFileExists(out->comm, out->h5path, exists));
  if (path) *path = out->h5path;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode OutputFileOpen(ClothOutput out, hid_t *file)
{
  PetscBool opened = PETSC_FALSE, exists = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(ClothH5FileOpen(out->comm, out->h5path, H5F_ACC_RDWR, file, &opened));
  if (!opened) PetscCall(ClothFileExists(out->comm, out->h5path, &exists));
  PetscCheck(opened || exists, out->comm, PETSC_ERR_FILE_OPEN, "Cannot open output series %s to append to: %s (was its directory deleted or moved during the run?)", out->h5path, strerror(ENOENT));
  PetscCheck(opened, out->comm, PETSC_ERR_FILE_READ, "Output series %s cannot be opened to append to (truncated, or not HDF5): move it away to start a new series", out->h5path);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* (Re)writes /topology/quads and makes sure /frames exists. */
static PetscErrorCode OutputWriteTopology(ClothOutput out, hid_t file, const ClothOutputTopology *topology)
{
  hid_t group;

  PetscFunctionBeginUser;
  PetscCall(OutputGroupOpenOrCreate(file, "topology", &group));
  PetscCall(ClothH5LinkDeleteIfExists(group, "quads"));
  PetscCall(ClothH5WriteIntTable(out->comm, group, "quads", topology->nquads, 4, topology->quads));
  ClothCallHDF5(H5Gclose(group));
  PetscCall(OutputGroupOpenOrCreate(file, "frames", &group));
  ClothCallHDF5(H5Gclose(group));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks that a frame kept from an earlier run holds every node field, since the .xdmf lists them all
   for every frame (a series written by an older clothsim may lack one). */
static PetscErrorCode OutputCheckKeptFrame(ClothOutput out, hid_t frame, const char name[])
{
  PetscBool exists;

  PetscFunctionBeginUser;
  for (PetscInt f = 0; f < OUTPUT_NFIELDS; f++) {
    PetscCall(ClothH5LinkExists(frame, OutputNodeFields[f].name, &exists));
    PetscCheck(exists, out->comm, PETSC_ERR_FILE_UNEXPECTED, "Output series %s: frame /frames/%s has no field %s (written by an older clothsim?): move the series away to start a new one", out->h5path, name, OutputNodeFields[f].name);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Reads the frame groups of an existing series: those up to restart_time go into the frame list, the
   later ones are deleted. */
static PetscErrorCode OutputTrimFrames(ClothOutput out, hid_t file, PetscReal restart_time)
{
  hid_t            frames;
  H5G_info_t       info;
  OutputGroupName *drop;
  PetscInt         ndrop = 0;
  PetscReal        limit = restart_time + OUTPUT_RESTART_TIME_TOLERANCE * PetscMax(1.0, PetscAbsReal(restart_time));

  PetscFunctionBeginUser;
  ClothCallHDF5(frames = H5Gopen2(file, "frames", H5P_DEFAULT));
  ClothCallHDF5(H5Gget_info(frames, &info));
  PetscCall(PetscMalloc1(info.nlinks, &drop));
  for (hsize_t i = 0; i < info.nlinks; i++) {
    char       name[CLOTH_NAME_LEN];
    hid_t      frame;
    PetscInt64 step;
    PetscReal  time;

    ClothCallHDF5(H5Lget_name_by_idx(frames, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof(name), H5P_DEFAULT));
    ClothCallHDF5(frame = H5Gopen2(frames, name, H5P_DEFAULT));
    PetscCall(ClothH5AttributeReadInt64(frame, "step", &step));
    PetscCall(ClothH5AttributeReadReal(frame, "time", &time));
    if (time <= limit) PetscCall(OutputCheckKeptFrame(out, frame, name));
    ClothCallHDF5(H5Gclose(frame));
    if (time > limit)
      PetscCall(PetscStrncpy(drop[ndrop++], name, sizeof(drop[0])));
    else
      PetscCall(OutputRecordFrame(out, step, time));
  }
  for (PetscInt i = 0; i < ndrop; i++) ClothCallHDF5(H5Ldelete(frames, drop[i], H5P_DEFAULT));
  PetscCall(PetscFree(drop));
  ClothCallHDF5(H5Gclose(frames));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One HDF DataItem: a (rows, cols) dataset of file NAME.h5 at path. */
static PetscErrorCode OutputXdmfDataItem(ClothOutput out, FILE *fp, const char indent[], PetscInt rows, PetscInt cols, const char numbertype[], size_t precision, const char path[])
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(out->comm, fp, "%s<DataItem Dimensions=\"%" PetscInt_FMT " %" PetscInt_FMT "\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:%s</DataItem>\n", indent, rows, cols, numbertype, (int)precision, out->h5name, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The grid "fabric" of one frame: quads, positions, node fields; with the Time element when given. */
static PetscErrorCode OutputXdmfFabricGrid(ClothOutput out, FILE *fp, const char indent[], PetscInt frame, PetscBool with_time)
{
  char group[CLOTH_NAME_LEN], path[CLOTH_PATH_LEN], inner[64];

  PetscFunctionBeginUser;
  PetscCall(OutputFrameGroupName(out->steps[frame], group, sizeof(group)));
  PetscCall(PetscSNPrintf(inner, sizeof(inner), "%s    ", indent));
  PetscCall(PetscFPrintf(out->comm, fp, "%s<Grid Name=\"fabric\" GridType=\"Uniform\">\n", indent));
  if (with_time) PetscCall(PetscFPrintf(out->comm, fp, "%s  <Time Value=\"%.17g\"/>\n", indent, (double)out->times[frame]));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"%" PetscInt_FMT "\">\n", indent, out->nquads));
  PetscCall(OutputXdmfDataItem(out, fp, inner, out->nquads, 4, "Int", sizeof(PetscInt), "/topology/quads"));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  </Topology>\n%s  <Geometry GeometryType=\"XYZ\">\n", indent, indent));
  PetscCall(PetscSNPrintf(path, sizeof(path), "/frames/%s/position", group));
  PetscCall(OutputXdmfDataItem(out, fp, inner, out->nparticles, 3, "Float", sizeof(double), path));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  </Geometry>\n", indent));
  for (PetscInt f = 0; f < OUTPUT_NFIELDS; f++) {
    PetscCall(PetscFPrintf(out->comm, fp, "%s  <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", indent, OutputNodeFields[f].name, OutputNodeFields[f].ncomp == 1 ? "Scalar" : "Vector"));
    PetscCall(PetscSNPrintf(path, sizeof(path), "/frames/%s/%s", group, OutputNodeFields[f].name));
    PetscCall(OutputXdmfDataItem(out, fp, inner, out->nparticles, OutputNodeFields[f].ncomp, "Float", sizeof(double), path));
    PetscCall(PetscFPrintf(out->comm, fp, "%s  </Attribute>\n", indent));
  }
  PetscCall(PetscFPrintf(out->comm, fp, "%s</Grid>\n", indent));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The grid of a static mesh (the same datasets in every frame). */
static PetscErrorCode OutputXdmfStaticGrid(ClothOutput out, FILE *fp, const char indent[], const OutputStaticMesh *mesh)
{
  char path[CLOTH_PATH_LEN], inner[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(inner, sizeof(inner), "%s    ", indent));
  PetscCall(PetscFPrintf(out->comm, fp, "%s<Grid Name=\"%s\" GridType=\"Uniform\">\n", indent, mesh->name));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  <Topology TopologyType=\"Triangle\" NumberOfElements=\"%" PetscInt_FMT "\">\n", indent, mesh->ntris));
  PetscCall(PetscSNPrintf(path, sizeof(path), "/static/%s/triangles", mesh->name));
  PetscCall(OutputXdmfDataItem(out, fp, inner, mesh->ntris, 3, "Int", sizeof(PetscInt), path));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  </Topology>\n%s  <Geometry GeometryType=\"XYZ\">\n", indent, indent));
  PetscCall(PetscSNPrintf(path, sizeof(path), "/static/%s/points", mesh->name));
  PetscCall(OutputXdmfDataItem(out, fp, inner, mesh->nverts, 3, "Float", sizeof(double), path));
  PetscCall(PetscFPrintf(out->comm, fp, "%s  </Geometry>\n%s</Grid>\n", indent, indent));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One time step: the fabric grid alone, or with static meshes a spatial collection holding them all. */
static PetscErrorCode OutputXdmfFrame(ClothOutput out, FILE *fp, PetscInt frame)
{
  PetscFunctionBeginUser;
  if (!out->nstatic) {
    PetscCall(OutputXdmfFabricGrid(out, fp, "      ", frame, PETSC_TRUE));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PetscFPrintf(out->comm, fp, "      <Grid Name=\"step_%06" PetscInt64_FMT "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", out->steps[frame]));
  PetscCall(PetscFPrintf(out->comm, fp, "        <Time Value=\"%.17g\"/>\n", (double)out->times[frame]));
  PetscCall(OutputXdmfFabricGrid(out, fp, "        ", frame, PETSC_FALSE));
  for (PetscInt m = 0; m < out->nstatic; m++) PetscCall(OutputXdmfStaticGrid(out, fp, "        ", &out->statics[m]));
  PetscCall(PetscFPrintf(out->comm, fp, "      </Grid>\n"));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rewrites NAME.xdmf through a temporary file, so that ParaView never sees half a file. */
static PetscErrorCode OutputWriteXdmf(ClothOutput out)
{
  char  tmp[CLOTH_PATH_LEN];
  FILE *fp;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", out->xdmfpath));
  PetscCall(ClothFileOpenText(out->comm, tmp, &fp));
  PetscCall(PetscFPrintf(out->comm, fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n  <Domain>\n"));
  if (out->run_id) PetscCall(PetscFPrintf(out->comm, fp, "    <!-- run_id %016llx: the run that wrote this series (attribute run_id of its .h5 and checkpoints) -->\n", (unsigned long long)out->run_id));
  PetscCall(PetscFPrintf(out->comm, fp, "    <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n", out->name));
  for (PetscInt i = 0; i < out->nframes; i++) PetscCall(OutputXdmfFrame(out, fp, i));
  PetscCall(PetscFPrintf(out->comm, fp, "    </Grid>\n  </Domain>\n</Xdmf>\n"));
  PetscCall(ClothFileCommitText(out->comm, fp, tmp, out->xdmfpath));
  out->xdmf_frames     = out->nframes;
  out->xdmf_written_at = MPI_Wtime();
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Rewrites the .xdmf when -output_xdmf_seconds have passed since its last rewrite (rank 0's clock decides for all:
   the rewrite is collective). */
static PetscErrorCode OutputWriteXdmfIfDue(ClothOutput out)
{
  int due;

  PetscFunctionBeginUser;
  due = out->xdmf_seconds <= 0 || out->xdmf_frames == 0 || MPI_Wtime() - out->xdmf_written_at >= out->xdmf_seconds;
  PetscCallMPI(MPI_Bcast(&due, 1, MPI_INT, 0, out->comm));
  if (due) PetscCall(OutputWriteXdmf(out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputSetXdmfInterval(ClothOutput out, PetscReal seconds)
{
  PetscFunctionBeginUser;
  PetscCheck(seconds >= 0, out->comm, PETSC_ERR_ARG_OUTOFRANGE, "ClothOutputSetXdmfInterval: %g s, expected >= 0 (-output_xdmf_seconds is checked where it is read)", (double)seconds);
  out->xdmf_seconds = seconds;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputFlush(ClothOutput out)
{
  PetscFunctionBeginUser;
  if (out && out->xdmf_frames != out->nframes) PetscCall(OutputWriteXdmf(out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A restart appends to the series of its own run only: another run's frames (perhaps of other particles, after
   -output_overwrite) would mix with its own. A series without run_id (an older clothsim's) is not checked. */
static PetscErrorCode OutputCheckRun(ClothOutput out, hid_t file, uint64_t run_id)
{
  PetscBool has;
  uint64_t  written;

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeExists(file, "run_id", &has));
  if (!has || !run_id) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothH5AttributeReadUInt64(file, "run_id", &written));
  if (written != run_id) PetscCall(ClothH5FileClose(&file));
  PetscCheck(written == run_id, out->comm, PETSC_ERR_USER_INPUT,
             "Output series %s was written by another run than the checkpoint's (its frames would mix with this run's): continue into another -output_dir, or move this series away to start a new one there", out->h5path);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Opens the series file: a new one, or with restart_time >= 0 an existing one trimmed to that time. */
static PetscErrorCode OutputSetUpFile(ClothOutput out, const ClothOutputTopology *topology, PetscReal restart_time)
{
  PetscBool exists = PETSC_FALSE;
  hid_t     file;

  PetscFunctionBeginUser;
  PetscCall(ClothFileExists(out->comm, out->h5path, &exists));
  if (restart_time >= 0 && exists) {
    PetscCall(OutputFileOpen(out, &file));
    PetscCall(OutputCheckRun(out, file, topology->run_id));
    PetscCall(OutputWriteTopology(out, file, topology));
    PetscCall(OutputTrimFrames(out, file, restart_time));
  } else {
    PetscCall(ClothH5FileCreate(out->comm, out->h5path, &file));
    if (topology->run_id) PetscCall(ClothH5AttributeWriteUInt64(file, "run_id", topology->run_id));
    PetscCall(ClothProvenanceWrite(out->comm, file, topology->scene)); /* what made the series; a restart appends to it */
    PetscCall(OutputWriteTopology(out, file, topology));
  }
  PetscCall(ClothH5FileClose(&file));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputCreate(MPI_Comm comm, const char dir[], const char name[], const ClothOutputTopology *topology, PetscReal restart_time, ClothOutput *out)
{
  ClothOutput o;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  PetscCall(PetscCommDuplicate(comm, &o->comm, NULL));
  PetscCall(PetscStrncpy(o->name, name, sizeof(o->name)));
  PetscCall(PetscSNPrintf(o->h5name, sizeof(o->h5name), "%s.h5", name));
  PetscCall(PetscSNPrintf(o->h5path, sizeof(o->h5path), "%s/%s.h5", dir, name));
  PetscCall(PetscSNPrintf(o->xdmfpath, sizeof(o->xdmfpath), "%s/%s.xdmf", dir, name));
  o->nparticles   = topology->nparticles;
  o->nquads       = topology->nquads;
  o->run_id       = topology->run_id;
  o->xdmf_seconds = CLOTH_OUTPUT_XDMF_SECONDS;
  PetscCall(ClothFileMakeDirectory(o->comm, dir));
  PetscCall(OutputSetUpFile(o, topology, restart_time));
  PetscCall(OutputWriteXdmf(o));
  *out = o;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The counts of a frame, as int64 attributes of its group: scalars that h5py reads without loading a
   dataset (g.attrs["body_contacts"]). */
static PetscErrorCode OutputWriteFrameCounts(hid_t group, const ClothOutputFrame *frame)
{
  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeWriteInt64(group, "body_contacts", frame->body_contacts));
  PetscCall(ClothH5AttributeWriteInt64(group, "self_contacts", frame->self_contacts));
  PetscCall(ClothH5AttributeWriteInt64(group, "self_contact_particles", frame->self_contact_particles));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Room for a frame (positions and node fields, 8 bytes a value) plus 1 MB, checked before the series is touched. */
static PetscErrorCode OutputCheckFrameSpace(ClothOutput out, PetscInt64 step)
{
  double bytes = 1e6 + 24.0 * (double)out->nparticles;
  char   what[CLOTH_PATH_LEN + 64], dir[CLOTH_PATH_LEN];
  char  *slash;

  PetscFunctionBeginUser;
  for (PetscInt f = 0; f < OUTPUT_NFIELDS; f++) bytes += 8.0 * (double)(OutputNodeFields[f].ncomp * out->nparticles);
  PetscCall(PetscStrncpy(dir, out->h5path, sizeof(dir)));
  slash = strrchr(dir, '/');
  if (slash)
    *slash = 0;
  else
    PetscCall(PetscStrncpy(dir, ".", sizeof(dir)));
  PetscCall(PetscSNPrintf(what, sizeof(what), "the frame of step %" PetscInt64_FMT " into %s", step, out->h5path));
  PetscCall(ClothFileCheckSpace(out->comm, dir, bytes, what));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes group /frames/NNNNNN (replacing one of the same step) with the positions, node fields and counts. */
static PetscErrorCode OutputWriteFrameFields(ClothOutput out, PetscInt64 step, PetscReal time, Vec position, const Vec fields[], const ClothOutputFrame *content)
{
  hid_t file, frames, frame;
  char  group[CLOTH_NAME_LEN], what[CLOTH_PATH_LEN + 64];

  PetscFunctionBeginUser;
  PetscCall(OutputCheckFrameSpace(out, step));
  PetscCall(OutputFrameGroupName(step, group, sizeof(group)));
  PetscCall(PetscSNPrintf(what, sizeof(what), "The frame of step %" PetscInt64_FMT " into %s", step, out->h5path));
  PetscCall(ClothWatchdogArm(what, NULL, CLOTH_EXIT_FILE));
  PetscCall(OutputFileOpen(out, &file));
  ClothCallHDF5(frames = H5Gopen2(file, "frames", H5P_DEFAULT));
  PetscCall(ClothH5LinkDeleteIfExists(frames, group));
  ClothCallHDF5(frame = H5Gcreate2(frames, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(ClothH5AttributeWriteInt64(frame, "step", step));
  PetscCall(ClothH5AttributeWriteReal(frame, "time", time));
  PetscCall(OutputWriteFrameCounts(frame, content));
  PetscCall(ClothH5WriteVec(frame, "position", position, 3));
  for (PetscInt f = 0; f < OUTPUT_NFIELDS; f++) PetscCall(ClothH5WriteVec(frame, OutputNodeFields[f].name, fields[f], OutputNodeFields[f].ncomp));
  ClothCallHDF5(H5Gclose(frame));
  ClothCallHDF5(H5Gclose(frames));
  PetscCall(ClothH5FileClose(&file));
  PetscCall(ClothWatchdogDisarm());
  PetscCall(OutputRecordFrame(out, step, time));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputWriteFrame(ClothOutput out, PetscInt step, PetscReal time, Vec position, const ClothOutputFrame *frame)
{
  PetscInt n;
  Vec      fields[OUTPUT_NFIELDS] = {frame->velocity, frame->strain, frame->body_contact, frame->self_contact, frame->stress, frame->pressure};

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(position, &n));
  PetscCheck(n == 3 * out->nparticles, out->comm, PETSC_ERR_ARG_SIZ, "Frame positions have size %" PetscInt_FMT ", the series has %" PetscInt_FMT " particles", n, out->nparticles);
  for (PetscInt f = 0; f < OUTPUT_NFIELDS; f++) {
    PetscCall(VecGetSize(fields[f], &n));
    PetscCheck(n == OutputNodeFields[f].ncomp * out->nparticles, out->comm, PETSC_ERR_ARG_SIZ, "Frame field %s has size %" PetscInt_FMT ", expected %" PetscInt_FMT " per particle (%" PetscInt_FMT " particles)", OutputNodeFields[f].name, n,
               OutputNodeFields[f].ncomp, out->nparticles);
  }
  PetscCall(OutputWriteFrameFields(out, step, time, position, fields, frame));
  PetscCall(OutputWriteXdmfIfDue(out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Enters a static mesh in the list (replacing one of the same name). */
static PetscErrorCode OutputRecordStaticMesh(ClothOutput out, const char name[], PetscInt nverts, PetscInt ntris)
{
  PetscInt  m    = 0;
  PetscBool same = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (; m < out->nstatic && !same; m++) PetscCall(PetscStrcmp(out->statics[m].name, name, &same));
  if (same)
    m--;
  else {
    PetscCall(PetscRealloc((size_t)(out->nstatic + 1) * sizeof(*out->statics), &out->statics));
    m = out->nstatic++;
  }
  PetscCall(PetscStrncpy(out->statics[m].name, name, sizeof(out->statics[m].name)));
  out->statics[m].nverts = nverts;
  out->statics[m].ntris  = ntris;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputAddStaticMesh(ClothOutput out, const char name[], PetscInt nverts, const PetscReal coords[], PetscInt ntris, const PetscInt tris[])
{
  hid_t file, statics, mesh;

  PetscFunctionBeginUser;
  PetscCall(OutputFileOpen(out, &file));
  PetscCall(OutputGroupOpenOrCreate(file, "static", &statics));
  PetscCall(ClothH5LinkDeleteIfExists(statics, name));
  ClothCallHDF5(mesh = H5Gcreate2(statics, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(ClothH5WriteRealTable(out->comm, mesh, "points", nverts, 3, coords));
  PetscCall(ClothH5WriteIntTable(out->comm, mesh, "triangles", ntris, 3, tris));
  ClothCallHDF5(H5Gclose(mesh));
  ClothCallHDF5(H5Gclose(statics));
  PetscCall(ClothH5FileClose(&file));
  PetscCall(OutputRecordStaticMesh(out, name, nverts, ntris));
  PetscCall(OutputWriteXdmf(out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputGetFrames(ClothOutput out, PetscInt *nframes, const PetscInt64 *steps[], const PetscReal *times[])
{
  PetscFunctionBeginUser;
  if (nframes) *nframes = out->nframes;
  if (steps) *steps = out->steps;
  if (times) *times = out->times;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothOutputDestroy(ClothOutput *out)
{
  PetscFunctionBeginUser;
  if (!*out) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(ClothOutputFlush(*out));
  PetscCall(PetscFree((*out)->steps));
  PetscCall(PetscFree((*out)->times));
  PetscCall(PetscFree((*out)->statics));
  PetscCall(PetscCommDestroy(&(*out)->comm));
  PetscCall(PetscFree(*out));
  PetscFunctionReturn(PETSC_SUCCESS);
}
