/* File-system helpers: see fileutil.h. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <time.h>
#include <unistd.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include "fileutil.h"

#define FILE_LOCK_NAME ".clothsim.lock"
#define FILE_LOCK_TEXT_LEN 512

/* The module's one shape: rank 0 runs action(ctx), plain C returning 0 or an errno value (or a code < 0 of the
   caller's), and every rank gets that result in *err, so that all ranks take the same error path. */
static PetscErrorCode RunOnRankZero(MPI_Comm comm, int (*action)(void *), void *ctx, int *err)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  *err = rank == 0 ? action(ctx) : 0;
  PetscCallMPI(MPI_Bcast(err, 1, MPI_INT, 0, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* mkdir -p of the directory ctx on the calling rank; returns 0 or an errno value. */
static int MakeDirectoryLocal(void *ctx)
{
  const char *dir = ctx;
  char        path[CLOTH_PATH_LEN];
  size_t      len = strlen(dir);

  if (len == 0) return 0;
  if (len >= sizeof(path)) return ENAMETOOLONG;
  memcpy(path, dir, len + 1);
  for (char *p = path + 1;; p++) {
    if (*p == '/' || *p == '\0') {
      char        end = *p;
      struct stat st;

      *p = '\0';
      if (mkdir(path, 0777) != 0 && errno != EEXIST) return errno;
      if (stat(path, &st) != 0) return errno;
      if (!S_ISDIR(st.st_mode)) return ENOTDIR;
      *p = end;
      if (end == '\0') break;
    }
  }
  return 0;
}

PetscErrorCode ClothFileMakeDirectory(MPI_Comm comm, const char dir[])
{
  int err;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, MakeDirectoryLocal, (void *)dir, &err));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot create directory %s: %s", dir, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 1 when the path ctx names a regular file, else 0. */
static int IsRegularFileLocal(void *ctx)
{
  struct stat st;

  return stat((const char *)ctx, &st) == 0 && S_ISREG(st.st_mode);
}

PetscErrorCode ClothFileExists(MPI_Comm comm, const char path[], PetscBool *exists)
{
  int found;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, IsRegularFileLocal, (void *)path, &found));
  *exists = found ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 0 when the path ctx is a regular file that can be opened for reading, -1: a directory, -2: not a regular file,
   else the errno value. */
static int CheckReadableLocal(void *ctx)
{
  const char *path = ctx;
  struct stat st;
  FILE       *fp;

  if (stat(path, &st) != 0) return errno;
  if (S_ISDIR(st.st_mode)) return -1;
  if (!S_ISREG(st.st_mode)) return -2;
  if (!(fp = fopen(path, "rb"))) return errno;
  fclose(fp);
  return 0;
}

PetscErrorCode ClothFileCheckReadable(MPI_Comm comm, const char what[], const char path[], const char in_directory[])
{
  int err;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, CheckReadableLocal, (void *)path, &err));
  PetscCheck(err != -1, comm, PETSC_ERR_FILE_OPEN, "%s %s is a directory: expected a file (%s)", what, path, in_directory);
  PetscCheck(err != -2, comm, PETSC_ERR_FILE_OPEN, "%s %s is not a regular file: expected a file (%s)", what, path, in_directory);
  PetscCheck(err != ENOENT, comm, PETSC_ERR_FILE_OPEN, "%s %s does not exist", what, path);
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "%s %s cannot be read: %s", what, path, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  const char *dir, *holder;
  int         fd;
  char        text[FILE_LOCK_TEXT_LEN];
} DirectoryLock;

/* Rank 0 only, plain C: opens and locks dir/.clothsim.lock of the DirectoryLock ctx; returns 0 and the locked fd, or
   EAGAIN with the holder's text in text (another live run), or another errno (ENOLCK and the like: no locks here). */
static int LockDirectoryLocal(void *ctx)
{
  DirectoryLock *lk  = ctx;
  const char    *dir = lk->dir, *holder = lk->holder;
  int           *fd        = &lk->fd;
  char          *text      = lk->text;
  const size_t   len       = sizeof(lk->text);
  const size_t   path_len  = strlen(dir) + sizeof(FILE_LOCK_NAME) + 1;
  char          *path      = malloc(path_len);
  struct flock   lock      = {.l_type = F_WRLCK, .l_whence = SEEK_SET, .l_start = 0, .l_len = 0};
  char           host[256] = "unknown", started[64] = "";
  time_t         now = time(NULL);
  int            err = 0;

  *fd = -1;
  if (!path) return ENOMEM;
  snprintf(path, path_len, "%s/%s", dir, FILE_LOCK_NAME);
  if ((*fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644)) < 0)
    err = errno;
  else if (fcntl(*fd, F_SETLK, &lock) != 0) {
    ssize_t got;

    err                     = (errno == EACCES || errno == EAGAIN) ? EAGAIN : errno;
    got                     = pread(*fd, text, len - 1, 0);
    text[got > 0 ? got : 0] = 0;
    if (got > 0 && text[got - 1] == '\n') text[got - 1] = 0;
    close(*fd);
    *fd = -1;
  } else {
    gethostname(host, sizeof(host) - 1);
    strftime(started, sizeof(started), "%Y-%m-%d %H:%M:%S", localtime(&now));
    snprintf(text, len, "%s, pid %ld on host %s, started %s", holder, (long)getpid(), host, started);
    /* a failed write is ignored: the lock holds all the same, the text is only for people */
    if (ftruncate(*fd, 0) == 0 && pwrite(*fd, text, strlen(text), 0) >= 0 && pwrite(*fd, "\n", 1, (off_t)strlen(text)) >= 0) err = 0;
  }
  free(path);
  return err;
}

