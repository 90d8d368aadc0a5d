// post's VTK code: .vtu files, pictures of the deformed body (damage like
// the seed paper's Figs. 6-7, fields on the half body clipped at its
// mid-plane like Figs. 8-9) and line charts (load-settlement, energies).
// C interface in vtk_output.h; every function catches every exception.
#include "vtk_output.h"

#include "geoscni/error.h"
#include "geoscni/files.h"
#include "geoscni/post.h"

#include <X11/Xlib.h>

#include <vtkAxis.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkContourFilter.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFeatureEdges.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlane.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRect.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTableBasedClipDataSet.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnstructuredGrid.h>
#include <vtkVariant.h>
#include <vtkVersion.h>
#include <vtkWindowToImageFilter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <exception>
#include <string>

struct gsn_vtk_grid {
    vtkSmartPointer<vtkUnstructuredGrid> grid;
};

namespace
{

// Picture and chart sizes in pixels.
constexpr int PICTURE_WIDTH = 1200;
constexpr int PICTURE_HEIGHT = 900;
constexpr int CHART_WIDTH = 1000;
constexpr int CHART_HEIGHT = 700;

int raise_exception(const char *where, const char *what)
{
    return gsn_error_raise(GSN_ERR_LIBRARY, __FILE__, __LINE__, where,
                           "VTK failed: %s", what);
}

// A VTK writer that failed: "no space left on device" when VTK says so or
// the disk is full (files.h), else its error code.
int vtk_write_error(const char *path, unsigned long code)
{
    char what[96];
    snprintf(what, sizeof what, "cannot write it (VTK error code %lu)", code);
    return gsn_write_error_raise(
        __FILE__, __LINE__, __func__, path,
        code == vtkErrorCode::OutOfDiskSpaceError ? ENOSPC : 0, what);
}

// Runs write() (a writer's Write, true if it wrote) with VTK's own error
// log off: a failed write is reported by the caller, once, with the file
// and its cause.
template <class Write> bool quietly(Write write)
{
    int shown = vtkObject::GetGlobalWarningDisplay();
    vtkObject::GlobalWarningDisplayOff();
    bool written = write();
    vtkObject::SetGlobalWarningDisplay(shown);
    return written;
}

// Writes what a render window shows to a PNG.
int window_write_png(vtkRenderWindow *window, const char *path)
{
    vtkNew<vtkWindowToImageFilter> capture;
    capture->SetInput(window);
    capture->SetInputBufferTypeToRGB();
    capture->ReadFrontBufferOff();
    capture->Update();
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(path);
    writer->SetInputConnection(capture->GetOutputPort());
    if (!quietly([&] {
            writer->Write();
            return writer->GetErrorCode() == 0;
        }))
        return vtk_write_error(path, writer->GetErrorCode());
    return GSN_OK;
}

void text_style(vtkTextProperty *text, int size, bool bold)
{
    text->SetColor(0.0, 0.0, 0.0);
    text->SetFontFamilyToArial();
    text->SetFontSize(size);
    text->SetBold(bold);
    text->SetItalic(false);
    text->SetShadow(false);
}

// The blue-to-red rainbow of the seed paper's figures.
vtkSmartPointer<vtkLookupTable> rainbow(double low, double high)
{
    auto table = vtkSmartPointer<vtkLookupTable>::New();
    table->SetNumberOfTableValues(256);
    table->SetHueRange(0.667, 0.0);
    table->SetSaturationRange(1.0, 1.0);
    table->SetValueRange(1.0, 1.0);
    table->SetRange(low, high);
    table->Build();
    return table;
}

struct picture_spec {
    const char *bar_title;
    int field; // frame field, or -1: the point array named array
    const char *array;
    int component; // column of the field; -1: the length of its row
    double scale;  // shown value = scale * field value
    bool clip;
    bool categories; // a cell array of categories (the layers)
};

picture_spec picture_spec_of(int picture)
{
    switch (picture) {
    case GSN_VTK_PICTURE_CLIP_UX:
        return {"u_x [m]", GSN_FRAME_DISPLACEMENT, nullptr, 0, 1.0, true,
                false};
    case GSN_VTK_PICTURE_CLIP_UY:
        return {"u_y [m]", GSN_FRAME_DISPLACEMENT, nullptr, 1, 1.0, true,
                false};
    case GSN_VTK_PICTURE_CLIP_UZ:
        return {"u_z [m]", GSN_FRAME_DISPLACEMENT, nullptr, 2, 1.0, true,
                false};
    case GSN_VTK_PICTURE_CLIP_EQUIVALENT_STRESS:
        return {"equivalent stress [kPa]",
                GSN_FRAME_EQUIVALENT_STRESS,
                nullptr,
                0,
                1e-3,
                true,
                false};
    case GSN_VTK_PICTURE_CLIP_DISPLACEMENT:
        return {"|u| [m]", GSN_FRAME_DISPLACEMENT, nullptr, -1, 1.0, true,
                false};
    case GSN_VTK_PICTURE_CLIP_EQUIVALENT_PLASTIC_STRAIN:
        return {"equivalent plastic strain [-]",
                GSN_FRAME_EQUIVALENT_PLASTIC_STRAIN,
                nullptr,
                0,
                1.0,
                true,
                false};
    case GSN_VTK_PICTURE_LAYERS:
        return {"layer", -1, "volume", 0, 1.0, false, true};
    case GSN_VTK_PICTURE_PORE_PRESSURE:
        return {
            "pore pressure [kPa]", -1, "pore_pressure", 0, 1e-3, false, false};
    default:
        return {"damage [-]", GSN_FRAME_DAMAGE, nullptr, 0, 1.0, false, false};
    }
}

// A colour for each category (the layers), named in the legend.
vtkSmartPointer<vtkLookupTable> categories(vtkStringArray *names)
{
    static const double palette[8][3] = {
        {0.85, 0.65, 0.35}, {0.45, 0.60, 0.85}, {0.55, 0.75, 0.45},
        {0.80, 0.45, 0.45}, {0.65, 0.55, 0.80}, {0.95, 0.85, 0.45},
        {0.50, 0.50, 0.50}, {0.40, 0.75, 0.75}};
    auto table = vtkSmartPointer<vtkLookupTable>::New();
    vtkIdType count = names->GetNumberOfValues();
    table->SetNumberOfTableValues(count);
    table->IndexedLookupOn();
    for (vtkIdType k = 0; k < count; ++k) {
        const double *c = palette[k % 8];
        table->SetTableValue(k, c[0], c[1], c[2], 1.0);
        table->SetAnnotation(vtkVariant((double)k), names->GetValue(k));
    }
    table->SetRange(0.0, count > 1 ? (double)(count - 1) : 1.0);
    return table;
}

// Colour range of a field: damage always [0, 1] so frames compare; others
// the field's own range, widened when it is (nearly) constant.
void colour_range(const picture_spec &spec, vtkDataArray *shown,
                  double range[2])
{
    if (spec.field == GSN_FRAME_DAMAGE) {
        range[0] = 0.0;
        range[1] = 1.0;
        return;
    }
    shown->GetRange(range, 0);
    if (spec.categories)
        return;
    double span = range[1] - range[0];
    double size = std::max(std::fabs(range[0]), std::fabs(range[1]));
    if (!(span > 1e-9 * size) || size == 0.0) {
        double pad = size > 0.0 ? 0.05 * size : 1.0;
        range[0] -= pad;
        range[1] += pad;
    }
}

// Round tick values (1, 2, 2.5 or 5 times a power of ten, about six of
// them) for a colour range; unless fixed, the range is widened to the ticks
// around it so the bar starts and ends on a labelled value.
vtkSmartPointer<vtkDoubleArray> nice_ticks(double range[2], bool fixed)
{
    auto ticks = vtkSmartPointer<vtkDoubleArray>::New();
    double span = range[1] - range[0];
    double raw = span / 6.0;
    double power = std::pow(10.0, std::floor(std::log10(raw)));
    double step = 10.0 * power;
    for (double factor : {1.0, 2.0, 2.5, 5.0})
        if (factor * power >= raw) {
            step = factor * power;
            break;
        }
    if (!fixed) {
        range[0] = step * std::floor(range[0] / step + 1e-9);
        range[1] = step * std::ceil(range[1] / step - 1e-9);
        span = range[1] - range[0];
    }
    for (double k = std::ceil(range[0] / step - 1e-9);
         k * step <= range[1] + 1e-9 * span; k += 1.0)
        ticks->InsertNextValue(std::fabs(k) < 0.5 ? 0.0 : k * step);
    return ticks;
}

int grid_render(const gsn_vtk_grid *g, enum gsn_vtk_picture picture,
                const double bounds[6], const char *title, const char *path)
{
    GSN_CHECK(picture >= 0 && picture < GSN_VTK_PICTURE_COUNT, GSN_ERR_INTERNAL,
              "unknown picture %d", (int)picture);
    picture_spec spec = picture_spec_of(picture);
    vtkUnstructuredGrid *grid = g->grid;
    vtkIdType n = grid->GetNumberOfPoints();

    // The shown scalar, scaled to the bar's units, on a shallow copy.
    const char *array =
        spec.field >= 0 ? gsn_frame_fields[spec.field].path : spec.array;
    vtkDataArray *source = spec.categories
                               ? grid->GetCellData()->GetArray(array)
                               : grid->GetPointData()->GetArray(array);
    GSN_CHECK(source != nullptr, GSN_ERR_INTERNAL, "grid lacks the array %s",
              array);
    if (spec.categories)
        n = grid->GetNumberOfCells();
    vtkNew<vtkDoubleArray> shown;
    shown->SetName("shown");
    shown->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i) {
        double value = 0.0;
        if (spec.component >= 0)
            value = source->GetComponent(i, spec.component);
        else
            for (int k = 0; k < source->GetNumberOfComponents(); ++k)
                value +=
                    source->GetComponent(i, k) * source->GetComponent(i, k);
        shown->SetValue(
            i, spec.scale * (spec.component >= 0 ? value : std::sqrt(value)));
    }
    vtkNew<vtkUnstructuredGrid> copy;
    copy->ShallowCopy(grid);
    if (spec.categories) {
        copy->GetCellData()->AddArray(shown);
        copy->GetCellData()->SetActiveScalars("shown");
    } else {
        copy->GetPointData()->AddArray(shown);
        copy->GetPointData()->SetActiveScalars("shown");
    }

