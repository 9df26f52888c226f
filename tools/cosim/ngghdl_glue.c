/* ngghdl_glue.c - run a GHDL-elaborated VHDL design inside ngspice's XSPICE
 * d_cosim code model (wrsim mixed-signal co-simulation, docs/vhdl-ams-subset.md
 * "Mixed signal").
 *
 * Purpose
 *   This file is linked INTO the shared library of one digital top entity.
 *   d_cosim (through ngghdl_loader.so, which gives each instance a private
 *   copy of that library) calls Cosim_setup(); from then on ngspice drives
 *   the VHDL time forward with step() and feeds input bits with in_fn(), and
 *   the glue reports output bits with info->out_fn().  Everything runs in the
 *   ngspice thread: ghdl_main() runs on a private stack and control is handed
 *   back and forth with swapcontext() (a coroutine).
 *
 * Build (what wrsim.ghdl.build() runs)
 *   gcc -O2 -fPIC -Wall -Wextra -c ngghdl_glue.c -o ngghdl_glue.o \
 *       -I/usr/lib/ghdl/include/ghdl -I/usr/share/ngspice/scripts/src
 *   ghdl-llvm -a --std=08 --workdir=W design files...
 *   ghdl-llvm -e --std=08 --workdir=W -shared -Wl,ngghdl_glue.o \
 *       -Wl,-Wl,-Bsymbolic -Wl,-lm -o TOP.so TOP
 *   Headers: vpi_user.h from ghdl-common, ngspice/cosim.h and cmtypes.h from
 *   the ngspice package (46: input_due() reads d_cosim's private layout of
 *   that version; wrsim refuses another, batch.DCOSIM_NGSPICE).
 *
 * Netlist (see ngghdl_loader.c)
 *   aecu [in bits] [out bits] ecu
 *   .model ecu d_cosim(simulation="ngghdl_loader.so" lib_args=["TOP.so"]
 *   + sim_args=["TOP" "@args.txt"] irreversible=1)
 *   sim_args[0] is the program name GHDL uses in its messages; every later
 *   argument is a GHDL run option (-gNAME=VALUE, --vcd=FILE, ...).  "@FILE"
 *   reads more options from FILE, one per line ('#' starts a comment line):
 *   ngspice's numparam mangles "=" followed by a non-number inside .model
 *   strings ("--vcd=x.vcd" gives "Undefined parameter [x.vcd]").
 *
 * Ports
 *   Found by iterating vpiNet on the top module (GHDL 2.0's vpiPort iterator
 *   is empty); vpiDirection 1 = in, 2 = out, 5 = internal signal (ignored;
 *   also what GHDL reports for "buffer" ports).  d_cosim's input list holds
 *   the "in" ports and its output list the "out" ports, each in declaration
 *   order; a port of width W contributes W consecutive bits, left to right
 *   (MSB first for "downto" vectors and for integers).  Carried types:
 *   std_logic, bit, boolean and their vectors both ways; integer/natural (32
 *   bits, two's complement) as outputs only, because GHDL 2.0's
 *   vpi_put_value ignores integer signals.  inout ports, enumerations other
 *   than std_logic/bit/boolean, and reals are refused at setup.
 *
 * Time
 *   step(info) asks for VHDL time info->vtime [s].  The glue applies the
 *   queued inputs at GHDL's current time, arms cbAfterDelay(target - now)
 *   and, when it fires, cbReadWriteSynch so that GHDL pauses after the last
 *   delta cycle at the target.  An output change (cbValueChange) pauses at the
 *   end of that time step instead; step() then reports the outputs and sets
 *   info->vtime to the time of the change, and d_cosim cuts the SPICE step
 *   back to it.  An output named by an argument "+lazy=NAME" (a port no
 *   analog element reads: a digital neighbour or a recording reads it) does
 *   not pause GHDL: its changes are reported at the end of the step, so they
 *   cost the analog solver no step of its own (wrsim marks such ports), or
 *   later, when a report there would make d_cosim drop an input it still
 *   holds (input_due(): the glue reads d_cosim's input queue, whose layout
 *   is that of ngspice 46).
 *   GHDL 2.0 cannot remove a cbAfterDelay (vpi_remove_cb returns
 *   0 and it fires anyway), so every timed callback carries a generation
 *   number and stale ones are ignored.  d_cosim only calls step() on accepted
 *   SPICE steps (irreversible=N), so GHDL never has to go back in time; the
 *   price is that a VHDL reaction to an input event (even a combinational
 *   one) reaches SPICE at the end of the accepted step holding that event.
 *   Inputs start as 'U' in the glue, so the values ngspice passes at t = 0
 *   always reach the VHDL side.  Outputs start as '0', like d_cosim's, so
 *   only outputs that differ from '0' after VHDL time 0 are reported then
 *   (they reach SPICE at the end of its first time step, with d_cosim's
 *   warning "output scheduled with impossible delay").
 *
 * Environment
 *   NGGHDL_FATAL=1  if the VHDL simulation ends with a non-zero status
 *                   (assertion failure, error) the glue exits ngspice with
 *                   that status; otherwise the outputs freeze and ngspice
 *                   goes on.  wrsim always sets it (wrsim.ghdl.RUN_ENV).
 *   NGGHDL_PORTS=1  print the port map at setup (wrsim's preflight uses it).
 *   NGGHDL_STATS=1  print step/wake/event counts and the wall time in step().
 *   NGGHDL_DEBUG=1  trace every hand-over, input and output.
 *
 * Hand-over: only the ucontext coroutine.  GHDL's run-time is single-threaded
 * and never returns from ghdl_main() until the simulation ends, so it needs a
 * stack of its own; with makecontext/swapcontext a hand-over costs about
 * 1.3 us per step, against 7-54 us with a thread and two semaphores (which
 * wait on the scheduler; measured with the research prototype on 2 busy
 * cores).  A pthread fallback would only matter on a C library without
 * ucontext (musl), where Debian's GHDL does not run anyway, so there is none.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <time.h>
#include <ucontext.h>

#include <vpi_user.h>           /* GHDL's, /usr/lib/ghdl/include/ghdl */
#include "ngspice/cmtypes.h"    /* Digital_t */
#include "ngspice/cosim.h"      /* struct co_info */