PetscErrorCode ClothFileLockDirectory(MPI_Comm comm, const char dir[], const char holder[], int *fd)
{
  DirectoryLock lk = {.dir = dir, .holder = holder, .fd = -1, .text = ""};
  int           err;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, LockDirectoryLocal, &lk, &err));
  *fd = lk.fd;
  PetscCallMPI(MPI_Bcast(lk.text, (PetscMPIInt)sizeof(lk.text), MPI_CHAR, 0, comm));
  PetscCheck(err != EAGAIN, comm, PETSC_ERR_USER_INPUT, "output directory %s is in use by another run (%s; lock %s/%s): wait for it to end, or choose another -output_dir", dir, lk.text[0] ? lk.text : "holder unknown", dir, FILE_LOCK_NAME);
  PetscCheck(err != EACCES && err != EROFS && err != ENOENT && err != ENOTDIR && err != ENOSPC, comm, PETSC_ERR_FILE_WRITE, "output directory %s: cannot create the lock file %s in it: %s", dir, FILE_LOCK_NAME, strerror(err));
  if (err) PetscCall(PetscFPrintf(comm, PETSC_STDERR, "WARNING: output directory %s cannot be locked (%s): nothing stops a second run from writing into it at the same time\n", dir, strerror(err)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFileUnlockDirectory(int *fd)
{
  PetscFunctionBeginUser;
  if (*fd >= 0) {
    if (ftruncate(*fd, 0) != 0) { /* ignored: an unheld lock file's text is harmless */
    }
    close(*fd); /* releases the lock */
  }
  *fd = -1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

typedef struct {
  const char *tmp, *path;
  FILE       *fp;
} TextFile;

/* Opens ctx's tmp for writing into its fp; returns 0 or an errno value. */
static int OpenTextLocal(void *ctx)
{
  TextFile *file = ctx;

  errno    = 0;
  file->fp = fopen(file->tmp, "w");
  return file->fp ? 0 : (errno ? errno : EIO);
}

PetscErrorCode ClothFileOpenText(MPI_Comm comm, const char tmp[], FILE **fp)
{
  TextFile file = {tmp, NULL, NULL};
  int      err;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, OpenTextLocal, &file, &err));
  *fp = file.fp;
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "Cannot create %s: %s", tmp, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Flushes, syncs and closes ctx's fp, removing its tmp on a write error; returns 0 or an errno value. */
static int CloseTextLocal(void *ctx)
{
  TextFile *file = ctx;
  int       err  = 0;

  errno = 0;
  if (fflush(file->fp) != 0 || ferror(file->fp)) err = errno ? errno : EIO;
  if (!err && fsync(fileno(file->fp)) != 0) err = errno;
  if (fclose(file->fp) != 0 && !err) err = errno;
  if (err) remove(file->tmp);
  return err;
}

PetscErrorCode ClothFileCommitText(MPI_Comm comm, FILE *fp, const char tmp[], const char path[])
{
  TextFile file = {tmp, path, fp};
  int      err;

  PetscFunctionBeginUser;
  PetscCall(RunOnRankZero(comm, CloseTextLocal, &file, &err));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot write %s: %s; %s is left as it was", tmp, strerror(err), path);
  PetscCall(ClothFileRename(comm, tmp, path));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothFileCheckSpace(MPI_Comm comm, const char dir[], double bytes, const char what[])
{
  PetscMPIInt rank;
  double      avail = -1; /* -1: unknown (statvfs failed): the write goes ahead */

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    struct statvfs fs;

    if (statvfs(dir, &fs) == 0) avail = (double)fs.f_bavail * (double)fs.f_frsize;
  }
  PetscCallMPI(MPI_Bcast(&avail, 1, MPI_DOUBLE, 0, comm));
  PetscCheck(avail < 0 || avail >= bytes, comm, PETSC_ERR_FILE_WRITE, "Cannot write %s: it needs about %.3g MB, the file system of %s has %.3g MB free (%s); the files already written are left as they were", what, bytes / 1e6, dir, avail / 1e6,
             strerror(ENOSPC));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* rename(2) of ctx's tmp onto its path; returns 0 or an errno value. */
static int RenameLocal(void *ctx)
{
  const TextFile *file = ctx;

  return rename(file->tmp, file->path) != 0 ? errno : 0;
}

PetscErrorCode ClothFileRename(MPI_Comm comm, const char from[], const char to[])
{
  TextFile file = {from, to, NULL};
  int      err;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Barrier(comm));
  PetscCall(RunOnRankZero(comm, RenameLocal, &file, &err));
  PetscCheck(!err, comm, PETSC_ERR_FILE_WRITE, "Cannot rename %s to %s: %s", from, to, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}
