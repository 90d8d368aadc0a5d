// Delaunay neighbours of a point set with CGAL's Delaunay_triangulation_3
// (TOOLCHAIN.md, "Clipped Voronoi cells"): only the graph is used; the cells
// themselves are clipped by our own code. Every exception is caught here.
#include "delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
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
using CellBase = CGAL::Triangulation_cell_base_with_info_3<
    int, Kernel, CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
using DataStructure =
    CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;

// The Delaunay triangulation of the n points, each vertex knowing its
// index; false if CGAL merged duplicates.
bool triangulate(const double *points, int n, Delaunay &triangulation)
{
    std::vector<std::pair<Kernel::Point_3, int>> input;
    input.reserve(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        input.emplace_back(Kernel::Point_3(points[3 * i], points[3 * i + 1],
                                           points[3 * i + 2]),
                           i);
    triangulation.insert(input.begin(), input.end());
    return static_cast<int>(triangulation.number_of_vertices()) == n;
}

int neighbours_build(const double *points, int n, int **offset_out,
                     int **index_out)
{
    Delaunay triangulation;
    if (!triangulate(points, n, triangulation))
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

int tetrahedra_build(const double *points, int n, int *count_out,
                     int **tetrahedra_out, int **neighbour_out)
{
    Delaunay triangulation;
    if (!triangulate(points, n, triangulation))
        return GSN_DELAUNAY_DUPLICATES;
    if (triangulation.dimension() < 3)
        return GSN_DELAUNAY_FLAT;
    // number the finite cells in CGAL's order, then list each one's
    // vertices and its neighbour across the face opposite each vertex
    std::vector<Delaunay::Cell_handle> cells;
    cells.reserve(triangulation.number_of_finite_cells());
    for (auto c = triangulation.finite_cells_begin();
         c != triangulation.finite_cells_end(); ++c) {
        c->info() = static_cast<int>(cells.size());
        cells.push_back(c);
    }
    size_t count = cells.size();
    int *tetrahedra = static_cast<int *>(
        std::malloc(std::max<size_t>(4 * count, 1) * sizeof(int)));
    int *neighbour = static_cast<int *>(
        std::malloc(std::max<size_t>(4 * count, 1) * sizeof(int)));
    if (!tetrahedra || !neighbour) {
        std::free(tetrahedra);
        std::free(neighbour);
        return GSN_DELAUNAY_MEMORY;
    }
    for (size_t t = 0; t < count; ++t)
        for (int k = 0; k < 4; ++k) {
            tetrahedra[4 * t + k] = cells[t]->vertex(k)->info();
            Delaunay::Cell_handle other = cells[t]->neighbor(k);
            neighbour[4 * t + k] =
                triangulation.is_infinite(other) ? -1 : other->info();
        }
    *count_out = static_cast<int>(count);
    *tetrahedra_out = tetrahedra;
    *neighbour_out = neighbour;
    return GSN_DELAUNAY_OK;
}

} // namespace

extern "C" int gsn_delaunay_tetrahedra(const double *points, int n, int *count,
                                       int **tetrahedra, int **neighbour)
{
    *count = 0;
    *tetrahedra = nullptr;
    *neighbour = nullptr;
    try {
        return tetrahedra_build(points, n, count, tetrahedra, neighbour);
    } catch (const std::bad_alloc &) {
        return GSN_DELAUNAY_MEMORY;
    } catch (...) {
        return GSN_DELAUNAY_FAILED;
    }
}

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
