/* Convex polyhedra clipped by planes (see polyhedron.h). */
#include "polyhedron.h"

#include <math.h>
#include <string.h>

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

void gsn_poly_init_box(struct gsn_poly *p, const double lo[3],
                       const double hi[3], const int label[6])
{
    /* vertex k has x = hi if bit 0, y = hi if bit 1, z = hi if bit 2 */
    for (int k = 0; k < 8; ++k) {
        p->vertex[3 * k + 0] = (k & 1) ? hi[0] : lo[0];
        p->vertex[3 * k + 1] = (k & 2) ? hi[1] : lo[1];
        p->vertex[3 * k + 2] = (k & 4) ? hi[2] : lo[2];
    }
    p->vertex_count = 8;
    /* counter-clockwise seen from outside */
    static const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    p->face_count = 6;
    for (int f = 0; f < 6; ++f) {
        p->face_label[f] = label[f];
        p->face_start[f] = 4 * f;
        for (int k = 0; k < 4; ++k)
            p->entry[4 * f + k] = faces[f][k];
        int axis = f / 2;
        double *plane = &p->face_plane[4 * f];
        plane[0] = plane[1] = plane[2] = 0.0;
        plane[axis] = (f % 2) ? 1.0 : -1.0;
        plane[3] = (f % 2) ? hi[axis] : -lo[axis];
    }
    p->face_start[6] = 24;
}

int gsn_poly_init_tetrahedron(struct gsn_poly *p, const double *vertices,
                              const int label[4])
{
    const double(*v)[3] = (const double(*)[3])vertices;
    double e1[3], e2[3], e3[3], c[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = v[1][k] - v[0][k];
        e2[k] = v[2][k] - v[0][k];
        e3[k] = v[3][k] - v[0][k];
    }
    cross3(e1, e2, c);
    double det = dot3(c, e3);
    if (det == 0.0)
        return 0;
    /* orient so that 0,1,2 is clockwise seen from vertex 3 (outside) */
    int order[4] = {0, 1, 2, 3};
    if (det < 0.0) {
        order[1] = 2;
        order[2] = 1;
    }
    for (int k = 0; k < 4; ++k)
        memcpy(&p->vertex[3 * k], v[order[k]], sizeof(double[3]));
    p->vertex_count = 4;
    /* faces opposite local vertex 3, 2, 1, 0, outward orientation */
    static const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    static const int opposite[4] = {3, 2, 1, 0};
    p->face_count = 4;
    for (int f = 0; f < 4; ++f) {
        p->face_start[f] = 3 * f;
        for (int k = 0; k < 3; ++k)
            p->entry[3 * f + k] = faces[f][k];
        p->face_label[f] = label[order[opposite[f]]];
        double a[3], b[3], n[3];
        const double *x0 = &p->vertex[3 * faces[f][0]];
        const double *x1 = &p->vertex[3 * faces[f][1]];
        const double *x2 = &p->vertex[3 * faces[f][2]];
        for (int k = 0; k < 3; ++k) {
            a[k] = x1[k] - x0[k];
            b[k] = x2[k] - x0[k];
        }
        cross3(a, b, n);
        double length = sqrt(dot3(n, n));
        double *plane = &p->face_plane[4 * f];
        for (int k = 0; k < 3; ++k)
            plane[k] = n[k] / length;
        plane[3] = (dot3(plane, x0) + dot3(plane, x1) + dot3(plane, x2)) / 3.0;
    }
    p->face_start[4] = 12;
    return 1;
}

void gsn_poly_copy(struct gsn_poly *restrict to,
                   const struct gsn_poly *restrict from)
{
    to->vertex_count = from->vertex_count;
    to->face_count = from->face_count;
    int entries = from->face_start[from->face_count];
    memcpy(to->vertex, from->vertex,
           sizeof(double) * 3 * (size_t)from->vertex_count);
    memcpy(to->face_label, from->face_label,
           sizeof(int) * (size_t)from->face_count);
    memcpy(to->face_plane, from->face_plane,
           sizeof(double) * 4 * (size_t)from->face_count);
    memcpy(to->face_start, from->face_start,
           sizeof(int) * (size_t)(from->face_count + 1));
    memcpy(to->entry, from->entry, sizeof(int) * (size_t)entries);
}

