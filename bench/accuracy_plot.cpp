// The speed-and-accuracy chart (bench/accuracy_chart.sh): error against
// time (the CPU time of a 1-thread run, column cpu_s: on a shared machine
// the wall time of an idle core) on log-log axes, one curve per method, from
// the CSV that accuracy_run writes; the legend gives each method's convergence
// rate, the least-squares slope of log(error) against log(spacing). Drawn with
// VTK's vtkChartXY like post's plots, on post's private Xvfb when there is
// no display (post/src/display.h).
//
//   accuracy_plot CSV PROBLEM PNG [TITLE [ERROR_LABEL]]
//
// Prints the rates. Exit status 0, 1 (VTK or I/O failed), 2 (bad input).
extern "C" {
#include "display.h"
}

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotLine.h>
#include <vtkRect.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{

struct series {
    std::vector<double> spacing, time, error;
};

// The methods in the order of the legend, with their labels.
const char *const METHODS[][2] = {{"scni", "SCNI"},
                                  {"mscni", "SCNI + MSCNI"},
                                  {"dni", "DNI"},
                                  {"gauss2", "Gauss 2x2x2"},
                                  {"gauss3", "Gauss 3x3x3"}};

// Okabe-Ito, as post's charts.
const unsigned char COLOURS[][3] = {
    {0, 114, 178}, {213, 94, 0}, {0, 158, 115}, {204, 121, 167}, {230, 159, 0}};

// Reads the rows of one problem: method -> spacing, wall time, error.
bool read_csv(const char *path, const std::string &problem,
              std::map<std::string, series> &out)
{
    std::ifstream file(path);
    if (!file)
        return false;
    std::string line;
    std::getline(file, line);
    std::vector<std::string> names;
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');)
        names.push_back(name);
    auto column = [&](const char *name) {
        for (size_t i = 0; i < names.size(); ++i)
            if (names[i] == name)
                return (int)i;
        return -1;
    };
    int c_problem = column("problem"), c_method = column("method"),
        c_spacing = column("spacing"), c_wall = column("cpu_s"),
        c_error = column("error");
    if (c_problem < 0 || c_method < 0 || c_spacing < 0 || c_wall < 0 ||
        c_error < 0)
        return false;
    while (std::getline(file, line)) {
        std::vector<std::string> cells;
        std::stringstream row(line);
        for (std::string cell; std::getline(row, cell, ',');)
            cells.push_back(cell);
        if ((int)cells.size() < (int)names.size() ||
            cells[c_problem] != problem)
            continue;
        series &s = out[cells[c_method]];
        s.spacing.push_back(std::stod(cells[c_spacing]));
        s.time.push_back(std::stod(cells[c_wall]));
        s.error.push_back(std::stod(cells[c_error]));
    }
    return true;
}

// Least-squares slope of log(error) against log(spacing).
double rate(const series &s)
{
    size_t n = s.spacing.size();
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < n; ++i) {
        double x = std::log(s.spacing[i]), y = std::log(s.error[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return n > 1 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : 0.0;
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

int draw(const std::map<std::string, series> &data, const char *title,
         const char *error_label, const char *png)
{
    const int width = 1000, height = 750;
    vtkNew<vtkContextView> view;
    view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    view->GetRenderWindow()->SetOffScreenRendering(1);
    view->GetRenderWindow()->SetSize(width, height);
    view->GetRenderWindow()->SetMultiSamples(8);
    vtkNew<vtkChartXY> chart;
    view->GetScene()->AddItem(chart);
    chart->SetTitle(title);
    chart->SetLayoutStrategy(vtkChart::AXES_TO_RECT);
    chart->SetSize(vtkRectf(120.0f, 90.0f, width - 160.0f, height - 160.0f));
    text_style(chart->GetTitleProperties(), 22, true);
    chart->SetShowLegend(true);
    chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
    chart->GetLegend()->SetLabelSize(17);
    const char *labels[2] = {"time: build + steps (s, CPU of 1 thread)",
                             error_label};
    const int axes[2] = {vtkAxis::BOTTOM, vtkAxis::LEFT};
    for (int a = 0; a < 2; ++a) {
        vtkAxis *axis = chart->GetAxis(axes[a]);
        axis->SetTitle(labels[a]);
        axis->SetLogScale(true);
        text_style(axis->GetTitleProperties(), 20, true);
        text_style(axis->GetLabelProperties(), 17, false);
        axis->GetGridPen()->SetColor(210, 210, 210);
    }
    int m = 0;
    for (const auto &method : METHODS) {
        auto found = data.find(method[0]);
        const unsigned char *c = COLOURS[m++];
        if (found == data.end())
            continue;
        const series &s = found->second;
        char label[128];
        std::snprintf(label, sizeof label, "%s: rate %.2f", method[1], rate(s));
        std::printf("%s\n", label);
        vtkNew<vtkTable> table;
        vtkNew<vtkDoubleArray> xs, ys;
        xs->SetName("time");
        ys->SetName(label);
        xs->SetNumberOfTuples((vtkIdType)s.time.size());
        ys->SetNumberOfTuples((vtkIdType)s.time.size());
        for (size_t i = 0; i < s.time.size(); ++i) {
            xs->SetValue((vtkIdType)i, s.time[i]);
            ys->SetValue((vtkIdType)i, s.error[i]);
        }
        table->AddColumn(xs);
        table->AddColumn(ys);
        auto *line = vtkPlotLine::SafeDownCast(chart->AddPlot(vtkChart::LINE));
        line->SetInputData(table, 0, 1);
        line->SetColor(c[0], c[1], c[2], 255);
        line->SetWidth(3.0);
        line->SetMarkerStyle(vtkPlotPoints::CIRCLE);
        line->SetMarkerSize(10.0);
        line->SetLabel(label);
    }
    view->GetRenderWindow()->Render();
    vtkNew<vtkWindowToImageFilter> capture;
    capture->SetInput(view->GetRenderWindow());
    capture->SetInputBufferTypeToRGB();
    capture->ReadFrontBufferOff();
    capture->Update();
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(png);
    writer->SetInputConnection(capture->GetOutputPort());
    writer->Write();
    if (writer->GetErrorCode() != 0) {
        std::fprintf(stderr, "accuracy_plot: cannot write %s\n", png);
        return 1;
    }
    return 0;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 4 || argc > 6) {
        std::fprintf(stderr,
                     "usage: %s CSV PROBLEM PNG [TITLE [ERROR_LABEL]]\n",
                     argv[0]);
        return 2;
    }
    std::map<std::string, series> data;
    try {
        if (!read_csv(argv[1], argv[2], data) || data.empty()) {
            std::fprintf(stderr, "accuracy_plot: no rows of %s in %s\n",
                         argv[2], argv[1]);
            return 2;
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "accuracy_plot: %s: %s\n", argv[1], e.what());
        return 2;
    }
    struct gsn_display display = {};
    if (gsn_display_open(&display) != 0 || !display.available) {
        std::fprintf(stderr, "accuracy_plot: no display: %s\n", display.reason);
        gsn_display_close(&display);
        return 1;
    }
    int status = 1;
    try {
        status = draw(data, argc >= 5 ? argv[4] : argv[2],
                      argc >= 6 ? argv[5] : "error", argv[3]);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "accuracy_plot: VTK failed: %s\n", e.what());
    } catch (...) {
        std::fprintf(stderr, "accuracy_plot: VTK failed\n");
    }
    gsn_display_close(&display);
    return status;
}
