#include "sim/emitters/emission.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "photometry/angles.h"
#include "photometry/frame.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

Result<ProfileSampler> ProfileSampler::create(const photometry::Distribution& profile) {
  if (Status s = photometry::validate(profile); !s.ok())
    return make_error("invalid emission profile: " + s.error().message);

  ProfileSampler s;
  s.type_ = profile.type;
  // Which grid axis is the polar one, and its solid-angle measure μ(p) with
  // dΩ = dμ dq (q the other, azimuthal axis):
  //   Type C: p = γ (vertical), μ = −cos γ;  Type B: p = H (horizontal),
  //   μ = sin H;  Type A: p = V (vertical), μ = sin V  (photometry/angles.h).
  s.polar_is_vertical_ = profile.type != photometry::PhotometricType::B;
  s.polar_is_gamma_ = profile.type == photometry::PhotometricType::C;
  auto expanded = std::make_shared<photometry::Distribution>(photometry::expand_symmetry(profile));
  const auto& hs = expanded->horizontal_deg;
  const auto& vs = expanded->vertical_deg;
  auto mu = [&](double p) { return s.polar_is_gamma_ ? -std::cos(p) : std::sin(p); };
  std::vector<double> flux;
  // Type C cells wider than 45° in C (coarse or rotational grids) are cut
  // into equal parts along C: the bilinear interpolant is linear along C, so
  // the parts are cells of the same interpolant, and inside every cell the
  // offset from its middle C angle stays within ±22.5° (sincos_small).
  constexpr double kMaxCellC = std::numbers::pi / 4.0;
  const auto along = [](double a, double b, double t) { return a + t * (b - a); };
  for (std::size_t h = 0; h + 1 < hs.size(); ++h) {
    const double dh_grid = (hs[h + 1] - hs[h]) * kDeg;
    const int parts =
        s.polar_is_gamma_ ? std::max(1, static_cast<int>(std::ceil(dh_grid / kMaxCellC - 1e-9))) : 1;
    for (std::size_t v = 0; v + 1 < vs.size(); ++v) {
      for (int k = 0; k < parts; ++k) {
        const double s0 = static_cast<double>(k) / parts, s1 = static_cast<double>(k + 1) / parts;
        Cell c;
        c.h0_rad = hs[h] * kDeg + s0 * dh_grid;
        c.dh_rad = dh_grid / parts;
        c.v0_rad = vs[v] * kDeg;
        c.dv_rad = (vs[v + 1] - vs[v]) * kDeg;
        c.i00 = along(expanded->at(h, v), expanded->at(h + 1, v), s0);
        c.i10 = along(expanded->at(h, v), expanded->at(h + 1, v), s1);
        c.i01 = along(expanded->at(h, v + 1), expanded->at(h + 1, v + 1), s0);
        c.i11 = along(expanded->at(h, v + 1), expanded->at(h + 1, v + 1), s1);
        c.i_min = std::min({c.i00, c.i10, c.i01, c.i11});
        c.i_max = std::max({c.i00, c.i10, c.i01, c.i11});
        c.cos_mid = std::cos(c.h0_rad + 0.5 * c.dh_rad);
        c.sin_mid = std::sin(c.h0_rad + 0.5 * c.dh_rad);
        const double p0 = s.polar_is_vertical_ ? c.v0_rad : c.h0_rad;
        const double dp = s.polar_is_vertical_ ? c.dv_rad : c.dh_rad;
        const double dq = s.polar_is_vertical_ ? c.dh_rad : c.dv_rad;
        const double p1 = p0 + dp;
        c.mu0 = mu(p0);
        c.mu1 = mu(p1);
        c.sin_p0 = std::sin(p0);
        c.cos_p0 = std::cos(p0);
        c.sin_p1 = std::sin(p1);
        c.cos_p1 = std::cos(p1);
        c.sin_pmid = std::sin(p0 + 0.5 * dp);
        c.cos_pmid = std::cos(p0 + 0.5 * dp);
        // ∫∫ I dμ dq of the bilinear interpolant: along q each corner's weight
        // integrates to Δq/2; along p, a1 = ∫ t dμ (t = (p − p0)/Δp) is
        //   (sin p1 − sin p0)/Δp − cos p1      for μ = −cos p,
        //   sin p1 + (cos p1 − cos p0)/Δp      for μ = sin p,
        // and ∫ (1 − t) dμ = μ1 − μ0 − a1.
        const double a1 = s.polar_is_gamma_ ? (std::sin(p1) - std::sin(p0)) / dp - std::cos(p1)
                                            : std::sin(p1) + (std::cos(p1) - std::cos(p0)) / dp;
        const double a0 = (c.mu1 - c.mu0) - a1;
        const double at_p0 = s.polar_is_vertical_ ? c.i00 + c.i10 : c.i00 + c.i01;
        const double at_p1 = s.polar_is_vertical_ ? c.i01 + c.i11 : c.i10 + c.i11;
        const double f = 0.5 * dq * (at_p0 * a0 + at_p1 * a1);
        if (!(f > 0.0)) continue;  // emits nothing: never chosen
        s.cells_.push_back(c);
        flux.push_back(f);
      }
    }
  }
  if (flux.empty()) return make_error("emission profile has no flux (all intensities zero)");
  s.cell_table_ = AliasTable(flux);
  s.flux_lm_ = s.cell_table_.total_weight();
  s.expanded_ = std::move(expanded);
  return s;
}