extern int ghdl_main(int argc, char **argv);

#define GHDL_STACK_SIZE (64u << 20) /* GHDL likes deep stacks (recursion) */
#define GUARD_SIZE      65536u      /* PROT_NONE below the stack */

struct port {
    vpiHandle h;
    char     *name;
    int       bits;       /* vpiSize */
    int       first;      /* index of the first bit in d_cosim's in/out list */
    char     *in_str;     /* pending input value, binstr (inputs) */
    int       in_dirty;
    char     *out_str;    /* last value reported to ngspice (outputs) */
    int       lazy;       /* output reported at the end of the step ("+lazy=NAME") */
};

struct ports {
    struct port *p;
    int          n, bits;
};

static struct {
    struct co_info *info;
    ucontext_t      spice_uc, ghdl_uc;
    void           *stack;
    int             started, finished, quit, verbose;
    double          tick;        /* seconds per GHDL time unit */
    uint64_t        now;         /* GHDL time at the last pause [ticks] */
    unsigned        gen;         /* generation of the armed pause */
    int             stopping;    /* an output changed: pause at end of step */
    int             held;        /* d_cosim holds the last report: it cut its step back for it */
    double          delay;       /* [s] d_cosim's output delay ("+delay=SECONDS"); 0: no d_cosim */
    struct ports    in, out;
    int             argc;
    char          **argv;
    int             n_lazy;
    char          **lazy;        /* "+lazy=NAME" arguments */
    unsigned long   n_step, n_wake, n_in_events, n_out_events, n_deferred, n_early;
    double          wall_in_step;
} G;

