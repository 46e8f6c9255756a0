#pragma once
// A texture's mean over one period of (u, v), for choices that are made once per surface
// (internal to the engine): Mitsuba steers the lobe choice of its two-lobe BRDFs (phong,
// ward) by its textures' averages. Such a choice changes only the noise, so for a varying
// texture the mean of a regular grid of lookups serves, where Mitsuba averages the texels.
#include "emlt/scene/texture.h"

namespace emlt {

inline Rgb texture_average(const TexturePtr& texture) {
  if (!texture) return Rgb(0.0f);
  if (auto c = texture->constant()) return glm::max(*c, Rgb(0.0f));
  constexpr int kSide = 64;
  Rgb sum(0.0f);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i)
      sum += glm::max(texture->eval(Vec2((i + 0.5f) / kSide, (j + 0.5f) / kSide)), Rgb(0.0f));
  return sum / float(kSide * kSide);
}

// How often a two-lobe BRDF (phong, ward) samples its specular lobe: the lobe's share of the
// luminance of the two reflectances' averages, as Mitsuba chooses; half when both are black.
inline float specular_lobe_probability(const TexturePtr& specular, const TexturePtr& diffuse) {
  const float specular_weight = luminance(texture_average(specular));
  const float diffuse_weight = luminance(texture_average(diffuse));
  const float total = specular_weight + diffuse_weight;
  return total > 0.0f ? specular_weight / total : 0.5f;
}

}  // namespace emlt