/* The vertex of out that splits edge (a, b) of p, created once per edge. */
static int clip_edge_vertex(const struct gsn_poly *p,
                            struct gsn_poly_scratch *s, int a, int b,
                            int *edge_a, int *edge_b, int *edge_vertex,
                            int *edge_count)
{
    if (a > b) {
        int t = a;
        a = b;
        b = t;
    }
    for (int e = 0; e < *edge_count; ++e)
        if (edge_a[e] == a && edge_b[e] == b)
            return edge_vertex[e];
    struct gsn_poly *out = &s->out;
    if (out->vertex_count >= POLY_MAX_VERTICES ||
        *edge_count >= POLY_MAX_VERTICES)
        return -1;
    double t = s->distance[a] / (s->distance[a] - s->distance[b]);
    const double *xa = &p->vertex[3 * a], *xb = &p->vertex[3 * b];
    double *x = &out->vertex[3 * out->vertex_count];
    for (int k = 0; k < 3; ++k)
        x[k] = xa[k] + t * (xb[k] - xa[k]);
    edge_a[*edge_count] = a;
    edge_b[*edge_count] = b;
    edge_vertex[*edge_count] = out->vertex_count;
    ++*edge_count;
    return out->vertex_count++;
}

enum gsn_poly_clip_result gsn_poly_clip(struct gsn_poly *p,
                                        struct gsn_poly_scratch *s,
                                        const double n[3], double b, int label,
                                        double eps)
{
    int outside = 0, inside = 0;
    for (int v = 0; v < p->vertex_count; ++v) {
        double d = dot3(n, &p->vertex[3 * v]) - b;
        s->distance[v] = d;
        s->side[v] = d > eps ? 1 : (d < -eps ? -1 : 0);
        outside += s->side[v] > 0;
        inside += s->side[v] < 0;
    }
    if (!outside) {
        /* a face lying in the plane now borders what the plane stands for */
        for (int f = 0; f < p->face_count; ++f) {
            int on = 1;
            for (int e = p->face_start[f]; e < p->face_start[f + 1]; ++e)
                on &= s->side[p->entry[e]] == 0;
            if (on && dot3(&p->face_plane[4 * f], n) > 0.0) {
                p->face_label[f] = label;
                memcpy(&p->face_plane[4 * f], n, sizeof(double[3]));
                p->face_plane[4 * f + 3] = b;
            }
        }
        return POLY_CLIP_UNCHANGED;
    }
    if (!inside) {
        p->vertex_count = 0;
        p->face_count = 0;
        p->face_start[0] = 0;
        return POLY_CLIP_EMPTY;
    }

    struct gsn_poly *out = &s->out;
    out->vertex_count = 0;
    for (int v = 0; v < p->vertex_count; ++v) {
        s->map[v] = -1;
        if (s->side[v] <= 0) {
            memcpy(&out->vertex[3 * out->vertex_count], &p->vertex[3 * v],
                   sizeof(double[3]));
            s->map[v] = out->vertex_count++;
        }
    }
    for (int v = 0; v < POLY_MAX_VERTICES; ++v)
        s->next[v] = -1;
    /* edges split so far: at most one per cut edge */
    int edge_a[POLY_MAX_FACES], edge_b[POLY_MAX_FACES];
    int edge_vertex[POLY_MAX_FACES], edge_count = 0;
    int segments = 0, entries = 0;
    out->face_count = 0;
    for (int f = 0; f < p->face_count; ++f) {
        int begin = p->face_start[f], end = p->face_start[f + 1];
        int k = end - begin;
        int face_out = 0;
        for (int e = begin; e < end; ++e)
            face_out += s->side[p->entry[e]] > 0;
        if (entries + k + 2 > POLY_MAX_ENTRIES ||
            out->face_count + 2 > POLY_MAX_FACES)
            return POLY_CLIP_OVERFLOW;
        int start = entries;
        /* transitions: exit (kept -> out) and entry (out -> kept) points */
        int event_kind[2 * POLY_MAX_FACES], event_vertex[2 * POLY_MAX_FACES];
        int events = 0;
        for (int t = 0; t < k; ++t) {
            int va = p->entry[begin + t], vb = p->entry[begin + (t + 1) % k];
            int sa = s->side[va], sb = s->side[vb];
            if (sa <= 0)
                out->entry[entries++] = s->map[va];
            if (!face_out)
                continue;
            int cut = -1;
            if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
                if (edge_count >= POLY_MAX_FACES)
                    return POLY_CLIP_OVERFLOW;
                cut = clip_edge_vertex(p, s, va, vb, edge_a, edge_b,
                                       edge_vertex, &edge_count);
                if (cut < 0)
                    return POLY_CLIP_OVERFLOW;
                out->entry[entries++] = cut;
            }
            if (events + 1 >= 2 * POLY_MAX_FACES)
                return POLY_CLIP_TOPOLOGY;
            if (sa <= 0 && sb > 0) {
                event_kind[events] = 0;
                event_vertex[events++] = sa < 0 ? cut : s->map[va];
            } else if (sa > 0 && sb <= 0) {
                event_kind[events] = 1;
                event_vertex[events++] = sb < 0 ? cut : s->map[vb];
            }
        }
        /* each exit P is followed by the entry Q that ends its run; the
         * face gets the edge P -> Q, the cap Q -> P */
        for (int e = 0; e < events; ++e) {
            if (event_kind[e] != 0)
                continue;
            int q = (e + 1) % events;
            if (event_kind[q] != 1)
                return POLY_CLIP_TOPOLOGY;
            int vp = event_vertex[e], vq = event_vertex[q];
            if (vp == vq)
                continue;
            if (s->next[vq] != -1)
                return POLY_CLIP_TOPOLOGY;
            s->next[vq] = vp;
            ++segments;
        }
        if (entries - start >= 3) {
            int g = out->face_count++;
            out->face_label[g] = p->face_label[f];
            memcpy(&out->face_plane[4 * g], &p->face_plane[4 * f],
                   sizeof(double[4]));
            out->face_start[g] = start;
        } else {
            entries = start;
        }
    }
    if (segments >= 3) {
        int first = -1;
        for (int v = 0; v < out->vertex_count && first < 0; ++v)
            if (s->next[v] != -1)
                first = v;
        int start = entries, v = first, steps = 0;
        do {
            if (entries >= POLY_MAX_ENTRIES)
                return POLY_CLIP_OVERFLOW;
            out->entry[entries++] = v;
            v = s->next[v];
            ++steps;
        } while (v != first && v != -1 && steps <= segments);
        if (v != first || steps != segments)
            return POLY_CLIP_TOPOLOGY;
        int g = out->face_count++;
        out->face_label[g] = label;
        memcpy(&out->face_plane[4 * g], n, sizeof(double[3]));
        out->face_plane[4 * g + 3] = b;
        out->face_start[g] = start;
    } else if (segments > 0) {
        return POLY_CLIP_TOPOLOGY;
    }
    out->face_start[out->face_count] = entries;
    if (out->face_count < 4) {
        p->vertex_count = 0;
        p->face_count = 0;
        p->face_start[0] = 0;
        return POLY_CLIP_EMPTY;
    }
    gsn_poly_copy(p, out);
    return POLY_CLIP_CUT;
}

