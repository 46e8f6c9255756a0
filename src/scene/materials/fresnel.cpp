#include "src/scene/materials/fresnel.h"

#include <algorithm>

namespace emlt {

float fresnel_dielectric(float cos_theta_i, float eta, float* cos_theta_t) {
  const bool outside = cos_theta_i >= 0.0f;
  // Relative IOR of the transmitted side over the incident side.
  const float eta_rel = outside ? eta : 1.0f / eta;
  const float cos_i = std::min(std::abs(cos_theta_i), 1.0f);
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta_rel * eta_rel);
  if (sin2_t >= 1.0f) {
    if (cos_theta_t) *cos_theta_t = 0.0f;
    return 1.0f;
  }
  const float cos_t = std::sqrt(1.0f - sin2_t);
  const float r_s = (cos_i - eta_rel * cos_t) / (cos_i + eta_rel * cos_t);
  const float r_p = (eta_rel * cos_i - cos_t) / (eta_rel * cos_i + cos_t);
  if (cos_theta_t) *cos_theta_t = outside ? -cos_t : cos_t;
  return glm::clamp(0.5f * (r_s * r_s + r_p * r_p), 0.0f, 1.0f);
}

float fresnel_conductor(float cos_theta_i, float eta, float k) {
  // Closed form of |r_s|^2 and |r_p|^2 for a complex IOR, written with
  // a^2 + b^2 = |n^2 - sin^2| and a = Re(sqrt(n^2 - sin^2)), which avoids complex numbers.
  const float cos_i = glm::clamp(cos_theta_i, 0.0f, 1.0f);
  const float cos2 = cos_i * cos_i;
  const float sin2 = 1.0f - cos2;
  const float re = eta * eta - k * k - sin2;
  const float a2_plus_b2 = std::sqrt(re * re + 4.0f * eta * eta * k * k);
  const float a = safe_sqrt(0.5f * (a2_plus_b2 + re));
  const float s_num = a2_plus_b2 + cos2 - 2.0f * a * cos_i;
  const float s_den = a2_plus_b2 + cos2 + 2.0f * a * cos_i;
  const float r_s = s_den > 0.0f ? s_num / s_den : 1.0f;
  const float p_num = a2_plus_b2 * cos2 + sin2 * sin2 - 2.0f * a * cos_i * sin2;
  const float p_den = a2_plus_b2 * cos2 + sin2 * sin2 + 2.0f * a * cos_i * sin2;
  const float r_p = r_s * (p_den > 0.0f ? p_num / p_den : 1.0f);
  return glm::clamp(0.5f * (r_s + r_p), 0.0f, 1.0f);
}

Rgb fresnel_conductor(float cos_theta_i, const Rgb& eta, const Rgb& k) {
  return {fresnel_conductor(cos_theta_i, eta.x, k.x), fresnel_conductor(cos_theta_i, eta.y, k.y),
          fresnel_conductor(cos_theta_i, eta.z, k.z)};
}

float fresnel_diffuse_reflectance(float eta) {
  // Composite Simpson in mu; the kink at the critical angle (eta < 1) only costs a little
  // accuracy at this resolution (~1e-6).
  constexpr int kSteps = 4096;
  const double h = 1.0 / kSteps;
  double sum = 0.0;
  for (int i = 0; i <= kSteps; ++i) {
    const double mu = i * h;
    const double weight = (i == 0 || i == kSteps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += weight * mu * fresnel_dielectric(static_cast<float>(mu), eta);
  }
  return static_cast<float>(2.0 * sum * h / 3.0);
}

}  // namespace emlt
