// Mitsuba 0.6's `coating` and `roughcoating` (src/scene/materials/coating.cpp,
// rough_coating.cpp) against Mitsuba's formulas written here independently in double
// precision: the nested BSDF seen at the refracted directions, the transmittance in and
// out, the absorption along both refracted paths, 1 / eta^2, the specular lobe and
// Mitsuba's sampling probabilities. Sampling is checked against pdf() by the harness's
// chi-square test, the weights against a quadrature of the value (energy), and the value
// for reciprocity. Each comparison is shown to notice a plausible slip ("teeth" tests).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/rough_transmittance.h"
#include "support/bsdf_harness.h"

using namespace emlt;
using test::incident;
using test::spherical_direction;

namespace {

constexpr double kMinPValue = 1e-3;

// Unpolarised Fresnel reflectance from the outside of an interface of relative IOR eta.
double fresnel(double cos_i, double eta) {
  cos_i = std::abs(cos_i);
  const double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// |cos| of the direction refracted into the layer.
double cos_inside(double cos_o, double eta) {
  return std::sqrt(1.0 - (1.0 - cos_o * cos_o) / (eta * eta));
}

// The layer's parameters for the references.
struct Layer {
  double eta = 1.6, thickness = 0.7;
  Rgb sigma_a{0.3f, 0.8f, 1.5f};
  Rgb kd{0.8f, 0.6f, 0.4f};
};

// Slips a reference can be told to make, to show the comparison notices them.
enum class Slip { None, NoEtaSquared, OutsidePathLength, OnePathOnly, NoTransmittanceOut };

// Mitsuba's coating over a Lambertian kd, for wo and wi above the surface.
double coating_over_lambert(const Layer& l, const Vec3& wo, const Vec3& wi, int c,
                            Slip slip = Slip::None) {
  const double co = wo.z, ci = wi.z;
  const double to = 1.0 - fresnel(co, l.eta), ti = 1.0 - fresnel(ci, l.eta);
  const double co_in = cos_inside(co, l.eta), ci_in = cos_inside(ci, l.eta);
  double path = 1.0 / co_in + 1.0 / ci_in;
  if (slip == Slip::OutsidePathLength) path = 1.0 / co + 1.0 / ci;
  if (slip == Slip::OnePathOnly) path = 1.0 / ci_in;
  const double absorption = std::exp(-l.sigma_a[c] * l.thickness * path);
  const double eta2 = slip == Slip::NoEtaSquared ? 1.0 : l.eta * l.eta;
  const double out = slip == Slip::NoTransmittanceOut ? 1.0 : to;
  return l.kd[c] / M_PI * out * ti * absorption / eta2;
}

BsdfPtr coated_lambert(const Layer& l) {
  return make_coating(make_lambertian(l.kd), float(l.eta), 1.0f, float(l.thickness),
                      make_constant_texture(l.sigma_a));
}

std::vector<std::pair<Vec3, Vec3>> pairs_above(int count, uint64_t seed) {
  Rng rng(seed, 0);
  std::vector<std::pair<Vec3, Vec3>> pairs;
  for (int n = 0; n < count; ++n) {
    const double co = 0.02 + 0.98 * rng.uniform(), ci = 0.02 + 0.98 * rng.uniform();
    pairs.emplace_back(spherical_direction(co, 2.0 * M_PI * rng.uniform()),
                       spherical_direction(ci, 2.0 * M_PI * rng.uniform()));
  }
  return pairs;
}

double worst_error(const Bsdf& bsdf,
                   const std::function<double(const Vec3&, const Vec3&, int)>& ref) {
  double worst = 0.0;
  for (const auto& [wo, wi] : pairs_above(2000, 11)) {
    const Rgb f = bsdf.eval({}, wo, wi);
    for (int c = 0; c < 3; ++c) {
      const double expected = ref(wo, wi, c);
      worst = std::max(worst, std::abs(f[c] - expected) / std::max(expected, 1e-4));
    }
  }
  return worst;
}

// Integral of f(wo, wi) |cos wi| over the sphere by a midpoint rule in (cos, phi).
Rgb quadrature_albedo(const Bsdf& bsdf, const BsdfContext& ctx, const Vec3& wo, int n = 400) {
  DVec3 sum(0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double c = -1.0 + 2.0 * (i + 0.5) / n, phi = 2.0 * M_PI * (j + 0.5) / n;
      const Vec3 wi = spherical_direction(c, phi);
      sum += DVec3(bsdf.eval(ctx, wo, wi)) * std::abs(c);
    }
  return Rgb(sum * (4.0 * M_PI / (double(n) * n)));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Values

TEST(Coating, NestedPartFollowsMitsubasFormula) {
  const Layer l;
  const BsdfPtr bsdf = coated_lambert(l);
  const auto ref = [&](const Vec3& wo, const Vec3& wi, int c) {
    return coating_over_lambert(l, wo, wi, c);
  };
  EXPECT_LT(worst_error(*bsdf, ref), 2e-4);
}

// The comparison notices a missing 1 / eta^2, the absorption along the outside directions'
// paths (or along one path only), and a transmittance left out on the way out.
TEST(CoatingTeeth, NoticesEtaAbsorptionAndTransmittanceSlips) {
  const Layer l;
  const BsdfPtr bsdf = coated_lambert(l);
  for (const Slip slip :
       {Slip::NoEtaSquared, Slip::OutsidePathLength, Slip::OnePathOnly, Slip::NoTransmittanceOut}) {
    const auto ref = [&](const Vec3& wo, const Vec3& wi, int c) {
      return coating_over_lambert(l, wo, wi, c, slip);
    };
    EXPECT_GT(worst_error(*bsdf, ref), 1e-2) << int(slip);
  }
}

TEST(Coating, SpecularDeltaAndItsProbabilityAreMitsubas) {
  const Layer l;
  const Rgb ks(0.9f, 0.8f, 0.7f);
  const BsdfPtr bsdf = make_coating(make_lambertian(l.kd), float(l.eta), 1.0f, float(l.thickness),
                                    make_constant_texture(l.sigma_a), ks);
  // Mitsuba's weight of the specular lobe: 1 / (1 + mean of exp(-2 d sigma_a)).
  double mean = 0.0;
  for (int c = 0; c < 3; ++c) mean += std::exp(-2.0 * l.thickness * l.sigma_a[c]) / 3.0;
  const double w = 1.0 / (mean + 1.0);
  for (const float cos_o : {0.05f, 0.3f, 0.7f, 1.0f}) {
    const Vec3 wo = incident(cos_o);
    const double f = fresnel(cos_o, l.eta);
    const double p = f * w / (f * w + (1.0 - f) * (1.0 - w));
    const auto s = bsdf->sample({}, wo, 0.5f * float(p), Vec2(0.3f, 0.4f));
    ASSERT_TRUE(s && s->is_delta());
    EXPECT_NEAR(s->pdf, p, 1e-5 + 1e-4 * p);
    EXPECT_NEAR(s->wi.x, -wo.x, 1e-6f);
    EXPECT_NEAR(s->wi.z, wo.z, 1e-6f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], ks[c] * f / p, 1e-4 * ks[c] * f / p);
    // The rest of the samples go to the nested BSDF, with the rest of the probability.
    const auto rest = bsdf->sample({}, wo, float(p) + 0.5f * float(1.0 - p), Vec2(0.3f, 0.4f));
    ASSERT_TRUE(rest && !rest->is_delta());
    EXPECT_NEAR(rest->pdf, bsdf->pdf({}, wo, rest->wi), 1e-4f * rest->pdf);
  }
}

TEST(Coating, NestedDeltaStaysADeltaThroughTheLayer) {
  // A mirror under the layer: wi mirrors wo, weighted by the transmittance in and out
  // (the same angle), the absorption along both paths and the choice of the nested lobe.
  const Layer l;
  const BsdfPtr bsdf = make_coating(make_mirror(Rgb(0.9f)), float(l.eta), 1.0f, float(l.thickness),
                                    make_constant_texture(l.sigma_a));
  double mean = 0.0;
  for (int c = 0; c < 3; ++c) mean += std::exp(-2.0 * l.thickness * l.sigma_a[c]) / 3.0;
  const double w = 1.0 / (mean + 1.0);
  for (const float cos_o : {0.1f, 0.5f, 0.9f}) {
    const Vec3 wo = incident(cos_o);
    const double f = fresnel(cos_o, l.eta);
    const double p_nested = 1.0 - f * w / (f * w + (1.0 - f) * (1.0 - w));
    const auto s = bsdf->sample({}, wo, 0.999f, Vec2(0.3f, 0.4f));
    ASSERT_TRUE(s && s->is_delta());
    EXPECT_NEAR(s->wi.x, -wo.x, 1e-5f);
    EXPECT_NEAR(s->wi.z, wo.z, 1e-5f);
    EXPECT_NEAR(s->pdf, p_nested, 1e-5);
    const double cos_in = cos_inside(cos_o, l.eta);
    for (int c = 0; c < 3; ++c) {
      const double expected = 0.9 * (1.0 - f) * (1.0 - f) *
                              std::exp(-2.0 * l.thickness * l.sigma_a[c] / cos_in) / p_nested;
      EXPECT_NEAR(s->weight[c], expected, 1e-4 * expected) << cos_o;
    }
    EXPECT_TRUE(is_black(bsdf->eval({}, wo, s->wi)));
    EXPECT_EQ(bsdf->pdf({}, wo, s->wi), 0.0f);
  }
}

TEST(Coating, BothSidesSeeTheSameLayer) {
  // Mitsuba's coating reflects on either side, and refracts into a layer on wo's side.
  const Layer l;
  const BsdfPtr bsdf = make_coating(make_two_sided(make_lambertian(l.kd)), float(l.eta), 1.0f,
                                    float(l.thickness), make_constant_texture(l.sigma_a));
  for (const auto& [wo, wi] : pairs_above(200, 13)) {
    const Vec3 wo_below(wo.x, wo.y, -wo.z), wi_below(wi.x, wi.y, -wi.z);
    const Rgb above = bsdf->eval({}, wo, wi), below = bsdf->eval({}, wo_below, wi_below);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(above[c], below[c], 1e-5f * above[c] + 1e-8f);
    EXPECT_NEAR(bsdf->pdf({}, wo, wi), bsdf->pdf({}, wo_below, wi_below), 1e-4f);
  }
  const auto s = bsdf->sample({}, Vec3(0.3f, 0.2f, -0.9327379f), 0.0f, Vec2(0.5f));
  ASSERT_TRUE(s && s->is_delta());
  EXPECT_LT(s->wi.z, 0.0f);
}

// ---------------------------------------------------------------------------------------
// Rough coating values

namespace {

// GGX D and Smith G1 (Walter et al. 2007), isotropic, for m and w above the surface.
double ggx_d(const Vec3& m, double alpha) {
  const double c2 = double(m.z) * m.z, t2 = (1.0 - c2) / c2, a2 = alpha * alpha;
  return a2 / (M_PI * c2 * c2 * (a2 + t2) * (a2 + t2));
}
double ggx_g1(const Vec3& w, double alpha) {
  const double c2 = double(w.z) * w.z, t2 = (1.0 - c2) / c2;
  return 2.0 / (1.0 + std::sqrt(1.0 + alpha * alpha * t2));
}

}  // namespace

TEST(RoughCoating, FollowsMitsubasFormula) {
  const Layer l;
  const double alpha = 0.25;
  const BsdfPtr bsdf = make_rough_coating(make_lambertian(l.kd), make_constant_texture(Rgb(0.25f)),
                                          MicrofacetType::Ggx, float(l.eta), 1.0f,
                                          float(l.thickness), make_constant_texture(l.sigma_a));
  // The rough transmittance as tabulated (its own tests compare it with Mitsuba's tables).
  const RoughTransmittance t(MicrofacetType::Ggx, float(l.eta), float(alpha));
  for (const bool drop_eta2 : {false, true}) {
    const auto ref = [&](const Vec3& wo, const Vec3& wi, int c) {
      const Vec3 h = glm::normalize(wo + wi);
      const double specular = fresnel(glm::dot(wo, h), l.eta) * ggx_d(h, alpha) *
                              ggx_g1(wo, alpha) * ggx_g1(wi, alpha) / (4.0 * wo.z * wi.z);
      const double co_in = cos_inside(wo.z, l.eta), ci_in = cos_inside(wi.z, l.eta);
      const double absorption = std::exp(-l.sigma_a[c] * l.thickness * (1.0 / co_in + 1.0 / ci_in));
      return specular + l.kd[c] / M_PI * t(wo.z, float(alpha)) * t(wi.z, float(alpha)) *
                            absorption / (drop_eta2 ? 1.0 : l.eta * l.eta);
    };
    if (drop_eta2)
      EXPECT_GT(worst_error(*bsdf, ref), 1e-2);  // teeth
    else
      EXPECT_LT(worst_error(*bsdf, ref), 2e-3);
  }
}

TEST(RoughCoating, NestedDeltaCarriesMitsubasWeight) {
  // Mitsuba's sample weight for a delta under a rough coating: the nested one times
  // T(cos_o) T(cos_i) A, not divided by the choice of the nested BSDF.
  const Layer l;
  const BsdfPtr bsdf = make_rough_coating(make_mirror(Rgb(1.0f)), make_constant_texture(Rgb(0.2f)),
                                          MicrofacetType::Beckmann, float(l.eta), 1.0f,
                                          float(l.thickness), make_constant_texture(l.sigma_a));
  const RoughTransmittance t(MicrofacetType::Beckmann, float(l.eta), 0.2f);
  for (const float cos_o : {0.2f, 0.6f, 0.95f}) {
    const Vec3 wo = incident(cos_o);
    const auto s = bsdf->sample({}, wo, 0.9999f, Vec2(0.3f, 0.4f));
    ASSERT_TRUE(s && s->is_delta());
    const double cos_in = cos_inside(cos_o, l.eta), tr = t(cos_o, 0.2f);
    for (int c = 0; c < 3; ++c) {
      const double expected = tr * tr * std::exp(-2.0 * l.thickness * l.sigma_a[c] / cos_in);
      EXPECT_NEAR(s->weight[c], expected, 1e-4 * expected) << cos_o;
    }
  }
}

TEST(Coatings, AreReciprocal) {
  const Layer l;
  const BsdfPtr rough_metal = make_rough_conductor(
      make_constant_texture(Rgb(0.3f)), Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.2f),
      make_constant_texture(Rgb(1.0f)), MicrofacetType::Ggx);
  const std::vector<BsdfPtr> bsdfs = {
      coated_lambert(l),
      make_coating(rough_metal, 1.33f, 1.0f, 2.0f, make_constant_texture(l.sigma_a)),
      make_rough_coating(make_lambertian(l.kd), make_constant_texture(Rgb(0.3f)),
                         MicrofacetType::Beckmann, float(l.eta), 1.0f, float(l.thickness),
                         make_constant_texture(l.sigma_a)),
      make_rough_coating(rough_metal, make_constant_texture(Rgb(0.15f)), MicrofacetType::Ggx, 1.5f,
                         1.0f, 1.0f, make_constant_texture(l.sigma_a))};
  for (const BsdfPtr& bsdf : bsdfs)
    for (const auto& [wo, wi] : pairs_above(500, 17)) {
      const Rgb a = bsdf->eval({}, wo, wi), b = bsdf->eval({}, wi, wo);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], 2e-4f * (a[c] + b[c]) + 1e-7f) << bsdf->name();
      // The same in importance transport: the 1 / eta^2 is both crossings', not radiance's.
      BsdfContext importance;
      importance.mode = TransportMode::Importance;
      const Rgb m = bsdf->eval(importance, wo, wi);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], m[c]);
    }
}

