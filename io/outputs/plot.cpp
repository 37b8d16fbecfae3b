#include "io/outputs/plot.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/support/file_io.h"
#include "io/support/process.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxImageBytes = 256u << 20;
constexpr auto kTimeout = std::chrono::seconds(60);

// Series colours: dark blue, red, green, orange, purple, grey; then again.
constexpr const char* kColours[] = {"#1f4e9a", "#c0392b", "#2e8b57", "#e67e22", "#7d3c98", "#555555"};

// A gnuplot single-quoted string: '' stands for ', control characters become
// spaces (a newline would end the command).
std::string quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'')
      out += "''";
    else if (static_cast<unsigned char>(c) < 0x20)
      out += ' ';
    else
      out += c;
  }
  return out + "'";
}

// Smallest 1, 2, 2.5 or 5 × 10^k at or above v > 0.
double nice_ceiling(double v) {
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * p >= v * (1.0 - 1e-12)) return m * p;
  return 10.0 * p;
}

struct Prepared {
  std::string block;  // datablock name, e.g. $s0_1
  const Series* series;
};

// Writes the datablock of one series; points that are non-finite or not
// positive on a logarithmic axis become gaps. Returns whether any point is left.
bool write_block(std::ostringstream& s, const std::string& name, const Series& series, bool log_x,
                 bool log_y) {
  s << name << " << EOD\n";
  bool any = false;
  for (std::size_t k = 0; k < series.x.size(); ++k) {
    const double x = series.x[k], y = series.y[k];
    const bool ok = std::isfinite(x) && std::isfinite(y) && (!log_x || x > 0.0) && (!log_y || y > 0.0);
    if (ok) {
      s << format_number(x, 17) << ' ' << format_number(y, 17) << '\n';
      any = true;
    } else {
      s << '\n';
    }
  }
  s << "EOD\n";
  return any;
}

std::string plot_command(const std::vector<Prepared>& prepared) {
  std::string cmd = "plot ";
  for (std::size_t k = 0; k < prepared.size(); ++k) {
    const Series& s = *prepared[k].series;
    if (k > 0) cmd += ", \\\n     ";
    const int dash = s.style == LineStyle::Solid ? 1 : (s.style == LineStyle::Dashed ? 2 : 3);
    cmd += prepared[k].block + " using 1:2 with " + (s.markers ? "linespoints pt 7 ps 0.6" : "lines") +
           " lw 2 dt " + std::to_string(dash) + " lc rgb '" +
           kColours[k % (sizeof kColours / sizeof kColours[0])] + "' " +
           (s.label.empty() ? std::string("notitle") : "title " + quote(s.label));
  }
  return cmd + "\n";
}

void polar_chart(std::ostringstream& s, const PolarChart& chart, std::size_t index) {
  std::vector<Prepared> prepared;
  double r_max = 0.0;
  for (std::size_t k = 0; k < chart.series.size(); ++k) {
    const std::string name = "$s" + std::to_string(index) + "_" + std::to_string(k);
    if (!write_block(s, name, chart.series[k], false, false)) continue;
    prepared.push_back({name, &chart.series[k]});
    for (double r : chart.series[k].y)
      if (std::isfinite(r)) r_max = std::max(r_max, r);
  }
  // Four or five grid circles at a round step.
  const double r_step = r_max > 0.0 ? nice_ceiling(r_max / 5.0) : 0.25;
  r_max = r_max > 0.0 ? std::ceil(r_max / r_step * (1.0 - 1e-12)) * r_step : 1.0;
  s << "reset\nset polar\nset angles degrees\nset theta bottom counterclockwise\n"
       "set size square\nunset border\nunset xtics\nunset ytics\n"
       "set grid polar 30 lt 1 lc rgb '#c8c8c8' dt 3\n"
    << "set rrange [0:" << format_number(r_max, 17) << "]\n"
    << "set xrange [" << format_number(-r_max, 17) << ":" << format_number(r_max, 17) << "]\n"
    << "set yrange [" << format_number(-r_max, 17) << ":" << format_number(r_max, 17) << "]\n"
    << "set rtics " << format_number(r_step, 17) << " format '%g' font ',9'\n"
    << "set ttics (";
  for (int a = -150; a <= 180; a += 30)
    s << (a == -150 ? "" : ", ") << "'" << std::abs(a) << "°' " << a;
  s << ")\nset key below\n";
  if (!chart.title.empty()) s << "set title " << quote(chart.title) << "\n";
  if (!chart.radius_label.empty())
    s << "set label 1 " << quote("[" + chart.radius_label + "]") << " at graph 1, graph 1 right\n";
  s << (prepared.empty() ? "plot 1/0 notitle\n" : plot_command(prepared));
}

