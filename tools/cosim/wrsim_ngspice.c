/* wrsim_ngspice: ngspice (libngspice) with exact 'above crossings.
 *
 * usage: wrsim_ngspice MAX_STEP STOP RESOLUTION NETLIST HOLDS [GUARD...]   (+NAME: a GUARD that switches no
 *        equation; HOLDS: the file of held values, or -)
 *
 * Sources NETLIST (its .control section runs the analysis and writes the raw file and the event record) and
 * makes every zero crossing of a GUARD node an analog time point: after each accepted point (SendData) the
 * last three values of each guard predict its next zero, by a parabola and by a secant; before each step
 * (GetSyncData, location 0) the step is shortened to end on the earliest target: RESOLUTION/2 past the
 * crossing when the two predictions agree within AGREE resolutions or the crossing is at most APPROACH
 * resolutions off, else 90 % of the way to the earlier prediction. The step is shortened rather than cut by
 * a breakpoint, after which ngspice would restart with a tenth of it. A guard can turn back between two crossings
 * (the Hall sensor's triangle of the angle peaks mid-pole), and a step that spans the turn and the zero behind it
 * gives the three points nothing to foresee: so once a guard has crossed twice, no step is longer than 1/SAMPLES
 * of the time between its last two crossings (or since the last, when that is longer), and never shorter than
 * APPROACH resolutions for that reason. A crossing seen more than RESOLUTION after it happened (interpolated
 * between the two points around it) counts as late; the counts close the log.
 *
 * A guard named +NAME only times a digital edge: its crossing changes no analog equation, so the step ngspice
 * had planned before the approach is as good after the landing, and the driver resumes it (GetSyncData,
 * location 1, the landing accepted) instead of letting ngspice grow the step back from the short landing step
 * by a factor of 2 per step (7 steps from 10 us to 1 ms, at every Hall edge); so it does after the digital
 * events that follow such a landing (XSPICE cuts a step to an event after GetSyncData has seen it: a step
 * accepted at less than CUT of the step approved). Crossings that switch equations, and breakpoints, keep
 * ngspice's own restart. The policy and its measurements: docs/performance.md; the Python side:
 * wrsim.backend.ngspice.shared.
 *
 * Held values (the event side of IEEE 1076.1's mixed-signal cycle): each is an external voltage source (`dc 0
 * external`) whose value the driver returns (GetVSRCData) and changes only at events: the crossing of a guard
 * (up, down or either way), the instants offset + k * period, or the first point (t = 0). At an event, every
 * hold it updates takes its new value from the values of the point the event landed on, all before any is
 * assigned (a signal assignment): `set` takes the target node's value, `offset` adds target - q, which sets the
 * quantity q whose derivative capacitor is referenced to the held node (a break: its charge, the integrated
 * state, does not jump, so q does). A ramp follows a hold with linear ramps of given rise and fall times
 * (S'ramp). The HOLDS file, one entry per line ('#' comments):
 *   hold SOURCE set|offset Q|- VALUE            (the hold's index is its order among the hold lines)
 *   on GUARD up|down|any COND|- HOLD=TARGET...  (COND: a node whose value > 0.5 enables the event;
 *                                               HOLD=TARGET@DELAY: the value arrives DELAY's value [s] later,
 *                                               replacing the values pending (inertial, IEEE 1076 10.5.2.2);
 *                                               HOLD=TARGET@DELAY^LIMIT: those pending within LIMIT's value
 *                                               before it (reject LIMIT inertial); HOLD=TARGET~DELAY: those due
 *                                               at or after it (transport); in each case but a run of its own
 *                                               value just before it; DELAY < 0: no change; HOLD=TARGET!FAULT:
 *                                               the run stops with an error when FAULT's value is 1, the value
 *                                               no number)
 *   every PERIOD OFFSET COND|- HOLD=TARGET...
 *   init COND|- HOLD=TARGET...                  (TARGET: the node whose value the hold takes)
 *   change HOLD[,HOLD...] COND|- HOLD=TARGET... (a change of a hold: a delta cycle, DELTA seconds later; once
 *                                               however many of the holds changed at the same point)
 *   at HOLD COND|- HOLD=TARGET...               (when the time reaches the value of HOLD: a time point there)
 *   ramp SOURCE HOLD RISE FALL
 *   last SOURCE HOLD                            (S'last_value: the value HOLD had before its last change)
 *   flag SOURCE HOLD                            (S'event: 1 from a change of HOLD to the next point, the delta
 *                                               cycle that sees it, else 0)
 *   # TEXT                                      (the source of the events that follow, named in errors)
 * Instants of `every` events and ends of ramps are analog time points. The values of a point are those before
 * its events, so what a change of a hold sets off runs at the next point, which the driver puts DELTA after it.
 *
 * ngspice's messages go to stdout; exit status 1 when ngspice asks to quit with an error, 2 on bad usage. */
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <ngspice/sharedspice.h>

