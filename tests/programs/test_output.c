/* Output series: writes the series that tests/checkers/check_xdmf.py then opens with ParaView and h5py.
   Prints nothing unless a check fails.

   Usage: mpiexec -n P test_output -dir DIR, which writes in DIR
     sheet.xdmf/.h5    two pieces (3 x 3 and 2 x 4 particles: 17 particles, 7 quads), frames at
                       steps 0, 10, 20 (times 0, 0.05, 0.1)
     restart.xdmf/.h5  frames at times 0.1, 0.2, 0.3; reopened with restart_time 0.2 (the frame at 0.3
                       is dropped), the frame at 0.2 written again (it replaces the old one), then a
                       new frame at 0.3 with positions shifted by 1000
     scene.xdmf/.h5    the sheet plus a static triangle mesh "mannequin" (4 points, 2 triangles),
                       frames at times 0 and 0.5
     fresh.xdmf/.h5    restart_time >= 0 with no series yet: starts a new one (one frame at 0.7)
   Position of particle i, component c at time t: shift + (i + c/2) (1 + t) + 1/8; velocity sin(i + c) + t;
   strain i t / 100; body_contact (i + step) mod 3; self_contact i mod 2; counts: body_contacts = step,
   self_contacts = step + 1, self_contact_particles = step + 2. */
#include <string.h>
#include "output.h"
#include "test_support.h"

static const char help[] = "Writes XDMF + HDF5 output series for check_xdmf.py.\n";

/* Two pattern pieces, row by row: nu x nv grids of particles, one after the other. */
static const PetscInt PieceSizes[2][2] = {{3, 3}, {2, 4}};

static PetscErrorCode CreateTopology(ClothOutputTopology *topology, PetscInt **quads)
{
  PetscInt nparticles = 0, nquads = 0, q = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(topology, sizeof(*topology))); /* no run identity, no scene */
  for (PetscInt p = 0; p < 2; p++) nquads += (PieceSizes[p][0] - 1) * (PieceSizes[p][1] - 1);
  PetscCall(PetscMalloc1(4 * nquads, quads));
  for (PetscInt p = 0; p < 2; p++) {
    PetscInt nu = PieceSizes[p][0], nv = PieceSizes[p][1];

    for (PetscInt j = 0; j < nv - 1; j++) {
      for (PetscInt i = 0; i < nu - 1; i++, q++) {
        PetscInt corner = nparticles + j * nu + i;

        (*quads)[4 * q + 0] = corner;
        (*quads)[4 * q + 1] = corner + 1;
        (*quads)[4 * q + 2] = corner + nu + 1;
        (*quads)[4 * q + 3] = corner + nu;
      }
    }
    nparticles += nu * nv;
  }
  topology->nparticles = nparticles;
  topology->nquads     = nquads;
  topology->quads      = *quads;
  topology->run_id     = 0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteFrame(ClothOutput out, MPI_Comm comm, PetscInt n, PetscInt step, PetscReal time, PetscReal shift)
{
  Vec              x, v, strain, body, self;
  PetscInt         lo, hi;
  PetscScalar     *xa, *va, *sa, *ba, *ca;
  ClothOutputFrame frame;

  PetscFunctionBeginUser;
  PetscCall(VecCreate(comm, &x));
  PetscCall(VecSetSizes(x, PETSC_DECIDE, 3 * n));
  PetscCall(VecSetBlockSize(x, 3));
  PetscCall(VecSetFromOptions(x));
  PetscCall(VecDuplicate(x, &v));
  PetscCall(VecGetOwnershipRange(x, &lo, &hi));
  PetscCall(VecGetArray(x, &xa));
  PetscCall(VecGetArray(v, &va));
  for (PetscInt k = lo; k < hi; k++) {
    PetscInt i = k / 3, c = k % 3;

    xa[k - lo] = shift + (i + 0.5 * c) * (1.0 + time) + 0.125;
    va[k - lo] = PetscSinReal((PetscReal)(i + c)) + time;
  }
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecRestoreArray(v, &va));
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, n, &strain));
  PetscCall(VecGetOwnershipRange(strain, &lo, &hi));
  PetscCall(VecGetArray(strain, &sa));
  for (PetscInt i = lo; i < hi; i++) sa[i - lo] = i * time / 100;
  PetscCall(VecRestoreArray(strain, &sa));
  PetscCall(VecDuplicate(strain, &body));
  PetscCall(VecDuplicate(strain, &self));
  PetscCall(VecGetArray(body, &ba));
  PetscCall(VecGetArray(self, &ca));
  for (PetscInt i = lo; i < hi; i++) {
    ba[i - lo] = (PetscReal)((i + step) % 3);
    ca[i - lo] = (PetscReal)(i % 2);
  }
  PetscCall(VecRestoreArray(self, &ca));
  PetscCall(VecRestoreArray(body, &ba));
  /* the fit maps reuse two of the fields: the writer treats every per-particle scalar alike */
  frame = (ClothOutputFrame){.velocity = v, .strain = strain, .body_contact = body, .self_contact = self, .stress = self, .pressure = body, .body_contacts = step, .self_contacts = step + 1, .self_contact_particles = step + 2};
  PetscCall(ClothOutputWriteFrame(out, step, time, x, &frame));
  PetscCall(VecDestroy(&body));
  PetscCall(VecDestroy(&self));
  PetscCall(VecDestroy(&strain));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks the frame list of out against the expected steps and times. */
