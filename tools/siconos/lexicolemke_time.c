/* Times Siconos numerics' lcp_lexicolemke on a corpus of floebench LCP dumps.
 *
 * Input: the text written by dumps_to_text.py (one record per dump: a
 * header "<file> <n> <contacts>", the n entries of q, then M row by row).
 * Output (stdout): CSV with the columns of `floebench lcp DIR --time`:
 *
 *   file,n,contacts,pivots,status,accepted_attempt,residual,cpu_us,
 *   first_termination,first_pivots
 *
 * - pivots: Siconos' iteration count (iparam[SICONOS_IPARAM_ITER_DONE]);
 * - status: "Solved" when lcp_lexicolemke returned info = 0, else "Failed"
 *   (what Siconos reports; whether z is right is judged on the residual);
 * - residual: recomputed on the original data the way floebench does
 *   (src/lcp/mod.rs `residual`): w = M z + q by a compensated dot product
 *   (Ogita-Rump-Oishi Dot2, error-free products by fma), then
 *   ||min(z, w)||_2 / max(||q||_2, DBL_EPSILON), both norms scaled by their
 *   largest entry; infinity if anything is non-finite;
 * - cpu_us: thread CPU time per solve (CLOCK_THREAD_CPUTIME_ID), measured as
 *   floebench does (src/lcp/timing.rs): a batch repeats the solve until at
 *   least MIN_BATCH seconds have elapsed, the time per solve of a batch is
 *   its time over its count, and the figure is the median over REPEAT
 *   batches;
 * - first_termination: Solved (info 0), MaxPivots (iteration cap reached) or
 *   RayTermination (info 1 before the cap: no pivot row);
 * - first_pivots = pivots (a single attempt).
 *
 * The iteration cap is floebench's default, 50 (n + 1) pivots
 * (DEFAULT_PIVOTS_PER_DIM), instead of Siconos' default, so that both
 * solvers have the same budget. Run on one core: `taskset -c 0`.
 *
 * Usage: lexicolemke_time CORPUS.txt [REPEAT [MIN_BATCH_SECONDS]] > out.csv
 */
#define _GNU_SOURCE
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "LCP_Solvers.h"
#include "LinearComplementarityProblem.h"
#include "NumericsMatrix.h"
#include "SolverOptions.h"
#include "lcp_cst.h"

static double thread_cpu(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* sum_j a_j b_j + c, compensated (Dot2). */
static double dot2_plus(const double *a, const double *b, size_t n, double c) {
  double p = c, s = 0.0;
  for (size_t j = 0; j < n; ++j) {
    double h = a[j] * b[j];
    double r = fma(a[j], b[j], -h);
    double np = p + h;
    double bb = np - p;
    double t = (p - (np - bb)) + (h - bb);
    p = np;
    s += t + r;
  }
  return p + s;
}

/* ||v||_2 scaled by its largest magnitude s (given). */
static double scaled_norm(const double *v, size_t n, double s) {
  if (s == 0.0 || !isfinite(s)) return s;
  double acc = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double x = v[i] / s;
    acc += x * x;
  }
  return s * sqrt(acc);
}

