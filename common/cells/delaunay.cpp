// Delaunay neighbours of a point set with CGAL's Delaunay_triangulation_3
// (TOOLCHAIN.md, "Clipped Voronoi cells"): only the graph is used; the cells
// themselves are clipped by our own code. Every exception is caught here.
#include "delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <utility>
#include <vector>

namespace
{

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;

int neighbours_build(const double *points, int n, int **offset_out,
                     int **index_out)
{
    std::vector<std::pair<Kernel::Point_3, int>> input;
    input.reserve(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        input.emplace_back(Kernel::Point_3(points[3 * i], points[3 * i + 1],
                                           points[3 * i + 2]),
                           i);
    Delaunay triangulation(input.begin(), input.end());
    if (static_cast<int>(triangulation.number_of_vertices()) != n)
        return GSN_DELAUNAY_DUPLICATES;

    std::vector<std::pair<int, int>> edges;
    if (triangulation.dimension() >= 1) {
        edges.reserve(8 * static_cast<size_t>(n));
        for (auto e = triangulation.finite_edges_begin();
             e != triangulation.finite_edges_end(); ++e) {
            int a = e->first->vertex(e->second)->info();
            int b = e->first->vertex(e->third)->info();
            edges.emplace_back(a, b);
            edges.emplace_back(b, a);
        }
    }
    std::sort(edges.begin(), edges.end());
    int *offset = static_cast<int *>(
        std::calloc(static_cast<size_t>(n) + 1, sizeof(int)));
    int *index = static_cast<int *>(
        std::malloc(std::max<size_t>(edges.size(), 1) * sizeof(int)));
    if (!offset || !index) {
        std::free(offset);
        std::free(index);
        return GSN_DELAUNAY_MEMORY;
    }
    for (size_t e = 0; e < edges.size(); ++e) {
        ++offset[edges[e].first + 1];
        index[e] = edges[e].second;
    }
    for (int i = 0; i < n; ++i)
        offset[i + 1] += offset[i];
    *offset_out = offset;
    *index_out = index;
    return GSN_DELAUNAY_OK;
}

} // namespace

extern "C" int gsn_delaunay_neighbours(const double *points, int n,
                                       int **offset, int **index)
{
    *offset = nullptr;
    *index = nullptr;
    try {
        return neighbours_build(points, n, offset, index);
    } catch (const std::bad_alloc &) {
        return GSN_DELAUNAY_MEMORY;
    } catch (...) {
        return GSN_DELAUNAY_FAILED;
    }
}
