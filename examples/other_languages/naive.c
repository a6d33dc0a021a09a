/* The textbook quadratic (rayverify's built-in `naive`), written as code that
 * runs outside rayverify: a stand-in for a GPU kernel. One source, three builds:
 *
 *   cc -O2 -ffp-contract=off -DNAIVE_FLOAT naive.c -lm -o naive_strict
 *       a program: reads batches of cases as CSV (rayverify corpus export
 *       --format csv, or `hunt --command --format csv` on stdin) and writes
 *       one results file per batch on stdout;
 *   cc -O2 -ffast-math -ffp-contract=fast -DNAIVE_FLOAT naive.c -lm -o naive_fast
 *       the same program as a GPU compiler would build it (reassociation,
 *       reciprocals, contraction into FMA where the target has it);
 *   cc -O2 -ffp-contract=off -shared -fPIC -DNAIVE_PLUGIN naive.c -o libnaive.so
 *       the same formula as a rayverify plugin (rayverify_plugin.h), whose
 *       audit the results of naive_strict must reproduce exactly.
 *
 *   f = o - c, a = d.d, b = 2 d.f, C = f.f - r^2, D = b^2 - 4aC
 *   D < 0: miss; D = 0: tangent t = -b/2a; D > 0: t = (-b -+ sqrt D)/2a
 * Without -DNAIVE_FLOAT the program computes in double.
 * Contract: query=line_roots,reports_tangent=yes (both roots of the line). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFINE_NAIVE(T, SQRT, NAME)                                                               \
    static inline int NAME(const T o[3], const T d[3], const T c[3], T r, T roots[2]) {                  \
        const T f[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};                                   \
        const T a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];                                      \
        const T b = (T)2 * (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]);                             \
        const T C = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) - r * r;                            \
        const T D = b * b - (T)4 * a * C;                                                         \
        if (D < 0) return 0;                                                                      \
        if (D == 0) {                                                                             \
            roots[0] = roots[1] = -b / ((T)2 * a);                                                \
            return 1;                                                                             \
        }                                                                                         \
        const T s = SQRT(D);                                                                      \
        roots[0] = (-b - s) / ((T)2 * a);                                                         \
        roots[1] = (-b + s) / ((T)2 * a);                                                         \
        return 2;                                                                                 \
    }

DEFINE_NAIVE(float, sqrtf, naive_float)
DEFINE_NAIVE(double, sqrt, naive_double)

#ifdef NAIVE_PLUGIN
#include "rayverify_plugin.h"

const rayverify_plugin_info* rayverify_plugin_describe(void) {
    static const rayverify_plugin_info info = {RAYVERIFY_PLUGIN_ABI_VERSION, "c_naive", "examples/other_languages/naive.c",
                                               "t = (-b -+ sqrt(b^2 - 4aC)) / 2a", RAYVERIFY_LINE_ROOTS, 0, 1, 0,
                                               "D == 0"};
    return &info;
}

int rayverify_plugin_intersect_double(const double o[3], const double d[3], const double c[3], double r, double tmin,
                                      double tmax, double roots[2]) {
    (void)tmin;
    (void)tmax;
    return naive_double(o, d, c, r, roots);
}

int rayverify_plugin_intersect_float(const float o[3], const float d[3], const float c[3], float r, float tmin,
                                     float tmax, float roots[2]) {
    (void)tmin;
    (void)tmax;
    return naive_float(o, d, c, r, roots);
}

#else

#ifdef NAIVE_FLOAT
typedef float real;
#define PRECISION "float"
#define READ strtof
#define INTERSECT naive_float
#else
typedef double real;
#define PRECISION "double"
#define READ strtod
#define INTERSECT naive_double
#endif

static void fail(const char* why) {
    fprintf(stderr, "naive: %s\n", why);
    exit(2);
}

/* The value after "key=" in the header line, copied into out. */
static int header_field(const char* line, const char* key, char* out, size_t size) {
    const char* at = strstr(line, key);
    if (!at) return 0;
    at += strlen(key);
    size_t n = strcspn(at, " \r\n");
    if (n >= size) return 0;
    memcpy(out, at, n);
    out[n] = '\0';
    return 1;
}

int main(void) {
    static char line[8192];
    const char* precision = PRECISION;
    /* One batch per header line, until the end of the input. */
    while (fgets(line, sizeof line, stdin)) {
        if (line[0] == '\n') continue;
        char stated[16], fingerprint[32], count_text[32];
        if (strncmp(line, "# rayverify cases v1 ", 21) != 0 || !header_field(line, "precision=", stated, sizeof stated) ||
            !header_field(line, "fingerprint=", fingerprint, sizeof fingerprint) ||
            !header_field(line, "cases=", count_text, sizeof count_text))
            fail("expected a '# rayverify cases v1 ...' header line");
        if (strcmp(stated, precision) != 0) fail("the cases are not in this build's precision");
        const long cases = strtol(count_text, NULL, 10);
        if (!fgets(line, sizeof line, stdin)) fail("no column header");
        printf("# rayverify results v1 precision=%s fingerprint=%s\nid,count,t0,t1\n", precision, fingerprint);
        for (long k = 0; k < cases; ++k) {
            if (!fgets(line, sizeof line, stdin)) fail("fewer cases than the header says");
            /* id,family,ox,oy,oz,dx,dy,dz,cx,cy,cz,r,tmin,tmax */
            char* cell[14];
            int n = 0;
            for (char* p = line; n < 14; ++n) {
                cell[n] = p;
                /* A quoted id (a scene ray's "px3,7/...") holds commas; it is copied quoted. */
                if (*p == '"' && !(p = strchr(p + 1, '"'))) fail("an unclosed quote");
                p = strchr(p, ',');
                if (!p) break;
                *p++ = '\0';
            }
            if (n < 11) fail("a case line with too few cells");
            real v[10];
            for (int i = 0; i < 10; ++i) v[i] = READ(cell[2 + i], NULL);
            real roots[2] = {0, 0};
            const int count = INTERSECT(v, v + 3, v + 6, v[9], roots);
            /* C99 hex floats: exact in either precision. */
            printf("%s,%d,%a,%a\n", cell[0], count, (double)roots[0], (double)roots[1]);
        }
        fflush(stdout);
    }
    return 0;
}

#endif
