#include "core/pool.h"

#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define POOL_MAX 256

/* Iterations a thread polls for the next round (a worker) or for the end
 * of the current one (the caller) before sleeping on the condition
 * variable, about 20–40 µs. A frame of a big mesh runs thousands of short
 * rounds back to back (vertex ranges, set-up, tiles); sleeping and being
 * woken for each took a sixth of a two-thread frame of the 2M-triangle
 * torus in the kernel. */
#define POOL_SPIN 4096

/* The spin-wait hint of each CPU family: it lets a sibling hardware thread
 * run and, on x86, avoids the memory-order flush when the loop exits. */
static inline void cpu_relax(void)
{
#if defined(__SSE2__)
    _mm_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

struct persp_pool {
    pthread_t thread[POOL_MAX];
    int nthreads; /* helper threads, excluding the caller */
    pthread_mutex_t mu;
    pthread_cond_t wake, done;
    unsigned long generation;
    int quit;
    int busy; /* helpers still working on this generation */
    /* Copies of generation and busy that threads poll without the mutex
     * (POOL_SPIN); the mutex-protected fields stay the source of truth. */
    atomic_ulong gen_seen;
    atomic_int busy_seen;
    /* POOL_SPIN, or 0 when the pool has more threads than the machine has
     * processors: a polling thread would then hold a processor that a
     * thread with work needs (2M torus, 8 threads on 2 processors: +50 %
     * wall with polling). */
    int spin;
    persp_task_fn fn;
    void *user;
    int tasks;
    atomic_int next;
};

typedef struct worker_arg {
    struct persp_pool *pool;
    int index;
} worker_arg;

static void drain(struct persp_pool *p, persp_task_fn fn, void *user, int tasks, int worker)
{
    for (;;) {
        int t = atomic_fetch_add(&p->next, 1);
        if (t >= tasks) break;
        fn(user, t, worker);
    }
}

static void *worker_main(void *arg)
{
    struct persp_pool *p = ((worker_arg *)arg)->pool;
    int index = ((worker_arg *)arg)->index;
    unsigned long seen = 0;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        if (!p->quit && p->generation == seen) {
            pthread_mutex_unlock(&p->mu);
            for (int i = 0; i < p->spin && atomic_load_explicit(&p->gen_seen, memory_order_acquire) == seen; i++)
                cpu_relax();
            pthread_mutex_lock(&p->mu);
        }
        while (!p->quit && p->generation == seen) pthread_cond_wait(&p->wake, &p->mu);
        if (p->quit) break;
        seen = p->generation;
        persp_task_fn fn = p->fn;
        void *user = p->user;
        int tasks = p->tasks;
        pthread_mutex_unlock(&p->mu);
        drain(p, fn, user, tasks, index);
        pthread_mutex_lock(&p->mu);
        atomic_store_explicit(&p->busy_seen, p->busy - 1, memory_order_release);
        if (--p->busy == 0) pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}


int persp__pool_workers(const persp_context *ctx) { return ctx && ctx->threads > 1 ? ctx->threads : 1; }

static persp_status pool_start(persp_context *ctx)
{
    struct persp_pool *p = persp__calloc(ctx, 1, sizeof *p + (size_t)ctx->threads * sizeof(worker_arg));
    if (!p) return PERSP_ERR_OUT_OF_MEMORY;
    worker_arg *args = (worker_arg *)(p + 1);
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    atomic_init(&p->next, 0);
    atomic_init(&p->gen_seen, 0);
    const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    p->spin = cpus > 0 && ctx->threads <= cpus ? POOL_SPIN : 0;
    atomic_init(&p->busy_seen, 0);
    for (int i = 0; i < ctx->threads - 1; i++) {
        args[i].pool = p;
        args[i].index = i + 1;
        if (pthread_create(&p->thread[i], NULL, worker_main, &args[i]) != 0) break;
        p->nthreads++;
    }
    ctx->pool = p;
    return PERSP_OK;
}

persp_status persp__pool_run(persp_context *ctx, int tasks, persp_task_fn fn, void *user)
{
    if (tasks <= 0) return PERSP_OK;
    if (persp__pool_workers(ctx) == 1 || tasks == 1) {
        for (int t = 0; t < tasks; t++) fn(user, t, 0);
        return PERSP_OK;
    }
    if (!ctx->pool) {
        persp_status st = pool_start(ctx);
        if (st != PERSP_OK) return st;
    }
    struct persp_pool *p = ctx->pool;
    pthread_mutex_lock(&p->mu);
    p->fn = fn;
    p->user = user;
    p->tasks = tasks;
    atomic_store(&p->next, 0);
    p->busy = p->nthreads;
    atomic_store_explicit(&p->busy_seen, p->nthreads, memory_order_relaxed);
    p->generation++;
    atomic_store_explicit(&p->gen_seen, p->generation, memory_order_release);
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    drain(p, fn, user, tasks, 0);
    for (int i = 0; i < p->spin && atomic_load_explicit(&p->busy_seen, memory_order_acquire) > 0; i++)
        cpu_relax();
    pthread_mutex_lock(&p->mu);
    while (p->busy > 0) pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
    return PERSP_OK;
}

/* The round-trip probe: the first task to start waits a bounded time for
 * the second (the same thread may claim both, one after the other, when
 * the other worker is slow to wake), then times trips of a counter that
 * each side advances in turn on its own cache line. */
#define PROBE_TRIPS 32
#define PROBE_WARM 4
#define PROBE_JOIN_NS 200000.0

typedef struct probe_job {
    _Alignas(64) atomic_int arrived; /* tasks started; negative once the first gave up */
    _Alignas(64) atomic_int ball;
    double ns;
} probe_job;

static void probe_task(void *user, int task, int worker)
{
    (void)task, (void)worker;
    probe_job *j = user;
    const int me = atomic_fetch_add(&j->arrived, 1);
    if (me < 0) return;
    if (me == 1) {
        for (int i = 0; i < PROBE_WARM + PROBE_TRIPS; i++) {
            while (atomic_load_explicit(&j->ball, memory_order_acquire) != 2 * i + 1) cpu_relax();
            atomic_store_explicit(&j->ball, 2 * i + 2, memory_order_release);
        }
        return;
    }
    const double t0 = persp__now_seconds();
    for (;;) {
        int expect = 1;
        if (atomic_load_explicit(&j->arrived, memory_order_acquire) == 2) break;
        if ((persp__now_seconds() - t0) * 1e9 > PROBE_JOIN_NS &&
            atomic_compare_exchange_strong(&j->arrived, &expect, -1000))
            return;
        cpu_relax();
    }
    double start = 0.0;
    for (int i = 0; i < PROBE_WARM + PROBE_TRIPS; i++) {
        if (i == PROBE_WARM) start = persp__now_seconds();
        atomic_store_explicit(&j->ball, 2 * i + 1, memory_order_release);
        while (atomic_load_explicit(&j->ball, memory_order_acquire) != 2 * i + 2) cpu_relax();
    }
    j->ns = (persp__now_seconds() - start) * 1e9 / PROBE_TRIPS;
}

double persp__pool_round_trip_ns(persp_context *ctx)
{
    if (persp__pool_workers(ctx) < 2) return 0.0;
    probe_job j;
    atomic_init(&j.arrived, 0);
    atomic_init(&j.ball, 0);
    j.ns = 0.0;
    if (persp__pool_run(ctx, 2, probe_task, &j) != PERSP_OK) return 0.0;
    return j.ns;
}

void persp__pool_destroy(persp_context *ctx)
{
    if (!ctx || !ctx->pool) return;
    struct persp_pool *p = ctx->pool;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    for (int i = 0; i < p->nthreads; i++) pthread_join(p->thread[i], NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->wake);
    pthread_cond_destroy(&p->done);
    persp__free(ctx, p);
    ctx->pool = NULL;
}