// ---------------------------------------------------------------------------------------
// Sampling and energy

namespace {

struct Case {
  std::string what;
  BsdfPtr bsdf;
  BsdfContext ctx;
};

std::vector<Case> cases() {
  const Layer l;
  const BsdfPtr rough_metal = make_rough_conductor(
      make_constant_texture(Rgb(0.3f)), Rgb(0.2f, 0.9f, 1.1f), Rgb(3.9f, 2.4f, 2.2f),
      make_constant_texture(Rgb(1.0f)), MicrofacetType::Ggx);
  const TexturePtr checker =
      make_checkerboard_texture(Rgb(0.05f), Rgb(0.5f), UvTransform{Vec2(4.0f), Vec2(0.0f)});
  BsdfContext textured;
  textured.uv = Vec2(0.3f, 0.1f);
  return {
      {"coating/lambert", coated_lambert(l), {}},
      {"coating/rough metal",
       make_coating(rough_metal, 1.33f, 1.0f, 2.0f, make_constant_texture(l.sigma_a)),
       {}},
      {"roughcoating ggx/lambert",
       make_rough_coating(make_lambertian(l.kd), make_constant_texture(Rgb(0.3f)),
                          MicrofacetType::Ggx, float(l.eta), 1.0f, float(l.thickness),
                          make_constant_texture(l.sigma_a)),
       {}},
      {"roughcoating beckmann/rough metal",
       make_rough_coating(rough_metal, make_constant_texture(Rgb(0.4f)), MicrofacetType::Beckmann,
                          1.5f, 1.0f, 1.0f, nullptr, Rgb(0.8f)),
       {}},
      {"roughcoating textured alpha",
       make_rough_coating(make_lambertian(l.kd), checker, MicrofacetType::Ggx, 1.5f, 1.0f, 1.0f,
                          nullptr),
       textured},
  };
}

}  // namespace

