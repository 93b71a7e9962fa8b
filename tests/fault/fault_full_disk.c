/* A disk that fills during a checkpoint's write, for tests/drivers/checkpoint_write_failure.sh (LD_PRELOAD).

   clothsim checks the free space before it creates a checkpoint, so on a real file system the disk can only
   fill inside HDF5's writes when something else writes at the same time, which no test can time. This
   library makes that happen: writes into temporary checkpoint files (".checkpoint_*.tmp") share a budget of
   CLOTH_FAULT_DISK_BYTES bytes in each process; a write beyond it fails with ENOSPC, as a full disk does.
   Truncating such a file gives its bytes back (the budget is then whole again), as it frees a real file's
   blocks. Other files are untouched. With CLOTH_FAULT_DISK_STALL set, a write beyond the budget never returns
   instead, as on a hung file system. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long long used; /* bytes written into temporary checkpoints since the last truncation to 0 */

static int IsCheckpointTemporary(const char path[])
{
  const char *base = strrchr(path, '/');

  base = base ? base + 1 : path;
  return strncmp(base, ".checkpoint_", 12) == 0 && strstr(base, ".tmp") != NULL;
}

static int FdIsCheckpointTemporary(int fd)
{
  char    link[64], path[4096];
  ssize_t n;

  snprintf(link, sizeof(link), "/proc/self/fd/%d", fd);
  if ((n = readlink(link, path, sizeof(path) - 1)) < 0) return 0;
  path[n] = 0;
  return IsCheckpointTemporary(path);
}

/* Whether a write of n bytes to fd fits the budget (and takes it), else errno = ENOSPC. */
static int Reserve(int fd, size_t n)
{
  const char *budget = getenv("CLOTH_FAULT_DISK_BYTES");

  if (!budget || !FdIsCheckpointTemporary(fd)) return 1;
  if (used + (long long)n > atoll(budget)) {
    if (getenv("CLOTH_FAULT_DISK_STALL"))
      for (;;) pause(); /* a hung file system (a lost NFS server): the write never returns */
    errno = ENOSPC;
    return 0;
  }
  used += (long long)n;
  return 1;
}

#define NEXT(name) ((__typeof__(&name))dlsym(RTLD_NEXT, #name))

ssize_t pwrite(int fd, const void *buf, size_t n, off_t off) { return Reserve(fd, n) ? NEXT(pwrite)(fd, buf, n, off) : -1; }
ssize_t pwrite64(int fd, const void *buf, size_t n, off_t off) { return Reserve(fd, n) ? NEXT(pwrite64)(fd, buf, n, off) : -1; }
ssize_t write(int fd, const void *buf, size_t n) { return Reserve(fd, n) ? NEXT(write)(fd, buf, n) : -1; }

static size_t IovBytes(const struct iovec *iov, int cnt)
{
  size_t n = 0;

  for (int i = 0; i < cnt; i++) n += iov[i].iov_len;
  return n;
}

ssize_t pwritev(int fd, const struct iovec *iov, int cnt, off_t off) { return Reserve(fd, IovBytes(iov, cnt)) ? NEXT(pwritev)(fd, iov, cnt, off) : -1; }
ssize_t pwritev64(int fd, const struct iovec *iov, int cnt, off_t off) { return Reserve(fd, IovBytes(iov, cnt)) ? NEXT(pwritev64)(fd, iov, cnt, off) : -1; }
ssize_t writev(int fd, const struct iovec *iov, int cnt) { return Reserve(fd, IovBytes(iov, cnt)) ? NEXT(writev)(fd, iov, cnt) : -1; }

int truncate(const char *path, off_t len)
{
  if (len == 0 && IsCheckpointTemporary(path)) used = 0;
  return NEXT(truncate)(path, len);
}
