/* The reference solver's integrator (wrsim.backend.reference_solver): a design's equations, generated as C by
 * CasADi into the same program (wr_eqs, wr_jac, wr_sites, wr_guards), integrated by SUNDIALS IDAS with event
 * location.
 *
 * Every condition of the equations that the states depend on (a relation, abs, min, max, sign, floor) is a mode:
 * within a mode the equations are smooth, and IDAS's root finding locates where the mode's argument leaves its
 * region, by more than a hysteresis band `eps`. There the mode changes, the algebraic unknowns are found again by
 * Newton with the states held (the states' derivatives follow from their rows) and IDAS restarts from that point.
 * The 'above guards are located the same way and recorded; they change nothing. Replayed digital levels change
 * only at the starts of the segments given in the input, where IDAS restarts too.
 *
 * Input (text, stdin): n nx np ns ng, the site kinds (0 a binary condition, 1 a floor), reltol abstol maxstep eps,
 * y0 (n), the segments (count, then per segment: start end levels[np]), the output times (count, times).
 * Output (stdout): "y t v..." per output time, "cross k t direction" per guard crossing, and the statistics
 * "steps", "events" (mode changes), "seconds" (the wall time of the integration alone), or one line "error ..."
 * and exit 1.
 *
 * SUNDIALS's prototypes are declared here (its runtime library libsundials_idas.so.5 holds IDAS, the serial vector
 * and the dense matrix and solver; SUNDIALS 6: sunrealtype double, sunindextype int64). */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef double sunrealtype;
typedef int64_t sunindextype;
typedef struct _generic_N_Vector *N_Vector;
typedef struct _generic_SUNMatrix *SUNMatrix;
typedef struct _generic_SUNLinearSolver *SUNLinearSolver;
typedef struct _SUNContext *SUNContext;
typedef int (*IDAResFn)(sunrealtype, N_Vector, N_Vector, N_Vector, void *);
typedef int (*IDARootFn)(sunrealtype, N_Vector, N_Vector, sunrealtype *, void *);
typedef int (*IDALsJacFn)(sunrealtype, sunrealtype, N_Vector, N_Vector, N_Vector, SUNMatrix, void *, N_Vector,
                          N_Vector, N_Vector);
typedef void (*IDAErrHandlerFn)(int, const char *, const char *, char *, void *);

#define IDA_NORMAL 1
#define IDA_ROOT_RETURN 2