#define APPROACH 50.0
#define AGREE 1.0
#define DELTA 1e-9          /* [s] the time a delta cycle takes */
#define CUT 0.01            /* a step accepted at less than this share of the step approved was cut by an event */
#define SAMPLES 4.0         /* a guard that crosses is sampled at least this often between two crossings */

typedef struct {
    const char *name;
    int index;              /* in the SendData vectors, -1 until the first point */
    int count;              /* points in the history */
    double t[3], g[3];      /* the last accepted points, oldest first */
    double target;          /* where the next step should end for this guard, INFINITY when nowhere */
    bool smooth;            /* the crossing changes no equation: resume the planned step after it */
    int sign;               /* of the guard at the last accepted point (+1 above 0, -1 not), 0 before it */
    int crossed;            /* the direction of a crossing at the last accepted point, 0 for none */
    double crossing;        /* the last crossing (interpolated between the points around it), -1 before one */
    double interval;        /* between the last two crossings, 0 before two */
    long landings;
    long late;              /* crossings seen more than RESOLUTION after they happened */
} guard_t;

static guard_t *guards;
static int nguards, time_index = -1, exit_status;
static double window, stop, max_step, resolution;
static double resume;       /* the step planned before an approach to a smooth guard, 0 when none */
static bool shortened;      /* the step under way was shortened onto a smooth guard's target */
static double approved;     /* the step as it left location 0 (XSPICE may still cut it to an event) */
static long points, resumed;

typedef struct {            /* a held value: an external voltage source */
    char source[160];       /* its name as ngspice gives it to GetVSRCData (lower case) */
    bool offset;            /* set q's derivative reference (target - q added) rather than the value */
    char q[160];
    int qi;                 /* its index in the SendData vectors, -1 for none */
    double value, next;
    double *due, *pending;  /* values assigned `after` a delay and when they arrive, earliest first */
    int npending, cap;
    bool changed;           /* at the last point */
    long changes;
} hold_t;

typedef enum { ON_GUARD, ON_CHANGE, EVERY, INIT, AT } kind_t;
enum { INERTIAL = -1, TRANSPORT = -2 };  /* the pulse rejection limit of a delay without a limit node */
typedef struct {
    kind_t kind;
    int guard, dir;         /* ON_GUARD: the guard and the direction (+1 up, -1 down, 0 any); AT: the hold */
    int *watch, nwatch;     /* ON_CHANGE: the holds a change of any of which fires it */
    double period, due;     /* EVERY: the next instant */
    char cond[160];
    int ci;
    int *holds, nholds;     /* the holds it updates, each from the value of its target node */
    char (*targets)[160];
    int *ti;
    char (*delays)[160];    /* ... that long later when it has a delay node ("" none) */
    int *di;
    char (*limits)[160];    /* ... rejecting the values pending within a limit node's value before it ("" none) */
    int *li;                /* its index; INERTIAL: the limit is the delay, TRANSPORT: 0 */
    char (*faults)[160];    /* ... a node that is 1 where the value is no number ("" none): the run stops there */
    int *fi;
    char where[240];        /* the source of the event: the '#' comment line before it in the HOLDS file */
    long fired;             /* times it fired in the current cascade window */
    double last, interval;  /* ON_GUARD: when it last fired, and the time since the firing before */
    int shrinking;          /* ... how many intervals in a row were each shorter than ZENO_RATIO of the one before */
} event_t;

typedef struct {            /* S'ramp of hold `hold`, or (last) S'last_value: a step to the value before a change */
    char source[160];
    int hold;
    double rise, fall, from, to, start, length;
    bool last;
} ramp_t;

typedef struct {            /* S'event of hold `hold`: 1 while the point after its change is solved, else 0 */
    char source[160];
    int hold;
} flag_t;

static hold_t *holds;
static event_t *events;
static ramp_t *ramps;
static flag_t *flags;
static int nholds, nevents, nramps, nflags;
static bool first_point = true;
static bool restart;        /* a hold changed at the last point: the next step is short, as after a breakpoint */
static bool cascade;        /* ... and an event is sensitive to it: the next point is a delta cycle later */
static double last_t = -1.0;
/* An event cascade: more than CASCADE_EVENTS events within CASCADE_SPAN of simulated time (a process that
 * triggers itself 1 fs later, events that accumulate like a bouncing ball's) ends the run with one error line
 * naming the event that fired most, instead of a simulation that never ends. */
#define CASCADE_EVENTS 100000L
#define CASCADE_SPAN 1e-6
static double cascade_start = -1.0;
static long cascade_count;
/* Zeno: the crossings of one event that come ZENO_RUN times in a row each sooner than ZENO_RATIO of the interval
 * before (a geometric series: a bouncing ball whose bounces accumulate) end the run with one error when the next
 * interval would be shorter than ZENO_NEAR resolutions. Closer, a crossing located RESOLUTION late leaves the
 * quantity past its threshold by more than the re-initialised motion brings back (the ball falls through the
 * floor without an error): there is no solution past the accumulation point to compute. */
#define ZENO_RUN 10
#define ZENO_RATIO 0.98
#define ZENO_NEAR 100.0