    // The half y >= (ymin + ymax) / 2 of the reference body (Figs. 8-9).
    // Nudged by 1e-5 of the width so a plane of mesh nodes lying exactly on
    // it (a structured mesh) does not leave zero-area slivers on the cut.
    double middle_y =
        0.5 * (bounds[2] + bounds[3]) + 1e-5 * (bounds[3] - bounds[2]);
    vtkNew<vtkPlane> plane;
    plane->SetOrigin(0.0, middle_y, 0.0);
    plane->SetNormal(0.0, 1.0, 0.0);
    vtkNew<vtkTableBasedClipDataSet> clip;
    clip->SetClipFunction(plane);
    clip->SetInputData(copy);
    vtkNew<vtkDataSetSurfaceFilter> surface;
    if (spec.clip)
        surface->SetInputConnection(clip->GetOutputPort());
    else
        surface->SetInputData(copy);
    surface->Update();

    double range[2];
    colour_range(spec, shown, range);
    vtkSmartPointer<vtkDoubleArray> ticks =
        nice_ticks(range, spec.field == GSN_FRAME_DAMAGE);
    vtkSmartPointer<vtkLookupTable> table = rainbow(range[0], range[1]);
    auto *names = vtkStringArray::SafeDownCast(
        grid->GetFieldData()->GetAbstractArray("volume_names"));
    if (spec.categories && names)
        table = categories(names);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(surface->GetOutputPort());
    mapper->SetLookupTable(table);
    if (spec.categories)
        mapper->SetScalarModeToUseCellFieldData();
    else
        mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray("shown");
    mapper->SetScalarRange(range);
    mapper->ScalarVisibilityOn();
    mapper->InterpolateScalarsBeforeMappingOn();
    vtkNew<vtkActor> body;
    body->SetMapper(mapper);
    body->GetProperty()->SetAmbient(0.25);
    body->GetProperty()->SetDiffuse(0.75);
    body->GetProperty()->SetSpecular(0.0);

