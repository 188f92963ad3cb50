/* The cross-core round trip of `persp bench`: how long one cache line
 * takes to go from one processor to another and back, between the
 * processors persp's threads may run on.
 *
 * Two threads pinned one to each of two processors pass a counter back and
 * forth through one line, each waiting for the other's increment. On a VM
 * the host decides where the vCPUs sit, and the figure moves with it: on
 * the 2-vCPU AMD EPYC of docs/PERFORMANCE.md 64-85 ns most of the time and
 * 330-350 ns in other periods, on the same idle machine, which halved
 * persp's two-thread rate on the big tori (its threads hand each other the
 * vertex stage's output and set-up's records). A two-thread figure is
 * therefore only read with this one beside it. */
#define _GNU_SOURCE
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>

/* Round trips a pass times; passes per pair, of which the median counts
 * (a pass the host interrupts is an outlier). */
enum { TRIPS = 4000, PASSES = 5 };

typedef struct ping {
    _Alignas(64) atomic_uint line;
    char pad[64 - sizeof(atomic_uint)];
    int cpu;
    int ok;
} ping;

static int pin(int cpu)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET((size_t)cpu, &set);
    return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

static void *pong(void *arg)
{
    ping *p = arg;
    p->ok = pin(p->cpu);
    /* Answers every odd value with the next even one. */
    for (unsigned i = 0; i < (unsigned)(PASSES * TRIPS); i++) {
        while (atomic_load_explicit(&p->line, memory_order_acquire) != 2 * i + 1) {
        }
        atomic_store_explicit(&p->line, 2 * i + 2, memory_order_release);
    }
    return NULL;
}

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median round trip in ns between processors a (this thread) and b; NaN
 * if either cannot be pinned to. */
static double round_trip(int a, int b)
{
    ping p;
    memset(&p, 0, sizeof p);
    atomic_init(&p.line, 0);
    p.cpu = b;
    if (!pin(a)) return NAN;
    pthread_t t;
    if (pthread_create(&t, NULL, pong, &p) != 0) return NAN;
    double pass[PASSES];
    unsigned v = 0;
    for (int k = 0; k < PASSES; k++) {
        const double t0 = seconds();
        for (int i = 0; i < TRIPS; i++, v += 2) {
            atomic_store_explicit(&p.line, v + 1, memory_order_release);
            while (atomic_load_explicit(&p.line, memory_order_acquire) != v + 2) {
            }
        }
        pass[k] = (seconds() - t0) * 1e9 / TRIPS;
    }
    pthread_join(t, NULL);
    qsort(pass, PASSES, sizeof *pass, cmp_double);
    return p.ok ? pass[PASSES / 2] : NAN;
}

cli_xcore cli_xcore_measure(void)
{
    cli_xcore r = {NAN, NAN, 0};
    cpu_set_t mask;
    if (sched_getaffinity(0, sizeof mask, &mask) != 0) return r;
    int cpu[CPU_SETSIZE], n = 0;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET((size_t)c, &mask)) cpu[n++] = c;
    /* The first processor against each other one (up to 63 pairs, about
     * 2 ms each at 100 ns): the spread is what threads placed anywhere in
     * the mask see. */
    for (int k = 1; k < n && k < 64; k++) {
        const double ns = round_trip(cpu[0], cpu[k]);
        if (isnan(ns)) continue;
        r.min_ns = r.pairs ? fmin(r.min_ns, ns) : ns;
        r.max_ns = r.pairs ? fmax(r.max_ns, ns) : ns;
        r.pairs++;
    }
    /* This thread goes back to every processor it had: the worker threads
     * a context starts later inherit its mask. */
    pthread_setaffinity_np(pthread_self(), sizeof mask, &mask);
    return r;
}
#else
cli_xcore cli_xcore_measure(void) { return (cli_xcore){NAN, NAN, 0}; }
#endif