int SUNContext_Create(void *comm, SUNContext *ctx);
N_Vector N_VNew_Serial(sunindextype length, SUNContext ctx);
sunrealtype *N_VGetArrayPointer(N_Vector v);
N_Vector N_VClone(N_Vector v);
void N_VDestroy(N_Vector v);
SUNMatrix SUNDenseMatrix(sunindextype m, sunindextype n, SUNContext ctx);
sunrealtype *SUNDenseMatrix_Column(SUNMatrix a, sunindextype j);
SUNLinearSolver SUNLinSol_Dense(N_Vector y, SUNMatrix a, SUNContext ctx);
void *IDACreate(SUNContext ctx);
int IDAInit(void *mem, IDAResFn res, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDAReInit(void *mem, sunrealtype t0, N_Vector y0, N_Vector yp0);
int IDASStolerances(void *mem, sunrealtype reltol, sunrealtype abstol);
int IDASetUserData(void *mem, void *data);
int IDASetMaxStep(void *mem, sunrealtype hmax);
int IDASetMaxNumSteps(void *mem, long steps);
int IDASetSuppressAlg(void *mem, int suppress);
int IDASetId(void *mem, N_Vector id);
int IDASetStopTime(void *mem, sunrealtype tstop);
int IDASetErrHandlerFn(void *mem, IDAErrHandlerFn handler, void *data);
int IDASetNoInactiveRootWarn(void *mem);
int IDARootInit(void *mem, int nroots, IDARootFn g);
int IDASetLinearSolver(void *mem, SUNLinearSolver ls, SUNMatrix a);
int IDASetJacFn(void *mem, IDALsJacFn jac);
int IDASolve(void *mem, sunrealtype tout, sunrealtype *tret, N_Vector y, N_Vector yp, int task);
int IDAGetRootInfo(void *mem, int *found);
int IDAGetNumSteps(void *mem, long *steps);
int IDAGetLastStep(void *mem, sunrealtype *hlast);
int IDASetInitStep(void *mem, sunrealtype hin);

static int n, nx, np, ns, ng, nroots;

typedef long long int casadi_int;
typedef int (*casadi_fn)(const double **arg, double **res, casadi_int *iw, double *w, int mem);
#define GENERATED(name)                                                                                              \
  int name(const double **arg, double **res, casadi_int *iw, double *w, int mem);                                    \
  int name##_work(casadi_int *sz_arg, casadi_int *sz_res, casadi_int *sz_iw, casadi_int *sz_w);
GENERATED(wr_eqs)
GENERATED(wr_jac)
GENERATED(wr_sites)
GENERATED(wr_guards)

static int *kind;                        /* per site: 0 binary (mode 0/1), 1 floor (mode an integer) */
static double *mode, *level, *site, *eqs, *jac, *work, eps;
static casadi_int *iwork;
static char said[512];                   /* IDAS's last message */
static long steps;                       /* IDAS's steps before the last restart (IDAReInit counts anew) */

static void call(casadi_fn f, double t, const double *y, double *out) {
  const double *arg[4] = {&t, y, level, mode};
  double *res[1] = {out};
  f(arg, res, iwork, work, 0);
}

static int residual(sunrealtype t, N_Vector yy, N_Vector yp, N_Vector rr, void *data) {
  double *y = N_VGetArrayPointer(yy), *d = N_VGetArrayPointer(yp), *r = N_VGetArrayPointer(rr);
  (void)data;
  call(wr_eqs, t, y, r);
  for (int i = 0; i < nx; i++) r[i] = d[i] - r[i]; /* x' = ode; the rest: alg = 0 */
  return 0;
}

static int jacobian(sunrealtype t, sunrealtype cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix a, void *data,
                    N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)yp, (void)rr, (void)data, (void)t1, (void)t2, (void)t3;
  call(wr_jac, t, N_VGetArrayPointer(yy), jac); /* dense, column-major d[ode; alg]/dy */
  for (int j = 0; j < n; j++) {
    double *col = SUNDenseMatrix_Column(a, j), *src = jac + (size_t)j * n;
    for (int i = 0; i < n; i++) col[i] = i < nx ? -src[i] + (i == j ? cj : 0.0) : src[i];
  }
  return 0;
}

/* Root functions: a binary site leaves its region when its argument passes -eps (mode 1: argument >= 0) or +eps
 * (mode 0); a floor site when its argument leaves [mode - eps, mode + 1 + eps]; a guard when it crosses zero. */
static int roots(sunrealtype t, N_Vector yy, N_Vector yp, sunrealtype *g, void *data) {
  (void)yp, (void)data;
  double *y = N_VGetArrayPointer(yy);
  call(wr_sites, t, y, site);
  int k = 0;
  for (int s = 0; s < ns; s++) {
    if (kind[s]) {
      g[k++] = site[s] - (mode[s] - eps);
      g[k++] = site[s] - (mode[s] + 1.0 + eps);
    } else
      g[k++] = site[s] + (mode[s] > 0.5 ? eps : -eps);
  }
  call(wr_guards, t, y, g + k);
  return 0;
}

/* Modes from the sites' arguments at (t, y): a mode changes only when its argument is beyond the band (`fresh`: at
 * the start, every mode from the sign); repeated while a change moves another site (nested conditions). */
static void settle(double t, const double *y, int fresh) {
  for (int pass = 0; pass < 20; pass++) {
    int changed = 0;
    call(wr_sites, t, y, site);
    for (int s = 0; s < ns; s++) {
      double m = mode[s], a = site[s];
      if (kind[s]) {
        if (fresh || a < m - eps || a > m + 1.0 + eps) m = floor(a);
      } else if (fresh)
        m = a >= 0.0;
      else if (m > 0.5 && a < -eps)
        m = 0.0;
      else if (m < 0.5 && a > eps)
        m = 1.0;
      if (m != mode[s]) mode[s] = m, changed = 1;
    }
    fresh = 0;
    if (!changed) return;
  }
}