    // The body's sharp edges (crest, toe, cut) as thin dark lines.
    // Triangles are first ordered consistently: the tetrahedra's own
    // orientation may vary, and a flipped neighbour reads as a sharp edge.
    vtkNew<vtkPolyDataNormals> oriented;
    oriented->SetInputConnection(surface->GetOutputPort());
    oriented->ConsistencyOn();
    oriented->SplittingOff();
    oriented->ComputeCellNormalsOff();
    vtkNew<vtkFeatureEdges> edges;
    edges->SetInputConnection(oriented->GetOutputPort());
    edges->SetFeatureAngle(30.0);
    edges->FeatureEdgesOn();
    edges->BoundaryEdgesOff();
    edges->NonManifoldEdgesOff();
    edges->ManifoldEdgesOff();
    edges->ColoringOff();
    vtkNew<vtkPolyDataMapper> edge_mapper;
    edge_mapper->SetInputConnection(edges->GetOutputPort());
    edge_mapper->ScalarVisibilityOff();
    edge_mapper->SetResolveCoincidentTopologyToPolygonOffset();
    vtkNew<vtkActor> outline;
    outline->SetMapper(edge_mapper);
    outline->GetProperty()->SetColor(0.15, 0.15, 0.15);
    outline->GetProperty()->SetLineWidth(1.5);
    outline->GetProperty()->LightingOff();

