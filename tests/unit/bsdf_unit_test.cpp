// Unit tests of the BSDF building blocks (Fresnel, GGX, conductor presets) and of the
// delta BSDFs (mirror, smooth dielectric, smooth plastic coating).
#include <gtest/gtest.h>

#include <cmath>

#include "emlt/core/rng.h"
#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"
#include "src/scene/materials/fresnel.h"
#include "src/scene/materials/microfacet.h"
#include "src/scene/materials/rough_transmittance.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

Vec3 direction(double cos_theta, double phi) {
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {static_cast<float>(sin_theta * std::cos(phi)),
          static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(cos_theta)};
}

// Reference Fresnel reflectance in double from the textbook amplitude coefficients, for
// light going from a medium of index n1 into one of index n2.
double reference_fresnel(double cos_i, double n1, double n2) {
  const double sin_t = n1 / n2 * std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
  const double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
  const double rp = (n2 * cos_i - n1 * cos_t) / (n2 * cos_i + n1 * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// ---------------------------------------------------------------------------------------
// Fresnel

TEST(BsdfFresnel, DielectricMatchesReferenceFromBothSides) {
  const float eta = 1.5f;
  EXPECT_NEAR(fresnel_dielectric(1.0f, eta), 0.04f, 1e-6f);
  for (double c = 0.01; c <= 1.0; c += 0.01) {
    float cos_t = 0.0f;
    EXPECT_NEAR(fresnel_dielectric(static_cast<float>(c), eta, &cos_t),
                reference_fresnel(c, 1.0, 1.5), 1e-5);
    EXPECT_LT(cos_t, 0.0f);  // refracted direction is inside
    EXPECT_NEAR(fresnel_dielectric(static_cast<float>(-c), eta, &cos_t),
                reference_fresnel(c, 1.5, 1.0), 1e-5);
    EXPECT_GE(cos_t, 0.0f);
  }
  float cos_t = 1.0f;
  EXPECT_EQ(fresnel_dielectric(-0.3f, eta, &cos_t), 1.0f);  // beyond the critical angle
  EXPECT_EQ(cos_t, 0.0f);
  EXPECT_EQ(fresnel_dielectric(0.0f, eta), 1.0f);           // grazing
  EXPECT_EQ(fresnel_dielectric(0.6f, 1.0f), 0.0f);          // index-matched: invisible
}

TEST(BsdfFresnel, ConductorReducesToDielectricAndPerfectMirror) {
  for (float c = 0.0f; c <= 1.0f; c += 0.05f) {
    EXPECT_NEAR(fresnel_conductor(c, 1.5f, 0.0f), fresnel_dielectric(c, 1.5f), 1e-5f) << c;
    EXPECT_NEAR(fresnel_conductor(c, 0.0f, 1.0f), 1.0f, 1e-6f) << c;
  }
  // Normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
  EXPECT_NEAR(fresnel_conductor(1.0f, 0.2f, 3.0f), (0.64 + 9.0) / (1.44 + 9.0), 1e-5);
  // Reflectance of a metal grows towards grazing incidence and reaches 1 there.
  EXPECT_GT(fresnel_conductor(0.1f, 0.2f, 3.0f), fresnel_conductor(0.9f, 0.2f, 3.0f));
  EXPECT_NEAR(fresnel_conductor(0.0f, 0.2f, 3.0f), 1.0f, 1e-6f);
}

TEST(BsdfFresnel, DiffuseReflectanceObeysInternalExternalRelation) {
  // Energy balance across the interface: 1 - Fdr(1/eta) = (1 - Fdr(eta)) / eta^2.
  for (const float eta : {1.2f, 1.33f, 1.5f, 2.0f}) {
    const double external = fresnel_diffuse_reflectance(eta);
    const double internal = fresnel_diffuse_reflectance(1.0f / eta);
    EXPECT_NEAR(1.0 - internal, (1.0 - external) / (eta * eta), 2e-4) << eta;
    EXPECT_GT(internal, external);
  }
  EXPECT_NEAR(fresnel_diffuse_reflectance(1.5f), 0.0918, 1e-3);  // tabulated value
}

// ---------------------------------------------------------------------------------------
// GGX

TEST(BsdfGgx, ProjectedNormalDistributionAndVisibleNormalsAreNormalised) {
  for (const float alpha : {0.05f, 0.3f, 0.8f}) {
    const MicrofacetDistribution ggx(MicrofacetType::Ggx, alpha);
    // Integrate over theta in pieces fine enough for the sharpest lobe.
    const auto integrate_hemisphere = [&](const std::function<double(const Vec3&)>& f) {
      double total = 0.0;
      const int pieces = 64;
      for (int p = 0; p < pieces; ++p) {
        const double t0 = 0.5 * M_PI * p / pieces, t1 = 0.5 * M_PI * (p + 1) / pieces;
        total += test::integrate_2d(
            [&](double theta, double phi) {
              return f(direction(std::cos(theta), phi)) * std::sin(theta);
            },
            t0, t1, 0.0, 2.0 * M_PI, 32);
      }
      return total;
    };
    EXPECT_NEAR(integrate_hemisphere([&](const Vec3& m) { return ggx.D(m) * m.z; }), 1.0, 1e-3)
        << alpha;
    // Smith's G1 is exactly the normalisation of the visible normals: this catches an
    // inconsistent Lambda.
    for (const float cos_o : {1.0f, 0.5f, 0.1f}) {
      const Vec3 wo = direction(cos_o, 0.4);
      const double total =
          integrate_hemisphere([&](const Vec3& m) { return ggx.normal_pdf(wo, m); });
      EXPECT_NEAR(total, 1.0, 2e-3) << alpha << " " << cos_o;
    }
  }
}

TEST(BsdfGgx, VisibleNormalsFaceTheViewer) {
  const MicrofacetDistribution ggx(MicrofacetType::Ggx, 0.6f, 0.2f);
  Rng rng(3, 0);
  for (int n = 0; n < 10000; ++n) {
    const Vec3 wo = direction(std::max(1e-3f, rng.uniform()), 2.0 * M_PI * rng.uniform());
    const Vec3 m = ggx.sample_normal(wo, rng.uniform2());
    ASSERT_NEAR(glm::length(m), 1.0f, 1e-4f);
    ASSERT_GT(m.z, 0.0f);
    ASSERT_GE(glm::dot(wo, m), -1e-4f);
  }
}

TEST(BsdfConductorPresets, KnownNamesGivePlausibleReflectance) {
  for (const char* name : {"Cu", "Ag", "Au", "Al", "Cr", "none"}) {
    Rgb eta(-1.0f), k(-1.0f);
    ASSERT_TRUE(conductor_preset(name, &eta, &k)) << name;
    const Rgb r0 = fresnel_conductor(1.0f, eta, k);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(r0[c], 0.3f) << name;  // gold's blue is the lowest, 0.324
      EXPECT_LE(r0[c], 1.0f) << name;
    }
  }
  Rgb eta, k;
  ASSERT_TRUE(conductor_preset("Au", &eta, &k));
  const Rgb gold = fresnel_conductor(1.0f, eta, k);
  EXPECT_GT(gold.x, gold.y);  // gold is yellow: red > green > blue
  EXPECT_GT(gold.y, gold.z + 0.2f);
  ASSERT_TRUE(conductor_preset("none", &eta, &k));
  EXPECT_EQ(fresnel_conductor(0.3f, eta, k), Rgb(1.0f));
  eta = Rgb(7.0f);
  EXPECT_FALSE(conductor_preset("unobtainium", &eta, &k));
  EXPECT_EQ(eta, Rgb(7.0f));
}

// ---------------------------------------------------------------------------------------
// Mirror

TEST(BsdfMirror, ReflectsExactlyAboutTheNormal) {
  const BsdfPtr mirror = make_mirror(Rgb(0.9f, 0.8f, 0.7f));
  EXPECT_EQ(mirror->lobes(), kLobeSpecular | kLobeReflection);
  EXPECT_TRUE(mirror->is_purely_delta());
  EXPECT_EQ(mirror->name(), "mirror");
  const Vec3 wo = glm::normalize(Vec3(0.3f, -0.5f, 0.6f));
  const auto s = mirror->sample({}, wo, 0.3f, Vec2(0.2f, 0.9f));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
  EXPECT_TRUE(s->is_delta());
  EXPECT_EQ(s->lobe, kLobeSpecular | kLobeReflection);
  EXPECT_EQ(s->pdf, 1.0f);
  EXPECT_EQ(s->pdf_reverse, 1.0f);
  EXPECT_EQ(s->weight, Rgb(0.9f, 0.8f, 0.7f));
  EXPECT_NEAR(s->value.x * s->wi.z, 0.9f, 1e-6f);
  EXPECT_EQ(mirror->pdf({}, wo, s->wi), 0.0f);
  EXPECT_TRUE(is_black(mirror->eval({}, wo, s->wi)));
  EXPECT_FALSE(mirror->sample({}, -wo, 0.3f, Vec2(0.5f)));
}

// ---------------------------------------------------------------------------------------
// Smooth dielectric

constexpr float kGlass = 1.5f;

std::optional<BsdfSample> sample_lobe(const Bsdf& bsdf, const Vec3& wo, bool reflect,
                                      TransportMode mode = TransportMode::Radiance) {
  return bsdf.sample(BsdfContext{Vec2(0.0f), mode}, wo, reflect ? 0.0f : kOneMinusEpsilon,
                     Vec2(0.5f));
}

TEST(BsdfDielectric, LobesAndName) {
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  EXPECT_EQ(glass->lobes(), kLobeSpecular | kLobeReflection | kLobeTransmission);
  EXPECT_TRUE(glass->is_purely_delta());
  EXPECT_EQ(glass->name(), "dielectric");
  const Vec3 wo = direction(0.6, 1.0);
  const auto r = sample_lobe(*glass, wo, true), t = sample_lobe(*glass, wo, false);
  ASSERT_TRUE(r && t);
  EXPECT_EQ(r->lobe, kLobeSpecular | kLobeReflection);
  EXPECT_EQ(t->lobe, kLobeSpecular | kLobeTransmission);
  EXPECT_EQ(r->wi, Vec3(-wo.x, -wo.y, wo.z));
  EXPECT_EQ(r->eta, 1.0f);
  EXPECT_EQ(glass->pdf({}, wo, t->wi), 0.0f);
  EXPECT_TRUE(is_black(glass->eval({}, wo, t->wi)));
}

TEST(BsdfDielectric, RefractionObeysSnellsLawFromBothSides) {
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  for (const double cos_o : {0.99, 0.7, 0.3, 0.05, -0.99, -0.9, -0.76}) {
    const Vec3 wo = direction(cos_o, 2.3);
    const auto t = sample_lobe(*glass, wo, false);
    ASSERT_TRUE(t) << cos_o;
    ASSERT_EQ(t->lobe, kLobeSpecular | kLobeTransmission) << cos_o;
    const double n_o = cos_o > 0 ? 1.0 : kGlass, n_i = cos_o > 0 ? kGlass : 1.0;
    EXPECT_NEAR(t->eta, n_i / n_o, 1e-6);
    EXPECT_LT(t->wi.z * wo.z, 0.0f);  // crosses the interface
    EXPECT_NEAR(glm::length(t->wi), 1.0f, 1e-6f);
    const double sin_o = std::hypot(wo.x, wo.y), sin_i = std::hypot(t->wi.x, t->wi.y);
    EXPECT_NEAR(n_o * sin_o, n_i * sin_i, 1e-5) << cos_o;
    // Same plane of incidence, on the opposite side of the normal.
    EXPECT_NEAR(wo.x * t->wi.y - wo.y * t->wi.x, 0.0, 1e-5);
    EXPECT_LE(wo.x * t->wi.x + wo.y * t->wi.y, 0.0f);
  }
}

TEST(BsdfDielectric, ReflectionFrequencyMatchesFresnel) {
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  Rng rng(11, 0);
  const int n = 50000;
  for (const double cos_o : {1.0, 0.8, 0.4, 0.1, 0.02, -1.0, -0.9, -0.8}) {
    const Vec3 wo = direction(cos_o, 0.5);
    const double fresnel =
        cos_o > 0 ? reference_fresnel(cos_o, 1.0, kGlass) : reference_fresnel(-cos_o, kGlass, 1.0);
    int reflected = 0;
    for (int i = 0; i < n; ++i) {
      const auto s = glass->sample({}, wo, rng.uniform(), rng.uniform2());
      ASSERT_TRUE(s);
      const bool is_reflection = (s->lobe & kLobeReflection) != 0;
      reflected += is_reflection;
      ASSERT_NEAR(s->pdf, is_reflection ? fresnel : 1.0 - fresnel, 1e-5);
    }
    const double sigma = std::sqrt(n * fresnel * (1.0 - fresnel));
    EXPECT_NEAR(reflected, n * fresnel, 5.0 * sigma + 1.0) << cos_o;
  }
}

TEST(BsdfDielectric, TotalInternalReflectionBeyondCriticalAngle) {
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  const double critical_cos = std::sqrt(1.0 - 1.0 / (kGlass * kGlass));  // ~0.745
  for (const double cos_o : {-0.74, -0.5, -0.1, -0.01}) {
    ASSERT_LT(-cos_o, critical_cos);
    const Vec3 wo = direction(cos_o, 1.2);
    for (const float u_lobe : {0.0f, 0.5f, kOneMinusEpsilon}) {
      const auto s = glass->sample({}, wo, u_lobe, Vec2(0.5f));
      ASSERT_TRUE(s);
      EXPECT_EQ(s->lobe, kLobeSpecular | kLobeReflection);
      EXPECT_EQ(s->pdf, 1.0f);
      EXPECT_EQ(s->weight, Rgb(1.0f));
      EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
    }
  }
}

TEST(BsdfDielectric, RadianceAndImportanceDifferByEtaSquaredInTransmission) {
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  for (const double cos_o : {0.9, 0.3, -0.95, -0.8}) {
    const Vec3 wo = direction(cos_o, 0.1);
    const auto radiance = sample_lobe(*glass, wo, false, TransportMode::Radiance);
    const auto importance = sample_lobe(*glass, wo, false, TransportMode::Importance);
    ASSERT_TRUE(radiance && importance);
    EXPECT_EQ(radiance->wi, importance->wi);
    EXPECT_EQ(radiance->pdf, importance->pdf);
    const float eta2 = radiance->eta * radiance->eta;
    EXPECT_NEAR(importance->weight.x / radiance->weight.x, eta2, 1e-5f * eta2);
    EXPECT_NEAR(importance->value.y / radiance->value.y, eta2, 1e-5f * eta2);
    EXPECT_NEAR(radiance->weight.z, 1.0f / eta2, 1e-6f);
    // Reflection is the same in both modes.
    EXPECT_EQ(sample_lobe(*glass, wo, true, TransportMode::Radiance)->weight,
              sample_lobe(*glass, wo, true, TransportMode::Importance)->weight);
  }
}

TEST(BsdfDielectric, WhiteInterfaceConservesImportance) {
  // Expected weight over the lobe choice: F * w_R + (1 - F) * w_T == 1.
  const BsdfPtr glass = make_dielectric(1.33f, 1.0f);
  for (const double cos_o : {1.0, 0.6, 0.2, 0.01, -1.0, -0.8, -0.7}) {  // no TIR
    const Vec3 wo = direction(cos_o, 0.9);
    const auto r = sample_lobe(*glass, wo, true, TransportMode::Importance);
    const auto t = sample_lobe(*glass, wo, false, TransportMode::Importance);
    ASSERT_TRUE(r && t);
    const double total = r->pdf * r->weight.x + (1.0 - r->pdf) * t->weight.x;
    EXPECT_NEAR(total, 1.0, 1e-6) << cos_o;
    EXPECT_NEAR(r->pdf + t->pdf, 1.0, 1e-6) << cos_o;
  }
}

TEST(BsdfDielectric, ReverseProbabilityMatchesSamplingBackwards) {
  // Refracting back from wi must return wo with the probability stored as pdf_reverse:
  // this verifies that Fresnel transmission is the same from both sides.
  const BsdfPtr glass = make_dielectric(kGlass, 1.0f);
  for (const double cos_o : {0.95, 0.5, 0.1, -0.95, -0.8}) {
    const Vec3 wo = direction(cos_o, 2.0);
    const auto forward = sample_lobe(*glass, wo, false);
    ASSERT_TRUE(forward && (forward->lobe & kLobeTransmission));
    const auto backward = sample_lobe(*glass, forward->wi, false);
    ASSERT_TRUE(backward && (backward->lobe & kLobeTransmission));
    EXPECT_NEAR(glm::length(backward->wi - wo), 0.0f, 1e-5f);
    EXPECT_NEAR(forward->pdf_reverse, backward->pdf, 1e-5f) << cos_o;
    EXPECT_NEAR(backward->pdf_reverse, forward->pdf, 1e-5f) << cos_o;
    EXPECT_NEAR(forward->eta * backward->eta, 1.0f, 1e-6f);
  }
}

// ---------------------------------------------------------------------------------------
// Smooth plastic (delta coating)

TEST(BsdfPlastic, SmoothCoatingIsADeltaLobe) {
  const BsdfPtr plastic = make_rough_plastic(0.0f, Rgb(0.5f), Rgb(1.0f));
  EXPECT_EQ(plastic->lobes(), kLobeSpecular | kLobeDiffuse | kLobeReflection);
  EXPECT_FALSE(plastic->is_purely_delta());
  const BsdfPtr rough = make_rough_plastic(0.2f, Rgb(0.5f), Rgb(1.0f));
  EXPECT_EQ(rough->lobes(), kLobeGlossy | kLobeDiffuse | kLobeReflection);
  const Vec3 wo = direction(0.5, 0.3);
  const auto s = plastic->sample({}, wo, 0.0f, Vec2(0.3f));
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->is_delta());
  EXPECT_EQ(s->lobe, kLobeSpecular | kLobeReflection);
  EXPECT_EQ(s->wi, Vec3(-wo.x, -wo.y, wo.z));
  EXPECT_EQ(s->pdf_reverse, s->pdf);
  // The delta carries F(cos_o) of the coating in total.
  const double fresnel = reference_fresnel(0.5, 1.000277, 1.49);
  EXPECT_NEAR(s->value.x * s->wi.z, fresnel, 1e-5);
  // Without the delta, eval is the diffuse part only; its selection probability is the
  // complement of the delta's.
  const auto d = plastic->sample({}, wo, kOneMinusEpsilon, Vec2(0.3f));
  ASSERT_TRUE(d && !d->is_delta());
  EXPECT_NEAR(d->pdf, (1.0f - s->pdf) * d->wi.z / kPi, 1e-5f);
  EXPECT_EQ(d->lobe, kLobeDiffuse | kLobeReflection);
}

