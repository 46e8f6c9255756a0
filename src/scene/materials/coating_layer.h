#pragma once
// What Mitsuba 0.6's `coating` and `roughcoating` share (internal to the engine): a
// dielectric layer of relative IOR eta = n_layer / n_outside and some thickness, with an
// absorption coefficient sigma_a, over a nested BSDF. Mitsuba does not simulate the layer
// (no light bounces between the interface and the base): the nested BSDF is evaluated at
// the directions refracted into the layer, weighted by the interface's transmittance on
// the way in and out, by Beer's law along the two straight paths through the layer, and
// by 1 / eta^2. That last factor is the solid-angle compression of the two refractions
// together (d omega_inside / d omega_outside = cos_out / (eta^2 cos_in) for each); being
// the same for both directions it keeps the model reciprocal, so Mitsuba applies it in
// both transport modes and so do we. The layer is the same seen from either side: a
// direction below the surface is refracted into a layer below it.
#include <cmath>
#include <utility>

#include "emlt/scene/bsdf.h"
#include "src/scene/materials/texture_param.h"

namespace emlt {

class CoatingLayer {
 public:
  CoatingLayer(float eta, float thickness, TexturePtr sigma_a)
      : eta_(eta), thickness_(thickness), sigma_a_(std::move(sigma_a)) {
    // Mitsuba steers samples towards the interface's reflection when the layer absorbs
    // much: its weight against the nested BSDF is 1 / (1 + mean attenuation through twice
    // the thickness), from sigma_a's average over the texture (here over a grid of it).
    Rgb average(0.0f);
    if (sigma_a_.is_constant()) {
      average = sigma_a_.constant_value();
    } else {
      constexpr int kSide = 64;
      for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i)
          average += sigma_a_.at(Vec2((i + 0.5f) / kSide, (j + 0.5f) / kSide));
      average /= float(kSide * kSide);
    }
    const Rgb attenuation = glm::exp(-2.0f * thickness_ * average);
    specular_weight_ = 1.0f / ((attenuation.x + attenuation.y + attenuation.z) / 3.0f + 1.0f);
  }

  float eta() const { return eta_; }

  // The direction inside the layer that w (outside, either side) refracts into, on w's
  // side; z == 0 when there is none (total internal reflection, possible for eta < 1).
  Vec3 refract_in(const Vec3& w) const { return bend(w, 1.0f / eta_); }
  // The direction outside that w (inside the layer) leaves by; z == 0 under total
  // internal reflection.
  Vec3 refract_out(const Vec3& w) const { return bend(w, eta_); }

  // Beer's law along both paths through the layer, at depth `thickness` below the
  // interface: exp(-sigma_a d (1 / |cos wo'| + 1 / |cos wi'|)) for the refracted pair.
  Rgb attenuation(const BsdfContext& ctx, const Vec3& wo_in, const Vec3& wi_in) const {
    if (sigma_a_.is_constant() && is_black(sigma_a_.constant_value())) return Rgb(1.0f);
    const Rgb optical_depth = sigma_a_.at(ctx) * thickness_;
    return glm::exp(-optical_depth * (1.0f / std::abs(wo_in.z) + 1.0f / std::abs(wi_in.z)));
  }

  // The density of wi outside per density of wi_in inside: |cos wi| / (eta^2 |cos wi_in|).
  float jacobian(const Vec3& wi, const Vec3& wi_in) const {
    return std::abs(wi.z) / (eta_ * eta_ * std::abs(wi_in.z));
  }

  // Mitsuba's probability of sampling the interface's reflection rather than the nested
  // BSDF, given the fraction `reflected` of light from wo that the interface reflects:
  // that fraction reweighted by the sampling weight above.
  float specular_probability(float reflected) const {
    const float specular = reflected * specular_weight_;
    const float total = specular + (1.0f - reflected) * (1.0f - specular_weight_);
    return total > 0.0f ? specular / total : 0.0f;
  }

 private:
  // Snell's law with ratio `scale` = n_from / n_to, keeping w's side.
  static Vec3 bend(const Vec3& w, float scale) {
    const float sin2 = scale * scale * (w.x * w.x + w.y * w.y);
    if (sin2 >= 1.0f) return Vec3(0.0f);
    const float cos_t = std::sqrt(1.0f - sin2);
    return Vec3(scale * w.x, scale * w.y, w.z < 0.0f ? -cos_t : cos_t);
  }

  float eta_;
  float thickness_;
  TextureParam sigma_a_;
  float specular_weight_ = 0.5f;
};

}  // namespace emlt