Vec3 ProfileSampler::sample(PhotonRandom& rng) const {
  const Cell& c = cells_[cell_table_.sample(rng.uniform())];
  if (rng.low_discrepancy()) {
    double u1, u2;
    rng.uniform_pair(&u1, &u2);
    return sample_in_cell(c, u1, u2);
  }
  for (;;) {
    // Uniform in solid angle over the cell: uniform along q and in μ.
    const double u = rng.uniform();
    const double m = c.mu0 + rng.uniform() * (c.mu1 - c.mu0);
    const double r = rng.uniform() * c.i_max;
    // Type C: below the smallest corner the bilinear intensity accepts
    // whatever the polar position, and the direction needs only μ and C, so
    // the acos is skipped (the same draws and the same photons as the full
    // test, which follows).
    const auto type_c_direction = [&](double s) {
      double sd, cd;  // of the offset from the cell's middle C angle, |offset| ≤ 22.5°
      sincos_small((s - 0.5) * c.dh_rad, &sd, &cd);
      const double sin_g = std::sqrt(std::max(0.0, 1.0 - m * m));
      return Vec3{sin_g * (c.cos_mid * cd - c.sin_mid * sd), sin_g * (c.sin_mid * cd + c.cos_mid * sd),
                  m};  // z = −cos γ = μ
    };
    if (polar_is_gamma_ && r < c.i_min) return type_c_direction(u);
    const double p = polar_is_gamma_ ? std::acos(std::clamp(-m, -1.0, 1.0))
                                     : std::asin(std::clamp(m, -1.0, 1.0));
    const double p0 = polar_is_vertical_ ? c.v0_rad : c.h0_rad;
    const double dp = polar_is_vertical_ ? c.dv_rad : c.dh_rad;
    const double tp = std::clamp((p - p0) / dp, 0.0, 1.0);
    const double s = polar_is_vertical_ ? u : tp;  // along H (or C)
    const double t = polar_is_vertical_ ? tp : u;  // along V (or γ)
    const double i = (1.0 - t) * ((1.0 - s) * c.i00 + s * c.i10) + t * ((1.0 - s) * c.i01 + s * c.i11);
    if (r < i) {
      if (polar_is_gamma_) return type_c_direction(s);
      return photometry::direction_from_grid(type_, (c.h0_rad + s * c.dh_rad) / kDeg,
                                             (c.v0_rad + t * c.dv_rad) / kDeg);
    }
  }
}