TEST(BsdfPlastic, CoatingIsSampledMoreOftenWhereItReflectsMore) {
  // Diffuse 0.5 vs white coating: albedo-based weight 2/3 for the coating, then scaled by
  // the light the coating reflects, 1 - T(cos_o), against T(cos_o) (as Mitsuba does): ~9%
  // coating samples at normal incidence (1 - T = 0.047), half at grazing incidence.
  const BsdfPtr plastic = make_rough_plastic(0.3f, Rgb(0.5f), Rgb(1.0f));
  const auto glossy_fraction = [&](double cos_o) {
    Rng rng(13, 0);
    int glossy = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const auto s = plastic->sample({}, direction(cos_o, 0.2), rng.uniform(), rng.uniform2());
      glossy += s && (s->lobe & kLobeGlossy);
    }
    return static_cast<double>(glossy) / n;
  };
  const auto coating_probability = [](double cos_o) {
    const double reflected = 1.0 - RoughTransmittance::integrate(MicrofacetType::Ggx, 0.3f,
                                                                 1.49f / 1.000277f, cos_o, 32);
    return reflected * 2 / (reflected * 2 + (1 - reflected));
  };
  EXPECT_NEAR(glossy_fraction(1.0), coating_probability(1.0), 0.01);  // all samples valid
  // At grazing incidence (probability 0.48) a few sampled normals reflect below the
  // surface and are lost.
  EXPECT_GT(coating_probability(0.05), 5.0 * coating_probability(1.0));
  EXPECT_LE(glossy_fraction(0.05), coating_probability(0.05) + 0.01);
  EXPECT_GT(glossy_fraction(0.05), 0.9 * coating_probability(0.05));
}

