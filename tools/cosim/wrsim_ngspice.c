/* wrsim_ngspice: ngspice (libngspice) with exact 'above crossings.
 *
 * usage: wrsim_ngspice MAX_STEP STOP RESOLUTION NETLIST [GUARD...]   (a GUARD written +NAME switches no equation)
 *
 * Sources NETLIST (its .control section runs the analysis and writes the raw file and the event record) and
 * makes every zero crossing of a GUARD node an analog time point: after each accepted point (SendData) the
 * last three values of each guard predict its next zero, by a parabola and by a secant; before each step
 * (GetSyncData, location 0) the step is shortened to end on the earliest target: RESOLUTION/2 past the
 * crossing when the two predictions agree within AGREE resolutions or the crossing is at most APPROACH
 * resolutions off, else 90 % of the way to the earlier prediction. The step is shortened rather than cut by
 * a breakpoint, after which ngspice would restart with a tenth of it.
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
 * ngspice's messages go to stdout; exit status 1 when ngspice asks to quit with an error, 2 on bad usage. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ngspice/sharedspice.h>

#define APPROACH 50.0
#define AGREE 1.0
#define CUT 0.01            /* a step accepted at less than this share of the step approved was cut by an event */

typedef struct {
    const char *name;
    int index;              /* in the SendData vectors, -1 until the first point */
    int count;              /* points in the history */
    double t[3], g[3];      /* the last accepted points, oldest first */
    double target;          /* where the next step should end for this guard, INFINITY when nowhere */
    bool smooth;            /* the crossing changes no equation: resume the planned step after it */
    long landings;
} guard_t;

static guard_t *guards;
static int nguards, time_index = -1, exit_status;
static double window, stop, max_step, resolution;
static double resume;       /* the step planned before an approach to a smooth guard, 0 when none */
static bool shortened;      /* the step under way was shortened onto a smooth guard's target */
static double approved;     /* the step as it left location 0 (XSPICE may still cut it to an event) */
static long points, resumed;

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
        x->count = 0;                                    /* the analysis restarted: forget the course */
    if (x->count == 3) {
        memmove(x->t, x->t + 1, 2 * sizeof(double));
        memmove(x->g, x->g + 1, 2 * sizeof(double));
        x->count = 2;
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

static int send_data(pvecvaluesall v, int count, int id, void *user)
{
    (void)count; (void)id; (void)user;
    if (time_index < 0) {
        for (int k = 0; k < v->veccount; k++) {
            const char *name = v->vecsa[k]->name;
            if (strcmp(name, "time") == 0)
                time_index = k;
            for (int j = 0; j < nguards; j++) {
                size_t n = strlen(guards[j].name);
                if (strcmp(name, guards[j].name) == 0 || (strncmp(name, "v(", 2) == 0 &&
                    strncmp(name + 2, guards[j].name, n) == 0 && strcmp(name + 2 + n, ")") == 0))
                    guards[j].index = k;
            }
        }
        for (int j = 0; j < nguards; j++)
            if (guards[j].index < 0)
                printf("error: 'above guard %s is not among the saved vectors\n", guards[j].name);
        if (time_index < 0)
            return 0;
    }
    double t = v->vecsa[time_index]->creal;
    points++;
    for (int j = 0; j < nguards; j++)
        if (guards[j].index >= 0)
            observe(&guards[j], t, v->vecsa[guards[j].index]->creal);
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

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: %s MAX_STEP STOP RESOLUTION NETLIST [GUARD...]\n", argv[0]);
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
    nguards = argc - 5;
    guards = calloc(nguards > 0 ? (size_t)nguards : 1, sizeof(guard_t));
    for (int j = 0; j < nguards; j++) {
        guards[j].smooth = argv[5 + j][0] == '+';
        guards[j].name = argv[5 + j] + guards[j].smooth;
        guards[j].index = -1;
        guards[j].target = INFINITY;
    }
    int ident = 0;
    ngSpice_Init(send_char, send_stat, controlled_exit, send_data, send_init, bg_running, NULL);
    ngSpice_Init_Sync(NULL, NULL, get_sync, &ident, NULL);
    size_t len = strlen(argv[4]) + 8;
    char *command = malloc(len);
    snprintf(command, len, "source %s", argv[4]);
    ngSpice_Command(command);
    printf("wrsim crossings: %ld accepted points, %ld resumed steps; steps shortened per guard:", points, resumed);
    for (int j = 0; j < nguards; j++)
        printf("%s %s %ld", j ? "," : "", guards[j].name, guards[j].landings);
    printf("\n");
    fflush(stdout);
    return exit_status ? 1 : 0;
}