static void dbg(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void dbg(const char *fmt, ...)
{
    va_list ap;
    if (!G.verbose)
        return;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
}

/* A setup error: ngspice cannot go on without a working instance (d_cosim
 * would call a NULL step()), so say why and end the process, as GHDL itself
 * does for elaboration errors.  wrsim's preflight runs the same setup first. */
static void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
static void fail(const char *fmt, ...)
{
    va_list ap;
    fputs("ngghdl: error: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}

static void *xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p)
        fail("out of memory");
    return p;
}

/* ---------------------------------------------------------------- GHDL side
 * Everything in this section runs on GHDL's stack, inside VPI callbacks. */

static uint64_t ghdl_now(void)
{
    s_vpi_time t = { .type = vpiSimTime };
    vpi_get_time(NULL, &t);
    return ((uint64_t)(uint32_t)t.high << 32) | (uint32_t)t.low;
}

static PLI_INT32 wake_cb(p_cb_data cb);

/* Resume wake_cb() after 'delay' ticks, or after the last delta cycle of the
 * current time when delay is 0.  user_data = generation * 2 + (1 if timed). */
static void arm(uint64_t delay, unsigned gen)
{
    s_vpi_time t = { .type = vpiSimTime };
    s_cb_data  cb;

    memset(&cb, 0, sizeof cb);
    t.low = (PLI_UINT32)delay;
    t.high = (PLI_UINT32)(delay >> 32);
    cb.reason = delay ? cbAfterDelay : cbReadWriteSynch;
    cb.cb_rtn = wake_cb;
    cb.time = &t;
    cb.user_data = (PLI_BYTE8 *)(((uintptr_t)gen << 1) | (delay != 0));
    vpi_register_cb(&cb);
}

/* Put the queued input values; returns 1 if there were any. */
static int apply_inputs(void)
{
    s_vpi_value v = { .format = vpiBinStrVal };
    int         any = 0;

    for (int i = 0; i < G.in.n; i++) {
        struct port *p = &G.in.p[i];
        if (!p->in_dirty)
            continue;
        p->in_dirty = 0;
        any = 1;
        v.value.str = p->in_str;
        vpi_put_value(p->h, &v, NULL, vpiNoDelay);
        dbg("ngghdl: t=%.9g s put %s=%s\n", G.now * G.tick, p->name, p->in_str);
    }
    return any;
}

/* The pause point: give control to ngspice; when it comes back, apply the
 * queued inputs and schedule the next pause at info->vtime. */
static void pause_here(void)
{
    for (;;) {
        G.now = ghdl_now();
        swapcontext(&G.ghdl_uc, &G.spice_uc);
        G.n_wake++;
        if (G.quit) {
            /* GHDL 2.0 checks the break flag only after cbAfterDelay
             * callbacks: one tick later is the earliest it stops. */
            vpi_control(vpiFinish, 0);
            arm(1, ++G.gen);
            return;
        }
        int    had_input = apply_inputs();
        double want = G.info->vtime / G.tick;
        uint64_t target = want <= (double)G.now ? G.now : (uint64_t)llround(want);

        G.stopping = 0;
        ++G.gen;
        if (target > G.now) {
            arm(target - G.now, G.gen);
            return;                 /* let GHDL run up to the target */
        }
        if (had_input) {
            arm(0, G.gen);          /* run the delta cycles of the input */
            return;
        }
        /* Nothing to do at this time: report back at once. */
    }
}

static PLI_INT32 wake_cb(p_cb_data cb)
{
    uintptr_t ud = (uintptr_t)cb->user_data;

    if ((unsigned)(ud >> 1) != G.gen || G.quit)
        return 0;                   /* stale: superseded by a later arm() */
    if (ud & 1) {
        /* Target time reached, but its VHDL events have not run yet: pause
         * after its last delta cycle, so outputs made exactly at the target
         * are reported now. */
        arm(0, G.gen);
        return 0;
    }
    pause_here();
    return 0;
}

/* An output net had an event: pause at the end of this time step. */
static PLI_INT32 change_cb(p_cb_data cb)
{
    (void)cb;
    if (!G.stopping && G.started && !G.quit) {
        G.stopping = 1;
        arm(0, ++G.gen);
    }
    return 0;
}

static void watch(struct port *p)
{
    static s_vpi_time  t = { .type = vpiSuppressTime };
    static s_vpi_value v = { .format = vpiSuppressVal };
    s_cb_data          cb;

    memset(&cb, 0, sizeof cb);
    cb.reason = cbValueChange;
    cb.cb_rtn = change_cb;
    cb.obj = p->h;
    cb.time = &t;
    cb.value = &v;
    vpi_register_cb(&cb);
}

static void add_port(struct ports *set, vpiHandle h, const char *name, int bits)
{
    set->p = realloc(set->p, (size_t)(set->n + 1) * sizeof *set->p);
    if (!set->p)
        fail("out of memory");
    struct port *p = &set->p[set->n++];
    memset(p, 0, sizeof *p);
    p->h = h;
    p->name = strdup(name);
    p->bits = bits;
    p->first = set->bits;
    set->bits += bits;
}

/* Classify one net of the top entity; returns an error text or NULL. */
static const char *take_net(vpiHandle h)
{
    const char *name = vpi_get_str(vpiName, h);
    int         dir = vpi_get(vpiDirection, h);
    int         bits = vpi_get(vpiSize, h);
    int         vector = vpi_get(vpiVector, h);
    static char why[512];

    dbg("ngghdl: net %s size %d vector %d dir %d\n", name, bits, vector, dir);
    if (dir != vpiInput && dir != vpiOutput && dir != vpiInout)
        return NULL;                /* internal signal (or buffer port) */
    if (dir == vpiInout)
        snprintf(why, sizeof why, "port '%s' is inout: only in and out "
                 "ports are supported", name);
    else if (bits < 1 || (!vector && bits != 1 && bits != 32))
        snprintf(why, sizeof why, "port '%s' has a type the glue cannot "
                 "carry (std_logic, bit, boolean, their vectors, integer)",
                 name);
    else if (dir == vpiInput && !vector && bits == 32)
        snprintf(why, sizeof why, "input port '%s' is an integer: GHDL 2.0 "
                 "cannot set integer signals through VPI; use "
                 "std_logic_vector", name);
    else {
        add_port(dir == vpiInput ? &G.in : &G.out, h, name, bits);
        return NULL;
    }
    return why;
}

static PLI_INT32 start_cb(p_cb_data cb)
{
    (void)cb;
    G.tick = pow(10.0, vpi_get(vpiTimePrecision, NULL));

    vpiHandle it = vpi_iterate(vpiModule, NULL);
    vpiHandle top = it ? vpi_scan(it) : NULL;
    if (!top)
        fail("GHDL has no top module");
    vpi_free_object(it);
    dbg("ngghdl: top %s, time unit %g s\n", vpi_get_str(vpiName, top), G.tick);

    /* GHDL 2.0: vpiPort yields nothing; ports are nets with a direction. */
    it = vpi_iterate(vpiNet, top);
    vpiHandle   h;
    const char *why = NULL;
    while (it && (h = vpi_scan(it)))
        if (!why)
            why = take_net(h);
    if (why)
        fail("%s", why);
    for (int i = 0; i < G.in.n; i++) {
        struct port *p = &G.in.p[i];
        p->in_str = xcalloc((size_t)p->bits + 1, 1);
        memset(p->in_str, 'U', (size_t)p->bits);
    }
    for (int i = 0; i < G.out.n; i++) {
        struct port *p = &G.out.p[i];
        p->out_str = xcalloc((size_t)p->bits + 1, 1);
        memset(p->out_str, '0', (size_t)p->bits);   /* d_cosim starts at 0 */
        for (int k = 0; k < G.n_lazy; k++)
            if (strcasecmp(G.lazy[k], p->name) == 0)
                p->lazy = 1;
        if (!p->lazy)
            watch(p);
    }
    for (int k = 0; k < G.n_lazy; k++) {
        int found = 0;
        for (int i = 0; i < G.out.n; i++)
            found |= strcasecmp(G.lazy[k], G.out.p[i].name) == 0;
        if (!found)
            fail("+lazy=%s: the design has no output port of that name", G.lazy[k]);
    }
    G.started = 1;
    pause_here();                   /* first hand-over: Cosim_setup returns */
    return 0;
}

static void vpi_startup(void)
{
    s_cb_data cb;
    memset(&cb, 0, sizeof cb);
    cb.reason = cbStartOfSimulation;
    cb.cb_rtn = start_cb;
    vpi_register_cb(&cb);
}

/* GHDL calls these in the library named by --vpi= (this very library). */
void (*vlog_startup_routines[])(void) = { vpi_startup, NULL };

/* Entry of GHDL's coroutine; when it returns, uc_link resumes ngspice. */
static void ghdl_entry(void)
{
    int rc = ghdl_main(G.argc, G.argv);
    G.finished = 1;
    if (!G.quit && G.started) {
        G.now = ghdl_now();
        fprintf(stderr, "ngghdl: VHDL simulation ended at t=%.9g s with status "
                "%d; outputs are frozen from now on\n", G.now * G.tick, rc);
        if (rc != 0 && getenv("NGGHDL_FATAL")) {
            fprintf(stderr, "ngghdl: error: VHDL simulation failed "
                    "(NGGHDL_FATAL is set): ending ngspice\n");
            exit(rc);
        }
    }
}

/* -------------------------------------------------------------- ngspice side */

static void resume_ghdl(void)
{
    swapcontext(&G.spice_uc, &G.ghdl_uc);
}

/* Read the outputs; report bits that differ from what ngspice last saw
 * (only when 'report' is set).  Returns the number of differing bits. */
static int scan_outputs(struct co_info *info, int report)
{
    s_vpi_value v = { .format = vpiBinStrVal };
    int         changed = 0;

    for (int i = 0; i < G.out.n; i++) {
        struct port *p = &G.out.p[i];
        vpi_get_value(p->h, &v);    /* safe: GHDL is parked in a callback */
        if (!v.value.str)
            continue;
        for (int k = 0; k < p->bits; k++) {
            char c = v.value.str[k];
            if (c == p->out_str[k])
                continue;
            changed++;
            if (!report)
                continue;
            p->out_str[k] = c;
            Digital_t d = { UNKNOWN, STRONG };
            switch (c) {
            case '0': d.state = ZERO; break;
            case '1': d.state = ONE; break;
            case 'L': d.state = ZERO; d.strength = RESISTIVE; break;
            case 'H': d.state = ONE; d.strength = RESISTIVE; break;
            case 'Z': d.strength = HI_IMPEDANCE; break;
            default: break;         /* U X W - */
            }
            G.n_out_events++;
            dbg("ngghdl: t=%.9g s out %s[%d]=%c\n", G.now * G.tick, p->name,
                k, c);
            info->out_fn(info, (unsigned)(p->first + k), &d);
        }
    }
    return changed;
}

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The start of d_cosim's instance in ngspice 46 (src/xspice/icm/digital/
 * d_cosim/cfunc.mod, struct instance and struct pend_in): our co_info, then
 * the queue of the inputs XSPICE has passed to it for this step. */