static void keep_message(int code, const char *module, const char *function, char *msg, void *data) {
  (void)code, (void)module, (void)data;
  snprintf(said, sizeof said, "%s: %s", function, msg);
}

static void *checked(void *p) {
  if (!p) {
    printf("error out of memory\n");
    exit(1);
  }
  return p;
}

static int fail(const char *what, double t) {
  printf("error %s at t = %.9g s%s%s\n", what, t, said[0] ? ": " : "", said);
  return 1;
}

/* The algebraic unknowns consistent with the states at t (Newton on the algebraic rows, the Jacobian at every
 * iterate, LU with partial pivoting) and the states' derivatives from their rows: 0, or -1 where Newton does not
 * converge in 50 iterations (y and yp unchanged then). */
static double *lu, *rhs, *znew;
static int consistent(double t, double *y, double *yp) {
  int na = n - nx;
  memcpy(znew, y, sizeof(double) * n);
  for (int it = 0; it < 50; it++) {
    call(wr_eqs, t, znew, eqs);
    double worst = 0.0;
    for (int i = 0; i < na; i++) rhs[i] = -eqs[nx + i], worst = fmax(worst, fabs(eqs[nx + i]));
    if (!isfinite(worst)) return -1;
    call(wr_jac, t, znew, jac);
    for (int j = 0; j < na; j++)
      for (int i = 0; i < na; i++) lu[(size_t)j * na + i] = jac[(size_t)(nx + j) * n + nx + i];
    for (int k = 0; k < na; k++) { /* column-major LU, the pivot row swapped into k, applied to rhs as well */
      int piv = k;
      for (int i = k + 1; i < na; i++)
        if (fabs(lu[(size_t)k * na + i]) > fabs(lu[(size_t)k * na + piv])) piv = i;
      if (lu[(size_t)k * na + piv] == 0.0) return -1;
      if (piv != k) {
        for (int j = 0; j < na; j++) {
          double w = lu[(size_t)j * na + k];
          lu[(size_t)j * na + k] = lu[(size_t)j * na + piv], lu[(size_t)j * na + piv] = w;
        }
        double w = rhs[k];
        rhs[k] = rhs[piv], rhs[piv] = w;
      }
      for (int i = k + 1; i < na; i++) {
        double f = lu[(size_t)k * na + i] / lu[(size_t)k * na + k];
        for (int j = k + 1; j < na; j++) lu[(size_t)j * na + i] -= f * lu[(size_t)j * na + k];
        rhs[i] -= f * rhs[k];
      }
    }
    double step = 0.0;
    for (int k = na - 1; k >= 0; k--) {
      double v = rhs[k];
      for (int j = k + 1; j < na; j++) v -= lu[(size_t)j * na + k] * rhs[j];
      rhs[k] = v / lu[(size_t)k * na + k];
      step = fmax(step, fabs(rhs[k]) / (1e-3 * fabs(znew[nx + k]) + 1e-9));
    }
    for (int i = 0; i < na; i++) znew[nx + i] += rhs[i];
    if (step <= 1.0 && worst <= 1e-6) break; /* the step within 1e-3 of each unknown (+1e-9), the rows within 1e-6 */
    if (it == 49) return -1;
  }
  memcpy(y, znew, sizeof(double) * n);
  call(wr_eqs, t, y, eqs);
  for (int i = 0; i < n; i++) yp[i] = i < nx ? eqs[i] : 0.0;
  return 0;
}

/* Restart at t after a mode change or a segment start, from consistent algebraic unknowns and derivatives where
 * Newton finds them, else from the values before (IDAS's first step, of order 1 and as short as its error test
 * asks, corrects them). IDACalcIC's line search fails at some of these points. The first step is the one IDAS had
 * reached (`keep`), else IDAS's own estimate; the point is kept for `retry`. */
