/* ngghdl_loader.c - d_cosim "simulation" library that gives every d_cosim
 * instance, and every run, a private copy of a GHDL design library built
 * with ngghdl_glue.c (wrsim mixed-signal co-simulation).
 *
 * Purpose
 *   The GHDL run-time keeps its state in globals and ghdl_main() runs once per
 *   loaded copy; GHDL also dlopen()s the design library itself for --vpi=, so
 *   d_cosim's dlclose() never unloads it.  Loaded directly, a design library
 *   serves one instance for one run: a second instance of the same design, or
 *   a second "run" in one ngspice session, would share (and break) the first
 *   one's GHDL.  This loader copies the library to $TMPDIR/ngghdl-XXXXXX.so,
 *   dlopen()s the copy with RTLD_LOCAL (the design is linked -Bsymbolic, so
 *   its GHDL run-time binds to itself and not to another copy) and unlinks
 *   the file once GHDL has elaborated.  Copies stay mapped until ngspice
 *   exits (about 1.3 MB each); they are never dlclose()d because GHDL holds
 *   its own reference and may have registered exit handlers.
 *
 * Build (what wrsim.ghdl.build() runs, once per build folder)
 *   gcc -O2 -fPIC -Wall -Wextra -shared ngghdl_loader.c -o ngghdl_loader.so \
 *       -I/usr/share/ngspice/scripts/src -ldl
 *
 * Netlist
 *   .model ecu d_cosim(simulation="ngghdl_loader.so" lib_args=["TOP.so"]
 *   + sim_args=["TOP" "@args.txt"] irreversible=1)
 *   lib_args[0] is the design library; sim_args go to the design unchanged.
 *   Each instance needs its own irreversible=N (N >= 1): with a shared
 *   value ngspice warns "Duplicate value 1 in cm_irreversible()" and steps
 *   only one of them.
 *
 * Environment
 *   TMPDIR  folder for the private copies (default /tmp).
 *   The design's own variables (NGGHDL_FATAL, ...) are described in
 *   ngghdl_glue.c.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "ngspice/cmtypes.h"
#include "ngspice/cosim.h"

/* What the loader keeps per instance, in info->handle (the glue does not use
 * that field). */
struct instance {
    void (*design_cleanup)(struct co_info *);
};

/* d_cosim would call a NULL step() after a failed setup: end ngspice with a
 * message instead, as GHDL does for its own elaboration errors. */
static void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
static void fail(const char *fmt, ...)
{
    va_list ap;
    fputs("ngghdl_loader: error: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(1);
}

/* The copy being elaborated: GHDL exits the process on elaboration errors,
 * so it is also removed at exit. */
static char pending[4096];

static void unlink_pending(void)
{
    if (pending[0])
        unlink(pending);
    pending[0] = 0;
}

/* Copy src to a new file made from dst_template ("...XXXXXX.so"). */
static void copy_file(const char *src, char *dst_template)
{
    int in = open(src, O_RDONLY);
    if (in < 0)
        fail("cannot open design library '%s': %s", src, strerror(errno));
    int out = mkstemps(dst_template, 3);
    if (out < 0)
        fail("cannot create '%s': %s", dst_template, strerror(errno));
    char    buf[1 << 16];
    ssize_t n;
    while ((n = read(in, buf, sizeof buf)) > 0)
        if (write(out, buf, (size_t)n) != n) {
            n = -1;
            break;
        }
    if (n < 0)
        fail("cannot copy '%s' to '%s': %s", src, dst_template,
             strerror(errno));
    close(in);
    fchmod(out, 0700);
    close(out);
}

static void loader_cleanup(struct co_info *info)
{
    struct instance *inst = info->handle;
    if (inst && inst->design_cleanup)
        inst->design_cleanup(info);
    free(inst);
    info->handle = NULL;
}

void Cosim_setup(struct co_info *info)
{
    const char *design = info->lib_argc ? info->lib_argv[0] : NULL;
    const char *tmp = getenv("TMPDIR");
    static int  registered;

    if (!design)
        fail("lib_args=[\"design.so\"] is missing on the d_cosim .model line");
    if (!registered++)
        atexit(unlink_pending);
    if ((size_t)snprintf(pending, sizeof pending, "%s/ngghdl-XXXXXX.so",
                         tmp && *tmp ? tmp : "/tmp") >= sizeof pending)
        fail("TMPDIR is too long");
    copy_file(design, pending);
    void *h = dlopen(pending, RTLD_NOW | RTLD_LOCAL);
    if (!h)
        fail("%s", dlerror());
    void (*setup)(struct co_info *) =
        (void (*)(struct co_info *))dlsym(h, "Cosim_setup");
    if (!setup)
        fail("'%s' has no Cosim_setup (not built with ngghdl_glue.c?)",
             design);
    setup(info);                    /* GHDL has dlopen()ed the copy by now */
    unlink_pending();

    struct instance *inst = calloc(1, sizeof *inst);
    if (!inst)
        fail("out of memory");
    inst->design_cleanup = info->cleanup;
    info->handle = inst;
    info->cleanup = loader_cleanup;
}