Vec3 ProfileSampler::sample_in_cell(const Cell& c, double u1, double u2) const {
  // Type C, the intensity constant along γ at both C ends (a hard-edged
  // cone's one cell, flat parts of a profile): the marginal is uniform in
  // μ = −cos γ and inverts exactly, without the Newton steps below (which
  // reach the same μ to 10⁻¹² of the cell; a wide cell's take the library's
  // sin and cos at every step).
  if (polar_is_gamma_ && c.i00 == c.i01 && c.i10 == c.i11) {
    const double m = c.mu0 + u1 * (c.mu1 - c.mu0);
    const double lo = c.i00, hi = c.i10;
    double a = u2;  // uniform along C where the two ends agree
    if (lo != hi) {
      const double denominator = std::sqrt((1.0 - u2) * lo * lo + u2 * hi * hi) + lo;
      if (denominator > 0.0) a = std::clamp(u2 * (lo + hi) / denominator, 0.0, 1.0);
    }
    double sd, cd;  // of the offset from the cell's middle C angle, |offset| ≤ 22.5°
    sincos_small((a - 0.5) * c.dh_rad, &sd, &cd);
    const double sin_g = std::sqrt(std::max(0.0, 1.0 - m * m));
    return {sin_g * (c.cos_mid * cd - c.sin_mid * sd), sin_g * (c.sin_mid * cd + c.cos_mid * sd), m};
  }
  // The polar axis p (γ, H or V) and its fraction t = (p − p0)/Δp; the
  // azimuthal fraction a along the other axis. The bilinear intensity's
  // mean over a at the polar ends: i_p0, i_p1.
  const double p0 = polar_is_vertical_ ? c.v0_rad : c.h0_rad;
  const double dp = polar_is_vertical_ ? c.dv_rad : c.dh_rad;
  const double i_p0 = 0.5 * (polar_is_vertical_ ? c.i00 + c.i10 : c.i00 + c.i01);
  const double i_p1 = 0.5 * (polar_is_vertical_ ? c.i01 + c.i11 : c.i10 + c.i11);
  // Marginal CDF along p: G(p) = ∫ ((1 − t) i_p0 + t i_p1) dμ from p0, with
  //   μ = −cos p:  ∫ dμ = cos p0 − cos p,  ∫ t dμ = (sin p − sin p0 − (p − p0) cos p)/Δp
  //   μ = sin p:   ∫ dμ = sin p − sin p0,  ∫ t dμ = ((p − p0) sin p + cos p − cos p0)/Δp
  const double sin_p0 = c.sin_p0, cos_p0 = c.cos_p0;
  const auto cdf = [&](double p, double sp, double cp) {
    const double whole = polar_is_gamma_ ? cos_p0 - cp : sp - sin_p0;
    const double with_t = polar_is_gamma_ ? (sp - sin_p0 - (p - p0) * cp) / dp
                                          : ((p - p0) * sp + cp - cos_p0) / dp;
    return i_p0 * whole + (i_p1 - i_p0) * with_t;
  };
  const double p1 = p0 + dp;
  const double total = cdf(p1, c.sin_p1, c.cos_p1);
  const double target = u1 * total;
  // sin and cos of p in the cell: about its middle by their Taylor series
  // to x⁷ and x⁸ where the cell spans at most 0.1 rad (truncation below
  // 3·10⁻¹⁸ at |x| ≤ 0.05), by sincos_small to π/4, by the library beyond.
  const double p_mid = p0 + 0.5 * dp;
  const bool tiny = dp <= 0.1, small = dp <= std::numbers::pi / 4.0;
  const auto trig = [&](double q, double* sq, double* cq) {
    if (!small) {
      *sq = std::sin(q);
      *cq = std::cos(q);
      return;
    }
    double sd, cd;
    const double x = q - p_mid;
    if (tiny) {
      const double x2 = x * x;
      sd = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040))));
      cd = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320))));
    } else {
      sincos_small(x, &sd, &cd);
    }
    *sq = c.sin_pmid * cd + c.cos_pmid * sd;
    *cq = c.cos_pmid * cd - c.sin_pmid * sd;
  };
  // x with density ∝ (1 − x)·lo + x·hi on [0, 1] (lo, hi ≥ 0): the root of
  // the quadratic CDF, written without cancellation.
  const auto invert_linear = [](double u, double lo, double hi) {
    const double denominator = std::sqrt((1.0 - u) * lo * lo + u * hi * hi) + lo;
    return denominator > 0.0 ? std::clamp(u * (lo + hi) / denominator, 0.0, 1.0) : u;
  };
  // First guess: the density along t taken as linear between its values at
  // the ends (intensity × dμ/dp), then safeguarded Newton steps on
  // G(p) = target inside [p0, p1].
  const double w0 = polar_is_gamma_ ? c.sin_p0 : c.cos_p0, w1 = polar_is_gamma_ ? c.sin_p1 : c.cos_p1;
  double p = p0 + invert_linear(u1, i_p0 * w0, i_p1 * w1) * dp;
  double lo = p0, hi = p1;
  double sp, cp;
  trig(p, &sp, &cp);
  for (int k = 0; k < 24; ++k) {
    const double g = cdf(p, sp, cp) - target;
    // Done at 10⁻¹² of the cell's flux (the uniforms have steps of 2⁻³²);
    // stopping here also keeps rounding noise from sending the steps on.
    if (std::abs(g) <= 1e-12 * total) break;
    if (g > 0.0) hi = p; else lo = p;
    const double t = (p - p0) / dp;
    const double density = ((1.0 - t) * i_p0 + t * i_p1) * (polar_is_gamma_ ? sp : cp);
    double next = density > 0.0 ? p - g / density : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // bisection where Newton leaves the bracket
    const double step = std::abs(next - p);
    p = next;
    trig(p, &sp, &cp);
    if (step <= 1e-12 * dp) break;
  }
  const double tp = std::clamp((p - p0) / dp, 0.0, 1.0);
  // Along the azimuthal axis the intensity is linear between its values at
  // a = 0 and a = 1 for this polar position.
  const double a_lo = polar_is_vertical_ ? (1.0 - tp) * c.i00 + tp * c.i01 : (1.0 - tp) * c.i00 + tp * c.i10;
  const double a_hi = polar_is_vertical_ ? (1.0 - tp) * c.i10 + tp * c.i11 : (1.0 - tp) * c.i01 + tp * c.i11;
  const double a = invert_linear(u2, a_lo, a_hi);
  if (polar_is_gamma_) {
    double sd, cd;  // of the offset from the cell's middle C angle, |offset| ≤ 22.5°
    sincos_small((a - 0.5) * c.dh_rad, &sd, &cd);
    return {sp * (c.cos_mid * cd - c.sin_mid * sd), sp * (c.sin_mid * cd + c.cos_mid * sd), -cp};
  }
  const double s = polar_is_vertical_ ? a : tp;  // along H
  const double t = polar_is_vertical_ ? tp : a;  // along V
  return photometry::direction_from_grid(type_, (c.h0_rad + s * c.dh_rad) / kDeg, (c.v0_rad + t * c.dv_rad) / kDeg);
}

