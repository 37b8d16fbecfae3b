#include "photometry/ugr.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/flux.h"
#include "photometry/intensity_sampler.h"
#include "photometry/luminance.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kH = 2.0;  // luminaire plane above the eye [m]
constexpr std::size_t kRooms = 19;

// ------------------------------------------------------------ CIE 190 tables

// CIE 190:2010 Table 4: the weights F_GL1…4 of the cumulative zonal fluxes
// Φ1…4 in the direct flux on the floor cavity, by room index k.
struct FloorWeights {
  double k;
  std::array<double, 4> f_gl;
};
constexpr std::array<FloorWeights, 13> kCie190Table4 = {{
    {1.00, {0.690, 0.109, 0.085, -0.016}},
    {1.20, {0.578, 0.200, 0.127, -0.018}},
    {4.0 / 3.0, {0.528, 0.218, 0.170, -0.017}},
    {1.50, {0.485, 0.215, 0.222, -0.012}},
    {1.60, {0.466, 0.207, 0.249, -0.006}},
    {12.0 / 7.0, {0.448, 0.198, 0.272, 0.005}},
    {2.00, {0.338, 0.257, 0.351, -0.018}},
    {2.40, {0.296, 0.203, 0.449, -0.006}},
    {8.0 / 3.0, {0.280, 0.165, 0.499, 0.006}},
    {3.00, {0.264, 0.125, 0.541, 0.027}},
    {24.0 / 7.0, {0.248, 0.058, 0.628, 0.032}},
    {4.00, {0.239, -0.012, 0.690, 0.058}},
    {4.80, {0.232, -0.084, 0.740, 0.098}},
}};

// CIE 190:2010 Table 5: transfer factors (F_T,FW, F_T,WW − 1 as printed,
// F_T,CW) per reflectance set (kUgrReflectances' order) and room
// (ugr_room_sizes()' order).
using Transfer = std::array<double, 3>;
constexpr std::array<std::array<Transfer, kRooms>, 5> kCie190Table5 = {{
    {{{0.220, 0.422, 0.646}, {0.199, 0.376, 0.571}, {0.187, 0.351, 0.531}, {0.174, 0.322, 0.488},
      {0.167, 0.307, 0.466}, {0.160, 0.290, 0.443}, {0.187, 0.351, 0.531}, {0.158, 0.295, 0.439},
      {0.142, 0.265, 0.389}, {0.124, 0.230, 0.335}, {0.115, 0.211, 0.307}, {0.105, 0.190, 0.279},
      {0.115, 0.211, 0.307}, {0.094, 0.175, 0.247}, {0.083, 0.155, 0.215}, {0.071, 0.133, 0.183},
      {0.105, 0.190, 0.279}, {0.083, 0.153, 0.216}, {0.071, 0.133, 0.183}}},
    {{{0.188, 0.217, 0.553}, {0.173, 0.196, 0.497}, {0.164, 0.184, 0.465}, {0.154, 0.171, 0.432},
      {0.149, 0.164, 0.415}, {0.143, 0.156, 0.397}, {0.164, 0.184, 0.465}, {0.142, 0.159, 0.393},
      {0.129, 0.144, 0.351}, {0.114, 0.127, 0.307}, {0.106, 0.117, 0.283}, {0.098, 0.106, 0.259},
      {0.106, 0.117, 0.283}, {0.088, 0.098, 0.231}, {0.078, 0.088, 0.203}, {0.067, 0.076, 0.174},
      {0.098, 0.106, 0.259}, {0.078, 0.086, 0.204}, {0.067, 0.076, 0.174}}},
    {{{0.198, 0.380, 0.445}, {0.178, 0.338, 0.393}, {0.166, 0.314, 0.365}, {0.154, 0.287, 0.335},
      {0.147, 0.273, 0.320}, {0.141, 0.257, 0.304}, {0.166, 0.314, 0.364}, {0.140, 0.263, 0.301},
      {0.125, 0.235, 0.267}, {0.108, 0.204, 0.230}, {0.100, 0.187, 0.211}, {0.091, 0.167, 0.191},
      {0.100, 0.187, 0.211}, {0.081, 0.154, 0.169}, {0.071, 0.137, 0.147}, {0.061, 0.117, 0.125},
      {0.091, 0.167, 0.191}, {0.071, 0.134, 0.148}, {0.061, 0.117, 0.125}}},
    {{{0.172, 0.198, 0.386}, {0.157, 0.179, 0.346}, {0.148, 0.167, 0.324}, {0.138, 0.155, 0.301},
      {0.133, 0.147, 0.288}, {0.128, 0.140, 0.276}, {0.148, 0.167, 0.324}, {0.126, 0.143, 0.272},
      {0.114, 0.129, 0.244}, {0.100, 0.113, 0.212}, {0.093, 0.104, 0.196}, {0.085, 0.094, 0.179},
      {0.093, 0.104, 0.196}, {0.076, 0.087, 0.158}, {0.067, 0.078, 0.140}, {0.058, 0.067, 0.120},
      {0.085, 0.094, 0.179}, {0.068, 0.077, 0.140}, {0.058, 0.067, 0.120}}},
    {{{0.157, 0.181, 0.227}, {0.141, 0.162, 0.203}, {0.132, 0.151, 0.190}, {0.123, 0.139, 0.176},
      {0.118, 0.132, 0.169}, {0.113, 0.124, 0.161}, {0.132, 0.151, 0.190}, {0.112, 0.128, 0.159},
      {0.100, 0.115, 0.142}, {0.087, 0.101, 0.124}, {0.081, 0.092, 0.114}, {0.074, 0.083, 0.104},
      {0.081, 0.092, 0.114}, {0.066, 0.077, 0.092}, {0.058, 0.069, 0.081}, {0.049, 0.059, 0.069},
      {0.074, 0.083, 0.104}, {0.058, 0.067, 0.081}, {0.049, 0.059, 0.069}}},
}};