/* The time after the last point at which g reaches 0 if it keeps its course: by the parabola through the last
 * three points (the return value) and by the secant through the last two (*secant); NAN where it does not. */
static double predict(const guard_t *x, double *secant)
{
    int n = x->count;
    double t1 = x->t[n - 2], g1 = x->g[n - 2], t2 = x->t[n - 1], g2 = x->g[n - 1];
    *secant = NAN;
    if (t2 <= t1 || g2 == g1 || g2 == 0.0)
        return NAN;
    double d1 = (g2 - g1) / (t2 - t1);
    if ((g2 > 0.0) == (d1 > 0.0))
        return NAN;                                      /* moving away from 0 */
    *secant = t2 - g2 / d1;
    if (n == 3 && x->t[0] < t1) {
        double a = (d1 - (g1 - x->g[0]) / (t1 - x->t[0])) / (t2 - x->t[0]);
        double s = d1 + a * (t2 - t1);                   /* g ~ g2 + s (t - t2) + a (t - t2)^2 */
        double disc = s * s - 4.0 * a * g2;
        if (a != 0.0 && disc >= 0.0) {
            double r1 = t2 + (-s + sqrt(disc)) / (2.0 * a), r2 = t2 + (-s - sqrt(disc)) / (2.0 * a);
            double best = INFINITY;
            if (r1 > t2) best = r1;
            if (r2 > t2 && r2 < best) best = r2;
            if (isfinite(best)) return best;
        }
        if (s != 0.0 && (g2 > 0.0) != (s > 0.0))
            return t2 - g2 / s;
    }
    return *secant;
}

/* A guard's target: RESOLUTION/2 past its predicted crossing when the prediction is sure (parabola and secant
 * agree within AGREE resolutions, i.e. the course is straight enough for either) or near (APPROACH resolutions),
 * else 90 % of the way to the earlier of the two predictions. */
static void observe(guard_t *x, double t, double g)
{
    if (x->count > 0 && t <= x->t[x->count - 1])
        x->count = 0, x->crossing = -1.0, x->interval = 0.0;  /* the analysis restarted: forget the course */
    if (x->count == 3) {
        memmove(x->t, x->t + 1, 2 * sizeof(double));
        memmove(x->g, x->g + 1, 2 * sizeof(double));
        x->count = 2;
    }
    int sign = g > 0.0 ? 1 : -1;
    x->crossed = x->sign != 0 && sign != x->sign ? sign : 0;
    x->sign = sign;
    if (x->crossed && x->count > 0) {
        double t1 = x->t[x->count - 1], g1 = x->g[x->count - 1];
        double at = g1 != g ? t1 + (t - t1) * g1 / (g1 - g) : t;
        x->late += t - at > resolution;
        x->interval = x->crossing >= 0.0 ? at - x->crossing : 0.0;
        x->crossing = at;
    }
    x->t[x->count] = t;
    x->g[x->count] = g;
    x->count++;
    x->target = INFINITY;
    if (x->count < 2)
        return;
    double secant, tc = predict(x, &secant);
    if (isnan(tc) || !(t < tc && tc <= t + window))
        return;
    bool sure = x->count == 3 && fabs(tc - secant) <= AGREE * resolution;
    if (sure || tc - t <= APPROACH * resolution)
        x->target = tc + 0.5 * resolution;
    else
        x->target = t + 0.9 * (fmin(tc, secant) - t);
}

static int send_char(char *text, int id, void *user)
{
    (void)id; (void)user;
    if (strncmp(text, "stdout ", 7) == 0 || strncmp(text, "stderr ", 7) == 0)
        text += 7;
    puts(text);
    return 0;
}

static int send_stat(char *text, int id, void *user) { (void)text; (void)id; (void)user; return 0; }
static int send_init(pvecinfoall data, int id, void *user) { (void)data; (void)id; (void)user; return 0; }
static int bg_running(NG_BOOL running, int id, void *user) { (void)running; (void)id; (void)user; return 0; }

static int controlled_exit(int status, NG_BOOL unload, NG_BOOL quit, int id, void *user)
{
    (void)unload; (void)quit; (void)id; (void)user;
    exit_status = status;
    return 0;
}

/* The index of node or vector `name` among the SendData vectors (`name` or `v(name)`), -1 when absent. */
static int vector_index(pvecvaluesall v, const char *name)
{
    size_t n = strlen(name);
    for (int k = 0; k < v->veccount; k++) {
        const char *vec = v->vecsa[k]->name;
        if (strcmp(vec, name) == 0 || (strncmp(vec, "v(", 2) == 0 && strncmp(vec + 2, name, n) == 0 &&
                                       strcmp(vec + 2 + n, ")") == 0))
            return k;
    }
    return -1;
}

