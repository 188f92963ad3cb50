/*
 * persp-import: the process persp imports a model in (src/model/import_run.c).
 * It sets its own limits before it reads a byte of the model, since
 * posix_spawn sets none, then answers persp over stdin (a socket) through
 * persp__import_serve. Installed beside libpersp (PREFIX/libexec/persp/);
 * not a command for users.
 *
 *   persp-import --memory BYTES --cpu SECONDS
 *
 * Exit: 0 answered; 1 the socket failed; 2 usage; 3 out of memory (an
 * allocation failed and nothing caught it); 4 the limits or the system-call
 * filter could not be set.
 */
extern "C" {
#include "model/import_run.h"
#include "model/import_wire.h"
}

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#endif

#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <sys/prctl.h>
#include <sys/syscall.h>

#include <cerrno>
#include <cstddef>
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

/* A seccomp filter (Linux, seccomp(2)): after it, the importer may use
 * memory, the socket it was given and the signals that end it, and no
 * other system call: every other one fails with EPERM, so that a reader
 * that is made to run code of a hostile file's choosing cannot open a file,
 * start a program or reach the network. A system call a reader needed
 * would fail as well, not end the process; none of the readers persp tests
 * does. Not in the sanitizer builds, whose runtime reads /proc and starts
 * a symbolizer when it reports. */
#if defined(PERSP_IMPORT_RLIMIT_AS) && (defined(__x86_64__) || defined(__aarch64__))
#define PERSP_IMPORT_SECCOMP 1
#if defined(__x86_64__)
#define PERSP_AUDIT_ARCH AUDIT_ARCH_X86_64
#else
#define PERSP_AUDIT_ARCH AUDIT_ARCH_AARCH64
#endif
int confine()
{
    static const long allowed[] = {
        SYS_read, SYS_write, SYS_readv, SYS_writev, SYS_recvfrom, SYS_sendto, SYS_recvmsg, SYS_sendmsg,
        SYS_ppoll, SYS_mmap, SYS_munmap, SYS_mremap, SYS_brk, SYS_madvise, SYS_mprotect, SYS_close,
        SYS_fstat, SYS_newfstatat, SYS_lseek, SYS_exit, SYS_exit_group, SYS_rt_sigreturn,
        SYS_rt_sigprocmask, SYS_rt_sigaction, SYS_futex, SYS_clock_gettime, SYS_clock_nanosleep,
        SYS_nanosleep, SYS_getpid, SYS_gettid, SYS_tgkill, SYS_sched_yield, SYS_getrandom,
        SYS_restart_syscall, SYS_prlimit64,
#ifdef SYS_poll
        SYS_poll,
#endif
    };
    const unsigned n = sizeof allowed / sizeof allowed[0];
    struct sock_filter prog[64];
    unsigned k = 0;
    prog[k++] = BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, arch));
    prog[k++] = BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, PERSP_AUDIT_ARCH, 1, 0);
    prog[k++] = BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS);
    prog[k++] = BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(struct seccomp_data, nr));
    for (unsigned i = 0; i < n; i++)
        prog[k++] = BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, (unsigned)allowed[i], (unsigned char)(n - i), 0);
    prog[k++] = BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ERRNO | (EPERM & SECCOMP_RET_DATA));
    prog[k++] = BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW);
    struct sock_fprog fprog;
    fprog.len = (unsigned short)k;
    fprog.filter = prog;
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0) return -1;
    return prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, &fprog, 0, 0);
}
#endif

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
#ifdef PERSP_IMPORT_SECCOMP
    if (!bad) bad = confine() != 0;
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
