// Every lobe of sim::Material behind one interface: its value, its sampler
// with the sampler's density, and its albedo — what a white furnace test,
// a chi-square test of the sampler and next-event estimation need.
//
// Frame: local, z the normal on the side the light arrives from, so wi.z > 0
// (wi points back towards where the light came from); wo.z > 0 reflects,
// wo.z < 0 transmits. `front`: whether that side is the surface's front
// (the side its normal points to): the dielectric's air side, the measured
// BSDF's front data. Tangent-plane axes: x along the material's tangent
// (the glossy lobe's mx).
//
// Each lobe alone, with its weight not applied:
//   lobe_evaluate  f(wi, wo) · |cos θo|                            [1/sr]
//                  0 for the delta lobes (mirror, dielectric)
//   lobe_pdf       the density of lobe_sample's wo over the sphere [1/sr];
//                  0 for the delta lobes
//   lobe_sample    wo with that density and weight = evaluate / pdf (delta
//                  lobes: the lobe's own event, weight 1, delta = true)
//   lobe_albedo    ∫ evaluate dωo (delta lobes: 1): what the tracer's
//                  scatter() lets survive on average.
// The surface (every lobe with its weight at the angle of incidence,
// Material::over_incidence): surface_evaluate = Σ w_k(θi) · lobe_evaluate_k
// over the non-delta lobes; that is the BSDF · |cos θo| a next-event
// connection multiplies by.
//
// The tracer scatters with sim::scatter (sim/bsdfs/material.h), which for each
// lobe is the analog process these functions describe: the photon leaves
// with density lobe_evaluate / lobe_albedo and survives with chance
// lobe_albedo (for the compensated glossy lobe by roulette and redirection:
// sim/bsdfs/glossy_energy.h).
#pragma once

#include <memory>

#include "photometry/vec3.h"
#include "sim/bsdfs/abg.h"
#include "sim/bsdfs/glossy_energy.h"
#include "sim/bsdfs/material.h"
#include "sim/samplers/random.h"
#include "sim/scene.h"

namespace gonio::sim {

// What prepare() derives from a material's parameters.
struct MaterialTables {
  std::shared_ptr<const GlossyEnergy> glossy;  // glossy > 0 with compensation
  double glossy_kappa = 0.0;                   // κ (glossy_energy.h)
  std::shared_ptr<const AbgTable> abg_reflect, abg_transmit;
};

// Fills m.tables (idempotent; tables are shared per process, so preparing
// many materials with the same parameters is cheap). The tracer prepares
// its own copies; callers of scatter() and of the functions below prepare
// theirs (unprepared, a compensated glossy lobe scatters as single
// scattering and the ABg lobes absorb).
void prepare(Material& m);

bool is_delta(Lobe lobe);

double lobe_evaluate(const Material& m, Lobe lobe, const Vec3& wi, const Vec3& wo, bool front = true);
double lobe_pdf(const Material& m, Lobe lobe, const Vec3& wi, const Vec3& wo, bool front = true);

struct LobeSample {
  Vec3 wo;              // local; the zero vector where nothing leaves
  double weight = 0.0;  // f |cos θo| / pdf (delta lobes: 1)
  double pdf = 0.0;     // [1/sr]; 0 for delta lobes
  bool delta = false;
};
LobeSample lobe_sample(const Material& m, Lobe lobe, const Vec3& wi, PhotonRandom& rng, bool front = true);

// ∫ lobe_evaluate dωo, the chance that scatter() lets the photon go on.
// Glossy: E_F(wi) + κ (1 − E(wi)) by quadrature (glossy_energy.h).
double lobe_albedo(const Material& m, Lobe lobe, const Vec3& wi, bool front = true);

// A lobe's weight at an angle of incidence (cos θi > 0), and the surface.
double weight_at(const Material& m, Lobe lobe, double cos_theta_i);
double surface_evaluate(const Material& m, const Vec3& wi, const Vec3& wo, bool front = true);

}  // namespace gonio::sim