double gsn_poly_radius2(const struct gsn_poly *p)
{
    double r2 = 0.0;
    for (int v = 0; v < p->vertex_count; ++v) {
        const double *x = &p->vertex[3 * v];
        double d = dot3(x, x);
        if (d > r2)
            r2 = d;
    }
    return r2;
}

void gsn_poly_volume(const struct gsn_poly *p, double *volume, double moment[3])
{
    double v6 = 0.0, m24[3] = {0.0, 0.0, 0.0};
    for (int f = 0; f < p->face_count; ++f) {
        int begin = p->face_start[f], end = p->face_start[f + 1];
        const double *x0 = &p->vertex[3 * p->entry[begin]];
        for (int e = begin + 1; e + 1 < end; ++e) {
            const double *x1 = &p->vertex[3 * p->entry[e]];
            const double *x2 = &p->vertex[3 * p->entry[e + 1]];
            double c[3];
            cross3(x1, x2, c);
            double d = dot3(x0, c); /* 6 x volume of (origin, x0, x1, x2) */
            v6 += d;
            for (int k = 0; k < 3; ++k)
                m24[k] += d * (x0[k] + x1[k] + x2[k]);
        }
    }
    *volume = v6 / 6.0;
    for (int k = 0; k < 3; ++k)
        moment[k] = m24[k] / 24.0;
}

