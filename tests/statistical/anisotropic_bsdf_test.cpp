// Mitsuba 0.6's microfacet models in full: anisotropic roughness (alpha_u along the shading
// frame's s axis, alpha_v along t) for Beckmann, GGX and Phong, Mitsuba's separable Smith
// masking-shadowing, in the rough conductor and the rough dielectric. Checks the
// distributions against formulas written out independently here (which also pins which
// axis alpha_u belongs to: sampling and density would agree with each other even with the
// axes swapped), their normalisation, sampling against pdf (chi-square), sample/eval/pdf
// agreement, reciprocity and energy.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/microfacet.h"
#include "support/bsdf_harness.h"

using namespace emlt;
using test::incident;
using test::spherical_direction;

namespace {

constexpr double kMinPValue = 1e-3;

const MicrofacetType kTypes[] = {MicrofacetType::Ggx, MicrofacetType::Beckmann,
                                 MicrofacetType::Phong};

std::string type_name(MicrofacetType type) {
  return type == MicrofacetType::Ggx ? "ggx" : type == MicrofacetType::Beckmann ? "beckmann" : "phong";
}

struct AlphaPair {
  float u, v;
};
const AlphaPair kAlphas[] = {{0.05f, 0.4f}, {0.4f, 0.1f}, {0.3f, 0.3f}, {0.8f, 0.2f}};

// Integral over the upper hemisphere (solid angle), in pieces fine enough for a lobe of
// width 0.05 in either direction.
double integrate_hemisphere(const std::function<double(const Vec3&)>& f) {
  double total = 0.0;
  const int theta_pieces = 96, phi_pieces = 32;
  for (int p = 0; p < theta_pieces; ++p) {
    const double t0 = 0.5 * M_PI * p / theta_pieces, t1 = 0.5 * M_PI * (p + 1) / theta_pieces;
    for (int q = 0; q < phi_pieces; ++q) {
      const double p0 = 2.0 * M_PI * q / phi_pieces, p1 = 2.0 * M_PI * (q + 1) / phi_pieces;
      total += test::integrate_2d(
          [&](double theta, double phi) {
            return f(spherical_direction(std::cos(theta), phi)) * std::sin(theta);
          },
          t0, t1, p0, p1, 8);
    }
  }
  return total;
}

// ---------------------------------------------------------------------------------------
// The formulas, written out from the papers (Walter et al. 2007; Ashikhmin & Shirley 2000;
// Mitsuba 0.6's documentation of alpha_u / alpha_v and its Phong exponent 2 / alpha^2 - 2)
// in spherical coordinates, independently of microfacet.cpp's Cartesian forms.

double reference_D(MicrofacetType type, double au, double av, double theta, double phi) {
  const double c = std::cos(theta), t2 = std::tan(theta) * std::tan(theta);
  const double cp = std::cos(phi), sp = std::sin(phi);
  const double azimuthal = cp * cp / (au * au) + sp * sp / (av * av);
  switch (type) {
    case MicrofacetType::Ggx:
      return 1.0 / (M_PI * au * av * std::pow(c, 4) * square(1.0 + t2 * azimuthal));
    case MicrofacetType::Beckmann:
      return std::exp(-t2 * azimuthal) / (M_PI * au * av * std::pow(c, 4));
    case MicrofacetType::Phong: {
      const double eu = 2.0 / (au * au) - 2.0, ev = 2.0 / (av * av) - 2.0;
      return std::sqrt((eu + 2.0) * (ev + 2.0)) / (2.0 * M_PI) *
             std::pow(c, eu * cp * cp + ev * sp * sp);
    }
  }
  return 0.0;
}

// Smith G1 of a direction (theta, phi) seen by a front-facing microfacet, as Mitsuba has it.
double reference_G1(MicrofacetType type, double au, double av, double theta, double phi) {
  const double alpha = std::sqrt(square(std::cos(phi) * au) + square(std::sin(phi) * av));
  const double tan_theta = std::tan(theta);
  if (type == MicrofacetType::Ggx)
    return 2.0 / (1.0 + std::sqrt(1.0 + square(alpha * tan_theta)));
  const double a = 1.0 / (alpha * tan_theta);
  return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

TEST(AnisotropicMicrofacet, MatchesTheFormulasWithAlphaUAlongS) {
  for (const MicrofacetType type : kTypes) {
    for (const AlphaPair a : kAlphas) {
      const MicrofacetDistribution dist(type, a.u, a.v);
      for (const double theta : {0.0, 0.05, 0.2, 0.6, 1.1}) {
        for (const double phi : {0.0, 0.4, M_PI / 2, 2.0, 4.0}) {
          const Vec3 m = spherical_direction(std::cos(theta), phi);
          const double expected = reference_D(type, a.u, a.v, theta, phi);
          const std::string what = type_name(type) + " " + std::to_string(a.u) + "/" +
                                   std::to_string(a.v) + " theta " + std::to_string(theta) +
                                   " phi " + std::to_string(phi);
          EXPECT_NEAR(dist.D(m), expected, 2e-4 * expected + 1e-6) << what;
          if (theta > 0.0) {
            // G1 of the direction m for the macro normal (always front-facing).
            const double g1 = reference_G1(type, a.u, a.v, theta, phi);
            EXPECT_NEAR(dist.G1(m, Vec3(0, 0, 1)), g1, 1e-5) << what;
          }
        }
      }
    }
  }
}

TEST(AnisotropicMicrofacet, IsNormalisedAndVisibleNormalsToo) {
  for (const MicrofacetType type : kTypes) {
    for (const AlphaPair a : kAlphas) {
      const MicrofacetDistribution dist(type, a.u, a.v);
      const std::string what = type_name(type) + " " + std::to_string(a.u) + "/" + std::to_string(a.v);
      EXPECT_NEAR(integrate_hemisphere([&](const Vec3& m) { return dist.D(m) * m.z; }), 1.0, 2e-3)
          << what;
      if (type == MicrofacetType::Phong) continue;  // no exact Lambda of its own
      // Smith's 1 / (1 + Lambda) normalises the visible normals only when Lambda is the
      // one of this anisotropic D (projected roughness along wo's azimuth).
      for (const float cos_o : {0.9f, 0.4f, 0.1f}) {
        for (const double phi : {0.3, 1.2, 2.5}) {
          const Vec3 wo = spherical_direction(cos_o, phi);
          const double g1 = 1.0 / (1.0 + dist.lambda(wo));
          const double visible = integrate_hemisphere([&](const Vec3& m) {
            return g1 * std::max(0.0f, glm::dot(wo, m)) * dist.D(m) / wo.z;
          });
          EXPECT_NEAR(visible, 1.0, 3e-3) << what << " cos_o " << cos_o << " phi " << phi;
          if (type == MicrofacetType::Ggx) {
            // The sampling density of GGX's visible normals is that very function.
            const double sampled = integrate_hemisphere([&](const Vec3& m) { return dist.normal_pdf(wo, m); });
            EXPECT_NEAR(sampled, 1.0, 3e-3) << what;
          }
        }
      }
    }
  }
}

TEST(AnisotropicMicrofacet, MitsubasBeckmannG1FitsTheExactOne) {
  for (const AlphaPair a : kAlphas) {
    const MicrofacetDistribution dist(MicrofacetType::Beckmann, a.u, a.v);
    for (float c = 0.02f; c < 1.0f; c += 0.03f) {
      for (const double phi : {0.1, 0.9, 1.6, 3.0}) {
        const Vec3 w = spherical_direction(c, phi);
        const double exact = 1.0 / (1.0 + dist.lambda(w));
        EXPECT_NEAR(dist.G1(w, Vec3(0, 0, 1)), exact, 4e-3 * exact) << c << " " << phi;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// BSDFs.

BsdfPtr conductor(MicrofacetType type, AlphaPair a, const char* material = "Ag") {
  Rgb eta, k;
  conductor_preset(material, &eta, &k);
  return make_rough_conductor(make_constant_texture(Rgb(a.u)), eta, k,
                              make_constant_texture(Rgb(1.0f)), type,
                              make_constant_texture(Rgb(a.v)));
}

BsdfPtr glass(MicrofacetType type, AlphaPair a) {
  return make_rough_dielectric(make_constant_texture(Rgb(a.u)), 1.5f, 1.0f, type, Rgb(1.0f),
                               Rgb(1.0f), make_constant_texture(Rgb(a.v)));
}

struct Case {
  std::string label;
  std::function<BsdfPtr()> make;
  Vec3 wo;
  TransportMode mode = TransportMode::Radiance;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.label; }

std::vector<Case> chi_square_cases() {
  std::vector<Case> cases;
  for (const MicrofacetType type : kTypes) {
    const std::string t = type_name(type);
    for (const AlphaPair a : {AlphaPair{0.05f, 0.4f}, AlphaPair{0.5f, 0.15f}}) {
      const std::string as = std::to_string(int(a.u * 100 + 0.5f)) + "_" +
                             std::to_string(int(a.v * 100 + 0.5f));
      for (const float c : {0.9f, 0.5f, 0.15f}) {
        const std::string cs = std::to_string(int(c * 100 + 0.5f));
        cases.push_back({t + "_conductor_" + as + "_cos" + cs, [=] { return conductor(type, a); },
                         spherical_direction(c, 1.1)});
        cases.push_back({t + "_glass_" + as + "_cos" + cs, [=] { return glass(type, a); },
                         spherical_direction(c, 2.0)});
      }
      cases.push_back({t + "_glass_" + as + "_inside", [=] { return glass(type, a); },
                       spherical_direction(-0.6, 0.5)});
      cases.push_back({t + "_glass_" + as + "_importance", [=] { return glass(type, a); },
                       spherical_direction(0.4, 4.0), TransportMode::Importance});
      cases.push_back({t + "_two_sided_conductor_" + as + "_back",
                       [=] { return make_two_sided(conductor(type, a)); },
                       spherical_direction(-0.5, 5.0)});
    }
  }
  return cases;
}

class AnisotropicChiSquare : public ::testing::TestWithParam<Case> {};

TEST_P(AnisotropicChiSquare, SamplesFollowPdf) {
  const Case& param = GetParam();
  const BsdfPtr bsdf = param.make();
  const BsdfContext ctx{Vec2(0.0f), param.mode};
  const test::ChiSquareOutcome outcome =
      test::run_chi_square(*bsdf, ctx, param.wo, test::density_of(*bsdf, ctx, param.wo), 101);
  EXPECT_GT(outcome.chi2.p_value, kMinPValue)
      << bsdf->name() << " statistic " << outcome.chi2.statistic << " dof "
      << outcome.chi2.degrees_of_freedom;
  EXPECT_LE(outcome.density_integral, 1.0 + 1e-3);
  const double sigma = std::sqrt(0.25 / test::ChiSquareSetup{}.samples);
  EXPECT_NEAR(outcome.density_integral, outcome.sampled_fraction, 4.0 * sigma + 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Materials, AnisotropicChiSquare, ::testing::ValuesIn(chi_square_cases()),
                         [](const auto& info) { return info.param.label; });

// The chi-square test tells the axes apart: samples of alpha (0.1, 0.3) against the
// density of (0.3, 0.1) fail, for every distribution.
TEST(AnisotropicChiSquareTeeth, RejectsTheDensityWithSwappedAxes) {
  for (const MicrofacetType type : kTypes) {
    const BsdfPtr sampled = conductor(type, {0.1f, 0.3f}), swapped = conductor(type, {0.3f, 0.1f});
    const Vec3 wo = spherical_direction(0.7, 0.8);
    const auto outcome = test::run_chi_square(*sampled, {}, wo, test::density_of(*swapped, {}, wo), 7);
    EXPECT_LT(outcome.chi2.p_value, 1e-6) << type_name(type);
  }
}

std::vector<std::pair<std::string, BsdfPtr>> materials() {
  std::vector<std::pair<std::string, BsdfPtr>> all;
  for (const MicrofacetType type : kTypes)
    for (const AlphaPair a : {AlphaPair{0.05f, 0.4f}, AlphaPair{0.6f, 0.2f}, AlphaPair{0.25f, 0.25f}}) {
      const std::string label = type_name(type) + " " + std::to_string(a.u) + "/" + std::to_string(a.v);
      all.push_back({label + " conductor", conductor(type, a, "Cu")});
      all.push_back({label + " glass", glass(type, a)});
    }
  return all;
}

TEST(AnisotropicBsdf, SampleAgreesWithEvalAndPdf) {
  for (const auto& [label, bsdf] : materials()) {
    Rng rng(41, 0);
    int checked = 0;
    for (int n = 0; n < 3000; ++n) {
      const Vec3 wo = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      for (const TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
        const BsdfContext ctx{Vec2(0.0f), mode};
        const auto s = bsdf->sample(ctx, wo, rng.uniform(), rng.uniform2());
        if (!s) continue;
        const std::string what = label + " wo " + std::to_string(wo.x) + "," +
                                 std::to_string(wo.y) + "," + std::to_string(wo.z);
        ASSERT_TRUE(is_finite(s->weight) && s->pdf > 0.0f) << what;
        const float pdf = bsdf->pdf(ctx, wo, s->wi), reverse = bsdf->pdf(ctx, s->wi, wo);
        EXPECT_NEAR(s->pdf, pdf, 1e-3f * pdf) << what;
        EXPECT_NEAR(s->pdf_reverse, reverse, 1e-3f * reverse) << what;
        const Rgb f = bsdf->eval(ctx, wo, s->wi);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(s->value[c], f[c], 1e-3f * f[c] + 1e-7f) << what;
          EXPECT_NEAR(s->weight[c], f[c] * std::abs(s->wi.z) / pdf,
                      1e-3f * s->weight[c] + 1e-7f) << what;
        }
        ++checked;
      }
    }
    EXPECT_GT(checked, 2000) << label;
  }
}

TEST(AnisotropicBsdf, Reciprocity) {
  for (const auto& [label, bsdf] : materials()) {
    Rng rng(47, 0);
    for (int n = 0; n < 3000; ++n) {
      const Vec3 wo = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      const Vec3 wi = spherical_direction(2.0 * rng.uniform() - 1.0, 2.0 * M_PI * rng.uniform());
      // Radiance transport in one direction is importance transport in the other (for
      // reflection both are the plain, symmetric BRDF).
      const Rgb forward = bsdf->eval({Vec2(0.0f), TransportMode::Radiance}, wo, wi);
      const Rgb backward = bsdf->eval({Vec2(0.0f), TransportMode::Importance}, wi, wo);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(forward[c], backward[c], 2e-4f * std::max(1.0f, forward[c])) << label;
    }
  }
}

TEST(AnisotropicBsdf, NeverCreatesEnergy) {
  for (const MicrofacetType type : kTypes) {
    for (const AlphaPair a : kAlphas) {
      // A perfect reflector (F = 1) and glass in importance mode (no 1/eta^2 radiance
      // scaling): what comes out is at most what went in.
      for (const BsdfPtr& bsdf : {conductor(type, a, "none"), glass(type, a)}) {
        for (const float c : {1.0f, 0.7f, 0.3f, 0.05f, -0.4f}) {
          if (c < 0.0f && !(bsdf->lobes() & kLobeTransmission)) continue;
          // Mitsuba's Phong masks with the Beckmann G1, which a rough Phong surface's heavy
          // tails outgrow towards grazing angles: the model itself then reflects more than
          // it receives (PhongCreatesEnergyAsMitsubasDoes below); exempt from this bound.
          if (type == MicrofacetType::Phong && std::max(a.u, a.v) > 0.4f) continue;
          const BsdfContext ctx{Vec2(0.0f), TransportMode::Importance};
          const test::Albedo albedo =
              test::estimate_albedo(*bsdf, ctx, spherical_direction(c, 0.9), 40000, 61);
          EXPECT_LE(albedo.mean.x, 1.0f + 4.0f * albedo.standard_error.x + 2e-3f)
              << bsdf->name() << " " << a.u << "/" << a.v << " cos " << c;
        }
      }
    }
  }
}

// References from an independent numerical integration (numpy, 3000 x 6000 midpoint rule)
// of D(h) G1(wo, h) G1(wi, h) / (4 cos_o) with Mitsuba's isotropic Phong: above 1 for a
// rough surface at grazing incidence, as in Mitsuba.
TEST(AnisotropicBsdf, PhongCreatesEnergyAsMitsubasDoes) {
  const struct {
    float alpha, cos_o;
    double albedo;
  } references[] = {{0.2f, 0.3f, 0.9255}, {0.5f, 0.05f, 1.0408}, {0.8f, 0.05f, 1.1861}};
  for (const auto& ref : references) {
    const BsdfPtr bsdf = conductor(MicrofacetType::Phong, {ref.alpha, ref.alpha}, "none");
    const test::Albedo a = test::estimate_albedo(*bsdf, {}, incident(ref.cos_o), 100000, 67);
    EXPECT_NEAR(a.mean.x, ref.albedo, 4.0 * a.standard_error.x + 2e-3) << ref.alpha;
  }
}

// A conductor's value is Mitsuba's F D G1(wo) G1(wi) / (4 cos_o cos_i), with the formulas
// above: the end-to-end check that the BSDF uses the separable G and the right axes.
TEST(AnisotropicBsdf, ConductorValueIsMitsubas) {
  for (const MicrofacetType type : kTypes) {
    const AlphaPair a{0.25f, 0.6f};  // rough enough that both G1 are well below 1
    const BsdfPtr bsdf = conductor(type, a, "none");  // F = 1
    for (const double phi : {0.0, 0.7, M_PI / 2}) {
      const Vec3 wo = spherical_direction(0.5, phi), wi = spherical_direction(0.3, phi + M_PI + 0.1);
      const Vec3 h = glm::normalize(wo + wi);
      const double h_theta = std::acos(double(h.z)), h_phi = std::atan2(double(h.y), double(h.x));
      const auto g1 = [&](const Vec3& w) {
        return reference_G1(type, a.u, a.v, std::acos(double(w.z)), std::atan2(double(w.y), double(w.x)));
      };
      const double expected = reference_D(type, a.u, a.v, h_theta, h_phi) * g1(wo) * g1(wi) /
                              (4.0 * wo.z * wi.z);
      EXPECT_NEAR(bsdf->eval({}, wo, wi).x, expected, 1e-3 * expected) << type_name(type) << " " << phi;
    }
  }
}

}  // namespace
