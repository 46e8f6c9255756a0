#pragma once
// Fresnel reflectance shared by the built-in BSDFs (internal to the engine).
#include "emlt/core/math.h"

namespace emlt {

// Unpolarised reflectance of a smooth dielectric interface. `eta` is n_inside / n_outside
// (inside = against the normal); `cos_theta_i` is signed, negative when the incident
// direction is inside. On return *cos_theta_t (if given) is the signed cosine of the
// refracted direction, which lies on the opposite side; it is 0 under total internal
// reflection, where the reflectance is 1.
float fresnel_dielectric(float cos_theta_i, float eta, float* cos_theta_t = nullptr);

// Unpolarised reflectance of a conductor with complex IOR eta + i k relative to the
// outside medium, for 0 <= cos_theta_i <= 1. eta = 0, k = 1 gives exactly 1.
float fresnel_conductor(float cos_theta_i, float eta, float k);
Rgb fresnel_conductor(float cos_theta_i, const Rgb& eta, const Rgb& k);

// Cosine-weighted hemispherical average 2 * integral_0^1 F(mu) mu dmu of the dielectric
// reflectance seen from the outside of an interface with relative IOR `eta` (pass 1/eta
// for the inside, where total internal reflection contributes). Computed numerically;
// meant for construction time, not per sample.
float fresnel_diffuse_reflectance(float eta);

}  // namespace emlt
