/*
 * persp-import: the process persp imports a model in (src/io/import_run.c).
 * It sets its own limits before it reads a byte of the model, since
 * posix_spawn sets none, then answers persp over stdin (a socket) through
 * persp__import_serve. Installed beside libpersp (PREFIX/libexec/persp/);
 * not a command for users.
 *
 *   persp-import --memory BYTES --cpu SECONDS
 *
 * Exit: 0 answered; 1 the socket failed; 2 usage; 3 out of memory (an
 * allocation failed and nothing caught it); 4 the limits could not be set.
 */
extern "C" {
#include "io/import_run.h"
#include "io/import_wire.h"
}

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#endif

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <sys/resource.h>
#include <unistd.h>

namespace {

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define PERSP_IMPORT_RLIMIT_AS 1
#endif

/* Set when operator new ran out: Assimp's readers catch std::bad_alloc and
 * word it as a malformed file, which persp then reports correctly. */
volatile int g_out_of_memory = 0;

void on_new_failure()
{
    g_out_of_memory = 1;
    throw std::bad_alloc();
}

int out_of_memory() { return g_out_of_memory; }

[[noreturn]] void on_terminate()
{
    _exit(g_out_of_memory ? PERSP_IMPORT_EXIT_OUT_OF_MEMORY : 1);
}

#if defined(__SANITIZE_ADDRESS__)
/* The instrumented build: AddressSanitizer's allocator enforces the limit
 * (max_allocation_size_mb and hard_rss_limit_mb, from libpersp) and reports running out as an error of
 * its own before any new_handler runs. Its kind of report tells running
 * out from a bug; either ends the process, out of memory with its exit
 * code, a bug by SIGABRT (abort_on_error). */
void on_sanitizer_death()
{
    const char *d = __asan_get_report_description();
    if (d && (std::strstr(d, "out-of-memory") || std::strstr(d, "allocation-size-too-big") ||
              std::strstr(d, "rss-limit")))
        _exit(PERSP_IMPORT_EXIT_OUT_OF_MEMORY);
}
#endif

#ifdef PERSP_IMPORT_RLIMIT_AS
/* The address space mapped now (code, libraries, stack): the limit is this
 * plus the memory the import may use. */
unsigned long long mapped_now()
{
    unsigned long long pages = 0;
    FILE *f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    if (std::fscanf(f, "%llu", &pages) != 1) pages = 0;
    std::fclose(f);
    return pages * (unsigned long long)sysconf(_SC_PAGESIZE);
}
#endif

int set_limit(int which, unsigned long long soft, unsigned long long hard)
{
    struct rlimit r;
    r.rlim_cur = (rlim_t)soft;
    r.rlim_max = (rlim_t)hard;
    return setrlimit(which, &r);
}

int parse(const char *s, unsigned long long *out)
{
    char *end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(s, &end, 10);
    if (errno || !end || *end || end == s) return 0;
    *out = v;
    return 1;
}

} // namespace

int main(int argc, char **argv)
{
    unsigned long long memory = 0, cpu = 0;
    if (argc != 5 || std::strcmp(argv[1], "--memory") != 0 || !parse(argv[2], &memory) ||
        std::strcmp(argv[3], "--cpu") != 0 || !parse(argv[4], &cpu) || cpu == 0) {
        std::fprintf(stderr, "usage: persp-import --memory BYTES --cpu SECONDS (started by libpersp)\n");
        return PERSP_IMPORT_EXIT_USAGE;
    }
    /* Descriptors a careless parent left open are not the importer's. */
    for (int fd = 3; fd < 1024; fd++) close(fd);
#ifdef PERSP_IMPORT_RLIMIT_AS
    const unsigned long long base = mapped_now();
#endif
    int bad = set_limit(RLIMIT_CORE, 0, 0) != 0 || set_limit(RLIMIT_FSIZE, 0, 0) != 0 ||
              set_limit(RLIMIT_NOFILE, 3, 3) != 0 ||
              /* SIGXCPU at the limit, SIGKILL a second later. */
              set_limit(RLIMIT_CPU, cpu, cpu + 1) != 0;
#ifdef PERSP_IMPORT_RLIMIT_AS
    /* A sanitizer reserves terabytes of shadow address space; its own
     * allocator limit (ASAN_OPTIONS from libpersp) holds that build. */
    if (!bad && memory) bad = base == 0 || set_limit(RLIMIT_AS, base + memory, base + memory) != 0;
#endif
    if (bad) return PERSP_IMPORT_EXIT_LIMITS;
#if defined(__SANITIZE_ADDRESS__)
    __sanitizer_set_death_callback(on_sanitizer_death);
#endif
    std::set_new_handler(on_new_failure);
    std::set_terminate(on_terminate);
    int rc = persp__import_serve(0, out_of_memory);
    return rc == 0 ? 0 : (g_out_of_memory ? PERSP_IMPORT_EXIT_OUT_OF_MEMORY : 1);
}