static double *kept_y, *kept_yp, *kept_mode, kept_t, kept_h;
static int restart(void *mem, double t, N_Vector y, N_Vector yp, int keep) {
  long since = 0;
  IDAGetNumSteps(mem, &since);
  steps += since;
  consistent(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp));
  double h = 0.0;
  if (keep && since > 0) IDAGetLastStep(mem, &h);
  kept_t = t, kept_h = h;
  memcpy(kept_y, N_VGetArrayPointer(y), sizeof(double) * n);
  memcpy(kept_yp, N_VGetArrayPointer(yp), sizeof(double) * n);
  memcpy(kept_mode, mode, sizeof(double) * ns);
  if (IDAReInit(mem, t, y, yp) != 0) return fail("IDAReInit failed", t);
  IDASetInitStep(mem, h);
  return 0;
}

/* After IDAS failed: when it had not taken a step since a restart with the step it had reached (after a mode change
 * the states may move faster than that step allows, and ten cuts by 4 do not reach their scale), the same restart
 * again with IDAS's own first step (1); else 0. */
static int retry(void *mem, double *t, N_Vector y, N_Vector yp) {
  long since = 0;
  IDAGetNumSteps(mem, &since);
  if (since > 0 || kept_h == 0.0) return 0;
  memcpy(N_VGetArrayPointer(y), kept_y, sizeof(double) * n);
  memcpy(N_VGetArrayPointer(yp), kept_yp, sizeof(double) * n);
  memcpy(mode, kept_mode, sizeof(double) * ns);
  *t = kept_t, kept_h = 0.0, said[0] = 0;
  return IDAReInit(mem, *t, y, yp) == 0 && IDASetInitStep(mem, 0.0) == 0;
}