    vtkNew<vtkScalarBarActor> bar;
    bar->SetLookupTable(table);
    if (spec.categories && names) {
        bar->SetDrawAnnotations(true);
        bar->SetNumberOfLabels(0);
        text_style(bar->GetAnnotationTextProperty(), 20, false);
    } else {
        bar->SetUseCustomLabels(true);
        bar->SetCustomLabels(ticks);
    }
    bar->SetLabelFormat("%g");
    bar->SetOrientationToHorizontal();
    bar->SetPosition(0.34, 0.03);
    bar->SetWidth(0.58);
    bar->SetHeight(0.12);
    bar->SetBarRatio(0.3);
    bar->UnconstrainedFontSizeOn();
    text_style(bar->GetLabelTextProperty(), 20, false);

    // The bar's title left of it (VTK puts it over the middle label).
    // The water table on the layers: the line where the water's head above
    // a point changes sign, drawn over the body in blue.
    vtkNew<vtkContourFilter> table_line;
    vtkNew<vtkPolyDataMapper> table_mapper;
    vtkNew<vtkActor> water;
    bool wet = spec.categories &&
               grid->GetPointData()->GetArray("water_head") != nullptr;
    if (wet) {
        table_line->SetInputConnection(surface->GetOutputPort());
        table_line->SetInputArrayToProcess(
            0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "water_head");
        table_line->SetValue(0, 0.0);
        table_mapper->SetInputConnection(table_line->GetOutputPort());
        table_mapper->ScalarVisibilityOff();
        table_mapper->SetResolveCoincidentTopologyToPolygonOffset();
        water->SetMapper(table_mapper);
        water->GetProperty()->SetColor(0.05, 0.25, 0.95);
        water->GetProperty()->SetLineWidth(4.0);
        water->GetProperty()->LightingOff();
    }

    vtkNew<vtkTextActor> bar_title;
    bar_title->SetInput(wet ? "layer, water table (blue)" : spec.bar_title);
    text_style(bar_title->GetTextProperty(), 24, true);
    bar_title->GetTextProperty()->SetJustificationToRight();
    bar_title->GetTextProperty()->SetVerticalJustificationToCentered();
    bar_title->SetPosition(0.32 * PICTURE_WIDTH, 44);

    vtkNew<vtkTextActor> heading;
    heading->SetInput(title);
    text_style(heading->GetTextProperty(), 26, true);
    heading->GetTextProperty()->SetJustificationToCentered();
    heading->GetTextProperty()->SetVerticalJustificationToTop();
    heading->SetPosition(0.5 * PICTURE_WIDTH, PICTURE_HEIGHT - 20);

    // The body on a renderer above the title and the colour bar, which sit
    // on a full-window white renderer underneath (layer 0).
    vtkNew<vtkRenderer> overlay;
    overlay->SetBackground(1.0, 1.0, 1.0);
    overlay->SetLayer(0);
    overlay->AddActor2D(bar);
    overlay->AddActor2D(heading);
    overlay->AddActor2D(bar_title);
    vtkNew<vtkRenderer> renderer;
    renderer->SetLayer(1);
    renderer->SetViewport(0.0, 0.13, 1.0, 0.93);
    renderer->AddActor(body);
    renderer->AddActor(outline);
    if (wet)
        renderer->AddActor(water);

