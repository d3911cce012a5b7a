/* What kind of file a path names, whether two paths name one file (stat(2)), absolute paths, and
   the handling of SIGINT, SIGTERM and SIGHUP, for mpm_files. */
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* 0: nothing there (or not reachable), 1: a regular file, 2: a folder, 3: anything else
   (a device, a FIFO, a socket). Symbolic links are followed. */
int mpm_path_kind(const char *path)
{
    struct stat s;
    if (stat(path, &s) != 0) return 0;
    if (S_ISREG(s.st_mode)) return 1;
    if (S_ISDIR(s.st_mode)) return 2;
    return 3;
}

/* 1 when both paths exist and name the same file (same device and inode), else 0. */
int mpm_same_file(const char *a, const char *b)
{
    struct stat s, t;
    if (stat(a, &s) != 0 || stat(b, &t) != 0) return 0;
    return s.st_dev == t.st_dev && s.st_ino == t.st_ino;
}

/* The absolute path of `path` into `out` (`size` bytes, NUL-terminated): realpath(3) of the path when
   it exists, else realpath of its folder joined with its last component (a file about to be written),
   else the path itself joined to the working folder. Returns the length, or -1 if it does not fit. */
int mpm_absolute_path(const char *path, char *out, int size)
{
    char resolved[PATH_MAX];
    char folder[PATH_MAX];
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    size_t n;
    if (realpath(path, resolved) != NULL) {
        n = strlen(resolved);
        if (n + 1 > (size_t)size) return -1;
        memcpy(out, resolved, n + 1);
        return (int)n;
    }
    if (slash == path) { /* "/name" */
        strcpy(folder, "/");
    } else if (slash) {
        n = (size_t)(slash - path);
        if (n + 1 > sizeof folder) return -1;
        memcpy(folder, path, n);
        folder[n] = '\0';
    } else {
        strcpy(folder, ".");
    }
    if (realpath(folder, resolved) == NULL) {
        if (path[0] == '/') {
            resolved[0] = '\0';
        } else if (getcwd(resolved, sizeof resolved) == NULL) {
            return -1;
        }
        name = path;
    }
    n = strlen(resolved);
    if (n + strlen(name) + 2 > (size_t)size) return -1;
    memcpy(out, resolved, n);
    if (n == 0 || out[n - 1] != '/') out[n++] = '/';
    strcpy(out + n, name);
    return (int)strlen(out);
}

/* Signals. The partial output file this process is writing is removed by the handler of SIGINT,
   SIGTERM and SIGHUP before the signal ends the process as it would have (its default action,
   re-raised): an interrupted run leaves no .part file. A sweep catches the signals instead
   (mpm_catch_interrupts): the first one is only recorded, the running cases see it at their next
   step and stop, and the sweep writes what it finished; a second one ends the process at once (as
   above). Only unlink(2), signal(2) and raise(3) run in the handler (async-signal-safe). One partial
   file per process (a run, a sweep or a merge writes one file). */
static char partial_path[4352];
static volatile sig_atomic_t partial_set = 0;
static volatile sig_atomic_t catching = 0;
static volatile sig_atomic_t caught = 0;
static int handlers_installed = 0;

static void on_signal(int sig)
{
    if (catching && caught == 0) {
        caught = sig;
        return;
    }
    if (partial_set) unlink(partial_path);
    partial_set = 0;
    signal(sig, SIG_DFL);
    raise(sig);
}

static void install_handlers(void)
{
    static const int signals[] = {SIGINT, SIGTERM, SIGHUP};
    if (handlers_installed) return;
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; ++i) {
        struct sigaction action;
        struct sigaction old;
        memset(&action, 0, sizeof action);
        action.sa_handler = on_signal;
        sigemptyset(&action.sa_mask);
        /* a signal the caller ignores (nohup) stays ignored */
        if (sigaction(signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        sigaction(signals[i], &action, NULL);
    }
    handlers_installed = 1;
}

/* Register `path` (NUL-terminated) as this process's partial file; returns 0, or -1 if too long.
   Call it before creating the file: a signal between the two then finds nothing to remove, where
   the other order would leave the file behind. */
int mpm_register_partial(const char *path)
{
    size_t n = strlen(path);
    if (n >= sizeof partial_path) return -1;
    partial_set = 0;
    memcpy(partial_path, path, n + 1);
    install_handlers();
    partial_set = 1;
    return 0;
}

/* The partial file is renamed or removed (or was never created): nothing to remove any more. */
void mpm_forget_partial(void)
{
    partial_set = 0;
}

/* From now on the first SIGINT, SIGTERM or SIGHUP is recorded, not acted on (see above). A signal
   recorded before stays recorded (one per process). */
void mpm_catch_interrupts(void)
{
    install_handlers();
    catching = 1;
}

/* Back to the default: a signal ends the process (removing the partial file). */
void mpm_release_interrupts(void)
{
    catching = 0;
}

/* The signal recorded since mpm_catch_interrupts, 0 if none. */
int mpm_interrupt_signal(void)
{
    return caught;
}

/* A write beyond the file-size limit (ulimit -f) fails with EFBIG, which the writers report with the
   file's name, instead of ending the process with SIGXFSZ (whose default action, and the Fortran
   runtime's handler, kill it with a core dump or a backtrace and no word about the file). */
void mpm_file_size_errors(void)
{
    signal(SIGXFSZ, SIG_IGN);
}

/* Test hook: create the file `marker` (NUL-terminated; a test waits for it), then sleep until a signal
   is recorded (at most `seconds`); returns at once if one was recorded before. */
void mpm_wait_for_signal(int seconds, const char *marker)
{
    FILE *f = fopen(marker, "w");
    if (f) fclose(f);
    for (int i = 0; i < 10 * seconds && caught == 0; ++i) usleep(100000);
}
