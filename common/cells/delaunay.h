/* Delaunay neighbours by CGAL (delaunay.cpp, behind this C interface). */
#ifndef GEOSCNI_CELLS_DELAUNAY_H
#define GEOSCNI_CELLS_DELAUNAY_H

#ifdef __cplusplus
extern "C" {
#endif

enum gsn_delaunay_status {
    GSN_DELAUNAY_OK = 0,
    GSN_DELAUNAY_DUPLICATES, /* CGAL merged coincident points */
    GSN_DELAUNAY_MEMORY,
    GSN_DELAUNAY_FAILED /* CGAL threw */
};

/* Neighbours of each of the n points (n x 3, row-major) in CSR form, sorted
 * by index: offset (n + 1) and index, malloc'ed, the caller frees both.
 * Points of a lower-dimensional set get their lower-dimensional Delaunay
 * neighbours. Not thread-safe inside; call from one thread. */
int gsn_delaunay_neighbours(const double *points, int n, int **offset,
                            int **index);

#ifdef __cplusplus
}
#endif
#endif