static int find_vectors(pvecvaluesall v)
{
    int missing = 0;
    time_index = vector_index(v, "time");
    for (int j = 0; j < nguards; j++)
        if ((guards[j].index = vector_index(v, guards[j].name)) < 0)
            printf("error: 'above guard %s is not among the saved vectors\n", guards[j].name), missing++;
    for (int h = 0; h < nholds; h++)
        if (holds[h].offset && (holds[h].qi = vector_index(v, holds[h].q)) < 0)
            printf("error: quantity %s of held value %s is not among the saved vectors\n", holds[h].q,
                   holds[h].source), missing++;
    for (int e = 0; e < nevents; e++) {
        if (events[e].cond[0] && (events[e].ci = vector_index(v, events[e].cond)) < 0)
            printf("error: event condition %s is not among the saved vectors\n", events[e].cond), missing++;
        for (int k = 0; k < events[e].nholds; k++) {
            if ((events[e].ti[k] = vector_index(v, events[e].targets[k])) < 0)
                printf("error: event target %s is not among the saved vectors\n", events[e].targets[k]), missing++;
            if (events[e].delays[k][0] && (events[e].di[k] = vector_index(v, events[e].delays[k])) < 0)
                printf("error: event delay %s is not among the saved vectors\n", events[e].delays[k]), missing++;
            if (events[e].limits[k][0] && (events[e].li[k] = vector_index(v, events[e].limits[k])) < 0)
                printf("error: event limit %s is not among the saved vectors\n", events[e].limits[k]), missing++;
            if (events[e].faults[k][0] && (events[e].fi[k] = vector_index(v, events[e].faults[k])) < 0)
                printf("error: event fault %s is not among the saved vectors\n", events[e].faults[k]), missing++;
        }
    }
    return missing;
}

static double ramp_value(const ramp_t *r, double t)
{
    if (r->length <= 0.0 || t >= r->start + r->length)
        return r->to;
    if (t <= r->start)
        return r->from;
    return r->from + (r->to - r->from) * (t - r->start) / r->length;
}

/* Value `value` of hold h arrives at `due` with pulse rejection limit `limit` (IEEE 1076 10.5.2.2): the values
 * pending at or after `due` are dropped, and so are those within `limit` before it (inertial: the limit is the
 * delay; transport: 0) but for the run of values just before it that equal it (they change nothing: `s <= v
 * after d` again before v arrived keeps its arrival). */
static void schedule(hold_t *h, double due, double value, double limit)
{
    while (h->npending > 0 && h->due[h->npending - 1] >= due)
        h->npending--;
    int keep = 0, same = h->npending;                /* [0, keep) before the limit, [same, npending) equal */
    while (keep < h->npending && h->due[keep] < due - limit)
        keep++;
    while (same > keep && fabs(h->pending[same - 1] - value) <= 1e-12 * fmax(1.0, fabs(value)))
        same--;
    memmove(h->due + keep, h->due + same, (size_t)(h->npending - same) * sizeof(double));
    memmove(h->pending + keep, h->pending + same, (size_t)(h->npending - same) * sizeof(double));
    h->npending -= same - keep;
    if (h->npending == h->cap) {
        h->cap = h->cap ? 2 * h->cap : 4;
        h->due = realloc(h->due, (size_t)h->cap * sizeof(double));
        h->pending = realloc(h->pending, (size_t)h->cap * sizeof(double));
        if (!h->due || !h->pending) {
            fprintf(stderr, "out of memory for the values pending on %s\n", h->source);
            exit(1);
        }
    }
    h->due[h->npending] = due;
    h->pending[h->npending++] = value;
}

/* Whether one of the holds that ON_CHANGE event x watches changed at the last point. */
static bool watched_changed(const event_t *x)
{
    for (int k = 0; k < x->nwatch; k++)
        if (holds[x->watch[k]].changed)
            return true;
    return false;
}

/* The events that fire at the accepted point t: every hold they update takes its new value from this point's
 * values, then all are assigned; a ramp whose hold changed starts from where it is. */