void line_chart(std::ostringstream& s, const LineChart& chart, std::size_t index) {
  std::vector<Prepared> prepared;
  for (std::size_t k = 0; k < chart.series.size(); ++k) {
    const std::string name = "$s" + std::to_string(index) + "_" + std::to_string(k);
    if (!write_block(s, name, chart.series[k], chart.log_x, chart.log_y)) continue;
    prepared.push_back({name, &chart.series[k]});
  }
  const auto range = [](std::optional<double> lo, std::optional<double> hi, bool empty, bool log) {
    if (empty && !lo && !hi) return std::string(log ? "[1:10]" : "[0:1]");
    return "[" + (lo ? format_number(*lo, 17) : std::string("*")) + ":" +
           (hi ? format_number(*hi, 17) : std::string("*")) + "]";
  };
  s << "reset\nset grid lt 1 lc rgb '#d8d8d8'\n" << (chart.key_below ? "set key below\n" : "set key top right\n")
    << "set xrange " << range(chart.x_min, chart.x_max, prepared.empty(), chart.log_x) << "\n"
    << "set yrange " << range(chart.y_min, chart.y_max, prepared.empty(), chart.log_y) << "\n";
  if (chart.log_x) s << "set logscale x\nset format x '%g'\n";
  if (chart.log_y) s << "set logscale y\nset format y '%g'\n";
  if (!chart.title.empty()) s << "set title " << quote(chart.title) << "\n";
  if (!chart.x_label.empty()) s << "set xlabel " << quote(chart.x_label) << "\n";
  if (!chart.y_label.empty()) s << "set ylabel " << quote(chart.y_label) << "\n";
  s << (prepared.empty() ? "plot 1/0 notitle\n" : plot_command(prepared));
}

Result<std::string> script_for(const Figure& figure, ImageFormat format) {
  if (figure.charts.empty()) return make_error("a figure needs at least one chart");
  if (figure.width_px < 100 || figure.width_px > 10000 || figure.height_px < 100 ||
      figure.height_px > 10000)
    return make_error("figure size " + std::to_string(figure.width_px) + "x" +
                      std::to_string(figure.height_px) + " is outside 100..10000 pixels");
  for (const Chart& chart : figure.charts) {
    const auto& series = std::holds_alternative<PolarChart>(chart) ? std::get<PolarChart>(chart).series
                                                                   : std::get<LineChart>(chart).series;
    for (const Series& s : series)
      if (s.x.size() != s.y.size())
        return make_error("series '" + s.label + "' has " + std::to_string(s.x.size()) + " x and " +
                          std::to_string(s.y.size()) + " y values");
  }
  std::ostringstream s;
  const std::string size = std::to_string(figure.width_px) + "," + std::to_string(figure.height_px);
  if (format == ImageFormat::Svg)
    s << "set terminal svg size " << size << " dynamic background rgb 'white' font 'DejaVu Sans,11'\n";
  else
    s << "set terminal pngcairo size " << size << " background rgb 'white' font 'DejaVu Sans,10'\n";
  s << "set encoding utf8\nset termoption noenhanced\n"
    << "set multiplot layout 1," << figure.charts.size();
  if (!figure.title.empty()) s << " title " << quote(figure.title) << " font ',13'";
  s << "\n";
  for (std::size_t k = 0; k < figure.charts.size(); ++k) {
    if (const auto* polar = std::get_if<PolarChart>(&figure.charts[k]))
      polar_chart(s, *polar, k);
    else
      line_chart(s, std::get<LineChart>(figure.charts[k]), k);
  }
  s << "unset multiplot\n";
  return s.str();
}

// Runs gnuplot on a script; returns what it wrote to standard output.
Result<std::string> run_gnuplot(const std::string& script) {
  ScratchDir dir("gonio-plot");
  if (dir.path().empty()) return make_error(std::string("cannot create a scratch directory: ") + std::strerror(errno));
  const std::string script_path = (dir.path() / "figure.gp").string();
  {
    std::ofstream f(script_path, std::ios::binary);
    f << script;
    if (!f) return make_error("cannot write the plot script to " + script_path);
  }
  const char* env = std::getenv("GONIO_GNUPLOT");
  const std::string program = env && *env ? env : "gnuplot";
  Result<ProcessOutput> run = run_program(
      {program, script_path}, kTimeout, kMaxImageBytes,
      "plots need gnuplot, Debian package gnuplot-nox (scripts/setup.sh installs it), or "
      "$GONIO_GNUPLOT naming the program");
  if (!run.ok()) return run.error();
  const std::string& messages = run.value().err;
  if (run.value().exit_code != 0)
    return make_error("gnuplot failed" +
                 (messages.empty() ? std::string() : ": " + last_lines(messages, 400)));
  if (run.value().out.empty())
    return make_error("gnuplot wrote no image" +
                 (messages.empty() ? std::string() : ": " + last_lines(messages, 400)));
  return std::move(run.value().out);
}

}  // namespace

Result<ImageFormat> image_format_for(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".svg") return ImageFormat::Svg;
  if (ext == ".png") return ImageFormat::Png;
  Error e;
  e.where.file = path;
  e.message = "cannot tell the image format: the name must end in .svg or .png";
  return e;
}

Result<std::string> render_figure(const Figure& figure, ImageFormat format) {
  Result<std::string> script = script_for(figure, format);
  if (!script.ok()) return script.error();
  return run_gnuplot(script.value());
}

Status write_figure(const std::string& path, const Figure& figure) {
  const Result<ImageFormat> format = image_format_for(path);
  if (!format.ok()) return format.error();
  Result<std::string> bytes = render_figure(figure, format.value());
  if (!bytes.ok()) {
    Error e = bytes.error();
    if (e.where.file.empty()) e.where.file = path;
    return e;
  }
  return write_file_atomic(path, bytes.value());
}

}  // namespace gonio::io
