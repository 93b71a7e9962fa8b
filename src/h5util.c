/* Parallel HDF5 helpers: see h5util.h. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "h5util.h"

/* The longest string attribute read: clothsim writes names and paths (CLOTH_PATH_LEN) as attributes. */
#define CLOTH_H5_MAX_STRING_ATTRIBUTE (1 << 20)

/* The longest file name Open MPI 4.1's ompio opens (measured: 244 opens, 245 aborts in MPI_File_open). */
#define CLOTH_OMPIO_PATH_MAX 244

/* Open MPI's ROMIO component, which opens long names: romio321 in Open MPI 4, romio341 in 5. */
#if defined(OPEN_MPI) && OMPI_MAJOR_VERSION >= 5
#define CLOTH_OMPI_ROMIO "romio341"
#else
#define CLOTH_OMPI_ROMIO "romio321"
#endif

#if defined(PETSC_USE_COMPLEX) || !defined(PETSC_USE_REAL_DOUBLE)
#error "clothsim writes PetscScalar as float64: it needs a real, double precision PETSc build"
#endif

#if defined(PETSC_USE_64BIT_INDICES)
#define CLOTH_H5_NATIVE_INT H5T_NATIVE_INT64
#define CLOTH_H5_FILE_INT H5T_STD_I64LE
#else
#define CLOTH_H5_NATIVE_INT H5T_NATIVE_INT32
#define CLOTH_H5_FILE_INT H5T_STD_I32LE
#endif

/* File access through MPI-IO; metadata is read by one rank and broadcast, and written collectively,
   which keeps opening a file cheap on many ranks. */