static void fire(pvecvaluesall v, double t)
{
    bool any = false;
    for (int k = 0; k < nholds; k++) {                  /* values assigned after a delay that ends here */
        hold_t *h = &holds[k];
        while (h->npending > 0 && h->due[0] <= t + 1e-12 * fmax(1.0, fabs(h->due[0]))) {
            h->next = h->pending[0];
            h->npending--;
            memmove(h->due, h->due + 1, (size_t)h->npending * sizeof(double));
            memmove(h->pending, h->pending + 1, (size_t)h->npending * sizeof(double));
            any = true;
        }
    }
    for (int e = 0; e < nevents; e++) {
        event_t *x = &events[e];
        bool due = false;
        if (x->kind == INIT)
            due = first_point;
        else if (x->kind == EVERY && t >= x->due - 1e-12 * fmax(1.0, fabs(x->due))) {
            due = true;                                  /* the point landed on the instant (get_sync) */
            double tol = 1e-12 * fmax(1.0, fabs(x->due));
            if (!(x->due + x->period > x->due + tol)) {  /* a period time cannot resolve: it would never advance */
                printf("error: the period %g s of %s is below the resolution of time at t = %.9g s (1e-12 of t, at "
                       "least 1 ps)\n", x->period, x->where[0] ? x->where : "an unnamed event", t);
                fflush(stdout);
                exit(1);
            }
            x->due += (floor((t + tol - x->due) / x->period) + 1.0) * x->period;  /* the first instant after t */
        } else if (x->kind == ON_CHANGE) {
            due = watched_changed(x);
        } else if (x->kind == AT) {
            double at = holds[x->guard].value;
            due = t >= at - 1e-12 * fmax(1.0, fabs(at));
        } else if (x->kind == ON_GUARD) {
            int c = guards[x->guard].crossed;
            due = c != 0 && (x->dir == 0 || x->dir == c);
        }
        if (!due || (x->ci >= 0 && !(v->vecsa[x->ci]->creal > 0.5)))
            continue;
        if (t - cascade_start > CASCADE_SPAN) {
            cascade_start = t;
            cascade_count = 0;
            for (int j = 0; j < nevents; j++)
                events[j].fired = 0;
        }
        x->fired++;
        if (x->kind == ON_GUARD) {
            double interval = t - x->last;
            x->shrinking = x->last > 0.0 && interval < ZENO_RATIO * x->interval ? x->shrinking + 1 : 0;
            double next = interval * interval / x->interval;  /* the series' next term */
            if (x->shrinking >= ZENO_RUN && next < ZENO_NEAR * resolution) {
                printf("error: the events of %s accumulate (a Zeno model): %d intervals in a row each shorter "
                       "than the one before, the last %.3g s at t = %.9g s, and the series ends at t = %.9g s; "
                       "the model has no solution past that time (change it so that the events stop, e.g. a "
                       "contact that holds once the rebound is below a threshold)\n",
                       x->where[0] ? x->where : "an unnamed event", x->shrinking, interval, t,
                       t + next / (1.0 - interval / x->interval));
                fflush(stdout);
                exit(1);
            }
            x->last = t;
            x->interval = interval;
        }
        if (++cascade_count > CASCADE_EVENTS) {
            const event_t *most = x;
            for (int j = 0; j < nevents; j++)
                if (events[j].fired > most->fired)
                    most = &events[j];
            printf("error: an event cascade at t = %.9g s: %ld events within %g s, %ld of them the one of %s\n", t,
                   cascade_count, t - cascade_start, most->fired, most->where[0] ? most->where : "an unnamed event");
            fflush(stdout);
            exit(1);
        }
        for (int k = 0; k < x->nholds; k++) {
            hold_t *h = &holds[x->holds[k]];
            double target = v->vecsa[x->ti[k]]->creal;
            if (x->fi[k] >= 0 && v->vecsa[x->fi[k]]->creal > 0.5) {
                printf("error: at t = %.9g s the value assigned has none (a division by zero, the square root of a "
                       "negative number, the logarithm of one not above zero, a fractional power of a negative "
                       "number, an integer past integer'high): %s\n", t,
                       x->where[0] ? x->where : "an unnamed event");
                fflush(stdout);
                exit(1);
            }
            double delay = x->di[k] >= 0 ? v->vecsa[x->di[k]]->creal : 0.0;
            if (delay < 0.0)
                continue;                                /* the run assigned nothing to it */
            if (delay > 0.0)
                schedule(h, t + delay, target,
                         x->li[k] >= 0 ? v->vecsa[x->li[k]]->creal : x->li[k] == TRANSPORT ? 0.0 : delay);
            else {
                h->npending = 0;                         /* a value now replaces those pending */
                h->next = h->offset ? h->value + target - v->vecsa[h->qi]->creal : target;
            }
        }
        any = true;
    }
    for (int k = 0; k < nholds; k++)
        holds[k].changed = false;
    if (!any)
        return;
    for (int r = 0; r < nramps; r++) {
        ramp_t *x = &ramps[r];
        const hold_t *h = &holds[x->hold];
        if (!isnan(h->next) && h->next != h->value) {
            x->from = ramp_value(x, t);
            x->to = x->last ? h->value : h->next;
            x->start = t;
            x->length = x->last ? 0.0 : x->to > x->from ? x->rise : x->fall;
        }
    }
    for (int k = 0; k < nholds; k++)
        if (!isnan(holds[k].next)) {
            holds[k].changed = holds[k].next != holds[k].value;
            restart = restart || holds[k].changed;
            holds[k].changes += holds[k].changed;
            holds[k].value = holds[k].next;
            holds[k].next = NAN;
        }
}

/* The quiescent point has a wall-time bound of its own: ngspice's operating point of some singular systems (the
 * transient's, with its gmin and source stepping) never returns, and a run that ends with wrsim's overall timeout
 * says less than an error naming the quiescent point. */
#define OP_WALL 60            /* [s], or the environment's WRSIM_OP_WALL */
static volatile int first_point_seen;

static void *op_watchdog(void *arg)
{
    (void)arg;
    const char *given = getenv("WRSIM_OP_WALL");
    unsigned wall = given && atoi(given) > 0 ? (unsigned)atoi(given) : OP_WALL;
    sleep(wall);
    if (!first_point_seen) {
        printf("error: the quiescent point was not found within %u s of wall time (ngspice's operating point does "
               "not converge: are the equations at t = 0 singular or contradictory?)\n", wall);
        fflush(stdout);
        _exit(1);
    }
    return NULL;
}