static PetscErrorCode CheckFrames(ClothOutput out, MPI_Comm comm, PetscInt n, const PetscInt64 steps[], const PetscReal times[])
{
  PetscInt          nframes;
  const PetscInt64 *s;
  const PetscReal  *t;

  PetscFunctionBeginUser;
  PetscCall(ClothOutputGetFrames(out, &nframes, &s, &t));
  PetscCheck(nframes == n, comm, PETSC_ERR_PLIB, "Series has %" PetscInt_FMT " frames, expected %" PetscInt_FMT, nframes, n);
  for (PetscInt i = 0; i < n; i++)
    PetscCheck(s[i] == steps[i] && t[i] == times[i], comm, PETSC_ERR_PLIB, "Frame %" PetscInt_FMT " is step %" PetscInt64_FMT " at %g, expected step %" PetscInt64_FMT " at %g", i, s[i], (double)t[i], steps[i], (double)times[i]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteSheet(MPI_Comm comm, const char dir[], const ClothOutputTopology *topology)
{
  ClothOutput      out;
  const PetscInt64 steps[] = {0, 10, 20};
  const PetscReal  times[] = {0, 0.05, 0.1};

  PetscFunctionBeginUser;
  PetscCall(ClothOutputCreate(comm, dir, "sheet", topology, -1, &out));
  for (PetscInt i = 0; i < 3; i++) PetscCall(WriteFrame(out, comm, topology->nparticles, (PetscInt)steps[i], times[i], 0));
  PetscCall(CheckFrames(out, comm, 3, steps, times));
  PetscCall(ClothOutputDestroy(&out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteRestart(MPI_Comm comm, const char dir[], const ClothOutputTopology *topology)
{
  ClothOutput      out;
  const PetscInt64 steps[] = {10, 20, 30};
  const PetscReal  times[] = {0.1, 0.2, 0.3};

  PetscFunctionBeginUser;
  PetscCall(ClothOutputCreate(comm, dir, "restart", topology, -1, &out));
  for (PetscInt i = 0; i < 3; i++) PetscCall(WriteFrame(out, comm, topology->nparticles, (PetscInt)steps[i], times[i], 0));
  PetscCall(ClothOutputDestroy(&out));
  PetscCall(ClothOutputCreate(comm, dir, "restart", topology, times[1], &out));
  PetscCall(CheckFrames(out, comm, 2, steps, times));
  PetscCall(WriteFrame(out, comm, topology->nparticles, (PetscInt)steps[1], times[1], 0)); /* the restart step again: replaces, no duplicate */
  PetscCall(CheckFrames(out, comm, 2, steps, times));
  PetscCall(WriteFrame(out, comm, topology->nparticles, (PetscInt)steps[2], times[2], 1000));
  PetscCall(CheckFrames(out, comm, 3, steps, times));
  PetscCall(ClothOutputDestroy(&out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteScene(MPI_Comm comm, const char dir[], const ClothOutputTopology *topology)
{
  ClothOutput     out;
  const PetscReal coords[] = {-1, -1, -1, 2, -1, -1, 2, 2, -1, -1, 2, -1};
  const PetscInt  tris[]   = {0, 1, 2, 0, 2, 3};

  PetscFunctionBeginUser;
  PetscCall(ClothOutputCreate(comm, dir, "scene", topology, -1, &out));
  PetscCall(ClothOutputAddStaticMesh(out, "mannequin", 4, coords, 2, tris));
  PetscCall(WriteFrame(out, comm, topology->nparticles, 0, 0.0, 0));
  PetscCall(WriteFrame(out, comm, topology->nparticles, 50, 0.5, 0));
  PetscCall(ClothOutputDestroy(&out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteFresh(MPI_Comm comm, const char dir[], const ClothOutputTopology *topology)
{
  ClothOutput      out;
  const PetscInt64 steps[] = {70};
  const PetscReal  times[] = {0.7};

  PetscFunctionBeginUser;
  PetscCall(ClothOutputCreate(comm, dir, "fresh", topology, 0.5, &out));
  PetscCall(CheckFrames(out, comm, 0, steps, times));
  PetscCall(WriteFrame(out, comm, topology->nparticles, (PetscInt)steps[0], times[0], 0));
  PetscCall(CheckFrames(out, comm, 1, steps, times));
  PetscCall(ClothOutputDestroy(&out));
  PetscFunctionReturn(PETSC_SUCCESS);
}

int main(int argc, char **argv)
{
  char                dir[CLOTH_PATH_LEN] = "test_output_series";
  ClothOutputTopology topology;
  PetscInt           *quads;
  MPI_Comm            comm;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-dir", dir, sizeof(dir), NULL));
  PetscCall(CreateTopology(&topology, &quads));
  PetscCall(WriteSheet(comm, dir, &topology));
  PetscCall(WriteRestart(comm, dir, &topology));
  PetscCall(WriteScene(comm, dir, &topology));
  PetscCall(WriteFresh(comm, dir, &topology));
  PetscCall(PetscFree(quads));
  PetscCall(TestCheckExpectationsUsed());
  PetscCall(PetscFinalize());
  return 0;
}
