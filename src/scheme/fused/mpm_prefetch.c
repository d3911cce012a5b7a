/* Prefetch hint for mpm_transfer's segment kernels: gfortran has no prefetch intrinsic, and its
 * -fprefetch-loop-arrays did not help those kernels. Asks for `bytes` bytes from `first` to be
 * brought into the cache (a hint: it never faults and changes no result). Optimised here whatever
 * the build profile (fpm passes no optimisation flag to C sources); a read hint, because a
 * write-intent hint (prefetchw) measured slower. */
#pragma GCC optimize("O2")
void mpm_prefetch_lines(const char *first, int bytes)
{
    for (int i = 0; i < bytes; i += 64) __builtin_prefetch(first + i, 0, 3);
}
