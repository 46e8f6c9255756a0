// Mitsuba 0.6's `mixturebsdf` and `blendbsdf`: the value is the weighted sum of the parts'
// values (a mixture's weights divided by their sum when they exceed 1 and energy
// conservation is on; a blend's weight the channel mean of its texture, clamped to [0, 1]),
// the density the weighted sum of the parts' densities, and sampling reflects what the sum
// reflects, delta parts included. Each comparison is shown to notice a plausible slip.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "emlt/core/rng.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "support/bsdf_harness.h"

using namespace emlt;
using namespace emlt::test;

namespace {

constexpr double kMinPValue = 1e-4;

Vec3 random_upper_direction(Rng& rng) {
  return spherical_direction(0.02 + 0.98 * rng.uniform(), 2.0 * M_PI * rng.uniform());
}

BsdfPtr rough_copper(float alpha) {
  Rgb eta, k;
  conductor_preset("Cu", &eta, &k);
  return make_rough_conductor(alpha, eta, k);
}

// The largest relative difference between bsdf's value and sum_i weights_i f_i.
double worst_value_error(const Bsdf& bsdf, const std::vector<BsdfPtr>& parts,
                         const std::vector<double>& weights, const BsdfContext& ctx = {}) {
  Rng rng(5, 0);
  double worst = 0.0;
  for (int n = 0; n < 3000; ++n) {
    const Vec3 wo = random_upper_direction(rng), wi = random_upper_direction(rng);
    const Rgb f = bsdf.eval(ctx, wo, wi);
    for (int c = 0; c < 3; ++c) {
      double expected = 0.0;
      for (size_t i = 0; i < parts.size(); ++i)
        expected += weights[i] * parts[i]->eval(ctx, wo, wi)[c];
      worst = std::max(worst, std::abs(f[c] - expected) / std::max(expected, 1e-3));
    }
  }
  return worst;
}

const std::vector<BsdfPtr> kParts = {make_lambertian(Rgb(0.8f, 0.3f, 0.2f)), rough_copper(0.2f)};

TEST(MixtureBsdf, EvaluatesTheWeightedSumScaledToConserveEnergy) {
  // 0.6 + 0.7 = 1.3: divided by 1.3 unless energy conservation is off.
  const BsdfPtr conserving = make_mixture(kParts, {0.6f, 0.7f});
  const BsdfPtr as_given = make_mixture(kParts, {0.6f, 0.7f}, false);
  const BsdfPtr below_one = make_mixture(kParts, {0.3f, 0.5f});
  EXPECT_LT(worst_value_error(*conserving, kParts, {0.6 / 1.3, 0.7 / 1.3}), 1e-5);
  EXPECT_LT(worst_value_error(*as_given, kParts, {0.6, 0.7}), 1e-5);
  EXPECT_LT(worst_value_error(*below_one, kParts, {0.3, 0.5}), 1e-5);  // left as it is
}

TEST(MixtureBsdfTeeth, NoticesUnscaledOrNormalisedWeights) {
  const BsdfPtr conserving = make_mixture(kParts, {0.6f, 0.7f});
  EXPECT_GT(worst_value_error(*conserving, kParts, {0.6, 0.7}), 0.2);
  const BsdfPtr below_one = make_mixture(kParts, {0.3f, 0.5f});
  EXPECT_GT(worst_value_error(*below_one, kParts, {0.3 / 0.8, 0.5 / 0.8}), 0.2);
}

TEST(BlendBsdf, WeightIsTheTexturesChannelMeanClampedToOne) {
  // A checkerboard of weights: channel means 0.3 and 1.4 (read as 1).
  const TexturePtr weight = make_checkerboard_texture(Rgb(0.1f, 0.3f, 0.5f), Rgb(1.2f, 1.4f, 1.6f));
  const BsdfPtr blend = make_blend(weight, kParts[0], kParts[1]);
  const BsdfContext dark{Vec2(0.1f, 0.1f)}, bright{Vec2(0.1f, 0.6f)};
  EXPECT_LT(worst_value_error(*blend, kParts, {0.7, 0.3}, dark), 1e-5);
  EXPECT_LT(worst_value_error(*blend, kParts, {0.0, 1.0}, bright), 1e-5);
  EXPECT_LT(worst_value_error(*make_blend(-0.5f, kParts[0], kParts[1]), kParts, {1.0, 0.0}), 1e-5);
  // Teeth: the weights the wrong way round, or the red channel instead of the mean.
  EXPECT_GT(worst_value_error(*blend, kParts, {0.3, 0.7}, dark), 0.2);
  EXPECT_GT(worst_value_error(*blend, kParts, {0.9, 0.1}, dark), 0.2);
}

// Sampling follows the density the mixture reports, and that density is the parts'
// densities weighted by the weights' shares.
TEST(WeightedSumSampling, SamplesFollowTheMixedDensity) {
  const BsdfPtr mixture = make_mixture(kParts, {0.6f, 0.7f});
  for (const float cos_o : {0.9f, 0.4f, 0.1f}) {
    const Vec3 wo = incident(cos_o);
    const ChiSquareOutcome outcome =
        run_chi_square(*mixture, {}, wo, density_of(*mixture, {}, wo), 3);
    EXPECT_GT(outcome.chi2.p_value, kMinPValue) << cos_o;
    const DirectionalDensity mixed = [&](const Vec3& wi) {
      return (0.6 * kParts[0]->pdf({}, wo, wi) + 0.7 * kParts[1]->pdf({}, wo, wi)) / 1.3;
    };
    EXPECT_NEAR(mixture->pdf({}, wo, incident(0.5f)), mixed(incident(0.5f)), 1e-5);
    EXPECT_GT(run_chi_square(*mixture, {}, wo, mixed, 4).chi2.p_value, kMinPValue) << cos_o;
  }
}

TEST(WeightedSumSamplingTeeth, RejectsEqualSharesForUnequalWeights) {
  const BsdfPtr mixture = make_mixture(kParts, {0.2f, 0.8f});
  const Vec3 wo = incident(0.6f);
  const DirectionalDensity equal = [&](const Vec3& wi) {
    return 0.5 * kParts[0]->pdf({}, wo, wi) + 0.5 * kParts[1]->pdf({}, wo, wi);
  };
  EXPECT_LT(run_chi_square(*mixture, {}, wo, equal, 4).chi2.p_value, 1e-6);
}

// What the sum reflects is what sampling carries: the weights' sum of the parts' albedos,
// a delta part (a mirror) included, for a mixture and for a textured blend.
TEST(WeightedSumEnergy, SampledAlbedoIsTheWeightedSumOfThePartsAlbedos) {
  const BsdfPtr white = make_lambertian(Rgb(1.0f)), mirror = make_mirror(Rgb(1.0f));
  struct Case {
    std::string label;
    BsdfPtr bsdf;
    BsdfContext ctx;
    double expected;
  };
  const TexturePtr weight = make_checkerboard_texture(Rgb(0.25f), Rgb(0.75f));
  const std::vector<Case> cases = {
      {"two whites conserved", make_mixture({white, white}, {0.7f, 0.6f}), {}, 1.0},
      {"mirror and white", make_mixture({mirror, white}, {0.3f, 0.5f}, false), {}, 0.8},
      {"mirror and white, 0.9 and 0.6", make_mixture({mirror, white}, {0.9f, 0.6f}), {}, 1.0},
      {"blend, weight 0.25",
       make_blend(weight, white, make_lambertian(Rgb(0.2f))),
       {Vec2(0.1f, 0.1f)},
       0.75 + 0.25 * 0.2},
      {"blend, weight 0.75",
       make_blend(weight, mirror, make_lambertian(Rgb(0.2f))),
       {Vec2(0.6f, 0.1f)},
       0.25 + 0.75 * 0.2},
  };
  for (const Case& c : cases)
    for (const float cos_o : {0.9f, 0.3f}) {
      const Albedo a = estimate_albedo(*c.bsdf, c.ctx, incident(cos_o), 200000, 11);
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(a.mean[ch], c.expected, 4.0 * a.standard_error[ch] + 2e-3)
            << c.label << " cos " << cos_o;
    }
}

}  // namespace