// ---------------------------------------------------------------------------------------
// Rough transmittance of a coating

TEST(BsdfRoughTransmittance, SmoothLimitIsFresnelFromBothSides) {
  for (const MicrofacetType type :
       {MicrofacetType::Ggx, MicrofacetType::Beckmann, MicrofacetType::Phong}) {
    for (const double mu : {1.0, 0.8, 0.5, 0.3, 0.1}) {
      EXPECT_NEAR(RoughTransmittance::integrate(type, 1e-4f, 1.5f, mu, 32),
                  1.0 - reference_fresnel(mu, 1.0, 1.5), 2e-4)
          << int(type) << " " << mu;
      if (mu > 0.8) {  // inside, away from the critical angle (cos 0.745)
        EXPECT_NEAR(RoughTransmittance::integrate(type, 1e-4f, 1.0f / 1.5f, mu, 32),
                    1.0 - reference_fresnel(mu, 1.5, 1.0), 2e-4)
            << int(type) << " " << mu;
      }
    }
  }
  // The hemispherical averages: 1 - Fdr from outside and inside.
  EXPECT_NEAR(RoughTransmittance::integrate_diffuse(MicrofacetType::Ggx, 1e-4f, 1.5f, 48, 64),
              1.0 - fresnel_diffuse_reflectance(1.5f), 2e-4);
  EXPECT_NEAR(
      RoughTransmittance::integrate_diffuse(MicrofacetType::Ggx, 1e-4f, 1.0f / 1.5f, 48, 64),
      1.0 - fresnel_diffuse_reflectance(1.0f / 1.5f), 1e-3);
}

