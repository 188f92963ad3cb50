/* Both ends of the importer's socket (src/model/import_wire.h). */
#define _GNU_SOURCE /* MSG_NOSIGNAL */
#include "model/import_wire.h"

#include <errno.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

int64_t persp__wire_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Waits until fd is ready for events or the deadline passes. */
static int wait_ready(wire_chan *c, short events)
{
    for (;;) {
        int timeout = -1;
        if (c->deadline_ms) {
            int64_t left = c->deadline_ms - persp__wire_now_ms();
            if (left <= 0) {
                c->failed = 2;
                return 0;
            }
            timeout = left > 60000 ? 60000 : (int)left;
        }
        struct pollfd p = {.fd = c->fd, .events = events, .revents = 0};
        int n = poll(&p, 1, timeout);
        if (n < 0 && errno != EINTR) {
            c->failed = 1;
            return 0;
        }
        /* POLLHUP with data still unread is read first: recv says when it ends. */
        if (n > 0) return 1;
    }
}

int persp__wire_write(wire_chan *c, const void *p, size_t n)
{
    const char *b = p;
    while (n && !c->failed) {
        if (!wait_ready(c, POLLOUT)) return 0;
        /* MSG_NOSIGNAL: an importer that died is a failed write, not a
         * SIGPIPE that ends the program. */
        ssize_t w = send(c->fd, b, n, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (w < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
        if (w <= 0) {
            c->failed = 1;
            return 0;
        }
        b += w;
        n -= (size_t)w;
    }
    return !c->failed;
}

int persp__wire_read(wire_chan *c, void *p, size_t n)
{
    char *b = p;
    while (n && !c->failed) {
        if (!wait_ready(c, POLLIN)) return 0;
        ssize_t r = recv(c->fd, b, n, MSG_DONTWAIT);
        if (r < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
        if (r <= 0) {
            c->failed = 1;
            return 0;
        }
        b += r;
        n -= (size_t)r;
    }
    return !c->failed;
}

int persp__wire_skip(wire_chan *c, uint64_t n)
{
    char buf[4096];
    while (n) {
        size_t k = n < sizeof buf ? (size_t)n : sizeof buf;
        if (!persp__wire_read(c, buf, k)) return 0;
        n -= k;
    }
    return 1;
}
