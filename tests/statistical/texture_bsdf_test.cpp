// Statistical tests of the materials added with textures: rough dielectric
// (GGX and Beckmann, both sides, both transport modes), thin dielectric, smooth
// conductor, Beckmann conductor and plastic, nonlinear plastic, and textured parameters.
// Same checks as the core BSDFs: sampling follows pdf() (chi-square over the sphere),
// pdf() integrates to the sampled mass, sample() agrees with eval()/pdf(), reciprocity,
// energy bounds.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "support/bsdf_harness.h"

using namespace emlt;
using test::incident;
using test::spherical_direction;

namespace {

constexpr double kMinPValue = 1e-3;

Rgb preset_eta(const char* name) {
  Rgb eta, k;
  conductor_preset(name, &eta, &k);
  return eta;
}
Rgb preset_k(const char* name) {
  Rgb eta, k;
  conductor_preset(name, &eta, &k);
  return k;
}

TexturePtr constant(float v) { return make_constant_texture(Rgb(v)); }

BsdfPtr rough_glass(float alpha, MicrofacetType type = MicrofacetType::Ggx, float eta = 1.5f) {
  return make_rough_dielectric(constant(alpha), eta, 1.0f, type);
}

// A checkerboard alpha: 0.1 where floor(2u) + floor(2v) is even, 0.5 elsewhere.
TexturePtr checker_alpha() { return make_checkerboard_texture(Rgb(0.1f), Rgb(0.5f)); }
const Vec2 kCell0(0.2f, 0.3f), kCell1(0.7f, 0.3f);

struct ChiSquareCase {
  std::string label;
  std::function<BsdfPtr()> make;
  float cos_theta_o;
  Vec2 uv{0.0f};
  TransportMode mode = TransportMode::Radiance;
};

void PrintTo(const ChiSquareCase& c, std::ostream* os) { *os << c.label; }

class NewBsdfChiSquare : public ::testing::TestWithParam<ChiSquareCase> {};

TEST_P(NewBsdfChiSquare, SamplesFollowPdfAndPdfIntegratesToSampledMass) {
  const ChiSquareCase& param = GetParam();
  const BsdfPtr bsdf = param.make();
  const BsdfContext ctx{param.uv, param.mode};
  const Vec3 wo = incident(param.cos_theta_o);
  const auto outcome = test::run_chi_square(*bsdf, ctx, wo, test::density_of(*bsdf, ctx, wo), 101);
  EXPECT_GT(outcome.chi2.p_value, kMinPValue)
      << bsdf->name() << " statistic " << outcome.chi2.statistic << " dof "
      << outcome.chi2.degrees_of_freedom;
  EXPECT_LE(outcome.density_integral, 1.0 + 1e-3);
  const double sigma = std::sqrt(0.25 / 200000.0);
  EXPECT_NEAR(outcome.density_integral, outcome.sampled_fraction, 4.0 * sigma + 1e-3);
}

std::vector<ChiSquareCase> chi_square_cases() {
  std::vector<ChiSquareCase> cases;
  for (const float alpha : {0.1f, 0.4f}) {
    const std::string a = std::to_string(int(alpha * 100 + 0.5f));
    const auto make = [alpha] { return rough_glass(alpha); };
    cases.push_back({"rough_glass_a" + a + "_outside", make, 0.8f});
    cases.push_back({"rough_glass_a" + a + "_outside_grazing", make, 0.15f});
    cases.push_back({"rough_glass_a" + a + "_inside", make, -0.9f});
    cases.push_back({"rough_glass_a" + a + "_inside_tir", make, -0.4f});
  }
  cases.push_back({"rough_glass_importance_inside", [] { return rough_glass(0.3f); }, -0.6f,
                   Vec2(0.0f), TransportMode::Importance});
  const auto beckmann_glass = [] { return rough_glass(0.3f, MicrofacetType::Beckmann); };
  cases.push_back({"beckmann_glass_outside", beckmann_glass, 0.6f});
  cases.push_back({"beckmann_glass_inside", beckmann_glass, -0.5f});
  const auto beckmann_gold = [] {
    return make_rough_conductor(constant(0.3f), preset_eta("Au"), preset_k("Au"), constant(1.0f),
                                MicrofacetType::Beckmann);
  };
  cases.push_back({"beckmann_conductor_oblique", beckmann_gold, 0.5f});
  cases.push_back({"beckmann_conductor_grazing", beckmann_gold, 0.1f});
  cases.push_back({"beckmann_plastic",
                   [] {
                     return make_rough_plastic(constant(0.2f), constant(0.5f), constant(1.0f),
                                               1.5f, 1.0f, true, MicrofacetType::Beckmann);
                   },
                   0.7f});
  const auto textured_conductor = [] {
    return make_rough_conductor(checker_alpha(), preset_eta("Fe"), preset_k("Fe"),
                                constant(1.0f));
  };
  cases.push_back({"textured_alpha_conductor_cell0", textured_conductor, 0.6f, kCell0});
  cases.push_back({"textured_alpha_conductor_cell1", textured_conductor, 0.6f, kCell1});
  cases.push_back({"two_sided_textured_plastic_back",
                   [] {
                     return make_two_sided(make_rough_plastic(
                         checker_alpha(), make_checkerboard_texture(Rgb(0.8f), Rgb(0.1f)),
                         constant(1.0f)));
                   },
                   -0.5f, kCell1});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Materials, NewBsdfChiSquare, ::testing::ValuesIn(chi_square_cases()),
                         [](const auto& info) { return info.param.label; });

// The harness must reject a rough dielectric density of slightly different roughness.
TEST(NewBsdfChiSquareTeeth, RejectsDielectricDensityOfNeighbouringRoughness) {
  const BsdfPtr sampled = rough_glass(0.3f), other = rough_glass(0.33f);
  const BsdfContext ctx;
  const Vec3 wo = incident(0.7f);
  EXPECT_LT(test::run_chi_square(*sampled, ctx, wo, test::density_of(*other, ctx, wo), 7)
                .chi2.p_value,
            1e-6);
}

// ---------------------------------------------------------------------------------------

struct NamedBsdf {
  std::string label;
  BsdfPtr bsdf;
  Vec2 uv{0.0f};
};

std::vector<NamedBsdf> new_materials() {
  return {
      {"rough_glass_a10", rough_glass(0.1f)},
      {"rough_glass_a50", rough_glass(0.5f)},
      {"rough_glass_low_ior", rough_glass(0.3f, MicrofacetType::Ggx, 1.1f)},
      {"beckmann_glass_a30", rough_glass(0.3f, MicrofacetType::Beckmann)},
      {"beckmann_conductor",
       make_rough_conductor(constant(0.25f), preset_eta("Cu"), preset_k("Cu"), constant(0.9f),
                            MicrofacetType::Beckmann)},
      {"nonlinear_plastic",
       make_rough_plastic(constant(0.2f), make_constant_texture(Rgb(0.7f, 0.4f, 0.1f)),
                          constant(1.0f), 1.5f, 1.0f, true)},
      {"textured_conductor_cell1",
       make_rough_conductor(checker_alpha(), preset_eta("Ti"), preset_k("Ti"),
                            make_checkerboard_texture(Rgb(1.0f), Rgb(0.5f))),
       kCell1},
      {"thin_glass", make_thin_dielectric(1.5f, 1.0f)},
      {"smooth_conductor", make_conductor(preset_eta("W"), preset_k("W"))},
  };
}

void expect_relative_near(double actual, double expected, double tolerance,
                          const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::max(std::abs(expected), 1e-6)) << what;
}

