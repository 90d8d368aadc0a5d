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
    GSN_DELAUNAY_FAILED, /* CGAL threw */
    GSN_DELAUNAY_FLAT    /* the points span no volume */
};

/* Neighbours of each of the n points (n x 3, row-major) in CSR form, sorted
 * by index: offset (n + 1) and index, malloc'ed, the caller frees both.
 * Points of a lower-dimensional set get their lower-dimensional Delaunay
 * neighbours. Not thread-safe inside; call from one thread. */
int gsn_delaunay_neighbours(const double *points, int n, int **offset,
                            int **index);

/* The Delaunay tetrahedra of the n points (positively oriented, as CGAL
 * makes them): count, then tetrahedra (count x 4 point indices) and
 * neighbour (count x 4: the tetrahedron across the face opposite vertex k,
 * -1 on the hull), malloc'ed, the caller frees both. Not thread-safe
 * inside; call from one thread. */
int gsn_delaunay_tetrahedra(const double *points, int n, int *count,
                            int **tetrahedra, int **neighbour);

#ifdef __cplusplus
}
#endif
#endif