TEST(CoatingSampling, MatchesPdfEverywhere) {
  for (const Case& c : cases())
    for (const float cos_o : {0.15f, 0.6f, 0.97f}) {
      const Vec3 wo = incident(cos_o);
      const auto outcome =
          test::run_chi_square(*c.bsdf, c.ctx, wo, test::density_of(*c.bsdf, c.ctx, wo), 23);
      EXPECT_GT(outcome.chi2.p_value, kMinPValue)
          << c.what << " cos " << cos_o << " statistic " << outcome.chi2.statistic;
    }
}

// The sampled weights average to the albedo that the value and the specular delta imply:
// this checks the weights' 1 / eta^2, Jacobian and lobe choice together.
TEST(CoatingEnergy, SampledAlbedoMatchesQuadrature) {
  for (const Case& c : cases())
    for (const float cos_o : {0.2f, 0.7f}) {
      const Vec3 wo = incident(cos_o);
      const test::Albedo sampled = test::estimate_albedo(*c.bsdf, c.ctx, wo, 200000, 29);
      Rgb expected = quadrature_albedo(*c.bsdf, c.ctx, wo);
      if (c.what == "coating/lambert" || c.what == "coating/rough metal") {
        // Plus the delta reflection, Ks F(cos_o) (Ks = 1 here).
        const float eta = c.what == "coating/lambert" ? 1.6f : 1.33f;
        expected += Rgb(float(fresnel(cos_o, eta)));
      }
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(sampled.mean[k], expected[k], 5.0 * sampled.standard_error[k] + 3e-3)
            << c.what << " cos " << cos_o << " channel " << k;
    }
}