int main(void) {
  double reltol, abstol, maxstep;
  if (scanf("%d %d %d %d %d", &n, &nx, &np, &ns, &ng) != 5) return printf("error bad input\n"), 1;
  kind = checked(calloc(ns + 1, sizeof *kind));
  for (int s = 0; s < ns; s++) scanf("%d", &kind[s]);
  scanf("%lf %lf %lf %lf", &reltol, &abstol, &maxstep, &eps);
  nroots = ng;
  for (int s = 0; s < ns; s++) nroots += kind[s] ? 2 : 1;

  casadi_int sz_arg, sz_res, sz_iw = 0, sz_w = 0, a, b, iw, w;
  int (*works[4])(casadi_int *, casadi_int *, casadi_int *, casadi_int *) = {wr_eqs_work, wr_jac_work,
                                                                            wr_sites_work, wr_guards_work};
  for (int f = 0; f < 4; f++) {
    works[f](&a, &b, &iw, &w);
    sz_iw = iw > sz_iw ? iw : sz_iw, sz_w = w > sz_w ? w : sz_w;
  }
  (void)sz_arg, (void)sz_res;
  iwork = checked(calloc(sz_iw + 1, sizeof *iwork));
  work = checked(calloc(sz_w + 1, sizeof *work));
  mode = checked(calloc(ns + 1, sizeof *mode));
  level = checked(calloc(np + 1, sizeof *level));
  site = checked(calloc(ns + 1, sizeof *site));
  jac = checked(calloc((size_t)n * n + 1, sizeof *jac));
  lu = checked(calloc((size_t)n * n + 1, sizeof *lu));
  rhs = checked(calloc(n + 1, sizeof *rhs));
  znew = checked(calloc(n + 1, sizeof *znew));
  eqs = checked(calloc(n + 1, sizeof *eqs));
  kept_y = checked(calloc(n + 1, sizeof *kept_y));
  kept_yp = checked(calloc(n + 1, sizeof *kept_yp));
  kept_mode = checked(calloc(ns + 1, sizeof *kept_mode));
  int *found = checked(calloc(nroots + 1, sizeof *found));

  SUNContext ctx;
  SUNContext_Create(NULL, &ctx);
  N_Vector y = checked(N_VNew_Serial(n, ctx)), yp = checked(N_VNew_Serial(n, ctx)), id = N_VNew_Serial(n, ctx);
  double *yv = N_VGetArrayPointer(y), *ypv = N_VGetArrayPointer(yp), *idv = N_VGetArrayPointer(id);
  for (int i = 0; i < n; i++) scanf("%lf", &yv[i]), ypv[i] = 0.0, idv[i] = i < nx;
  int nseg, nout;
  scanf("%d", &nseg);
  double *seg = checked(calloc((size_t)nseg * (2 + np) + 1, sizeof *seg));
  for (int k = 0; k < nseg * (2 + np); k++) scanf("%lf", &seg[k]);
  scanf("%d", &nout);
  double *out = checked(calloc(nout + 1, sizeof *out));
  for (int k = 0; k < nout; k++) scanf("%lf", &out[k]);

  void *mem = checked(IDACreate(ctx));
  SUNMatrix mat = checked(SUNDenseMatrix(n, n, ctx));
  SUNLinearSolver ls = checked(SUNLinSol_Dense(y, mat, ctx));
  IDAInit(mem, residual, seg[0], y, yp);
  IDASStolerances(mem, reltol, abstol);
  IDASetLinearSolver(mem, ls, mat);
  IDASetJacFn(mem, jacobian);
  IDASetId(mem, id);
  IDASetSuppressAlg(mem, 1); /* the error test on the differential states, as ngspice's on its reactive elements */
  IDASetMaxStep(mem, maxstep);
  IDASetMaxNumSteps(mem, 10000000L);
  IDASetErrHandlerFn(mem, keep_message, NULL);
  if (nroots) IDARootInit(mem, nroots, roots), IDASetNoInactiveRootWarn(mem);

  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  long events = 0, burst = 0;
  double last_event = -1.0;
  int next_out = 0;
  for (int k = 0; k < nseg; k++) {
    double start = seg[k * (2 + np)], end = seg[k * (2 + np) + 1], t = start;
    memcpy(level, &seg[k * (2 + np) + 2], sizeof(double) * np);
    settle(start, yv, k == 0);
    IDASetStopTime(mem, end);
    if (restart(mem, start, y, yp, k > 0)) return 1;
    while (t < end) {
      double tout = next_out < nout && out[next_out] <= end ? out[next_out] : end;
      int rc = IDASolve(mem, tout, &t, y, yp, IDA_NORMAL);
      if (rc < 0 && retry(mem, &t, y, yp)) continue;
      if (rc < 0) return fail("IDAS stopped", t);
      if (rc == IDA_ROOT_RETURN) {
        IDAGetRootInfo(mem, found);
        int r = 0, changed = 0;
        for (int s = 0; s < ns; s++) {
          if (kind[s]) {
            if (found[r]) mode[s] -= 1.0, changed = 1;
            if (found[r + 1]) mode[s] += 1.0, changed = 1;
            r += 2;
          } else if (found[r++])
            mode[s] = 1.0 - mode[s], changed = 1;
        }
        for (int j = 0; j < ng; j++)
          if (found[r + j]) printf("cross %d %.17g %d\n", j, t, found[r + j]);
        if (changed) { /* IDAS's history belongs to the old modes: a restart from a consistent point */
          events++;
          burst = t - last_event < 1e-9 ? burst + 1 : 0;
          last_event = t;
          if (burst > 1000) return fail("more than 1000 mode changes within 1 ns (a mode chattering)", t);
          settle(t, yv, 0);
          if (restart(mem, t, y, yp, 1)) return 1;
        }
      }
      while (next_out < nout && out[next_out] <= t) {
        printf("y %.17g", out[next_out]);
        for (int i = 0; i < n; i++) printf(" %.17g", yv[i]);
        printf("\n");
        next_out++;
      }
    }
  }
  clock_gettime(CLOCK_MONOTONIC, &t1);
  long since = 0;
  IDAGetNumSteps(mem, &since);
  printf("steps %ld\nevents %ld\nseconds %.9f\n", steps + since, events,
         (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
  return 0;
}