static int send_data(pvecvaluesall v, int count, int id, void *user)
{
    (void)count; (void)id; (void)user;
    first_point_seen = 1;
    if (time_index < 0) {
        if (find_vectors(v))
            exit_status = 1;
        if (time_index < 0)
            return 0;
    }
    double t = v->vecsa[time_index]->creal;
    points++;
    for (int j = 0; j < nguards; j++)
        if (guards[j].index >= 0)
            observe(&guards[j], t, v->vecsa[guards[j].index]->creal);
    if (t > last_t && exit_status == 0) {
        fire(v, t);
        first_point = false;
        last_t = t;
    }
    return 0;
}

/* The value of an external voltage source: a hold's, a ramp's or a flag's (0 for any other). A flag is 1 from
 * the point its hold changed at to the next (the delta cycle that sees the change): the events that fire there
 * read it. */
static int vsrc_data(double *value, double t, char *name, int id, void *user)
{
    (void)id; (void)user;
    *value = 0.0;
    for (int k = 0; k < nholds; k++)
        if (strcmp(name, holds[k].source) == 0) {
            *value = holds[k].value;
            return 0;
        }
    for (int r = 0; r < nramps; r++)
        if (strcmp(name, ramps[r].source) == 0) {
            *value = ramp_value(&ramps[r], t);
            return 0;
        }
    for (int f = 0; f < nflags; f++)
        if (strcmp(name, flags[f].source) == 0) {
            *value = holds[flags[f].hold].changed;
            return 0;
        }
    return 0;
}

/* Before each step (location 0): end it on the earliest target within it, or on the final time when it
 * reaches past half of the rest (with a step callback ngspice otherwise pulls a step that would pass the
 * final time back below it and halves its way towards it until the step is zero). After an accepted step
 * (location 1): resume the planned step after a landing on a smooth guard (see the header). */
static int get_sync(double t, double *delta, double old_delta, int redo, int id, int location, void *user)
{
    (void)id; (void)user;
    if (location == 1) {                                 /* after a step: t is its end, *delta the next step */
        if (redo)
            return 0;                                    /* rejected: ngspice retries it shorter */
        if (shortened || (resume > 0.0 && old_delta < CUT * approved)) {
            if (*delta < resume) {                       /* after a landing, or an event right after it */
                *delta = resume;
                resumed++;
            }
        } else {
            resume = 0.0;
        }
        return 0;
    }
    if (redo)
        return 0;
    shortened = false;
    for (int j = 0; j < nguards; j++)               /* no step spans a guard's course between two crossings */
        if (guards[j].interval > 0.0) {
            double bound = fmax(fmax(guards[j].interval, t - guards[j].crossing) / SAMPLES, APPROACH * resolution);
            *delta = fmin(*delta, bound);
        }
    int first = -1;
    for (int j = 0; j < nguards; j++)
        if (guards[j].target > t && guards[j].target < t + *delta && (first < 0 || guards[j].target < guards[first].target))
            first = j;
    if (first >= 0) {
        if (guards[first].smooth) {
            resume = fmax(resume, fmin(*delta, max_step));
            shortened = true;
        }
        *delta = guards[first].target - t;
        guards[first].landings++;
    }
    if (restart) {                                  /* the values jumped at the last point */
        cascade = false;
        for (int e = 0; e < nevents; e++)
            cascade = cascade || (events[e].kind == ON_CHANGE && watched_changed(&events[e]));
        *delta = fmin(*delta, cascade ? DELTA : resolution);
        restart = false;
    }
    for (int e = 0; e < nevents; e++)               /* instants of `every` events, exactly */
        if (events[e].kind == EVERY && events[e].due > t && events[e].due < t + *delta)
            *delta = events[e].due - t;
    for (int e = 0; e < nevents; e++)               /* times `at` events wait for, exactly */
        if (events[e].kind == AT && holds[events[e].guard].value > t && holds[events[e].guard].value < t + *delta)
            *delta = holds[events[e].guard].value - t;
    for (int k = 0; k < nholds; k++)                /* ends of delays, exactly */
        if (holds[k].npending > 0 && holds[k].due[0] > t && holds[k].due[0] < t + *delta)
            *delta = holds[k].due[0] - t;
    for (int r = 0; r < nramps; r++) {              /* the end of a ramp under way */
        double end = ramps[r].start + ramps[r].length;
        if (ramps[r].length > 0.0 && end > t && end < t + *delta)
            *delta = end - t;
    }
    if (t + 2.0 * *delta >= stop) {
        if (stop - t > max_step) {
            *delta = 0.5 * (stop - t);
        } else {
            *delta = stop - t;
            while (t + *delta > stop)
                *delta = nextafter(*delta, 0.0);
        }
    }
    approved = *delta;
    return 0;
}