// With a white Lambertian base and no absorption, a smooth coating reflects
// F + (1 - F) (1 / eta^2) integral (1 - F(cos_i)) cos_i / pi: less than everything (Mitsuba
// leaves the light reflected back down inside the layer out), and exactly that.
TEST(CoatingEnergy, WhiteFurnaceIsMitsubasClosedForm) {
  const double eta = 1.5;
  const BsdfPtr bsdf = make_coating(make_lambertian(Rgb(1.0f)), float(eta), 1.0f);
  double inner = 0.0;
  constexpr int kSteps = 20000;
  for (int i = 0; i < kSteps; ++i) {
    const double mu = (i + 0.5) / kSteps;
    inner += 2.0 * mu * (1.0 - fresnel(mu, eta)) / kSteps;
  }
  for (const float cos_o : {0.1f, 0.5f, 1.0f}) {
    const double f = fresnel(cos_o, eta);
    const double expected = f + (1.0 - f) * inner / (eta * eta);
    const test::Albedo a = test::estimate_albedo(*bsdf, {}, incident(cos_o), 400000, 31);
    EXPECT_NEAR(a.mean.x, expected, 4.0 * a.standard_error.x + 1e-3) << cos_o;
    EXPECT_LT(expected, 1.0);
    // Teeth: without the 1 / eta^2 the closed form would be brighter than the samples.
    EXPECT_GT(std::abs(a.mean.x - (f + (1.0 - f) * inner)), 0.1);
  }
}