struct dcosim_input {
    double       when;
    unsigned int which;
    Digital_t    what;
};
struct dcosim_instance {
    struct co_info       info;
    int                  q_index;    /* last queued input, -1: none */
    unsigned int         q_length;
    struct dcosim_input *q;
};

/* The earliest time [s] of an input d_cosim holds due in (after, until], or
 * -1.  When d_cosim cuts its step back for a report (to the report's time +
 * delay/3) it drops the inputs it still holds, counting on XSPICE to pass
 * them again; but XSPICE does not pass again what it passed before the new
 * end of the step, so such an input never reaches the design.  Only under
 * d_cosim ("+delay="; wrsim's preflight calls step() without it). */
static double input_due(struct co_info *info, double after, double until)
{
    const struct dcosim_instance *ip = (const struct dcosim_instance *)info;
    double first = -1;

    if (!(G.delay > 0) || ip->q_index < 0 || (unsigned)ip->q_index >= ip->q_length)
        return -1;
    for (int i = 0; i <= ip->q_index; i++)
        if (ip->q[i].when > after && ip->q[i].when <= until && (first < 0 || ip->q[i].when < first))
            first = ip->q[i].when;
    return first;
}

static void step(struct co_info *info)
{
    double t0 = wall();
    double want = info->vtime;
    double start = (double)G.now * G.tick;
    /* A target before the last report: XSPICE went back, abandoning the
     * step in which this unit reported outputs (another unit cut that step
     * short after this one had run to its end), and their events with it.
     * GHDL cannot go back; every output is reported again at the end of
     * this step, and d_cosim passes on those that differ from what the
     * backed-up nodes hold.  Not so when d_cosim still holds the last
     * report (it cut its step back to the report's time): it sends that
     * report itself when XSPICE comes back, also to an earlier time, and a
     * second report in the same call would cancel those events. */
    int rewound = G.now > 0 && info->vtime < (double)(G.now - 1) * G.tick && !G.held;
    dbg("ngghdl: step to %.12g s at %.12g s%s\n", info->vtime, G.now * G.tick, rewound ? " (rewound)" : "");

    G.n_step++;
    /* GHDL pauses at the target, or early after an output event; an event
     * that left the outputs as they were is no reason to stop. */
    while (!G.finished) {
        resume_ghdl();
        if (G.finished || !G.stopping || scan_outputs(info, 0))
            break;
    }
    G.wall_in_step += wall() - t0;
    G.held = 0;
    if (G.finished)
        return;
    if (G.stopping)
        info->vtime = (double)G.now * G.tick;
    /* A report would lose an input d_cosim holds (input_due).  Lazy outputs
     * (all that changed when GHDL did not stop) then wait for the next
     * report, after the input; that is the case d_cosim's way of stepping
     * makes common: it advances to an input's time before passing it on, and
     * lazy outputs are reported at the end of that advance.  Other outputs
     * cannot wait: they are reported a little early instead (by less than
     * delay/3), so that d_cosim's cut falls before the input, which XSPICE
     * then passes again; that is impossible only when the step began less
     * than delay/3 before (an error: the input is lost if d_cosim cuts). */
    double extra = G.delay / 3, due = rewound ? -1 : input_due(info, start, info->vtime + extra);
    int    early = 0;
    if (due >= 0 && !G.stopping) {
        G.n_deferred += scan_outputs(info, 0) > 0;
        return;
    }
    if (due >= 0) {
        early = due - extra * 1.01 > start;
        if (early) {
            info->vtime = due - extra * 1.01;
            G.n_early++;
        } else {
            fprintf(stderr, "ngghdl: error: the report of an output at t=%.12g s can "
                    "make d_cosim drop an input due %g s later\n", info->vtime, due - info->vtime);
        }
    }
    for (int i = 0; rewound && i < G.out.n; i++)
        memset(G.out.p[i].out_str, '?', (size_t)G.out.p[i].bits);
    scan_outputs(info, 1);
    /* d_cosim cuts its step back when the report comes more than its delay
     * before the step's end, and then holds the report until XSPICE is back
     * (after an early report, that may be to before GHDL's time). */
    G.held = G.stopping && (want - info->vtime > G.delay || early);
}