TEST(NewBsdfConsistency, SampleAgreesWithEvalPdfAndReversePdfInBothModes) {
  for (const auto& [label, bsdf, uv] : new_materials()) {
    Rng rng(41, 0);
    int checked = 0;
    for (int n = 0; n < 3000; ++n) {
      const Vec3 wo = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      for (const TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
        const BsdfContext ctx{uv, mode};
        const auto s = bsdf->sample(ctx, wo, rng.uniform(), rng.uniform2());
        if (!s) continue;
        const std::string what = label + " wo.z=" + std::to_string(wo.z);
        ASSERT_TRUE(is_finite(s->value) && is_finite(s->weight)) << what;
        ASSERT_GT(s->pdf, 0.0f) << what;
        ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f) << what;
        ASSERT_EQ(s->lobe & ~bsdf->lobes(), 0u) << what;
        for (int c = 0; c < 3; ++c)
          expect_relative_near(s->weight[c], s->value[c] * std::abs(s->wi.z) / s->pdf, 1e-3,
                               what + " weight");
        if (s->is_delta()) continue;
        expect_relative_near(s->pdf, bsdf->pdf(ctx, wo, s->wi), 2e-3, what + " pdf");
        expect_relative_near(s->pdf_reverse, bsdf->pdf(ctx, s->wi, wo), 2e-3, what + " pdf_rev");
        const Rgb f = bsdf->eval(ctx, wo, s->wi);
        for (int c = 0; c < 3; ++c) expect_relative_near(s->value[c], f[c], 2e-3, what + " value");
        ++checked;
      }
    }
    if (!bsdf->is_purely_delta()) {
      EXPECT_GT(checked, 1500) << label;
    }
  }
}