// ---------------------------------------------------------------------------------------
// Normal map

namespace {

// Mitsuba 0.6's perturbed frame for a tangent-space normal n (dp/du along x): n' = n / |n|,
// s' = x made orthogonal to n', t' = n' x s'; w in the base frame to the perturbed one.
DVec3 to_perturbed(const DVec3& n_raw, const DVec3& w) {
  const DVec3 n = glm::normalize(n_raw);
  const DVec3 s = glm::normalize(DVec3(1.0, 0.0, 0.0) - n * n.x);
  const DVec3 t = glm::cross(n, s);
  return {glm::dot(w, s), glm::dot(w, t), glm::dot(w, n)};
}

}  // namespace

TEST(NormalMap, NestedSeesThePerturbedFrameWithMitsubasCosine) {
  const DVec3 n(0.35, -0.2, 0.9);
  const Rgb encoded = Rgb(0.5 * n / glm::length(n) + 0.5);
  const BsdfPtr nested = make_rough_plastic(0.2f, Rgb(0.3f, 0.5f, 0.7f));
  const BsdfPtr bsdf = make_normal_map(nested, make_constant_texture(encoded));
  for (const bool with_ratio : {true, false}) {
    double worst = 0.0;
    int black = 0;
    for (const auto& [wo, wi] : pairs_above(1000, 37)) {
      const DVec3 wo_p = to_perturbed(n, DVec3(wo)), wi_p = to_perturbed(n, DVec3(wi));
      const Rgb f = bsdf->eval({}, wo, wi);
      if (wi_p.z <= 0.0) {  // Mitsuba's side check, on wi only
        black += is_black(f);
        continue;
      }
      const Rgb g = nested->eval({}, Vec3(wo_p), Vec3(wi_p));
      const double ratio = with_ratio ? wi_p.z / wi.z : 1.0;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(f[c] - g[c] * ratio) / std::max(g[c] * ratio, 1e-3));
    }
    if (with_ratio) {
      EXPECT_LT(worst, 1e-3);
      EXPECT_GT(black, 0);
    } else {
      EXPECT_GT(worst, 1e-2);  // teeth: the nested value alone is not Mitsuba's
    }
  }
}

