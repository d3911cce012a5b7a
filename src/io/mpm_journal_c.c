/* A journal file of records that survives a kill at any byte (mpm_journal). Each record is written by
   one write(2) as
       magic "MPMJ" (4 bytes) | kind (4) | payload length n (8) | payload (n) | checksum (8)
   the checksum a 64-bit FNV-1a hash of kind, length and payload (record_checksum). A reader takes the records in order
   and stops at the first that is incomplete or whose checksum differs (a torn last record: a kill or a
   full disk in the middle of a write); nothing after it is read. The writer holds an exclusive flock(2)
   on the file while it appends (the kernel drops it when the process dies, SIGKILL included), so a second
   process never appends to a journal in use. A failed append is cut off again (ftruncate to the length
   before it), so that the journal stays a sequence of whole records. Records reach the kernel at once
   (a killed process loses nothing it appended) and the disk within sync_seconds (fsync of the journal,
   and once of its folder), which bounds what a crash of the machine can lose; a sweep shorter than that
   makes no fsync (each costs milliseconds to a loaded disk). One journal per process. */
#include <errno.h>
#include <stdio.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static const uint32_t journal_magic = 0x4A4D504Du; /* "MPMJ" read as little-endian bytes */
static const double sync_seconds = 5.0;
static double last_sync = 0.0;
static int folder_synced = 0;
static char journal_path[4352];
static off_t journal_size = 0;

/* FNV-1a taken over 64-bit little-endian words (the bytes that do not fill a word one by one): a
   multiply per 8 bytes rather than per byte (a sweep's histories make megabytes of records).
   It detects a torn or changed record, not a forged one. */
static uint64_t fnv1a(const unsigned char *bytes, size_t n, uint64_t hash)
{
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t word;
        memcpy(&word, bytes + i, 8);
        hash ^= word;
        hash *= 1099511628211ull;
    }
    for (; i < n; ++i) {
        hash ^= bytes[i];
        hash *= 1099511628211ull;
    }
    return hash;
}

/* The checksum of a record: the hash of its kind, then of its length, then of its payload. */
static uint64_t record_checksum(uint32_t kind, uint64_t length, const unsigned char *payload)
{
    uint64_t hash = 14695981039346656037ull;
    hash = fnv1a((const unsigned char *)&kind, sizeof kind, hash);
    hash = fnv1a((const unsigned char *)&length, sizeof length, hash);
    return fnv1a(payload, (size_t)length, hash);
}

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void set_cause(int code, char *cause, int size)
{
    const char *text = strerror(code);
    size_t n = strlen(text);
    if (size < 1) return;
    if (n + 1 > (size_t)size) n = (size_t)size - 1;
    memcpy(cause, text, n);
    cause[n] = '\0';
    if (cause[0] >= 'A' && cause[0] <= 'Z' && !(n > 1 && cause[1] >= 'A' && cause[1] <= 'Z')) cause[0] += 'a' - 'A';
}

/* Make the folder entry of `path` durable (a new file survives a crash of the machine). */
static void sync_folder(const char *path)
{
    char *copy = strdup(path);
    int fd;
    if (copy == NULL) return;
    fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
    free(copy);
}

/* Open (or create) the journal `path` for appending, locked for this process, keeping its first `keep`
   bytes (0: start it empty; a resumed sweep keeps the whole records it read). `*found` is the size it
   had. Returns the descriptor; -2 when another process holds the lock; -1 on failure (`cause`). */
int mpm_journal_open(const char *path, long long keep, long long *found, char *cause, int size)
{
    struct stat s;
    int fd = open(path, O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    *found = 0;
    if (fd < 0) {
        set_cause(errno, cause, size);
        return -1;
    }
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        int code = errno;
        close(fd);
        if (code == EWOULDBLOCK) return -2;
        set_cause(code, cause, size);
        return -1;
    }
    if (fstat(fd, &s) != 0 || (s.st_size > keep && ftruncate(fd, (off_t)keep) != 0)) {
        set_cause(errno, cause, size);
        close(fd);
        return -1;
    }
    *found = (long long)s.st_size;
    journal_size = s.st_size > keep ? (off_t)keep : s.st_size;
    snprintf(journal_path, sizeof journal_path, "%s", path);
    folder_synced = 0;
    last_sync = now_seconds();
    return fd;
}

/* Append one record of `kind` with `length` bytes of `payload`; 0, or -1 with `cause` (the journal is
   cut back to its length before). */
int mpm_journal_append(int fd, int kind, const void *payload, long long length, char *cause, int size)
{
    uint32_t magic = journal_magic, k = (uint32_t)kind;
    uint64_t n = (uint64_t)length, sum;
    size_t total = 16 + (size_t)length + 8, done = 0;
    unsigned char *record = malloc(total);
    if (record == NULL) {
        set_cause(ENOMEM, cause, size);
        return -1;
    }
    sum = record_checksum(k, n, payload);
    memcpy(record, &magic, 4);
    memcpy(record + 4, &k, 4);
    memcpy(record + 8, &n, 8);
    memcpy(record + 16, payload, (size_t)length);
    memcpy(record + 16 + length, &sum, 8);
    while (done < total) {
        ssize_t w = write(fd, record + done, total - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            int code = w < 0 ? errno : ENOSPC;
            free(record);
            if (ftruncate(fd, journal_size) != 0) { /* the reader drops the torn record */ }
            set_cause(code, cause, size);
            return -1;
        }
        done += (size_t)w;
    }
    free(record);
    journal_size += (off_t)total;
    if (now_seconds() - last_sync >= sync_seconds) {
        fsync(fd);
        if (!folder_synced) sync_folder(journal_path);
        folder_synced = 1;
        last_sync = now_seconds();
    }
    return 0;
}

/* Close the journal (and with it its lock); one that is kept (`keep`) made durable first. */
void mpm_journal_close(int fd, int keep)
{
    if (fd < 0) return;
    if (keep) {
        fsync(fd);
        sync_folder(journal_path);
    }
    close(fd);
}

/* The record starting at `offset` of the `n` bytes `data` of a journal: its kind and payload length,
   and the offset of the next record; -1 when no whole record with a matching checksum starts there
   (the end of the journal, or a torn last record). */
long long mpm_journal_record(const unsigned char *data, long long n, long long offset, int *kind, long long *length)
{
    uint32_t magic, k;
    uint64_t len, sum;
    if (offset < 0 || n - offset < 24) return -1;
    memcpy(&magic, data + offset, 4);
    memcpy(&k, data + offset + 4, 4);
    memcpy(&len, data + offset + 8, 8);
    if (magic != journal_magic || len > (uint64_t)(n - offset - 24)) return -1;
    memcpy(&sum, data + offset + 16 + len, 8);
    if (sum != record_checksum(k, len, data + offset + 16)) return -1;
    *kind = (int)k;
    *length = (long long)len;
    return offset + 24 + (long long)len;
}