// Reflection is symmetric; refraction is symmetric between the radiance BSDF and its
// adjoint: f_importance(wo, wi) = f_radiance(wi, wo), i.e. f(wo, wi) / n_wi^2 = f(wi, wo) /
// n_wo^2 for the radiance BSDF (Veach 1997, 5.2).
TEST(NewBsdfReciprocity, ReflectionSymmetricAndRefractionAdjoint) {
  for (const auto& [label, bsdf, uv] : new_materials()) {
    Rng rng(47, 0);
    int transmissions = 0;
    for (int n = 0; n < 3000; ++n) {
      const Vec3 wo = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      const Vec3 wi = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      const BsdfContext radiance{uv, TransportMode::Radiance};
      const BsdfContext importance{uv, TransportMode::Importance};
      const Rgb forward = bsdf->eval(radiance, wo, wi);
      if (wo.z * wi.z > 0.0f) {
        const Rgb backward = bsdf->eval(radiance, wi, wo);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(forward[c], backward[c], 2e-4f * std::max(1.0f, forward[c])) << label;
      } else {
        const Rgb adjoint = bsdf->eval(importance, wi, wo);
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(forward[c], adjoint[c], 2e-4f * std::max(1.0f, forward[c])) << label;
        if (forward.x > 0.0f) ++transmissions;
      }
    }
    // Uniform pairs rarely land in a narrow refraction lobe; enough of them must.
    if (bsdf->lobes() & kLobeTransmission && !bsdf->is_purely_delta()) {
      EXPECT_GT(transmissions, 40) << label;
    }
  }
}

// Energy: light arriving along wo (importance transport follows the light) never leaves
// with more power, from either side; radiance transport entering the denser side is
// compressed by 1/eta^2 and also stays below 1.
TEST(NewBsdfEnergy, RoughDielectricNeverCreatesEnergy) {
  for (const MicrofacetType type : {MicrofacetType::Ggx, MicrofacetType::Beckmann})
    for (const float alpha : {0.05f, 0.3f, 0.8f})
      for (const float c : {0.95f, 0.6f, 0.2f, -0.95f, -0.6f, -0.2f}) {
        const BsdfPtr bsdf = rough_glass(alpha, type);
        const auto a = test::estimate_albedo(*bsdf, {Vec2(0.0f), TransportMode::Importance},
                                             incident(c), 20000, 61);
        EXPECT_LE(a.mean.x, 1.0f + 4.0f * a.standard_error.x + 2e-3f) << alpha << " " << c;
        if (c > 0.0f) {
          const auto r = test::estimate_albedo(*bsdf, {}, incident(c), 20000, 61);
          EXPECT_LE(r.mean.x, 1.0f + 4.0f * r.standard_error.x + 2e-3f) << alpha << " " << c;
        }
      }
}

TEST(NewBsdfEnergy, NearlySmoothRoughDielectricMatchesTheSmoothOne) {
  // At alpha = 0.01 single scattering loses almost nothing: the importance albedo is ~1
  // and the reflected fraction is the smooth interface's Fresnel reflectance.
  const BsdfPtr bsdf = rough_glass(0.01f);
  for (const float c : {0.9f, 0.5f, -0.9f, -0.5f}) {
    const Vec3 wo = incident(c);
    const auto a = test::estimate_albedo(*bsdf, {Vec2(0.0f), TransportMode::Importance}, wo,
                                         20000, 67);
    EXPECT_NEAR(a.mean.x, 1.0f, 0.01f) << c;
    Rng rng(5, 0);
    int reflected = 0, total = 20000;
    for (int n = 0; n < total; ++n) {
      const auto s = bsdf->sample({}, wo, rng.uniform(), rng.uniform2());
      if (s && s->wi.z * wo.z > 0.0f) ++reflected;
    }
    EXPECT_NEAR(double(reflected) / total, fresnel_dielectric(c, 1.5f), 0.01) << c;
  }
}