TEST(BsdfRoughTransmittance, MatchesMitsubasTables) {
  // Values of Mitsuba 0.6's data/microfacet/{ggx,beckmann}.dat (eta 1.5, interpolated as
  // its rtrans.h does); the rough coating transmits far more at grazing angles than the
  // smooth 1 - F (0.428 at mu 0.1, 0.109 at mu 0.02).
  const struct {
    MicrofacetType type;
    float alpha;
    double mu, mitsuba;
  } references[] = {{MicrofacetType::Ggx, 0.12f, 1.0, 0.95884},
                    {MicrofacetType::Ggx, 0.12f, 0.4, 0.86679},
                    {MicrofacetType::Ggx, 0.12f, 0.1, 0.63996},
                    {MicrofacetType::Ggx, 0.12f, 0.02, 0.60370},
                    {MicrofacetType::Ggx, 0.5f, 0.1, 0.62022},
                    {MicrofacetType::Beckmann, 0.2f, 0.4, 0.86456},
                    {MicrofacetType::Beckmann, 0.2f, 0.02, 0.58254}};
  for (const auto& r : references) {
    const RoughTransmittance table(r.type, 1.5f, r.alpha);
    EXPECT_NEAR(RoughTransmittance::integrate(r.type, r.alpha, 1.5f, r.mu, 32), r.mitsuba, 2e-4)
        << r.alpha << " " << r.mu;
    EXPECT_NEAR(table(static_cast<float>(r.mu), r.alpha), r.mitsuba, 3e-4)
        << r.alpha << " " << r.mu;
  }
}