double ProfileSampler::intensity_cd(const Vec3& local) const {
  return photometry::intensity_toward(*expanded_, local);
}

Result<AreaSampler> AreaSampler::create(const Mesh& mesh, bool two_sided) {
  if (mesh.indices.size() % 3 != 0)
    return make_error("mesh '" + mesh.name + "': index count is not a multiple of 3");
  AreaSampler s;
  s.two_sided_ = two_sided;
  std::vector<double> areas;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = mesh.indices[3 * t + k];
      if (i >= mesh.positions.size())
        return make_error("mesh '" + mesh.name + "': vertex index out of range");
      p[k] = to_double(mesh.positions[i]);
    }
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const double area = 0.5 * length(n);
    if (!(area > 0.0) || !std::isfinite(area)) continue;  // degenerate: emits nothing
    s.triangles_.push_back({p[0], p[1] - p[0], p[2] - p[0], basis_from_normal(n / (2.0 * area))});
    s.triangle_index_.push_back(static_cast<std::uint32_t>(t));
    areas.push_back(area);
  }
  if (areas.empty()) return make_error("emitting mesh '" + mesh.name + "' has no area");
  s.triangle_table_ = AliasTable(areas);
  s.area_m2_ = s.triangle_table_.total_weight();
  return s;
}

AreaSampler::Sample AreaSampler::sample(PhotonRandom& rng) const {
  const std::uint32_t k = triangle_table_.sample(rng.uniform());
  const Barycentric b = sample_uniform_triangle(rng.uniform(), rng.uniform());
  const Triangle& tri = triangles_[k];
  Sample out;
  out.position = tri.corner + b.b1 * tri.edge1 + b.b2 * tri.edge2;
  // The back side's basis: (t, −b, −n) is orthonormal and right-handed too.
  const bool back = two_sided_ && rng.uniform() < 0.5;
  const Basis frame = back ? Basis{tri.front.t, -tri.front.b, -tri.front.n} : tri.front;
  out.normal = frame.n;
  // Unit to rounding: an orthonormal basis applied to a unit vector.
  out.direction = frame.to_world(sample_cosine_hemisphere(rng));
  out.triangle = triangle_index_[k];
  return out;
}

double AreaSampler::pdf(const Vec3& front_normal, const Vec3& direction) const {
  const double c = dot(front_normal, direction);
  if (two_sided_) return 0.5 / area_m2_ * std::abs(c) / std::numbers::pi;
  return c > 0.0 ? c / (area_m2_ * std::numbers::pi) : 0.0;
}