/* (x1 - x0) x (x2 - x0): twice the vector area of triangle x0 x1 x2. */
static void twice_triangle_area(const double *x0, const double *x1,
                                const double *x2, double c[3])
{
    double a[3], b[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = x1[k] - x0[k];
        b[k] = x2[k] - x0[k];
    }
    cross3(a, b, c);
}

void gsn_poly_face_area(const struct gsn_poly *p, int f, double area[3])
{
    int begin = p->face_start[f], end = p->face_start[f + 1];
    const double *x0 = &p->vertex[3 * p->entry[begin]];
    area[0] = area[1] = area[2] = 0.0;
    for (int e = begin + 1; e + 1 < end; ++e) {
        const double *x1 = &p->vertex[3 * p->entry[e]];
        const double *x2 = &p->vertex[3 * p->entry[e + 1]];
        double c[3];
        twice_triangle_area(x0, x1, x2, c);
        for (int k = 0; k < 3; ++k)
            area[k] += 0.5 * c[k];
    }
}

int gsn_poly_face_quadrature(const struct gsn_poly *p, int f,
                             const double normal[3], int facet_points,
                             double *restrict point, double *restrict weight)
{
    int begin = p->face_start[f], end = p->face_start[f + 1];
    const double *x0 = &p->vertex[3 * p->entry[begin]];
    double total = 0.0, moment[3] = {0.0, 0.0, 0.0};
    int count = 0;
    for (int e = begin + 1; e + 1 < end; ++e) {
        const double *x1 = &p->vertex[3 * p->entry[e]];
        const double *x2 = &p->vertex[3 * p->entry[e + 1]];
        double c[3];
        twice_triangle_area(x0, x1, x2, c);
        double area = 0.5 * dot3(c, normal);
        if (facet_points == 3) {
            /* degree 2: barycentric (2/3, 1/6, 1/6) and permutations */
            const double *xs[3] = {x0, x1, x2};
            for (int q = 0; q < 3; ++q) {
                for (int k = 0; k < 3; ++k)
                    point[3 * count + k] =
                        (4.0 * xs[q][k] + xs[(q + 1) % 3][k] +
                         xs[(q + 2) % 3][k]) /
                        6.0;
                weight[count++] = area / 3.0;
            }
        } else {
            total += area;
            for (int k = 0; k < 3; ++k)
                moment[k] += area * (x0[k] + x1[k] + x2[k]) / 3.0;
        }
    }
    if (facet_points != 3) {
        for (int k = 0; k < 3; ++k)
            point[k] = total != 0.0 ? moment[k] / total : x0[k];
        weight[0] = total;
        count = 1;
    }
    return count;
}

int gsn_poly_meets_triangle(const struct gsn_poly *p, const double *t,
                            double eps, double area_eps)
{
    enum { MAX = POLY_MAX_FACES + 3 };
    double a[3 * MAX], b[3 * MAX];
    double *in = a, *out = b;
    int count = 3;
    memcpy(a, t, sizeof(double[3][3]));
    for (int f = 0; f < p->face_count && count >= 3; ++f) {
        const double *plane = &p->face_plane[4 * f];
        int n = 0;
        for (int k = 0; k < count; ++k) {
            const double *x = &in[3 * k], *y = &in[3 * ((k + 1) % count)];
            double dx = dot3(plane, x) - plane[3];
            double dy = dot3(plane, y) - plane[3];
            if (dx <= eps)
                memcpy(&out[3 * n++], x, sizeof(double[3]));
            if ((dx < -eps && dy > eps) || (dx > eps && dy < -eps)) {
                double s = dx / (dx - dy);
                for (int i = 0; i < 3; ++i)
                    out[3 * n + i] = x[i] + s * (y[i] - x[i]);
                ++n;
            }
            if (n >= MAX - 1)
                return 1; /* cannot happen for a convex polygon: be safe */
        }
        double *swap = in;
        in = out;
        out = swap;
        count = n;
    }
    if (count < 3)
        return 0;
    double area[3] = {0.0, 0.0, 0.0};
    for (int k = 1; k + 1 < count; ++k) {
        double u[3], v[3], c[3];
        for (int i = 0; i < 3; ++i) {
            u[i] = in[3 * k + i] - in[i];
            v[i] = in[3 * (k + 1) + i] - in[i];
        }
        cross3(u, v, c);
        for (int i = 0; i < 3; ++i)
            area[i] += 0.5 * c[i];
    }
    return sqrt(dot3(area, area)) > area_eps;
}