static void in_fn(struct co_info *info, unsigned int bit, Digital_t *val)
{
    (void)info;
    if (bit >= (unsigned)G.in.bits)
        return;
    struct port *p = G.in.p;
    while (bit >= (unsigned)(p->first + p->bits))
        p++;
    char c = val->strength == HI_IMPEDANCE ? 'Z'
           : val->state == ZERO ? '0' : val->state == ONE ? '1' : 'X';
    int  k = (int)bit - p->first;
    if (p->in_str[k] != c) {
        p->in_str[k] = c;
        p->in_dirty = 1;
        G.n_in_events++;
    }
}

static void print_stats(void)
{
    static int done;
    if (done || !G.started || !getenv("NGGHDL_STATS"))
        return;
    done = 1;
    fprintf(stderr, "ngghdl stats: step=%lu wake=%lu in_events=%lu "
            "out_events=%lu deferred=%lu early=%lu ghdl_time=%.9g s "
            "wall_in_step=%.3f s\n", G.n_step, G.n_wake, G.n_in_events,
            G.n_out_events, G.n_deferred, G.n_early,
            G.now * G.tick, G.wall_in_step);
}

/* ngspice -b may exit without destroying the instance: print at exit too. */
__attribute__((destructor)) static void stats_at_exit(void) { print_stats(); }

