/* The cause of an HDF5 call's failure in the words of the system, for mpm_hdf5's messages. HDF5's
   file drivers record the failing system call's errno in the error stack ("file write failed: ...,
   errno = 28, error message = 'No space left on device', ..."); the library's own message names only
   the operation. H5Ewalk2 does not clear the stack, so this runs right after the failing call. */
#include <hdf5.h>
#include <stdlib.h>
#include <string.h>

static herr_t errno_of(unsigned n, const H5E_error2_t *entry, void *data)
{
    const char *at;
    (void)n;
    if (entry->desc == NULL) return 0;
    at = strstr(entry->desc, "errno = ");
    if (at == NULL) return 0;
    *(int *)data = atoi(at + strlen("errno = "));
    return 1; /* the first one found: stop */
}

/* The system's text of the errno recorded in the default error stack (lower-case first letter, as a
   cause after a colon: "no space left on device") into `out` (`size` bytes, NUL-terminated); returns
   its length, 0 when the stack records no errno. */
int mpm_h5_failure_cause(char *out, int size)
{
    int code = 0;
    size_t n;
    const char *text;
    if (size < 1) return 0;
    out[0] = '\0';
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, errno_of, &code);
    if (code <= 0) return 0;
    text = strerror(code);
    n = strlen(text);
    if (n + 1 > (size_t)size) n = (size_t)size - 1;
    memcpy(out, text, n);
    out[n] = '\0';
    if (out[0] >= 'A' && out[0] <= 'Z' && !(n > 1 && out[1] >= 'A' && out[1] <= 'Z')) out[0] += 'a' - 'A';
    return (int)n;
}
