// Energy of the glossy lobe: its single-scattering albedo by quadrature, and
// the multiple-scattering compensation of Kulla and Conty (2017, "Revisiting
// physically based shading at Imageworks", SIGGRAPH course notes).
//
// The single-scattering microfacet lobe of sim/bsdfs/material.h reflects
//   E_F(wi) = ∫ f cos θo dωo ≤ 1,
// and with F = 1 (a white lobe) E(wi) falls below 1 for rough lobes: light
// that meets a second facet is not followed (0.46 at mx = my = 1 and normal
// incidence). Kulla and Conty return it as a second lobe
//   f_ms(wi, wo) = κ (1 − E(wi)) (1 − E(wo)) / (π (1 − E_avg)),
//   E_avg = 2 ∫ E(μ) μ dμ,
//   κ = F_avg² E_avg / (1 − F_avg (1 − E_avg)),  F_avg = f0 + (1 − f0)/21
// (F_avg: Schlick's F averaged over the cosine-weighted hemisphere; κ = 1
// for f0 = 1). It is reciprocal and, for f0 = 1, makes the lobe's albedo 1
// at every incidence: a white lobe reflects all it receives.
//
// The tracer does not read E(wi) from a table: the glossy sampler's survival
// weight F·G2/G1 (sim/bsdfs/material.h) is split into the masking part G2/G1 and
// Fresnel's F, and a photon that the masking roulette would absorb (chance
// 1 − E(wi), exactly) leaves instead in the second lobe with chance κ. So
// the compensated lobe conserves energy exactly, whatever the table's
// accuracy; the table E(μ) (φ-averaged for anisotropic lobes, linear
// between kEnergyBins + 1 nodes in μ) shapes only the second lobe's
// outgoing distribution, ∝ (1 − E(μo)) μo, and its evaluate() value.
#pragma once

#include <array>
#include <memory>

#include "photometry/vec3.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

inline constexpr int kEnergyBins = 64;
// The quadrature of glossy_single_albedo per table node (n × n points).
inline constexpr int kEnergyQuadrature = 128;
// The table code's revision: raise it whenever what a table holds for a
// roughness changes (quadrature, azimuths, nodes, the clamps), so that
// tables kept on disk by an older Gonio (tools/run/glossy_energy_cache.h)
// are built again rather than used.
inline constexpr int kGlossyEnergyRevision = 1;

struct GlossyEnergy {
  double mx = 0.0, my = 0.0;
  // E(μ) (F = 1) at μ = k/n, k = 0 … n (μ = 10⁻⁴ for k = 0), averaged over
  // the azimuth for anisotropic lobes; linear between.
  std::array<double, kEnergyBins + 1> e{};
  double e_avg = 1.0;  // 2 ∫ E μ dμ of the piecewise-linear table
  // Cumulative share of ∫ (1 − E(μ)) μ dμ up to the end of each bin.
  std::array<double, kEnergyBins> cdf{};

  double at(double mu) const;  // the table's E at μ (0 ≤ μ ≤ 1)
};

// ∫ f cos θo dωo of the single-scattering lobe with roughness mx, my and
// Schlick's f0 (use 1 for E), for a unit wi above the surface (local frame),
// by midpoint quadrature over Walter's Gaussian slopes (n × n points;
// relative error below 10⁻³ for n = 128 and roughness 0.05–2). 0 for
// wi.z <= 0.
double glossy_single_albedo(double mx, double my, double f0, const Vec3& wi_local, int n = kEnergyQuadrature);

// The table of a roughness, built once per process and shared (thread-safe;
// about 30 ms for an isotropic lobe, 8× that for an anisotropic one).
std::shared_ptr<const GlossyEnergy> glossy_energy(double mx, double my);

// The table of a roughness built now, not shared (what glossy_energy builds
// the first time).
std::shared_ptr<const GlossyEnergy> build_glossy_energy(double mx, double my);

// The table of a roughness from its nodes e (kept from an earlier build):
// e_avg and cdf computed from them as build_glossy_energy does, so that the
// nodes of a built table give back the same table, bit for bit. Null where
// a node is not in [0, 1] or the roughness is not positive and finite.
std::shared_ptr<const GlossyEnergy> glossy_energy_from_nodes(double mx, double my,
                                                            const std::array<double, kEnergyBins + 1>& e);

// Makes `table` the one glossy_energy(table->mx, table->my) shares from now
// on, unless the process already holds one for that roughness; returns the
// one shared.
std::shared_ptr<const GlossyEnergy> offer_glossy_energy(std::shared_ptr<const GlossyEnergy> table);

// κ above.
double multiple_scattering_factor(double f0, double e_avg);

// The second lobe, for wi and wo above the surface (local frame):
// f_ms · cos θo [1/sr] with κ, and the density of sample_glossy_ms [1/sr].
double glossy_ms_evaluate(const GlossyEnergy& t, double kappa, const Vec3& wi_local, const Vec3& wo_local);
double glossy_ms_pdf(const GlossyEnergy& t, const Vec3& wo_local);
// A direction with density glossy_ms_pdf: the bin of μo by its share, μo²
// uniform within it (density ∝ μ) kept with chance (1 − E(μo)) over its
// largest value in the bin, φ uniform.
Vec3 sample_glossy_ms(const GlossyEnergy& t, PhotonRandom& rng);

}  // namespace gonio::sim