static void cleanup(struct co_info *info)
{
    (void)info;
    print_stats();
    if (!G.finished) {
        G.quit = 1;
        resume_ghdl();              /* GHDL finishes and returns via uc_link */
    }
    munmap(G.stack, GHDL_STACK_SIZE + GUARD_SIZE);
    G.stack = NULL;
}

/* Add one GHDL argument, or take the glue's own "+lazy=NAME" or "+delay=SECONDS". */
static void push_arg(const char *a)
{
    if (strncmp(a, "+delay=", 7) == 0) {
        char *end;
        G.delay = strtod(a + 7, &end);
        if (*end || !(G.delay > 0))
            fail("+delay=%s: expected a time in seconds > 0", a + 7);
        return;
    }
    if (strncmp(a, "+lazy=", 6) == 0) {
        G.lazy = realloc(G.lazy, (size_t)(G.n_lazy + 1) * sizeof *G.lazy);
        if (!G.lazy)
            fail("out of memory");
        G.lazy[G.n_lazy++] = strdup(a + 6);
        return;
    }
    G.argv = realloc(G.argv, (size_t)(G.argc + 2) * sizeof *G.argv);
    if (!G.argv)
        fail("out of memory");
    G.argv[G.argc++] = strdup(a);
    G.argv[G.argc] = NULL;
}