    // A fixed oblique camera from the slope face's side (x up-slope, z up),
    // the same for every frame: set by the reference body's bounds.
    double centre[3] = {0.5 * (bounds[0] + bounds[1]),
                        0.5 * (bounds[2] + bounds[3]),
                        0.5 * (bounds[4] + bounds[5])};
    double direction[3] = {1.0, -1.35, 0.85};
    // a slab (a plane-strain section) is seen nearly square on, as a cut
    bool slab = bounds[3] - bounds[2] < 0.2 * (bounds[1] - bounds[0]);
    if (spec.clip || slab) {
        direction[0] = 0.45;
        direction[1] = -1.0;
        direction[2] = 0.4;
    }
    vtkCamera *camera = renderer->GetActiveCamera();
    camera->SetFocalPoint(centre);
    camera->SetPosition(centre[0] + direction[0], centre[1] + direction[1],
                        centre[2] + direction[2]);
    camera->SetViewUp(0.0, 0.0, 1.0);
    camera->SetViewAngle(25.0);
    double view_bounds[6];
    std::copy(bounds, bounds + 6, view_bounds);
    renderer->ResetCamera(view_bounds);
    camera->Zoom(spec.clip || slab ? 1.3 : 1.1);

    vtkNew<vtkRenderWindow> window;
    window->SetOffScreenRendering(1);
    window->SetSize(PICTURE_WIDTH, PICTURE_HEIGHT);
    window->SetMultiSamples(8);
    window->SetNumberOfLayers(2);
    window->AddRenderer(overlay);
    window->AddRenderer(renderer);
    window->Render();
    GSN_CALL(window_write_png(window, path));
    return GSN_OK;
}

// Distinct colours for the chart's curves (Okabe-Ito).
const unsigned char CURVE_COLOURS[][3] = {
    {0, 114, 178}, {213, 94, 0},   {0, 158, 115},  {204, 121, 167},
    {230, 159, 0}, {86, 180, 233}, {240, 228, 66}, {0, 0, 0}};

int chart_write(const char *path, const char *title, const char *x_label,
                const char *y_label, int series_count, const char *const *names,
                const int *counts, const double *const *x,
                const double *const *y, const gsn_chart_style *style)
{
    const gsn_chart_style plain = {};
    if (!style)
        style = &plain;
    vtkNew<vtkContextView> view;
    // No interactor: a chart is drawn once. VTK 9.1's X interactor opens a
    // display of its own at the first Render and calls XSync on it even when
    // that failed (a crash in libX11 with several posts side by side).
    view->GetRenderWindow()->SetInteractor(nullptr);
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    view->GetRenderWindow()->SetOffScreenRendering(1);
    view->GetRenderWindow()->SetSize(CHART_WIDTH, CHART_HEIGHT);
    view->GetRenderWindow()->SetMultiSamples(8);
    vtkNew<vtkChartXY> chart;
    view->GetScene()->AddItem(chart);
    chart->SetTitle(title);
    // The axes' corners in pixels, leaving room for the title, the axis
    // titles and the last tick label.
    chart->SetLayoutStrategy(vtkChart::AXES_TO_RECT);
    chart->SetSize(
        vtkRectf(110.0f, 90.0f, CHART_WIDTH - 160.0f, CHART_HEIGHT - 160.0f));
    text_style(chart->GetTitleProperties(), 24, true);
    chart->SetShowLegend(series_count > 1 || style->always_legend);
    chart->GetLegend()->SetHorizontalAlignment(
        style->legend_right ? vtkChartLegend::RIGHT : vtkChartLegend::LEFT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
    chart->GetLegend()->SetLabelSize(18);
    const char *labels[2] = {x_label, y_label};
    const int axes[2] = {vtkAxis::BOTTOM, vtkAxis::LEFT};
    for (int a = 0; a < 2; ++a) {
        vtkAxis *axis = chart->GetAxis(axes[a]);
        axis->SetTitle(labels[a]);
        axis->SetLogScale(style->log_axes != 0);
        text_style(axis->GetTitleProperties(), 20, true);
        text_style(axis->GetLabelProperties(), 18, false);
        axis->GetGridPen()->SetColor(210, 210, 210);
    }
    for (int s = 0; s < series_count; ++s) {
        vtkNew<vtkTable> table;
        vtkNew<vtkDoubleArray> xs, ys;
        xs->SetName(x_label);
        ys->SetName(names[s]);
        xs->SetNumberOfTuples(counts[s]);
        ys->SetNumberOfTuples(counts[s]);
        for (int i = 0; i < counts[s]; ++i) {
            xs->SetValue(i, x[s][i]);
            ys->SetValue(i, y[s][i]);
        }
        table->AddColumn(xs);
        table->AddColumn(ys);
        vtkPlot *line = chart->AddPlot(vtkChart::LINE);
        line->SetInputData(table, 0, 1);
        int colour = style->colour ? style->colour[s] : s;
        const unsigned char *c =
            CURVE_COLOURS[colour %
                          (sizeof CURVE_COLOURS / sizeof *CURVE_COLOURS)];
        line->SetColor(c[0], c[1], c[2], 255);
        line->SetWidth(3.0);
        line->SetLabel(names[s]);
        vtkPlotPoints *points = vtkPlotPoints::SafeDownCast(line);
        if (style->markers && points) {
            points->SetMarkerStyle(vtkPlotPoints::CIRCLE);
            points->SetMarkerSize(10.0);
        }
    }
    view->GetRenderWindow()->Render();
    GSN_CALL(window_write_png(view->GetRenderWindow(), path));
    return GSN_OK;
}

} // namespace

