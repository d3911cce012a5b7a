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