/* "@FILE": GHDL arguments from FILE, one per line. */
static void push_args_file(const char *path)
{
    FILE   *f = fopen(path, "r");
    char   *line = NULL;
    size_t  cap = 0;
    ssize_t n;

    if (!f)
        fail("cannot open GHDL argument file '%s'", path);
    while ((n = getline(&line, &cap, f)) >= 0) {
        line[strcspn(line, "\r\n")] = 0;
        if (line[0] && line[0] != '#')
            push_arg(line);
    }
    free(line);
    fclose(f);
}

void Cosim_setup(struct co_info *info)
{
    static int used;
    Dl_info    self;
    char      *vpiarg;

    if (used++)
        fail("this copy of the design library already runs an instance: "
             "load it through ngghdl_loader.so (one copy per instance)");
    memset(&G, 0, sizeof G);
    G.info = info;
    G.verbose = getenv("NGGHDL_DEBUG") != NULL;

    /* GHDL runs VPI start-up routines only of libraries named by --vpi=:
     * name ourselves, so no separate .vpi file is needed. */
    if (!dladdr((void *)Cosim_setup, &self) || !self.dli_fname)
        fail("dladdr cannot find the design library's own path");
    if (asprintf(&vpiarg, "--vpi=%s", self.dli_fname) < 0)
        fail("out of memory");
    push_arg(info->sim_argc ? info->sim_argv[0] : "ngghdl");
    push_arg(vpiarg);
    free(vpiarg);
    for (unsigned i = 1; i < info->sim_argc; i++) {
        const char *a = info->sim_argv[i];
        if (a[0] == '@')
            push_args_file(a + 1);
        else
            push_arg(a);
    }

    /* GHDL's stack, with a PROT_NONE guard at its low end so that a VHDL
     * stack overflow faults instead of corrupting memory. */
    G.stack = mmap(NULL, GHDL_STACK_SIZE + GUARD_SIZE, PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (G.stack == MAP_FAILED)
        fail("cannot map a stack for GHDL");
    mprotect(G.stack, GUARD_SIZE, PROT_NONE);
    getcontext(&G.ghdl_uc);
    G.ghdl_uc.uc_stack.ss_sp = (char *)G.stack + GUARD_SIZE;
    G.ghdl_uc.uc_stack.ss_size = GHDL_STACK_SIZE;
    G.ghdl_uc.uc_link = &G.spice_uc;
    makecontext(&G.ghdl_uc, ghdl_entry, 0);
    resume_ghdl();                  /* elaborate; back when start_cb pauses */
    if (!G.started)
        fail("GHDL ended before the simulation started (see its messages "
             "above)");

    info->in_count = (unsigned)G.in.bits;
    info->out_count = (unsigned)G.out.bits;
    info->inout_count = 0;
    info->step = step;
    info->in_fn = in_fn;
    info->cleanup = cleanup;
    info->method = Normal;
    if (G.verbose || getenv("NGGHDL_PORTS")) {
        for (int i = 0; i < G.in.n; i++)
            fprintf(stderr, "ngghdl: in  %s %d %d\n", G.in.p[i].name,
                    G.in.p[i].bits, G.in.p[i].first);
        for (int i = 0; i < G.out.n; i++)
            fprintf(stderr, "ngghdl: out %s %d %d\n", G.out.p[i].name,
                    G.out.p[i].bits, G.out.p[i].first);
    }
}