extern "C" const char *gsn_post_vtk_version(void)
{
    return vtkVersion::GetVTKVersion();
}

extern "C" int gsn_vtk_display_usable(void)
{
    // VTK aborts when its X connection fails: check the display first.
    Display *display = XOpenDisplay(nullptr);
    if (!display)
        return 0;
    XCloseDisplay(display);
    return 1;
}

extern "C" int gsn_vtk_grid_create(int point_count, const double *reference,
                                   int tetrahedron_count, const int *tetrahedra,
                                   const struct gsn_frame *frame,
                                   struct gsn_vtk_grid **grid)
{
    *grid = nullptr;
    GSN_CHECK(point_count == frame->particle_count, GSN_ERR_INTERNAL,
              "frame of %d particles for a mesh of %d points",
              frame->particle_count, point_count);
    gsn_vtk_grid *g = nullptr;
    try {
        g = new gsn_vtk_grid;
        g->grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
        // without displacements (output.fields) the points stay at X
        const bool moved = frame->present & (1u << GSN_FRAME_DISPLACEMENT);
        const double *u = frame->field[GSN_FRAME_DISPLACEMENT];
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        points->SetNumberOfPoints(point_count);
        for (vtkIdType i = 0; i < point_count; ++i)
            points->SetPoint(
                i, reference[3 * i] + (moved ? u[3 * i] : 0.0),
                reference[3 * i + 1] + (moved ? u[3 * i + 1] : 0.0),
                reference[3 * i + 2] + (moved ? u[3 * i + 2] : 0.0));
        g->grid->SetPoints(points);

        vtkNew<vtkIdTypeArray> offsets, connectivity;
        offsets->SetNumberOfTuples(tetrahedron_count + 1);
        connectivity->SetNumberOfTuples(4 * (vtkIdType)tetrahedron_count);
        for (vtkIdType t = 0; t <= tetrahedron_count; ++t)
            offsets->SetValue(t, 4 * t);
        for (vtkIdType k = 0; k < 4 * (vtkIdType)tetrahedron_count; ++k)
            connectivity->SetValue(k, tetrahedra[k]);
        vtkNew<vtkCellArray> cells;
        cells->SetData(offsets, connectivity);
        g->grid->SetCells(VTK_TETRA, cells);

        static const char *const voigt[6] = {"xx", "yy", "zz",
                                             "xy", "yz", "xz"};
        static const char *const xyz[3] = {"x", "y", "z"};
        for (int f = 0; f < GSN_FRAME_FIELD_COUNT; ++f) {
            if (!(frame->present & (1u << f)))
                continue; // not written (output.fields)
            int columns = gsn_frame_fields[f].columns;
            vtkNew<vtkDoubleArray> array;
            array->SetName(gsn_frame_fields[f].path);
            array->SetNumberOfComponents(columns);
            array->SetNumberOfTuples(point_count);
            std::copy(frame->field[f],
                      frame->field[f] + (size_t)columns * point_count,
                      array->GetPointer(0));
            for (int c = 0; c < columns && columns > 1; ++c)
                array->SetComponentName(c, columns == 6 ? voigt[c] : xyz[c]);
            g->grid->GetPointData()->AddArray(array);
        }
        // The frame's time, which ParaView shows for a lone .vtu.
        vtkNew<vtkDoubleArray> time;
        time->SetName("TimeValue");
        time->SetNumberOfTuples(1);
        time->SetValue(0, frame->time);
        g->grid->GetFieldData()->AddArray(time);
    } catch (const std::exception &e) {
        delete g;
        return raise_exception(__func__, e.what());
    } catch (...) {
        delete g;
        return raise_exception(__func__, "unknown exception");
    }
    *grid = g;
    return GSN_OK;
}

