/* cli_progress.c — a progress line on stderr for steps that run longer than about a second, only when stderr is
 * a terminal (or FRT_PROGRESS=always), and never with --quiet. A ticker thread draws it, so a step that is one
 * blocking call (a Vulkan submission) still shows its elapsed time. */
#include "cli.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define PROGRESS_DELAY_S 1.0 /* "runs longer than about a second": nothing is printed for quicker steps */
#define PROGRESS_TICK_NS 100000000L

static struct {
    bool enabled, always, running;
    pthread_t thread;
    pthread_mutex_t lock;
    char label[128];
    uint64_t total;
    _Atomic uint64_t done;
    double start;
    bool drawn;
    atomic_bool stop;
} P = {.lock = PTHREAD_MUTEX_INITIALIZER};

void frt_progress_init(bool quiet)
{
    const char *env = getenv("FRT_PROGRESS");
    P.always = env && strcmp(env, "always") == 0;
    bool never = env && strcmp(env, "never") == 0;
    P.enabled = !quiet && !never && (P.always || isatty(2));
}

/* Draws the line (caller holds the lock). */
static void draw(double now)
{
    char line[256];
    uint64_t done = atomic_load(&P.done);
    if (P.total)
        snprintf(line, sizeof line, "%s: %s %3.0f%% %.1f s", frt_cli_command, P.label,
                 100.0 * (double)(done > P.total ? P.total : done) / (double)P.total, now - P.start);
    else
        snprintf(line, sizeof line, "%s: %s %.1f s", frt_cli_command, P.label, now - P.start);
    /* \r and erase-to-end-of-line on a terminal; one line per update when forced into a log. */
    fprintf(stderr, P.always && !isatty(2) ? "%s\n" : "\r%s\033[K", line);
    fflush(stderr);
    P.drawn = true;
}

static void *ticker(void *arg)
{
    (void)arg;
    struct timespec tick = {0, PROGRESS_TICK_NS};
    double last = 0.0;
    while (!atomic_load(&P.stop)) {
        nanosleep(&tick, NULL);
        pthread_mutex_lock(&P.lock);
        double now = frt_now_seconds();
        /* On a terminal redraw every tick; into a log (FRT_PROGRESS=always) once a second. */
        bool due = P.always && !isatty(2) ? now - last >= 1.0 : true;
        if (!atomic_load(&P.stop) && (P.always || now - P.start >= PROGRESS_DELAY_S) && due) {
            draw(now);
            last = now;
        }
        pthread_mutex_unlock(&P.lock);
    }
    return NULL;
}

void frt_progress_begin(const char *label, uint64_t total)
{
    frt_progress_end();
    if (!P.enabled)
        return;
    pthread_mutex_lock(&P.lock);
    snprintf(P.label, sizeof P.label, "%s", label);
    P.total = total;
    atomic_store(&P.done, 0);
    P.start = frt_now_seconds();
    P.drawn = false;
    atomic_store(&P.stop, false);
    if (P.always)
        draw(P.start); /* forced (logs, tests): show every step, however short */
    pthread_mutex_unlock(&P.lock);
    P.running = pthread_create(&P.thread, NULL, ticker, NULL) == 0;
}

void frt_progress_set(uint64_t done)
{
    atomic_store(&P.done, done);
}

void frt_progress_end(void)
{
    if (!P.running)
        return;
    atomic_store(&P.stop, true);
    pthread_join(P.thread, NULL);
    P.running = false;
    if (P.drawn && isatty(2)) {
        fputs("\r\033[K", stderr); /* leave the terminal as it was; the summary line follows */
        fflush(stderr);
    }
}
