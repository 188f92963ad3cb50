/* A persistent worker pool (pthreads + C11 atomics). Tasks are claimed from
 * an atomic counter; which thread runs a task never changes its result, so
 * rendering is bit-identical for any thread count. */
#ifndef PERSP_CORE_POOL_H
#define PERSP_CORE_POOL_H

#include "core/internal.h"

typedef void (*persp_task_fn)(void *user, int task, int worker);

/* Runs fn(user, t, worker) for t in [0, tasks) on up to ctx->threads workers
 * (the calling thread is worker 0). Starts the pool on first use. */
persp_status persp__pool_run(persp_context *ctx, int tasks, persp_task_fn fn, void *user);
void persp__pool_destroy(persp_context *ctx);
/* Number of workers persp__pool_run may use (>= 1). */
int persp__pool_workers(const persp_context *ctx);
/* The time, in nanoseconds, for the calling thread and one other worker
 * to hand each other a cache line and back, averaged over a few dozen
 * trips; 0 when the pool has one worker or the other did not join the
 * probe within a fraction of a millisecond (src/render/sort_first.c). */
double persp__pool_round_trip_ns(persp_context *ctx);

#endif