TEST(NewBsdfEnergy, BeckmannConductorWithPerfectFresnelReflectsAtMostEverything) {
  for (const float alpha : {0.05f, 0.3f, 0.8f})
    for (const float c : {1.0f, 0.7f, 0.3f, 0.05f}) {
      const BsdfPtr bsdf = make_rough_conductor(constant(alpha), Rgb(0.0f), Rgb(1.0f),
                                                constant(1.0f), MicrofacetType::Beckmann);
      const auto a = test::estimate_albedo(*bsdf, {}, incident(c), 20000, 71);
      EXPECT_LE(a.mean.x, 1.0f + 4.0f * a.standard_error.x + 2e-3f) << alpha << " " << c;
      if (alpha == 0.05f && c >= 0.3f) {
        EXPECT_GT(a.mean.x, 0.97f) << c;
      }
    }
}

TEST(NewBsdfEnergy, NonlinearPlasticIsDarkerThanLinearAndBothStayBelowOne) {
  for (const float c : {0.9f, 0.5f, 0.1f}) {
    const auto linear = test::estimate_albedo(
        *make_rough_plastic(constant(0.0f), constant(0.6f), constant(1.0f), 1.5f, 1.0f, false),
        {}, incident(c), 40000, 73);
    const auto nonlinear = test::estimate_albedo(
        *make_rough_plastic(constant(0.0f), constant(0.6f), constant(1.0f), 1.5f, 1.0f, true), {},
        incident(c), 40000, 73);
    EXPECT_LT(nonlinear.mean.x, linear.mean.x) << c;
    EXPECT_LE(linear.mean.x, 1.0f + 4.0f * linear.standard_error.x) << c;
  }
}

TEST(ThinDielectric, ReflectsTheSlabFresnelAndTransmitsStraightThrough) {
  const BsdfPtr bsdf = make_thin_dielectric(1.5f, 1.0f);
  EXPECT_EQ(bsdf->name(), "thin_dielectric");
  for (const float c : {0.95f, 0.5f, 0.1f, -0.7f}) {
    const Vec3 wo = incident(c);
    const float r = fresnel_dielectric(std::abs(c), 1.5f), t = 1.0f - r;
    const float expected = r + t * t * r / (1.0f - r * r);
    Rng rng(9, 0);
    int reflected = 0, total = 40000;
    for (int n = 0; n < total; ++n) {
      const auto s = bsdf->sample({}, wo, rng.uniform(), rng.uniform2());
      ASSERT_TRUE(s);
      EXPECT_EQ(s->weight, Rgb(1.0f));  // white slab: no energy lost or created
      EXPECT_EQ(s->eta, 1.0f);
      if (s->wi.z * wo.z > 0.0f) {
        ++reflected;
        EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
      } else {
        EXPECT_EQ(s->wi, -wo);
      }
    }
    const double sigma = std::sqrt(expected * (1.0 - expected) / total);
    EXPECT_NEAR(double(reflected) / total, expected, 4.0 * sigma + 1e-4) << c;
  }
}

TEST(SmoothConductor, WeightIsTheConductorFresnelTermOfTheIncidentAngle) {
  const Rgb eta = preset_eta("Au"), k = preset_k("Au");
  const BsdfPtr gold = make_conductor(eta, k, Rgb(0.9f));
  for (const float c : {1.0f, 0.7f, 0.3f, 0.05f}) {
    const auto s = gold->sample({}, incident(c), 0.5f, Vec2(0.5f));
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->is_delta());
    const Rgb expected = 0.9f * fresnel_conductor(c, eta, k);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(s->weight[i], expected[i], 1e-6f) << c;
  }
  // Grazing light brightens towards white (what the old tinted-mirror approximation lost).
  const auto normal = gold->sample({}, incident(1.0f), 0.5f, Vec2(0.5f));
  const auto grazing = gold->sample({}, incident(0.02f), 0.5f, Vec2(0.5f));
  EXPECT_GT(grazing->weight.z, normal->weight.z + 0.3f);
  const auto mirror = make_conductor(Rgb(0.0f), Rgb(1.0f))->sample({}, incident(0.3f), 0.5f, Vec2(0.5f));
  EXPECT_NEAR(mirror->weight.x, 1.0f, 1e-6f);
  EXPECT_FALSE(gold->sample({}, incident(-0.5f), 0.5f, Vec2(0.5f)));  // one-sided
}