static PetscErrorCode H5FileAccessCreate(MPI_Comm comm, hid_t *fapl)
{
  PetscFunctionBeginUser;
  ClothCallHDF5(*fapl = H5Pcreate(H5P_FILE_ACCESS));
  ClothCallHDF5(H5Pset_fapl_mpio(*fapl, comm, MPI_INFO_NULL));
  ClothCallHDF5(H5Pset_all_coll_metadata_ops(*fapl, 1));
  ClothCallHDF5(H5Pset_coll_metadata_write(*fapl, 1));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5PrepareMPIIO(MPI_Comm comm, const char path[])
{
  PetscFunctionBeginUser;
#if defined(OPEN_MPI)
  {
    const char *io = getenv("OMPI_MCA_io");

    if (!io) {
      /* Open MPI fixes its MPI-IO component at the first MPI_File_open (measured with Open MPI 4.1.4: OMPI_MCA_io set
         after MPI_Init but before the first open takes effect, set after it does not); every open comes here first,
         so the first one sets it. Every rank takes the same branch: the environment mpiexec passed is alike. */
      PetscCheck(setenv("OMPI_MCA_io", CLOTH_OMPI_ROMIO, 1) == 0, comm, PETSC_ERR_SYS, "Cannot set OMPI_MCA_io: %s", strerror(errno));
      PetscCall(PetscInfo(NULL, "Open MPI's MPI-IO component %s chosen (before the first file, %s)\n", CLOTH_OMPI_ROMIO, path));
      PetscFunctionReturn(PETSC_SUCCESS);
    }
    /* here OMPI_MCA_io is set: by the first call (romio) or by the user */
    PetscCheck(strlen(path) <= CLOTH_OMPIO_PATH_MAX || strstr(io, "romio"), comm, PETSC_ERR_FILE_OPEN,
               "HDF5 file %s: the path has %zu characters; Open MPI's MPI-IO component ompio aborts on more than %d, and OMPI_MCA_io chooses it: use a shorter -output_dir (or a relative one), or run with OMPI_MCA_io=%s", path, strlen(path),
               CLOTH_OMPIO_PATH_MAX, CLOTH_OMPI_ROMIO);
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5FileCreate(MPI_Comm comm, const char path[], hid_t *file)
{
  hid_t fapl;

  PetscFunctionBeginUser;
  PetscCall(ClothH5PrepareMPIIO(comm, path));
  PetscCall(H5FileAccessCreate(comm, &fapl));
  ClothCallHDF5(*file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl));
  ClothCallHDF5(H5Pclose(fapl));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5FileOpen(MPI_Comm comm, const char path[], unsigned flags, hid_t *file, PetscBool *opened)
{
  hid_t       fapl;
  H5E_auto2_t print_errors;
  void       *print_errors_data;
  int         local, all;

  PetscFunctionBeginUser;
  PetscCall(ClothH5PrepareMPIIO(comm, path));
  PetscCall(H5FileAccessCreate(comm, &fapl));
  ClothCallHDF5(H5Eget_auto2(H5E_DEFAULT, &print_errors, &print_errors_data));
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, NULL, NULL));
  *file = H5Fopen(path, flags, fapl);
  ClothCallHDF5(H5Eset_auto2(H5E_DEFAULT, print_errors, print_errors_data));
  ClothCallHDF5(H5Pclose(fapl));
  local = *file >= 0;
  PetscCallMPI(MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_LAND, comm));
  if (!all) PetscCall(ClothH5FileClose(file));
  *opened = all ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5FileClose(hid_t *file)
{
  PetscFunctionBeginUser;
  if (*file >= 0) ClothCallHDF5(H5Fclose(*file));
  *file = -1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5LinkExists(hid_t loc, const char name[], PetscBool *exists)
{
  htri_t found;

  PetscFunctionBeginUser;
  ClothCallHDF5(found = H5Lexists(loc, name, H5P_DEFAULT));
  *exists = found > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5LinkDeleteIfExists(hid_t loc, const char name[])
{
  PetscBool exists = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(ClothH5LinkExists(loc, name, &exists));
  if (exists) ClothCallHDF5(H5Ldelete(loc, name, H5P_DEFAULT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Collective data transfer: the only kind that scales on a parallel file system. */
static PetscErrorCode H5TransferCreate(hid_t *dxpl)
{
  PetscFunctionBeginUser;
  ClothCallHDF5(*dxpl = H5Pcreate(H5P_DATASET_XFER));
  ClothCallHDF5(H5Pset_dxpl_mpio(*dxpl, H5FD_MPIO_COLLECTIVE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The shape (rows, ncomp) of v in a file and this rank's rows [start, start + count) of it. */
static PetscErrorCode H5VecRows(Vec v, PetscInt ncomp, hsize_t dims[2], hsize_t start[2], hsize_t count[2])
{
  PetscInt n, lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(v, &n));
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCheck(n % ncomp == 0 && lo % ncomp == 0 && hi % ncomp == 0, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "Vec of size %" PetscInt_FMT " owned [%" PetscInt_FMT ", %" PetscInt_FMT ") does not split into whole rows of %" PetscInt_FMT, n, lo, hi, ncomp);
  dims[0]  = (hsize_t)(n / ncomp);
  dims[1]  = (hsize_t)ncomp;
  start[0] = (hsize_t)(lo / ncomp);
  start[1] = 0;
  count[0] = (hsize_t)((hi - lo) / ncomp);
  count[1] = (hsize_t)ncomp;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Selects rows [start, start + count) of filespace and makes the matching memory space; a rank
   without rows selects nothing in both, and still takes part in the collective transfer. */
static PetscErrorCode H5SelectRows(hid_t filespace, const hsize_t start[2], const hsize_t count[2], hid_t *memspace)
{
  PetscFunctionBeginUser;
  ClothCallHDF5(*memspace = H5Screate_simple(2, count, NULL));
  if (count[0] > 0) {
    ClothCallHDF5(H5Sselect_hyperslab(filespace, H5S_SELECT_SET, start, NULL, count, NULL));
  } else {
    ClothCallHDF5(H5Sselect_none(filespace));
    ClothCallHDF5(H5Sselect_none(*memspace));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes the rows [start, start + count) of dataset loc/name, of shape dims, created here. */
static PetscErrorCode H5WriteRows(hid_t loc, const char name[], hid_t filetype, hid_t memtype, const hsize_t dims[2], const hsize_t start[2], const hsize_t count[2], const void *data)
{
  hid_t      filespace, memspace, dset, dxpl;
  const char empty = 0;

  PetscFunctionBeginUser;
  ClothCallHDF5(filespace = H5Screate_simple(2, dims, NULL));
  ClothCallHDF5(dset = H5Dcreate2(loc, name, filetype, filespace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  PetscCall(H5SelectRows(filespace, start, count, &memspace));
  PetscCall(H5TransferCreate(&dxpl));
  ClothCallHDF5(H5Dwrite(dset, memtype, memspace, filespace, dxpl, data ? data : (const void *)&empty));
  ClothCallHDF5(H5Pclose(dxpl));
  ClothCallHDF5(H5Sclose(memspace));
  ClothCallHDF5(H5Dclose(dset));
  ClothCallHDF5(H5Sclose(filespace));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5WriteVec(hid_t loc, const char name[], Vec v, PetscInt ncomp)
{
  hsize_t            dims[2], start[2], count[2];
  const PetscScalar *array;

  PetscFunctionBeginUser;
  PetscCall(H5VecRows(v, ncomp, dims, start, count));
  PetscCall(VecGetArrayRead(v, &array));
  PetscCall(H5WriteRows(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, dims, start, count, array));
  PetscCall(VecRestoreArrayRead(v, &array));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Checks that dataset dset has exactly the shape dims. */
static PetscErrorCode H5CheckShape(hid_t dset, const char name[], const hsize_t dims[2])
{
  hid_t   space;
  int     ndims;
  hsize_t found[2] = {0, 0};

  PetscFunctionBeginUser;
  ClothCallHDF5(space = H5Dget_space(dset));
  ClothCallHDF5(ndims = H5Sget_simple_extent_ndims(space));
  if (ndims == 2) ClothCallHDF5(H5Sget_simple_extent_dims(space, found, NULL));
  ClothCallHDF5(H5Sclose(space));
  PetscCheck(ndims == 2 && found[0] == dims[0] && found[1] == dims[1], PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "HDF5 dataset %s has %d dimensions (%llu x %llu), expected %llu x %llu", name, ndims, (unsigned long long)found[0],
             (unsigned long long)found[1], (unsigned long long)dims[0], (unsigned long long)dims[1]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5ReadVec(hid_t loc, const char name[], Vec v, PetscInt ncomp)
{
  hsize_t      dims[2], start[2], count[2];
  hid_t        dset, filespace, memspace, dxpl;
  PetscScalar *array, empty = 0;

  PetscFunctionBeginUser;
  PetscCall(H5VecRows(v, ncomp, dims, start, count));
  ClothCallHDF5(dset = H5Dopen2(loc, name, H5P_DEFAULT));
  PetscCall(H5CheckShape(dset, name, dims));
  ClothCallHDF5(filespace = H5Dget_space(dset));
  PetscCall(H5SelectRows(filespace, start, count, &memspace));
  PetscCall(H5TransferCreate(&dxpl));
  PetscCall(VecGetArrayWrite(v, &array));
  ClothCallHDF5(H5Dread(dset, H5T_NATIVE_DOUBLE, memspace, filespace, dxpl, array ? array : &empty));
  PetscCall(VecRestoreArrayWrite(v, &array));
  ClothCallHDF5(H5Pclose(dxpl));
  ClothCallHDF5(H5Sclose(memspace));
  ClothCallHDF5(H5Sclose(filespace));
  ClothCallHDF5(H5Dclose(dset));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A table held in full by every rank: rank 0 writes all rows, the others none. */
static PetscErrorCode H5WriteTable(MPI_Comm comm, hid_t loc, const char name[], hid_t filetype, hid_t memtype, PetscInt rows, PetscInt cols, const void *data)
{
  PetscMPIInt rank;
  hsize_t     dims[2], start[2] = {0, 0}, count[2];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  dims[0]  = (hsize_t)rows;
  dims[1]  = (hsize_t)cols;
  count[0] = rank == 0 ? dims[0] : 0;
  count[1] = dims[1];
  PetscCall(H5WriteRows(loc, name, filetype, memtype, dims, start, count, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5WriteIntTable(MPI_Comm comm, hid_t loc, const char name[], PetscInt rows, PetscInt cols, const PetscInt data[])
{
  PetscFunctionBeginUser;
  PetscCall(H5WriteTable(comm, loc, name, CLOTH_H5_FILE_INT, CLOTH_H5_NATIVE_INT, rows, cols, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5WriteRealTable(MPI_Comm comm, hid_t loc, const char name[], PetscInt rows, PetscInt cols, const PetscReal data[])
{
  PetscFunctionBeginUser;
  PetscCall(H5WriteTable(comm, loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, rows, cols, data));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A fixed-length, null-terminated string type of len characters. */
static PetscErrorCode H5StringType(size_t len, hid_t *type)
{
  PetscFunctionBeginUser;
  ClothCallHDF5(*type = H5Tcopy(H5T_C_S1));
  ClothCallHDF5(H5Tset_size(*type, len + 1));
  ClothCallHDF5(H5Tset_strpad(*type, H5T_STR_NULLTERM));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5WriteText(MPI_Comm comm, hid_t loc, const char name[], const char text[])
{
  PetscMPIInt rank;
  hid_t       type, space, dset, dxpl;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(H5StringType(strlen(text), &type));
  ClothCallHDF5(space = H5Screate(H5S_SCALAR));
  ClothCallHDF5(dset = H5Dcreate2(loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  if (rank) ClothCallHDF5(H5Sselect_none(space)); /* the same space as memory and file selection */
  PetscCall(H5TransferCreate(&dxpl));
  ClothCallHDF5(H5Dwrite(dset, type, space, space, dxpl, text));
  ClothCallHDF5(H5Pclose(dxpl));
  ClothCallHDF5(H5Dclose(dset));
  ClothCallHDF5(H5Sclose(space));
  ClothCallHDF5(H5Tclose(type));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeExists(hid_t obj, const char name[], PetscBool *exists)
{
  htri_t found;

  PetscFunctionBeginUser;
  ClothCallHDF5(found = H5Aexists(obj, name));
  *exists = found > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Writes a scalar attribute of the given file and memory types, replacing one of the same name. */
static PetscErrorCode H5AttributeWrite(hid_t obj, const char name[], hid_t filetype, hid_t memtype, const void *value)
{
  PetscBool exists = PETSC_FALSE;
  hid_t     space, attr;

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeExists(obj, name, &exists));
  if (exists) ClothCallHDF5(H5Adelete(obj, name));
  ClothCallHDF5(space = H5Screate(H5S_SCALAR));
  ClothCallHDF5(attr = H5Acreate2(obj, name, filetype, space, H5P_DEFAULT, H5P_DEFAULT));
  ClothCallHDF5(H5Awrite(attr, memtype, value));
  ClothCallHDF5(H5Aclose(attr));
  ClothCallHDF5(H5Sclose(space));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Opens attribute name of obj, refusing with a message that names the object when it is missing. */
static PetscErrorCode H5AttributeOpen(hid_t obj, const char name[], hid_t *attr)
{
  PetscBool exists                  = PETSC_FALSE;
  char      objname[CLOTH_PATH_LEN] = "?";

  PetscFunctionBeginUser;
  PetscCall(ClothH5AttributeExists(obj, name, &exists));
  if (!exists) (void)H5Iget_name(obj, objname, sizeof(objname));
  PetscCheck(exists, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "HDF5 object %s has no attribute %s", objname, name);
  ClothCallHDF5(*attr = H5Aopen(obj, name, H5P_DEFAULT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode H5AttributeRead(hid_t obj, const char name[], hid_t memtype, void *value)
{
  hid_t attr;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeOpen(obj, name, &attr));
  ClothCallHDF5(H5Aread(attr, memtype, value));
  ClothCallHDF5(H5Aclose(attr));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeWriteInt64(hid_t obj, const char name[], PetscInt64 value)
{
  int64_t v = (int64_t)value;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeWrite(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeWriteUInt64(hid_t obj, const char name[], uint64_t value)
{
  PetscFunctionBeginUser;
  PetscCall(H5AttributeWrite(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeWriteReal(hid_t obj, const char name[], PetscReal value)
{
  double v = (double)value;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeWrite(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeWriteString(hid_t obj, const char name[], const char value[])
{
  hid_t type;

  PetscFunctionBeginUser;
  PetscCall(H5StringType(strlen(value), &type));
  PetscCall(H5AttributeWrite(obj, name, type, type, value));
  ClothCallHDF5(H5Tclose(type));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeReadInt64(hid_t obj, const char name[], PetscInt64 *value)
{
  int64_t v;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeRead(obj, name, H5T_NATIVE_INT64, &v));
  *value = (PetscInt64)v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeReadUInt64(hid_t obj, const char name[], uint64_t *value)
{
  PetscFunctionBeginUser;
  PetscCall(H5AttributeRead(obj, name, H5T_NATIVE_UINT64, value));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeReadReal(hid_t obj, const char name[], PetscReal *value)
{
  double v;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeRead(obj, name, H5T_NATIVE_DOUBLE, &v));
  *value = (PetscReal)v;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothH5AttributeReadString(hid_t obj, const char name[], char value[], size_t len)
{
  hid_t  attr, filetype, memtype;
  size_t size;
  char  *buffer;

  PetscFunctionBeginUser;
  PetscCall(H5AttributeOpen(obj, name, &attr));
  ClothCallHDF5(filetype = H5Aget_type(attr));
  PetscCheck(H5Tget_class(filetype) == H5T_STRING && H5Tis_variable_str(filetype) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "HDF5 attribute %s is not a fixed-length string", name);
  PetscCheck((size = H5Tget_size(filetype)) > 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "HDF5 call failed: H5Tget_size(%s)", name);
  /* the size is the file's word: a damaged datatype may claim gigabytes, which would end in the allocator */
  PetscCheck(size <= CLOTH_H5_MAX_STRING_ATTRIBUTE, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "HDF5 attribute %s is a string of %zu bytes: expected at most %d (a name or a path)", name, size, CLOTH_H5_MAX_STRING_ATTRIBUTE);
  PetscCall(H5StringType(size, &memtype));
  PetscCall(PetscCalloc1(size + 1, &buffer));
  ClothCallHDF5(H5Aread(attr, memtype, buffer));
  PetscCall(PetscStrncpy(value, buffer, len));
  PetscCall(PetscFree(buffer));
  ClothCallHDF5(H5Tclose(memtype));
  ClothCallHDF5(H5Tclose(filetype));
  ClothCallHDF5(H5Aclose(attr));
  PetscFunctionReturn(PETSC_SUCCESS);
}
