#pragma once
// Microfacet normal distributions in the local shading frame (internal to the engine), as
// Mitsuba 0.6 defines them (src/bsdfs/microfacet.h there): Beckmann, GGX and Phong, each
// anisotropic with roughness alpha_u along the frame's s axis (the surface's dp/du) and
// alpha_v along t. Masking-shadowing is Mitsuba's: the separable Smith product
// G1(wo, m) G1(wi, m), with the exact G1 for GGX and Walter et al.'s rational fit of the
// Beckmann G1 for Beckmann and Phong.
#include "emlt/core/math.h"
#include "emlt/scene/materials.h"

namespace emlt {

class MicrofacetDistribution {
 public:
  // Roughness below kMinAlpha is clamped (Mitsuba clamps to the same value): D would no
  // longer be representable in float.
  static constexpr float kMinAlpha = 1e-4f;

  MicrofacetDistribution(MicrofacetType type, float alpha)
      : MicrofacetDistribution(type, alpha, alpha) {}
  MicrofacetDistribution(MicrofacetType type, float alpha_u, float alpha_v);

  MicrofacetType type() const { return type_; }
  float alpha_u() const { return alpha_u_; }
  float alpha_v() const { return alpha_v_; }
  bool isotropic() const { return alpha_u_ == alpha_v_; }

  // Normal distribution D(m) per unit solid angle of m (projected area normalised:
  // integral of D(m) m.z dm = 1). Zero for m below the macro surface.
  float D(const Vec3& m) const;
  // Smith's Lambda(w) in its exact form for this D (Phong: the Beckmann one for the same
  // alpha, which is what Mitsuba's G1 approximates for Phong too). 1 / (1 + Lambda) is the
  // normalisation of the visible normals; the BSDFs use G1 below.
  float lambda(const Vec3& w) const;
  // Mitsuba's Smith G1(w, m): zero when w sees the back of m (or m from below); GGX exact,
  // Beckmann and Phong by the rational fit (within ~0.35% of 1 / (1 + Lambda)).
  float G1(const Vec3& w, const Vec3& m) const;
  // Masking-shadowing of a pair, separable as in Mitsuba 0.6: G1(wo, m) G1(wi, m).
  float G(const Vec3& wo, const Vec3& wi, const Vec3& m) const { return G1(wo, m) * G1(wi, m); }

  // A microfacet normal (m.z > 0) for the direction wo, and its density: GGX samples the
  // normals visible from wo, D_wo(m) = G1(wo) max(0, wo.m) D(m) / |wo.z| (Heitz 2018);
  // Beckmann and Phong the full distribution D(m) m.z. wo may lie on either side; the
  // distribution is symmetric under z -> -z, so wo below the surface uses its mirror image.
  Vec3 sample_normal(const Vec3& wo, const Vec2& u) const;
  float normal_pdf(const Vec3& wo, const Vec3& m) const;
  // Density of wi = reflect(wo, m), m ~ sample_normal; zero unless wo, wi are on the
  // same side.
  float reflection_pdf(const Vec3& wo, const Vec3& wi) const;

 private:
  // alpha_u^2 w.x^2 + alpha_v^2 w.y^2: (alpha projected onto w's azimuth)^2 sin^2 theta.
  float projected_alpha2_sin2(const Vec3& w) const {
    return alpha_u_ * alpha_u_ * w.x * w.x + alpha_v_ * alpha_v_ * w.y * w.y;
  }
  Vec3 sample_ggx_visible(const Vec3& wo, const Vec2& u) const;
  Vec3 sample_beckmann(const Vec2& u) const;
  Vec3 sample_phong(const Vec2& u) const;

  MicrofacetType type_;
  float alpha_u_, alpha_v_;
  // Phong exponents along s and t, from alpha as Mitsuba converts it: 2 / alpha^2 - 2.
  float exponent_u_ = 0.0f, exponent_v_ = 0.0f;
};

// Half vector of a reflection pair; (0,0,1) for the degenerate wo == -wi.
inline Vec3 reflection_half_vector(const Vec3& wo, const Vec3& wi) {
  const Vec3 h = wo + wi;
  const float length2 = glm::dot(h, h);
  return length2 > 0.0f ? h / std::sqrt(length2) : Vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace emlt