TEST(BeckmannDistribution, IsNormalisedAndItsVisibleNormalsAreToo) {
  const auto integrate_hemisphere = [](const std::function<double(const Vec3&)>& f) {
    double total = 0.0;
    for (int p = 0; p < 64; ++p) {
      const double t0 = 0.5 * M_PI * p / 64, t1 = 0.5 * M_PI * (p + 1) / 64;
      total += test::integrate_2d(
          [&](double theta, double phi) {
            return f(spherical_direction(std::cos(theta), phi)) * std::sin(theta);
          },
          t0, t1, 0.0, 2.0 * M_PI, 32);
    }
    return total;
  };
  for (const float alpha : {0.05f, 0.3f, 0.8f}) {
    const MicrofacetDistribution beckmann(MicrofacetType::Beckmann, alpha);
    EXPECT_NEAR(integrate_hemisphere([&](const Vec3& m) { return beckmann.D(m) * m.z; }), 1.0,
                1e-3)
        << alpha;
    // Smith's G1 normalises the visible normals exactly when Lambda is consistent with D.
    for (const float cos_o : {0.9f, 0.4f, 0.1f}) {
      const Vec3 wo = spherical_direction(cos_o, 0.4);
      const double g1 = 1.0 / (1.0 + beckmann.lambda(wo));
      const double visible = integrate_hemisphere([&](const Vec3& m) {
        return g1 * std::max(0.0f, glm::dot(wo, m)) * beckmann.D(m) / wo.z;
      });
      EXPECT_NEAR(visible, 1.0, 3e-3) << alpha << " " << cos_o;
    }
  }
}

// ---------------------------------------------------------------------------------------
// Textured parameters read ctx.uv.

TEST(TexturedBsdf, ParametersFollowTheTextureAtTheQueriedUv) {
  const Rgb color0(0.8f, 0.2f, 0.1f), color1(0.1f, 0.3f, 0.9f);
  const BsdfPtr diffuse = make_lambertian(make_checkerboard_texture(color0, color1));
  const Vec3 wo = incident(0.6f), wi = spherical_direction(0.8, 2.0);
  const Rgb f0 = diffuse->eval({kCell0, TransportMode::Radiance}, wo, wi);
  const Rgb f1 = diffuse->eval({kCell1, TransportMode::Radiance}, wo, wi);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(f0[c], color0[c] / kPi, 1e-6f);
    EXPECT_NEAR(f1[c], color1[c] / kPi, 1e-6f);
  }
  const auto s = diffuse->sample({kCell1, TransportMode::Radiance}, wo, 0.5f, Vec2(0.3f, 0.6f));
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->weight.z, color1.z, 1e-6f);

  // A textured roughness equals the constant one of the texel's value.
  const Rgb eta = preset_eta("Ni"), k = preset_k("Ni");
  const BsdfPtr textured = make_rough_conductor(checker_alpha(), eta, k, constant(1.0f));
  const BsdfPtr smooth = make_rough_conductor(0.1f, eta, k), rough = make_rough_conductor(0.5f, eta, k);
  const BsdfContext at0{kCell0, TransportMode::Radiance}, at1{kCell1, TransportMode::Radiance};
  EXPECT_EQ(textured->eval(at0, wo, wi), smooth->eval({}, wo, wi));
  EXPECT_EQ(textured->eval(at1, wo, wi), rough->eval({}, wo, wi));
  EXPECT_EQ(textured->pdf(at1, wo, wi), rough->pdf({}, wo, wi));
  EXPECT_NE(textured->eval(at0, wo, wi), textured->eval(at1, wo, wi));

  const BsdfPtr plastic = make_rough_plastic(constant(0.2f), make_checkerboard_texture(color0, color1),
                                             constant(1.0f));
  const BsdfPtr plain = make_rough_plastic(0.2f, color1);
  EXPECT_EQ(plastic->eval(at1, wo, wi), plain->eval({}, wo, wi));
  EXPECT_EQ(plastic->pdf(at1, wo, wi), plain->pdf({}, wo, wi));
}

}  // namespace