Result<EmissionSampler> EmissionSampler::create(const SceneDesc& scene) {
  EmissionSampler s;
  std::vector<double> flux;
  for (std::size_t i = 0; i < scene.emitters.size(); ++i) {
    const Emitter& e = scene.emitters[i];
    const std::string what = "emitter " + std::to_string(i) + (e.name.empty() ? "" : " '" + e.name + "'");
    if (!std::isfinite(e.flux_lm) || e.flux_lm < 0.0)
      return make_error(what + ": flux must be finite and >= 0 lm");
    Source src;
    src.kind = e.kind;
    if (e.kind == Emitter::Kind::Point) {
      src.position = e.position;
      src.frame = e.frame;
      if (!std::isfinite(e.position.x) || !std::isfinite(e.position.y) || !std::isfinite(e.position.z))
        return make_error(what + ": position is not finite");
      const photometry::PhotometricFrame& f = e.frame;
      const double tol = 1e-6;
      if (!(std::abs(length(f.c0) - 1.0) < tol && std::abs(length(f.c90) - 1.0) < tol &&
            std::abs(length(f.up) - 1.0) < tol && std::abs(dot(f.c0, f.c90)) < tol &&
            std::abs(dot(f.c0, f.up)) < tol && dot(cross(f.c0, f.c90), f.up) > 1.0 - tol))
        return make_error(what + ": photometric frame is not orthonormal and right-handed");
      if (e.profile) {
        auto p = ProfileSampler::create(*e.profile);
        if (!p.ok()) return make_error(what + ": " + p.error().message);
        src.profile = std::make_shared<const ProfileSampler>(std::move(p.value()));
      }
    } else if (e.kind == Emitter::Kind::RaySet) {
      auto r = make_ray_set_sampler(e.rays);
      if (!r.ok()) return make_error(what + ": " + r.error().message);
      src.rays = std::make_shared<const RaySetSampler>(std::move(r.value()));
    } else {
      if (e.mesh >= scene.meshes.size())
        return make_error(what + ": mesh " + std::to_string(e.mesh) + " does not exist");
      const Mesh& mesh = scene.meshes[e.mesh];
      // An instanced mesh emits from one instance: sampled in world space
      // (a transform that scales unevenly changes the triangles' areas).
      Mesh placed_copy;
      if (mesh.instanced) {
        if (e.instance >= scene.instances.size() || scene.instances[e.instance].mesh != e.mesh)
          return make_error(what + ": the mesh is instanced and the emitter names no instance of it");
        placed_copy = mesh;
        transform(placed_copy, scene.instances[e.instance].to_world);
      } else if (e.instance != kNoInstance) {
        return make_error(what + ": names an instance, but its mesh is world geometry");
      }
      auto a = AreaSampler::create(mesh.instanced ? placed_copy : mesh, e.two_sided);
      if (!a.ok()) return make_error(what + ": " + a.error().message);
      src.area = std::make_shared<const AreaSampler>(std::move(a.value()));
    }
    s.emitters_.push_back(std::move(src));
    flux.push_back(e.flux_lm);
  }
  if (flux.empty()) return make_error("the scene has no emitter");
  double total = 0.0;
  for (double f : flux) total += f;
  if (!(total > 0.0) || !std::isfinite(total))
    return make_error("the scene's emitters have no flux in total");
  s.emitter_table_ = AliasTable(flux);
  s.total_flux_lm_ = total;
  return s;
}

EmittedPhoton EmissionSampler::sample(PhotonRandom& rng) const {
  EmittedPhoton out;
  out.emitter = emitters_.size() == 1 ? 0 : emitter_table_.sample(rng.uniform());
  const Source& src = emitters_[out.emitter];
  if (src.kind == Emitter::Kind::Point) {
    out.origin = src.position;
    const Vec3 local = src.profile ? src.profile->sample(rng)
                                   : sample_uniform_sphere(rng);
    out.direction = src.frame.to_world(local);
  } else if (src.kind == Emitter::Kind::RaySet) {
    const RaySetSampler::Sample r = src.rays->sample(rng.uniform());
    out.origin = r.position;
    out.direction = r.direction;
  } else {
    const AreaSampler::Sample a = src.area->sample(rng);
    out.origin = a.position;
    out.direction = a.direction;
    out.on_surface = true;
    out.surface_normal = a.normal;
  }
  return out;
}

}  // namespace gonio::sim