static int guard_index(const char *name)
{
    for (int j = 0; j < nguards; j++)
        if (strcmp(guards[j].name, name) == 0)
            return j;
    return -1;
}

/* The holds of a `change` line, HOLD[,HOLD...]; 0 when they are well formed. */
static int watch_list(event_t *x, const char *list)
{
    x->watch = calloc(strlen(list) / 2 + 1, sizeof(int));
    for (const char *p = list;; p++) {
        char *end;
        long h = strtol(p, &end, 10);
        if (end == p || h < 0 || h >= nholds)
            return -1;
        x->watch[x->nwatch++] = (int)h;
        if (*end != ',')
            return *end ? -1 : 0;
        p = end;
    }
}

static int hold_list(event_t *x, char *rest)
{
    size_t n = strlen(rest) / 2 + 1;
    x->holds = calloc(n, sizeof(int));
    x->targets = calloc(n, sizeof *x->targets);
    x->ti = calloc(n, sizeof(int));
    x->delays = calloc(n, sizeof *x->delays);
    x->di = calloc(n, sizeof(int));
    x->limits = calloc(n, sizeof *x->limits);
    x->li = calloc(n, sizeof(int));
    x->faults = calloc(n, sizeof *x->faults);
    x->fi = calloc(n, sizeof(int));
    for (char *tok = strtok(rest, " \t\n"); tok; tok = strtok(NULL, " \t\n")) {
        char *eq = strchr(tok, '=');
        int h = atoi(tok);
        char *fault = eq ? strchr(eq, '!') : NULL;
        x->fi[x->nholds] = -1;
        if (fault) {
            *fault = '\0';
            if (strlen(fault + 1) >= sizeof x->faults[0])
                return -1;
            strcpy(x->faults[x->nholds], fault + 1);
        }
        char *at = eq ? strpbrk(eq, "@~") : NULL;
        char *limit = at ? strchr(at, '^') : NULL;
        x->li[x->nholds] = at && *at == '~' ? TRANSPORT : INERTIAL;
        if (limit) {
            *limit = '\0';
            if (*at == '~' || strlen(limit + 1) >= sizeof x->limits[0])
                return -1;
            strcpy(x->limits[x->nholds], limit + 1);
        }
        if (at) {
            *at = '\0';
            if (strlen(at + 1) >= sizeof x->delays[0])
                return -1;
            strcpy(x->delays[x->nholds], at + 1);
        }
        x->di[x->nholds] = -1;
        if (!eq || h < 0 || h >= nholds || strlen(eq + 1) >= sizeof x->targets[0])
            return -1;
        strcpy(x->targets[x->nholds], eq + 1);
        x->holds[x->nholds++] = h;
    }
    return 0;
}

