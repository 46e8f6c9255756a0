#pragma once
// Isotropic GGX (Trowbridge-Reitz) microfacet distribution in the local shading frame
// (internal to the engine). Masking-shadowing is Smith's height-correlated form.
#include "emlt/core/math.h"
#include "emlt/scene/materials.h"

namespace emlt {

class GgxDistribution {
 public:
  // Roughness below kMinAlpha is clamped: D would no longer be representable in float.
  static constexpr float kMinAlpha = 1e-4f;

  explicit GgxDistribution(float alpha) : alpha_(glm::max(alpha, kMinAlpha)) {}
  float alpha() const { return alpha_; }

  // Normal distribution D(m) per unit solid angle of m (projected area normalised:
  // integral of D(m) m.z dm = 1). Zero for m below the macro surface.
  float D(const Vec3& m) const;
  // Smith Lambda(w): G1(w) = 1 / (1 + Lambda(w)).
  float lambda(const Vec3& w) const;
  float G1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
  // Height-correlated masking-shadowing for a reflection pair on the same side; symmetric.
  float G2(const Vec3& wo, const Vec3& wi) const {
    return 1.0f / (1.0f + lambda(wo) + lambda(wi));
  }

  // Samples a normal from the distribution of normals visible from wo (wo.z > 0):
  // D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z  (Heitz 2018).
  Vec3 sample_visible_normal(const Vec3& wo, const Vec2& u) const;
  float visible_normal_pdf(const Vec3& wo, const Vec3& m) const;

  // Solid-angle density of wi = reflect(wo, m) when m ~ D_wo: D_wo(h) / (4 wo.h)
  // = G1(wo) D(h) / (4 wo.z), with h the half vector. Zero unless both are above.
  float reflection_pdf(const Vec3& wo, const Vec3& wi) const;

 private:
  float alpha_;
};

// Beckmann (Gaussian slope) distribution, Mitsuba's default for rough materials. Smith's
// Lambda in its exact erf form; sampling draws from the full distribution D(m) m.z (not
// the visible normals), which is simple and exact.
class BeckmannDistribution {
 public:
  static constexpr float kMinAlpha = 1e-4f;
  explicit BeckmannDistribution(float alpha) : alpha_(glm::max(alpha, kMinAlpha)) {}
  float alpha() const { return alpha_; }
  float D(const Vec3& m) const;
  float lambda(const Vec3& w) const;
  // A normal with density D(m) m.z (solid angle of m), always above the macro surface.
  Vec3 sample_normal(const Vec2& u) const;

 private:
  float alpha_;
};

// One of the two distributions, chosen at run time, with the sampling each does best:
// GGX samples the normals visible from wo, Beckmann the full distribution. Directions may
// lie on either side; the distribution is symmetric under z -> -z, so queries for a wo
// below the surface use its mirror image above.
class MicrofacetDistribution {
 public:
  MicrofacetDistribution(MicrofacetType type, float alpha)
      : type_(type), ggx_(alpha), beckmann_(alpha) {}
  MicrofacetType type() const { return type_; }

  float D(const Vec3& m) const { return type_ == MicrofacetType::Ggx ? ggx_.D(m) : beckmann_.D(m); }
  float lambda(const Vec3& w) const {
    return type_ == MicrofacetType::Ggx ? ggx_.lambda(w) : beckmann_.lambda(w);
  }
  float G1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
  float G2(const Vec3& wo, const Vec3& wi) const {
    return 1.0f / (1.0f + lambda(wo) + lambda(wi));
  }

  // A microfacet normal (m.z > 0) for the direction wo, and its density.
  Vec3 sample_normal(const Vec3& wo, const Vec2& u) const;
  float normal_pdf(const Vec3& wo, const Vec3& m) const;
  // Density of wi = reflect(wo, m), m ~ sample_normal; zero unless wo, wi are on the
  // same side.
  float reflection_pdf(const Vec3& wo, const Vec3& wi) const;

 private:
  MicrofacetType type_;
  GgxDistribution ggx_;
  BeckmannDistribution beckmann_;
};

// Half vector of a reflection pair; (0,0,1) for the degenerate wo == -wi.
inline Vec3 reflection_half_vector(const Vec3& wo, const Vec3& wi) {
  const Vec3 h = wo + wi;
  const float length2 = glm::dot(h, h);
  return length2 > 0.0f ? h / std::sqrt(length2) : Vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace emlt