TEST(NormalMap, FlatMapIsTheNestedBsdf) {
  const BsdfPtr nested = make_lambertian(Rgb(0.4f, 0.5f, 0.6f));
  const BsdfPtr bsdf = make_normal_map(nested, make_constant_texture(Rgb(0.5f, 0.5f, 1.0f)));
  for (const auto& [wo, wi] : pairs_above(200, 41)) {
    const Rgb a = bsdf->eval({}, wo, wi), b = nested->eval({}, wo, wi);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6f);
  }
}

TEST(NormalMap, SamplingMatchesPdfAndImportanceIsTheAdjoint) {
  const BsdfPtr nested = make_rough_conductor(0.3f, Rgb(0.2f), Rgb(3.0f));
  const BsdfPtr lambert = make_lambertian(Rgb(0.7f));
  const TexturePtr normals = make_constant_texture(Rgb(0.7f, 0.4f, 0.9f));
  BsdfContext importance;
  importance.mode = TransportMode::Importance;
  for (const BsdfPtr& inner : {nested, lambert}) {
    const BsdfPtr bsdf = make_normal_map(inner, normals);
    for (const BsdfContext& ctx : {BsdfContext{}, importance})
      for (const float cos_o : {0.3f, 0.9f}) {
        const Vec3 wo = incident(cos_o);
        const auto outcome =
            test::run_chi_square(*bsdf, ctx, wo, test::density_of(*bsdf, ctx, wo), 43);
        EXPECT_GT(outcome.chi2.p_value, kMinPValue) << inner->name() << " cos " << cos_o;
        // The weights average to the albedo the value implies, in either mode.
        const test::Albedo a = test::estimate_albedo(*bsdf, ctx, wo, 100000, 47);
        const Rgb q = quadrature_albedo(*bsdf, ctx, wo);
        EXPECT_NEAR(a.mean.x, q.x, 5.0 * a.standard_error.x + 3e-3) << inner->name();
      }
    // Importance transport is the adjoint: f*(wo, wi) = f(wi, wo).
    for (const auto& [wo, wi] : pairs_above(300, 53)) {
      const Rgb adjoint = bsdf->eval(importance, wo, wi), forward = bsdf->eval({}, wi, wo);
      if (is_black(adjoint) || is_black(forward)) continue;  // the side check is wi's
      EXPECT_NEAR(adjoint.x, forward.x, 1e-4f * forward.x + 1e-7f);
    }
  }
}