// CIE 117:1995 Table 4.1: Guth's position index p by T/R (rows 0, 0.1, …,
// 3.0) and H/R (columns 0, 0.1, …, 1.9); kNo where the table is blank (the
// source is out of the field of view).
constexpr double kNo = -1.0;
constexpr std::array<std::array<double, 20>, 31> kCie117Table41 = {{
    {{1.00, 1.26, 1.53, 1.90, 2.35, 2.86, 3.50, 4.20, 5.00, 6.00, 7.00, 8.10, 9.25, 10.35, 11.70, 13.15, 14.70, 16.20, kNo, kNo}},  // T/R 0.0
    {{1.05, 1.22, 1.46, 1.80, 2.20, 2.75, 3.40, 4.10, 4.80, 5.80, 6.80, 8.00, 9.10, 10.30, 11.60, 13.00, 14.60, 16.10, kNo, kNo}},  // T/R 0.1
    {{1.12, 1.30, 1.50, 1.80, 2.20, 2.66, 3.18, 3.88, 4.60, 5.50, 6.50, 7.60, 8.75, 9.85, 11.20, 12.70, 14.00, 15.70, kNo, kNo}},  // T/R 0.2
    {{1.22, 1.38, 1.60, 1.97, 2.25, 2.70, 3.25, 3.90, 4.60, 5.45, 6.45, 7.40, 8.40, 9.50, 10.85, 12.10, 13.70, 15.00, kNo, kNo}},  // T/R 0.3
    {{1.32, 1.47, 1.70, 1.96, 2.35, 2.80, 3.30, 3.90, 4.60, 5.40, 6.40, 7.30, 8.30, 9.40, 10.60, 11.90, 13.20, 14.60, 16.00, kNo}},  // T/R 0.4
    {{1.43, 1.60, 1.82, 2.10, 2.48, 2.91, 3.40, 3.98, 4.70, 5.50, 6.40, 7.30, 8.30, 9.40, 10.50, 11.75, 13.00, 14.40, 15.70, kNo}},  // T/R 0.5
    {{1.55, 1.72, 1.98, 2.30, 2.65, 3.10, 3.60, 4.10, 4.80, 5.50, 6.40, 7.35, 8.40, 9.40, 10.50, 11.70, 13.00, 14.10, 15.40, kNo}},  // T/R 0.6
    {{1.70, 1.88, 2.12, 2.48, 2.87, 3.30, 3.78, 4.30, 4.88, 5.60, 6.50, 7.40, 8.50, 9.50, 10.50, 11.70, 12.85, 14.00, 15.20, kNo}},  // T/R 0.7
    {{1.82, 2.00, 2.32, 2.70, 3.08, 3.50, 3.92, 4.50, 5.10, 5.75, 6.60, 7.50, 8.60, 9.50, 10.60, 11.75, 12.80, 14.00, 15.10, kNo}},  // T/R 0.8
    {{1.96, 2.20, 2.54, 2.90, 3.30, 3.70, 4.20, 4.75, 5.30, 6.00, 6.75, 7.70, 8.70, 9.65, 10.75, 11.80, 12.90, 14.00, 15.00, 16.00}},  // T/R 0.9
    {{2.11, 2.40, 2.75, 3.10, 3.50, 3.91, 4.40, 5.00, 5.60, 6.20, 7.00, 7.90, 8.80, 9.75, 10.80, 11.90, 12.95, 14.00, 15.00, 16.00}},  // T/R 1.0
    {{2.30, 2.55, 2.92, 3.30, 3.72, 4.20, 4.70, 5.25, 5.80, 6.55, 7.20, 8.15, 9.00, 9.90, 10.95, 12.00, 13.00, 14.00, 15.00, 16.00}},  // T/R 1.1
    {{2.40, 2.75, 3.12, 3.50, 3.90, 4.35, 4.85, 5.50, 6.05, 6.70, 7.50, 8.30, 9.20, 10.00, 11.02, 12.10, 13.10, 14.00, 15.00, 16.00}},  // T/R 1.2
    {{2.55, 2.90, 3.30, 3.70, 4.20, 4.65, 5.20, 5.70, 6.30, 7.00, 7.70, 8.55, 9.35, 10.20, 11.20, 12.25, 13.20, 14.00, 15.00, 16.00}},  // T/R 1.3
    {{2.70, 3.10, 3.50, 3.90, 4.35, 4.85, 5.35, 5.85, 6.50, 7.25, 8.00, 8.70, 9.50, 10.40, 11.40, 12.40, 13.25, 14.05, 15.00, 16.00}},  // T/R 1.4
    {{2.85, 3.15, 3.65, 4.10, 4.55, 5.00, 5.50, 6.20, 6.80, 7.50, 8.20, 8.85, 9.70, 10.55, 11.50, 12.50, 13.30, 14.05, 15.02, 16.00}},  // T/R 1.5
    {{2.95, 3.40, 3.80, 4.25, 4.75, 5.20, 5.75, 6.30, 7.00, 7.65, 8.40, 9.00, 9.80, 10.80, 11.75, 12.60, 13.40, 14.20, 15.10, 16.00}},  // T/R 1.6
    {{3.10, 3.55, 4.00, 4.50, 4.90, 5.40, 5.95, 6.50, 7.20, 7.80, 8.50, 9.20, 10.00, 10.85, 11.85, 12.75, 13.45, 14.20, 15.10, 16.00}},  // T/R 1.7
    {{3.25, 3.70, 4.20, 4.65, 5.10, 5.60, 6.10, 6.75, 7.40, 8.00, 8.65, 9.35, 10.10, 11.00, 11.90, 12.80, 13.50, 14.20, 15.10, 16.00}},  // T/R 1.8
    {{3.43, 3.86, 4.30, 4.75, 5.20, 5.70, 6.30, 6.90, 7.50, 8.17, 8.80, 9.50, 10.20, 11.00, 12.00, 12.82, 13.55, 14.20, 15.10, 16.00}},  // T/R 1.9
    {{3.50, 4.00, 4.50, 4.90, 5.35, 5.80, 6.40, 7.10, 7.70, 8.30, 8.90, 9.60, 10.40, 11.10, 12.00, 12.85, 13.60, 14.30, 15.10, 16.00}},  // T/R 2.0
    {{3.60, 4.17, 4.65, 5.05, 5.50, 6.00, 6.60, 7.20, 7.82, 8.45, 9.00, 9.75, 10.50, 11.20, 12.10, 12.90, 13.70, 14.35, 15.10, 16.00}},  // T/R 2.1
    {{3.75, 4.25, 4.72, 5.20, 5.60, 6.10, 6.70, 7.35, 8.00, 8.55, 9.15, 9.85, 10.60, 11.30, 12.10, 12.90, 13.70, 14.40, 15.15, 16.00}},  // T/R 2.2
    {{3.85, 4.35, 4.80, 5.25, 5.70, 6.22, 6.80, 7.40, 8.10, 8.65, 9.30, 9.90, 10.70, 11.40, 12.20, 12.95, 13.70, 14.40, 15.20, 16.00}},  // T/R 2.3
    {{3.95, 4.40, 4.90, 5.35, 5.80, 6.30, 6.90, 7.50, 8.20, 8.80, 9.40, 10.00, 10.80, 11.50, 12.25, 13.00, 13.75, 14.45, 15.20, 16.00}},  // T/R 2.4
    {{4.00, 4.50, 4.96, 5.40, 5.85, 6.40, 6.95, 7.55, 8.25, 8.85, 9.50, 10.05, 10.85, 11.55, 12.30, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 2.5
    {{4.07, 4.55, 5.05, 5.47, 5.95, 6.46, 7.00, 7.65, 8.35, 8.95, 9.55, 10.10, 10.90, 11.60, 12.32, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 2.6
    {{4.10, 4.60, 5.10, 5.53, 6.00, 6.50, 7.50, 7.70, 8.40, 9.00, 9.60, 10.16, 10.92, 11.63, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 2.7
    {{4.15, 4.62, 5.15, 5.56, 6.05, 6.55, 7.08, 7.73, 8.45, 9.05, 9.65, 10.20, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 2.8
    {{4.20, 4.65, 5.17, 5.60, 6.07, 6.57, 7.12, 7.75, 8.50, 9.10, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 2.9
    {{4.22, 4.67, 5.20, 5.65, 6.12, 6.60, 7.15, 7.80, 8.55, 9.12, 9.70, 10.23, 10.95, 11.65, 12.35, 13.00, 13.80, 14.50, 15.25, 16.00}},  // T/R 3.0
}};

const FloorWeights& floor_weights(double x_h, double y_h) {
  const double k = x_h * y_h / (x_h + y_h);
  const auto* best = &kCie190Table4[0];
  for (const auto& row : kCie190Table4)
    if (std::abs(row.k - k) < std::abs(best->k - k)) best = &row;
  return *best;
}

// The zonal split of CIE 190 §4.2 (eq. 9–12): Cie190Zones (ugr.h).
Cie190Zones cie190_zones(const Distribution& d, const IntensitySampler& s, double total_lm) {
  Cie190Zones z;
  const double lamps_lm = d.rated_lamp_flux_lm();
  const bool relative = !d.absolute && std::isfinite(lamps_lm) && lamps_lm > 0.0;
  z.reference_lm = relative ? lamps_lm : total_lm;
  double lor = relative ? total_lm / lamps_lm : 1.0;
  if (relative && std::isfinite(d.declared_lor_percent) && d.declared_lor_percent > 0.0)
    lor = d.declared_lor_percent / 100.0;
  // Mean intensity over the C-planes at the zone midpoints 5°, 15°, …, 175°
  // (linear along γ, 1° steps in C), times the zone factor 2π sin γ Δγ.
  std::vector<double> c_deg(360), g_deg(18);
  for (int i = 0; i < 360; ++i) c_deg[i] = i;
  for (int j = 0; j < 18; ++j) g_deg[j] = 5.0 + 10.0 * j;
  const std::vector<double> cd = s.grid(c_deg, g_deg);
  std::array<double, 18> g{};
  double sum = 0.0;
  for (int j = 0; j < 18; ++j) {
    double mean = 0.0;
    for (int i = 0; i < 360; ++i) mean += cd[static_cast<std::size_t>(i) * 18 + j];
    mean /= 360.0;
    g[j] = mean * 2.0 * kPi * std::sin(g_deg[j] * kDeg) * (10.0 * kDeg);
    sum += g[j];
  }
  if (!(sum > 0.0) || !(z.reference_lm > 0.0) || !(lor > 0.0)) return z;
  for (double& v : g) v *= lor / sum;  // G_H / 1000: fractions of Φ
  const auto first = [&](int n) {
    double a = 0.0;
    for (int j = 0; j < n; ++j) a += g[j];
    return a;
  };
  z.r_dlo = first(9);
  z.r_ulo = first(18) - z.r_dlo;
  z.phi = {first(4) + 0.130 * g[4], first(6), first(7) + 0.547 * g[7], first(9)};
  z.defined = true;
  return z;
}

// CIE 190 eq. 7–8: the background luminance of room `room` and reflectance
// set `set` with `n` luminaires [cd/m²].
double cie190_background(const Cie190Zones& z, std::size_t room, std::size_t set, double x_m, double y_m,
                         double n) {
  const auto& fgl = floor_weights(x_m / kH, y_m / kH).f_gl;
  double f_df = 0.0;
  for (int i = 0; i < 4; ++i) f_df += z.phi[i] * fgl[i];
  const double f_dw = z.r_dlo - f_df, f_dc = z.r_ulo;
  const Transfer& ft = kCie190Table5[set][room];
  const double f_uwid = f_df * ft[0] + f_dw * ft[1] + f_dc * ft[2];
  const double b = z.reference_lm * n / (2.0 * kH * (x_m + y_m));
  return b * f_uwid / kPi;
}

// ------------------------------------------------------------ flux transfer

// A floor plane X × Y at H below a uniform array of luminaires (room axes;
// the luminaire's C0 along room y, the line of sight, when crosswise, along
// room x when endwise), and the share of the array's downward flux that
// lands on it directly.
struct FloorPlane {
  double x_m = 0.0, y_m = 0.0;
  bool endwise = false;
  double fraction = 0.0;  // [1], filled by direct_floor_fractions()
};

// Fills every floor's `fraction`: the luminaire's intensity on a 1° (C) ×
// 0.25° (γ) midpoint grid of the lower hemisphere, weighted by its cell's
// solid angle; a ring at horizontal distance t = H tan γ along C lands from
// the share P = (1 − t|c_x|/X)₊ (1 − t|c_y|/Y)₊ of the luminaire positions
// (c_x, c_y the plane's direction in room axes). P falls with γ, so per
// plane the rings that land are a prefix, and Σ flux·P over it is
// Σflux − (a + b) Σflux·t + ab Σflux·t² with a = |c_x|/X, b = |c_y|/Y:
// prefix sums along γ and one search per plane and floor. Planes are sampled
// a few at a time (little memory).
void direct_floor_fractions(const IntensitySampler& s, std::vector<FloorPlane>& floors) {
  constexpr int kPlanes = 360, kRings = 360, kChunk = 24;
  static_assert(kPlanes % kChunk == 0);
  const double dc = 2 * kPi / kPlanes, dg = 0.5 * kPi / kRings;
  std::vector<double> g_deg(kRings), sin_g(kRings), t_m(kRings);
  for (int j = 0; j < kRings; ++j) {
    const double g = (j + 0.5) * dg;
    g_deg[j] = g / kDeg;
    sin_g[j] = std::sin(g);
    t_m[j] = std::tan(g) * kH;
  }
  std::vector<double> c_deg(kChunk), sum0(kRings + 1), sum1(kRings + 1), sum2(kRings + 1);
  std::vector<double> direct(floors.size(), 0.0);
  double total = 0.0;
  for (int first = 0; first < kPlanes; first += kChunk) {
    for (int k = 0; k < kChunk; ++k) c_deg[k] = (first + k + 0.5) * dc / kDeg;
    const std::vector<double> cd = s.grid(c_deg, g_deg);
    for (int k = 0; k < kChunk; ++k) {
      for (int j = 0; j < kRings; ++j) {
        const double f = cd[k * kRings + j] * sin_g[j] * dc * dg, t = t_m[j];
        sum0[j + 1] = sum0[j] + f;
        sum1[j + 1] = sum1[j] + f * t;
        sum2[j + 1] = sum2[j] + f * t * t;
      }
      total += sum0[kRings];
      const double c = (first + k + 0.5) * dc;
      const double abs_cos = std::abs(std::cos(c)), abs_sin = std::abs(std::sin(c));
      for (std::size_t q = 0; q < floors.size(); ++q) {
        const FloorPlane& fl = floors[q];
        const double cx = fl.endwise ? abs_cos : abs_sin, cy = fl.endwise ? abs_sin : abs_cos;
        const auto lands = [&](double t) {
          return std::max(0.0, 1.0 - t * cx / fl.x_m) * std::max(0.0, 1.0 - t * cy / fl.y_m) > 0.0;
        };
        const std::size_t n =
            static_cast<std::size_t>(std::partition_point(t_m.begin(), t_m.end(), lands) - t_m.begin());
        if (n == 0) continue;  // nothing lands (also a degenerate room of zero size)
        const double a = cx / fl.x_m, b = cy / fl.y_m;
        direct[q] += sum0[n] - (a + b) * sum1[n] + a * b * sum2[n];
      }
    }
  }
  for (std::size_t q = 0; q < floors.size(); ++q) floors[q].fraction = total > 0.0 ? direct[q] / total : 0.0;
}

// The background luminance of the flux-transfer model [cd/m²]: `n`
// luminaires of `down_lm` / `up_lm`, `floor_fraction` of the downward flux
// directly on the floor plane.
double flux_transfer_background(double x_m, double y_m, double n, double down_lm, double up_lm,
                                double floor_fraction, const std::array<double, 3>& rho) {
  const double af = x_m * y_m, aw = 2 * (x_m + y_m) * kH;
  const double f_fc = facing_rectangles_view_factor(x_m, y_m, kH);
  const double f_fw = 1 - f_fc, f_wf = f_fw * af / aw, f_ww = 1 - 2 * f_wf;
  const double down = n * down_lm, up = n * up_lm;
  const double on_floor = down * floor_fraction;
  // Direct flux onto ceiling, walls, floor; solve in = direct + Fᵀ ρ in.
  const double dir_c = up, dir_w = down - on_floor, dir_f = on_floor;
  const double rc = rho[0], rw = rho[1], rf = rho[2];
  // in_c = dir_c + f_fc rf in_f + f_wf rw in_w
  // in_w = dir_w + f_fw rc in_c + f_fw rf in_f + f_ww rw in_w
  // in_f = dir_f + f_fc rc in_c + f_wf rw in_w
  double m[3][4] = {{1, -f_wf * rw, -f_fc * rf, dir_c},
                    {-f_fw * rc, 1 - f_ww * rw, -f_fw * rf, dir_w},
                    {-f_fc * rc, -f_wf * rw, 1, dir_f}};
  for (int k = 0; k < 3; ++k) {
    for (int r = k + 1; r < 3; ++r) {
      const double q = m[r][k] / m[k][k];
      for (int c = k; c < 4; ++c) m[r][c] -= q * m[k][c];
    }
  }
  double in[3];
  for (int k = 2; k >= 0; --k) {
    double val = m[k][3];
    for (int c = k + 1; c < 3; ++c) val -= m[k][c] * in[c];
    in[k] = val / m[k][k];
  }
  return (in[1] - dir_w) / aw / kPi;
}

// ------------------------------------------------------------ glare

// L² ω / p² of one luminaire at T across and R along the line of sight from
// the eye [m] [(cd/m²)² sr]; 0 where CIE 117's cut-offs leave it out, where
// it sends no light toward the eye or shows no area.
double glare_term(const IntensitySampler& sampler, const LuminousOpening& opening, double t, double r,
                  bool endwise) {
  if (!(r > 0.0) || std::abs(t) > 3.0 * r * (1.0 + 1e-12)) return 0.0;
  const double horiz = std::hypot(t, r);
  const double g_deg = std::atan2(horiz, kH) / kDeg;
  if (g_deg > 85.0 + 1e-9) return 0.0;
  // The direction from the luminaire to the eye in the luminaire's frame:
  // crosswise its C0 points back along the line of sight, endwise its C90.
  double c_deg = (endwise ? std::atan2(r, t) : std::atan2(-t, r)) / kDeg;
  if (c_deg < 0) c_deg += 360;
  const double i_cd = sampler.cd(c_deg, g_deg);
  if (i_cd <= 0.0) return 0.0;
  const double ap = projected_area_m2(opening, c_deg, g_deg);
  if (ap <= 0.0) return 0.0;
  const double r2 = horiz * horiz + kH * kH;
  const double p = guth_position_index(t, r, kH);
  if (!std::isfinite(p)) return 0.0;  // out of the field of view (a blank of Table 4.1)
  return i_cd * i_cd / (ap * r2 * p * p);
}

// glare_term() for the luminaire positions the rooms of one table share:
// with the walls on the spacing's grid, every luminaire sits at T = (m/2) S,
// R = (j + ½) S from the eye for integers m, j, whatever the room, so each
// term is computed once per orientation (lazily; NaN marks one not computed
// yet). Positions off that grid are computed directly.
class GlareTerms {
 public:
  GlareTerms(const IntensitySampler& sampler, const LuminousOpening& opening, double spacing_m, int half_m,
             int rows)
      : sampler_(sampler), opening_(opening), spacing_m_(spacing_m), half_m_(half_m), rows_(rows) {
    for (auto& t : terms_) t.assign(static_cast<std::size_t>(2 * half_m + 1) * rows, kNaN);
  }

  double at(double t, double r, int j, bool endwise) {
    const double m = 2.0 * t / spacing_m_;
    const double mi = std::round(m);
    if (m != mi || std::abs(mi) > half_m_ || j < 0 || j >= rows_ || r != (j + 0.5) * spacing_m_)
      return glare_term(sampler_, opening_, t, r, endwise);
    double& slot = terms_[endwise][static_cast<std::size_t>(static_cast<int>(mi) + half_m_) * rows_ + j];
    if (std::isnan(slot)) slot = glare_term(sampler_, opening_, t, r, endwise);
    return slot;
  }

 private:
  const IntensitySampler& sampler_;
  const LuminousOpening& opening_;
  double spacing_m_;
  int half_m_, rows_;
  std::vector<double> terms_[2];
};

struct Array {
  double x_m = 0, y_m = 0;  // room [m]
  int nx = 0, ny = 0;       // luminaires across and along the line of sight
  double n() const { return static_cast<double>(nx) * ny; }
};

Array array_of(double x_h, double y_h, double spacing_h) {
  Array a;
  a.x_m = x_h * kH;
  a.y_m = y_h * kH;
  const double s = spacing_h * kH;
  a.nx = std::max(1, static_cast<int>(std::lround(a.x_m / s)));
  a.ny = std::max(1, static_cast<int>(std::lround(a.y_m / s)));
  return a;
}

// Σ L² ω / p² over the array seen crosswise or endwise.
double glare_sum(GlareTerms& terms, const Array& a, double spacing_h, bool endwise) {
  const double s = spacing_h * kH;
  double sum = 0.0;
  for (int i = 0; i < a.nx; ++i) {
    const double t = (i + 0.5) * s - a.x_m / 2;
    for (int j = 0; j < a.ny; ++j) sum += terms.at(t, (j + 0.5) * s, j, endwise);
  }
  return sum;
}

double ugr_value(double sum, double lb) {
  if (!(lb > 0.0) || !(sum > 0.0)) return kNaN;
  return 8.0 * std::log10(0.25 / lb * sum);
}

bool has_area(const LuminousOpening& o) {
  return projected_area_m2(o, 0.0, 60.0) > 0.0 || projected_area_m2(o, 90.0, 60.0) > 0.0;
}

}  // namespace

const char* to_string(UgrBackground b) {
  switch (b) {
    case UgrBackground::Cie190:
      return "cie190";
    case UgrBackground::FluxTransfer:
      return "flux-transfer";
  }
  return "?";
}

std::optional<UgrBackground> parse_ugr_background(std::string_view text) {
  for (UgrBackground b : {UgrBackground::Cie190, UgrBackground::FluxTransfer})
    if (text == to_string(b)) return b;
  return std::nullopt;
}

std::vector<std::array<double, 2>> ugr_room_sizes() {
  std::vector<std::array<double, 2>> rooms;
  for (double x : {2.0, 4.0})
    for (double y : {2.0, 3.0, 4.0, 6.0, 8.0, 12.0}) rooms.push_back({x, y});
  for (double y : {4.0, 6.0, 8.0, 12.0}) rooms.push_back({8.0, y});
  for (double y : {4.0, 6.0, 8.0}) rooms.push_back({12.0, y});
  return rooms;
}

double guth_position_index(double t, double r, double h) {
  if (!(r > 0.0)) return kNaN;
  const double x = std::abs(t) / r * 10.0, y = std::abs(h) / r * 10.0;  // in table steps
  if (!(x <= 30.0 + 1e-9) || !(y <= 19.0 + 1e-9)) return kNaN;
  const int i = std::min(29, static_cast<int>(std::floor(x))), j = std::min(18, static_cast<int>(std::floor(y)));
  const double fx = std::clamp(x - i, 0.0, 1.0), fy = std::clamp(y - j, 0.0, 1.0);
  double p = 0.0;
  for (int di = 0; di < 2; ++di)
    for (int dj = 0; dj < 2; ++dj) {
      const double w = (di ? fx : 1.0 - fx) * (dj ? fy : 1.0 - fy);
      if (w == 0.0) continue;  // a corner the point does not use
      const double v = kCie117Table41[static_cast<std::size_t>(i + di)][static_cast<std::size_t>(j + dj)];
      if (v == kNo) return kNaN;  // next to a blank: out of the field of view
      p += w * v;
    }
  return p;
}

double ugr(const Distribution& d, std::size_t room, std::size_t reflectance_set, bool endwise,
           const UgrOptions& options) {
  GONIO_CHECK_MSG(validate(d).ok(), "ugr needs a valid distribution");
  GONIO_CHECK_MSG(room < kRooms && reflectance_set < kUgrReflectances.size(), "ugr: no such room or set");
  const auto [x_h, y_h] = ugr_room_sizes()[room];
  const IntensitySampler s(d);
  GlareTerms terms(s, d.opening, options.spacing_h * kH, 0, 0);
  const Array a = array_of(x_h, y_h, options.spacing_h);
  const double sum = glare_sum(terms, a, options.spacing_h, endwise);
  if (options.background == UgrBackground::Cie190) {
    const Cie190Zones z = cie190_zones(d, s, total_flux_lm(d));
    if (!z.defined) return kNaN;
    return ugr_value(sum, cie190_background(z, room, reflectance_set, a.x_m, a.y_m, a.n()));
  }
  std::vector<FloorPlane> floor{{a.x_m, a.y_m, endwise, 0.0}};
  direct_floor_fractions(s, floor);
  return ugr_value(sum, flux_transfer_background(a.x_m, a.y_m, a.n(), downward_flux_lm(d), upward_flux_lm(d),
                                                 floor[0].fraction, kUgrReflectances[reflectance_set]));
}

UgrTable ugr_table(const Distribution& d, const UgrOptions& options) {
  GONIO_CHECK_MSG(validate(d).ok(), "ugr_table needs a valid distribution");
  UgrTable t;
  t.background = options.background;
  t.spacing_h = options.spacing_h;
  t.flux_lm = total_flux_lm(d);
  if (!has_area(d.opening)) {
    t.why_undefined = "no luminous area toward the observer (point opening or one facing away): "
                      "UGR needs the luminaire's luminance";
    return t;
  }
  const double down_lm = downward_flux_lm(d), up_lm = upward_flux_lm(d);
  if (!(down_lm > 0.0) && !(up_lm > 0.0)) {
    t.why_undefined = "the distribution emits no light";
    return t;
  }
  const IntensitySampler s(d);
  const std::vector<std::array<double, 2>> sizes = ugr_room_sizes();
  double max_x_h = 0.0, max_y_h = 0.0;  // bound the luminaire positions (GlareTerms)
  for (const auto& [x, y] : sizes) {
    max_x_h = std::max(max_x_h, x);
    max_y_h = std::max(max_y_h, y);
  }
  GlareTerms terms(s, d.opening, t.spacing_h * kH, static_cast<int>(std::lround(max_x_h / t.spacing_h)),
                   static_cast<int>(std::lround(max_y_h / t.spacing_h)));
  Cie190Zones zones;
  std::vector<FloorPlane> floors;  // flux transfer: crosswise, endwise per room
  if (options.background == UgrBackground::Cie190) {
    zones = cie190_zones(d, s, t.flux_lm);
    if (!zones.defined) {
      t.why_undefined = "no flux in CIE 190's zones (the intensities at the zone midpoints are all 0)";
      return t;
    }
  } else {
    for (const auto& [x, y] : sizes)
      for (bool endwise : {false, true}) floors.push_back({x * kH, y * kH, endwise, 0.0});
    direct_floor_fractions(s, floors);
  }
  bool any = false;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    const auto [x, y] = sizes[r];
    const Array a = array_of(x, y, t.spacing_h);
    UgrRoom room;
    room.x_h = x;
    room.y_h = y;
    const double cross = glare_sum(terms, a, t.spacing_h, false);
    const double end = glare_sum(terms, a, t.spacing_h, true);
    for (std::size_t k = 0; k < kUgrReflectances.size(); ++k) {
      if (options.background == UgrBackground::Cie190) {
        const double lb = cie190_background(zones, r, k, a.x_m, a.y_m, a.n());
        room.crosswise[k] = ugr_value(cross, lb);
        room.endwise[k] = ugr_value(end, lb);
      } else {
        const auto& rho = kUgrReflectances[k];
        room.crosswise[k] = ugr_value(cross, flux_transfer_background(a.x_m, a.y_m, a.n(), down_lm, up_lm,
                                                                      floors[2 * r].fraction, rho));
        room.endwise[k] = ugr_value(end, flux_transfer_background(a.x_m, a.y_m, a.n(), down_lm, up_lm,
                                                                  floors[2 * r + 1].fraction, rho));
      }
      any = any || std::isfinite(room.crosswise[k]) || std::isfinite(room.endwise[k]);
    }
    t.rooms.push_back(room);
  }
  if (!any) {
    t.rooms.clear();
    t.why_undefined = "no light from the luminaires reaches the observer's eye (e.g. an uplight)";
    return t;
  }
  t.defined = true;
  return t;
}

Cie190Zones cie190_zones(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "cie190_zones needs a valid distribution");
  const IntensitySampler s(d);
  return cie190_zones(d, s, total_flux_lm(d));
}

}  // namespace gonio::photometry
