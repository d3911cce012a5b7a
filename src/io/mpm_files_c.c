/* What kind of file a path names, and whether two paths name one file (stat(2)), for mpm_files. */
#include <sys/stat.h>

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

/* The partial output file this process is writing, removed by the handler of SIGINT, SIGTERM and
   SIGHUP before the signal ends the process as it would have (its default action, re-raised): an
   interrupted run leaves no .part file. Only unlink(2), signal(2) and raise(3) run in the handler
   (async-signal-safe). One partial file per process (a run, a sweep or a merge writes one file). */
#include <signal.h>
#include <string.h>
#include <unistd.h>

static char partial_path[4352];
static volatile sig_atomic_t partial_set = 0;
static int handlers_installed = 0;

static void remove_partial_and_die(int sig)
{
    if (partial_set) unlink(partial_path);
    partial_set = 0;
    signal(sig, SIG_DFL);
    raise(sig);
}

/* Register `path` (NUL-terminated) as this process's partial file; returns 0, or -1 if too long. */
int mpm_register_partial(const char *path)
{
    static const int signals[] = {SIGINT, SIGTERM, SIGHUP};
    size_t n = strlen(path);
    if (n >= sizeof partial_path) return -1;
    partial_set = 0;
    memcpy(partial_path, path, n + 1);
    partial_set = 1;
    if (!handlers_installed) {
        for (size_t i = 0; i < sizeof signals / sizeof signals[0]; ++i) {
            struct sigaction action;
            struct sigaction old;
            memset(&action, 0, sizeof action);
            action.sa_handler = remove_partial_and_die;
            sigemptyset(&action.sa_mask);
            /* a signal the caller ignores (nohup) stays ignored */
            if (sigaction(signals[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
            sigaction(signals[i], &action, NULL);
        }
        handlers_installed = 1;
    }
    return 0;
}

/* The partial file is renamed or removed: the handlers have nothing to remove any more. */
void mpm_forget_partial(void)
{
    partial_set = 0;
}
