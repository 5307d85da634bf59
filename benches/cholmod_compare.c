/* CHOLMOD on the matrices `cargo bench --bench cholesky` writes
 * (target/cholesky/box-N.mtx): analysis (fill-reducing ordering and symbolic
 * factorisation) and supernodal numeric factorisation, timed separately,
 * median of 3 factorisations. Measurement only: not part of the build.
 *
 * CHOLMOD's default ordering strategy is used (it tries AMD and METIS and
 * keeps the order with less fill), then METIS alone.
 *
 * Debian / Ubuntu:
 *   apt-get install libsuitesparse-dev
 *   cc -O2 benches/cholmod_compare.c -I/usr/include/suitesparse -lcholmod -o target/cholmod_compare
 *   OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 target/cholmod_compare target/cholesky/box-16.mtx target/cholesky/box-21.mtx
 */
#include <cholmod.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int compare(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void run(cholmod_sparse *A, const char *label, int metis_only, cholmod_common *c) {
    c->supernodal = CHOLMOD_SUPERNODAL;
    if (metis_only) {
        c->nmethods = 1;
        c->method[0].ordering = CHOLMOD_METIS;
        c->postorder = 1;
    } else {
        c->nmethods = 0;
    }
    double start = now();
    cholmod_factor *L = cholmod_analyze(A, c);
    double analysis = now() - start;
    double times[3];
    for (int i = 0; i < 3; i++) {
        start = now();
        cholmod_factorize(A, L, c);
        times[i] = now() - start;
        if (c->status != CHOLMOD_OK) {
            fprintf(stderr, "factorisation failed (%d)\n", c->status);
            exit(1);
        }
    }
    qsort(times, 3, sizeof(double), compare);
    printf("  %-22s analysis %8.3f s  factorisation %8.3f s  nnz(L) %.0f  (ordering %d)\n", label,
           analysis, times[1], c->lnz, c->selected >= 0 ? c->method[c->selected].ordering : -1);
    cholmod_free_factor(&L, c);
}

int main(int argc, char **argv) {
    cholmod_common c;
    cholmod_start(&c);
    for (int i = 1; i < argc; i++) {
        FILE *f = fopen(argv[i], "r");
        if (!f) {
            perror(argv[i]);
            return 2;
        }
        cholmod_sparse *A = cholmod_read_sparse(f, &c);
        fclose(f);
        if (!A) {
            fprintf(stderr, "%s: not a sparse Matrix Market matrix\n", argv[i]);
            return 2;
        }
        printf("%s: %zu unknowns, %zu stored non-zeros\n", argv[i], A->nrow, cholmod_nnz(A, &c));
        run(A, "default (AMD or METIS)", 0, &c);
        run(A, "METIS", 1, &c);
        cholmod_free_sparse(&A, &c);
    }
    cholmod_finish(&c);
    return 0;
}