/* floebench's residual of z on (M row-major, q); w and tmp: scratch of n. */
static double residual(const double *m, const double *q, const double *z, size_t n, double *w,
                       double *tmp) {
  double qs = 0.0;
  int finite = 1;
  for (size_t i = 0; i < n; ++i) {
    finite &= isfinite(q[i]);
    if (fabs(q[i]) > qs) qs = fabs(q[i]);
  }
  if (!finite) return INFINITY;
  double den = scaled_norm(q, n, qs);
  if (den < DBL_EPSILON) den = DBL_EPSILON;
  double s = 0.0;
  for (size_t i = 0; i < n; ++i) {
    w[i] = dot2_plus(m + i * n, z, n, q[i]);
    finite &= isfinite(z[i]) & isfinite(w[i]);
    tmp[i] = z[i] < w[i] ? z[i] : w[i];
    if (fabs(tmp[i]) > s) s = fabs(tmp[i]);
  }
  if (!finite) return INFINITY;
  double r = scaled_norm(tmp, n, s) / den;
  return isnan(r) ? INFINITY : r;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s CORPUS.txt [REPEAT [MIN_BATCH_SECONDS]]\n", argv[0]);
    return 2;
  }
  FILE *f = fopen(argv[1], "r");
  if (!f) {
    perror(argv[1]);
    return 1;
  }
  int repeats = argc > 2 ? atoi(argv[2]) : 5;
  if (repeats < 1) repeats = 1;
  double min_batch = argc > 3 ? atof(argv[3]) : 1e-3;
  if (!(min_batch >= 0.0)) min_batch = 1e-3;

  SolverOptions *opts = solver_options_create(SICONOS_LCP_LEMKE);
  fprintf(stderr, "Siconos lexicolemke defaults: max iter %d, tol %g\n",
          opts->iparam[SICONOS_IPARAM_MAX_ITER], opts->dparam[SICONOS_DPARAM_TOL]);
  NumericsMatrix *nm = NM_new();
  printf("file,n,contacts,pivots,status,accepted_attempt,residual,cpu_us,first_termination,"
         "first_pivots\n");
  char name[4096];
  size_t n;
  int contacts;
  double *samples = malloc((size_t)repeats * sizeof(double));
  while (fscanf(f, "%4095s %zu %d", name, &n, &contacts) == 3) {
    double *q = malloc(n * sizeof(double));
    double *m = malloc(n * n * sizeof(double));  /* row-major, for the residual */
    double *mc = malloc(n * n * sizeof(double)); /* column-major, for Siconos */
    double *z = calloc(n, sizeof(double));
    double *w = calloc(n, sizeof(double));
    double *w2 = malloc(n * sizeof(double));
    double *tmp = malloc(n * sizeof(double));
    for (size_t i = 0; i < n; ++i)
      if (fscanf(f, "%lf", &q[i]) != 1) goto bad;
    for (size_t i = 0; i < n * n; ++i)
      if (fscanf(f, "%lf", &m[i]) != 1) goto bad;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) mc[j * n + i] = m[i * n + j];
    nm->storageType = NM_DENSE;
    nm->size0 = (int)n;
    nm->size1 = (int)n;
    nm->matrix0 = mc;
    LinearComplementarityProblem lcp;
    memset(&lcp, 0, sizeof lcp);
    lcp.size = (int)n;
    lcp.M = nm;
    lcp.q = q;
    int cap = 50 * ((int)n + 1);
    opts->iparam[SICONOS_IPARAM_MAX_ITER] = cap;

    int info = -1;
    double t0 = thread_cpu();
    lcp_lexicolemke(&lcp, z, w, &info, opts);
    double first = thread_cpu() - t0;
    int iters = opts->iparam[SICONOS_IPARAM_ITER_DONE];
    double r = residual(m, q, z, n, w2, tmp);

    long batch = first > 0.0 ? (long)ceil(min_batch / first) : 1024;
    if (batch < 1) batch = 1;
    if (batch > (1L << 24)) batch = 1L << 24;
    int got = 0;
    while (got < repeats) {
      int dummy = 0;
      double t1 = thread_cpu();
      for (long k = 0; k < batch; ++k) {
        lcp_lexicolemke(&lcp, z, w, &dummy, opts);
        __asm__ volatile("" : : "r"(z) : "memory");
      }
      double dt = thread_cpu() - t1;
      if (dt < min_batch && batch < (1L << 24)) {
        batch *= 2;
        continue;
      }
      samples[got++] = dt / (double)batch * 1e6;
    }
    qsort(samples, (size_t)repeats, sizeof(double), cmp_double);
    double med = repeats % 2 ? samples[repeats / 2]
                             : 0.5 * (samples[repeats / 2 - 1] + samples[repeats / 2]);
    const char *term = info == 0 ? "Solved" : (iters >= cap ? "MaxPivots" : "RayTermination");
    printf("%s,%zu,%d,%d,%s,lexicolemke,%.17g,%.4f,%s,%d\n", name, n, contacts, iters,
           info == 0 ? "Solved" : "Failed", r, med, term, iters);
    fflush(stdout);
    nm->matrix0 = NULL;
    free(q), free(m), free(mc), free(z), free(w), free(w2), free(tmp);
    continue;
  bad:
    fprintf(stderr, "%s: truncated record\n", name);
    return 1;
  }
  free(samples);
  return 0;
}