extern "C" int gsn_vtk_grid_add_point_field(struct gsn_vtk_grid *grid,
                                            const char *name,
                                            const double *values)
{
    try {
        vtkIdType n = grid->grid->GetNumberOfPoints();
        vtkNew<vtkDoubleArray> array;
        array->SetName(name);
        array->SetNumberOfTuples(n);
        std::copy(values, values + n, array->GetPointer(0));
        grid->grid->GetPointData()->AddArray(array);
    } catch (const std::exception &e) {
        return raise_exception(__func__, e.what());
    } catch (...) {
        return raise_exception(__func__, "unknown exception");
    }
    return GSN_OK;
}

extern "C" int
gsn_vtk_grid_add_cell_categories(struct gsn_vtk_grid *grid, const char *name,
                                 const int *values, int category_count,
                                 const char *const *category_names)
{
    try {
        vtkIdType n = grid->grid->GetNumberOfCells();
        vtkNew<vtkIntArray> array;
        array->SetName(name);
        array->SetNumberOfTuples(n);
        std::copy(values, values + n, array->GetPointer(0));
        grid->grid->GetCellData()->AddArray(array);
        vtkNew<vtkStringArray> names;
        names->SetName((std::string(name) + "_names").c_str());
        for (int k = 0; k < category_count; ++k)
            names->InsertNextValue(category_names[k]);
        grid->grid->GetFieldData()->AddArray(names);
    } catch (const std::exception &e) {
        return raise_exception(__func__, e.what());
    } catch (...) {
        return raise_exception(__func__, "unknown exception");
    }
    return GSN_OK;
}

extern "C" int gsn_vtk_picture_field(enum gsn_vtk_picture picture)
{
    return picture_spec_of(picture).field;
}

extern "C" void gsn_vtk_grid_destroy(struct gsn_vtk_grid **grid)
{
    if (!grid)
        return;
    try {
        delete *grid;
    } catch (...) {
        // Releasing VTK objects does not throw; nothing to recover.
    }
    *grid = nullptr;
}

extern "C" int gsn_vtk_grid_write(const struct gsn_vtk_grid *grid,
                                  const char *path)
{
    try {
        vtkNew<vtkXMLUnstructuredGridWriter> writer;
        writer->SetFileName(path);
        writer->SetInputData(grid->grid);
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff();
        writer->SetCompressorTypeToZLib();
        // zlib's fastest level: the frames are doubles, which no level
        // packs much (Slope I's 42 frames: 381 MB at 1, 375 MB at VTK's
        // default 5), and the default took 0.53 s a frame against 0.32
        // (post without pictures 22.1 s -> 13.3 s, 2026-12-07)
        writer->SetCompressionLevel(1);
        writer->SetHeaderTypeToUInt64();
        if (!quietly([&] {
                return writer->Write() == 1 && writer->GetErrorCode() == 0;
            }))
            return vtk_write_error(path, writer->GetErrorCode());
    } catch (const std::exception &e) {
        return raise_exception(__func__, e.what());
    } catch (...) {
        return raise_exception(__func__, "unknown exception");
    }
    return GSN_OK;
}

extern "C" int gsn_vtk_grid_render(const struct gsn_vtk_grid *grid,
                                   enum gsn_vtk_picture picture,
                                   const double bounds[6], const char *title,
                                   const char *path)
{
    try {
        GSN_CALL(grid_render(grid, picture, bounds, title, path));
    } catch (const std::exception &e) {
        return raise_exception(__func__, e.what());
    } catch (...) {
        return raise_exception(__func__, "unknown exception");
    }
    return GSN_OK;
}

extern "C" int gsn_vtk_chart_write(const char *path, const char *title,
                                   const char *x_label, const char *y_label,
                                   int series_count, const char *const *names,
                                   const int *counts, const double *const *x,
                                   const double *const *y,
                                   const struct gsn_chart_style *style)
{
    try {
        GSN_CALL(chart_write(path, title, x_label, y_label, series_count, names,
                             counts, x, y, style));
    } catch (const std::exception &e) {
        return raise_exception(__func__, e.what());
    } catch (...) {
        return raise_exception(__func__, "unknown exception");
    }
    return GSN_OK;
}