/* Read the HOLDS file (see the header); 0 when it is well formed. */
static int read_holds(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "cannot read %s\n", path);
        return 1;
    }
    char line[4096];
    int n = 0;
    while (fgets(line, sizeof line, f))
        n++;
    rewind(f);
    holds = calloc((size_t)n + 1, sizeof(hold_t));
    events = calloc((size_t)n + 1, sizeof(event_t));
    ramps = calloc((size_t)n + 1, sizeof(ramp_t));
    flags = calloc((size_t)n + 1, sizeof(flag_t));
    int lineno = 0, bad = 0;
    char where[240] = "";
    while (!bad && fgets(line, sizeof line, f)) {
        lineno++;
        char kind[16], a[160], b[160], c[160], d[160], e[160];
        int used = 0;
        if (line[0] == '#') {                            /* the source of the events that follow */
            snprintf(where, sizeof where, "%s", line + 1 + (line[1] == ' '));
            where[strcspn(where, "\n")] = '\0';
            continue;
        }
        if (sscanf(line, "%15s", kind) != 1)
            continue;
        int first_event = nevents;
        if (strcmp(kind, "hold") == 0) {
            hold_t *h = &holds[nholds];
            bad = sscanf(line, "%*s %159s %159s %159s %159s", h->source, a, h->q, b) != 4;
            h->offset = strcmp(a, "offset") == 0;
            h->value = atof(b);
            h->next = NAN;
            nholds++;
        } else if (strcmp(kind, "on") == 0) {
            event_t *x = &events[nevents++];
            bad = sscanf(line, "%*s %159s %159s %159s %n", a, b, c, &used) != 3;
            x->kind = ON_GUARD;
            x->guard = guard_index(a);
            x->dir = strcmp(b, "up") == 0 ? 1 : strcmp(b, "down") == 0 ? -1 : 0;
            strcpy(x->cond, strcmp(c, "-") ? c : "");
            bad = bad || x->guard < 0 || hold_list(x, line + used);
        } else if (strcmp(kind, "change") == 0 || strcmp(kind, "at") == 0) {
            event_t *x = &events[nevents++];
            int from = 0, to = 0;                        /* the hold (at) or holds (change), of any length */
            bad = sscanf(line, "%*s %n%*s%n %159s %n", &from, &to, c, &used) != 1;
            line[to] = '\0';
            x->kind = strcmp(kind, "at") == 0 ? AT : ON_CHANGE;
            strcpy(x->cond, strcmp(c, "-") ? c : "");
            if (x->kind == AT) {
                x->guard = atoi(line + from);
                bad = bad || x->guard < 0 || x->guard >= nholds;
            } else {
                bad = bad || watch_list(x, line + from);
            }
            bad = bad || hold_list(x, line + used);
        } else if (strcmp(kind, "every") == 0) {
            event_t *x = &events[nevents++];
            bad = sscanf(line, "%*s %159s %159s %159s %n", a, b, c, &used) != 3;
            x->kind = EVERY;
            x->period = atof(a);
            x->due = atof(b);
            strcpy(x->cond, strcmp(c, "-") ? c : "");
            bad = bad || !(x->period > 0.0) || hold_list(x, line + used);
        } else if (strcmp(kind, "init") == 0) {
            event_t *x = &events[nevents++];
            bad = sscanf(line, "%*s %159s %n", c, &used) != 1;
            x->kind = INIT;
            strcpy(x->cond, strcmp(c, "-") ? c : "");
            bad = bad || hold_list(x, line + used);
        } else if (strcmp(kind, "ramp") == 0) {
            ramp_t *r = &ramps[nramps++];
            bad = sscanf(line, "%*s %159s %159s %159s %159s", r->source, a, d, e) != 4;
            r->hold = atoi(a);
            r->rise = atof(d);
            r->fall = atof(e);
            bad = bad || r->hold < 0 || r->hold >= nholds;
            if (!bad)
                r->from = r->to = holds[r->hold].value;
        } else if (strcmp(kind, "last") == 0) {
            ramp_t *r = &ramps[nramps++];
            bad = sscanf(line, "%*s %159s %159s", r->source, a) != 2;
            r->hold = atoi(a);
            r->last = true;
            bad = bad || r->hold < 0 || r->hold >= nholds;
            if (!bad)
                r->from = r->to = holds[r->hold].value;
        } else if (strcmp(kind, "flag") == 0) {
            flag_t *g = &flags[nflags++];
            bad = sscanf(line, "%*s %159s %159s", g->source, a) != 2;
            g->hold = atoi(a);
            bad = bad || g->hold < 0 || g->hold >= nholds;
        } else {
            bad = 1;
        }
        for (int k = first_event; k < nevents; k++)
            snprintf(events[k].where, sizeof events[k].where, "%s", where);
    }
    fclose(f);
    for (int k = 0; k < nevents; k++)
        events[k].ci = -1;
    if (bad)
        fprintf(stderr, "%s:%d: malformed held-value entry\n", path, lineno);
    return bad;
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: %s MAX_STEP STOP RESOLUTION NETLIST HOLDS [GUARD...]\n", argv[0]);
        return 2;
    }
    max_step = atof(argv[1]);
    stop = atof(argv[2]);
    resolution = atof(argv[3]);
    window = 2.0 * max_step;
    if (!(max_step > 0.0 && stop > 0.0 && resolution > 0.0)) {
        fprintf(stderr, "%s: MAX_STEP, STOP and RESOLUTION must be > 0\n", argv[0]);
        return 2;
    }
    nguards = argc - 6;
    guards = calloc(nguards > 0 ? (size_t)nguards : 1, sizeof(guard_t));
    for (int j = 0; j < nguards; j++) {
        guards[j].smooth = argv[6 + j][0] == '+';
        guards[j].name = argv[6 + j] + guards[j].smooth;
        guards[j].index = -1;
        guards[j].target = INFINITY;
        guards[j].crossing = -1.0;
    }
    if (strcmp(argv[5], "-") != 0 && read_holds(argv[5]) != 0)
        return 2;
    int ident = 0;
    ngSpice_Init(send_char, send_stat, controlled_exit, send_data, send_init, bg_running, NULL);
    ngSpice_Init_Sync(vsrc_data, NULL, get_sync, &ident, NULL);
    pthread_t watchdog;
    if (pthread_create(&watchdog, NULL, op_watchdog, NULL) == 0)
        pthread_detach(watchdog);
    size_t len = strlen(argv[4]) + 8;
    char *command = malloc(len);
    snprintf(command, len, "source %s", argv[4]);
    ngSpice_Command(command);
    printf("wrsim crossings: %ld accepted points, %ld resumed steps; steps shortened per guard:", points, resumed);
    for (int j = 0; j < nguards; j++)
        printf("%s %s %ld", j ? "," : "", guards[j].name, guards[j].landings);
    printf("\nwrsim late crossings per guard:");
    for (int j = 0; j < nguards; j++)
        printf("%s %s %ld", j ? "," : "", guards[j].name, guards[j].late);
    printf("\n");
    if (nholds) {
        printf("wrsim held values: changes per value:");
        for (int k = 0; k < nholds; k++)
            printf("%s %s %ld", k ? "," : "", holds[k].source, holds[k].changes);
        printf("\n");
    }
    fflush(stdout);
    return exit_status ? 1 : 0;
}
