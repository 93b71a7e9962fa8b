/* The deadline of the collective file writes: see watchdog.h. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>
#include "watchdog.h"

static PetscReal WatchdogTimeout = CLOTH_IO_TIMEOUT_DEFAULT;
/* What the handler needs, prepared before the timer starts: it may only make async-signal-safe calls. */
static char         WatchdogMessage[CLOTH_PATH_LEN + 512];
static char         WatchdogRemovePath[CLOTH_PATH_LEN];
static volatile int WatchdogStatus;

static void WatchdogExpired(int sig)
{
  (void)sig;
  if (write(STDERR_FILENO, WatchdogMessage, strlen(WatchdogMessage)) < 0) { /* nothing left to report to */
  }
  if (WatchdogRemovePath[0]) (void)unlink(WatchdogRemovePath);
  _exit(WatchdogStatus);
}

static PetscErrorCode WatchdogSetTimer(PetscReal seconds)
{
  struct itimerval timer;

  PetscFunctionBeginUser;
  memset(&timer, 0, sizeof(timer));
  timer.it_value.tv_sec  = (time_t)seconds;
  timer.it_value.tv_usec = (suseconds_t)(1e6 * (seconds - (PetscReal)(time_t)seconds));
  PetscCheck(setitimer(ITIMER_REAL, &timer, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "Cannot set the -io_timeout timer: %s", strerror(errno));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothWatchdogSetTimeout(PetscReal seconds)
{
  PetscFunctionBeginUser;
  WatchdogTimeout = seconds;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode ClothWatchdogArm(const char what[], const char remove_path[], int status)
{
  struct sigaction action;
  PetscMPIInt      rank;

  PetscFunctionBeginUser;
  if (WatchdogTimeout <= 0) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(WatchdogMessage, sizeof(WatchdogMessage),
                          "ERROR: %s did not finish within %.1f s (-io_timeout): the file system hangs, or a write failed on some ranks only (a full disk?) and parallel HDF5 waits forever%s%s; the run is stopped\n", what, (double)WatchdogTimeout,
                          remove_path ? "; removed " : "", remove_path ? remove_path : ""));
  PetscCall(PetscStrncpy(WatchdogRemovePath, remove_path ? remove_path : "", sizeof(WatchdogRemovePath)));
  WatchdogStatus = status;
  memset(&action, 0, sizeof(action));
  action.sa_handler = WatchdogExpired;
  sigemptyset(&action.sa_mask);
  PetscCheck(sigaction(SIGALRM, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "Cannot install the -io_timeout handler: %s", strerror(errno));
  /* the other ranks 3 s later: usually rank 0's exit ends them first, and the message is printed once */
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(WatchdogSetTimer(WatchdogTimeout + (rank > 0 ? 3.0 : 0.0)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void ClothWatchdogCancel(void)
{
  const struct itimerval off = {{0, 0}, {0, 0}};

  (void)setitimer(ITIMER_REAL, &off, NULL);
}

PetscErrorCode ClothWatchdogDisarm(void)
{
  PetscFunctionBeginUser;
  if (WatchdogTimeout > 0) PetscCall(WatchdogSetTimer(0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