TEST(BsdfRoughTransmittance, HemisphericalAveragesAreReciprocal) {
  // Light entering from a uniformly bright outside equals light leaving to it: the outer
  // average over eta^2 is the inner average (exact for the smooth boundary, and for the
  // microfacet one since its BTDF is reciprocal up to eta^2).
  for (const MicrofacetType type : {MicrofacetType::Ggx, MicrofacetType::Beckmann}) {
    for (const float alpha : {0.05f, 0.12f, 0.4f}) {
      const double outside = RoughTransmittance::integrate_diffuse(type, alpha, 1.5f, 32, 32);
      const double inside =
          RoughTransmittance::integrate_diffuse(type, alpha, 1.0f / 1.5f, 32, 32);
      EXPECT_NEAR(outside / (1.5 * 1.5), inside, 5e-4) << int(type) << " " << alpha;
    }
  }
}

TEST(BsdfRoughTransmittance, TableFollowsTheIntegral) {
  // Constant roughness (one row) and a roughness range (rows over alpha), between nodes.
  const RoughTransmittance fixed(MicrofacetType::Ggx, 1.5f, 0.12f);
  const RoughTransmittance ranged(MicrofacetType::Beckmann, 1.5f, 0.0f, 1.0f);
  for (const float mu : {0.003f, 0.037f, 0.21f, 0.55f, 0.97f}) {
    EXPECT_NEAR(fixed(mu, 0.12f),
                RoughTransmittance::integrate(MicrofacetType::Ggx, 0.12f, 1.5f, mu, 32), 3e-4)
        << mu;
    for (const float alpha : {0.02f, 0.17f, 0.33f}) {
      EXPECT_NEAR(ranged(mu, alpha),
                  RoughTransmittance::integrate(MicrofacetType::Beckmann, alpha, 1.5f, mu, 32),
                  3e-3)
          << mu << " " << alpha;
    }
  }
  EXPECT_NEAR(fixed.diffuse(0.12f),
              RoughTransmittance::integrate_diffuse(MicrofacetType::Ggx, 0.12f, 1.5f, 32, 32),
              1e-6);
}

}  // namespace
