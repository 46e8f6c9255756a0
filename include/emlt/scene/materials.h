#pragma once
// Factories for the built-in BSDFs. Parameters follow Mitsuba 0.6 naming where one exists.
#include "emlt/scene/bsdf.h"

namespace emlt {

// One-sided BSDFs are black when wo or wi is below the surface; two_sided() mirrors the
// frame so the back behaves like the front (Mitsuba's `twosided`).
BsdfPtr make_lambertian(const Rgb& reflectance);
BsdfPtr make_mirror(const Rgb& reflectance = Rgb(1.0f));  // ideal specular reflection
// Smooth dielectric interface; int_ior inside (against the normal), ext_ior outside.
BsdfPtr make_dielectric(float int_ior = 1.5046f, float ext_ior = 1.000277f,
                        const Rgb& specular_reflectance = Rgb(1.0f),
                        const Rgb& specular_transmittance = Rgb(1.0f));
// GGX microfacet conductor with visible-normal sampling; eta/k are per-channel complex IOR.
BsdfPtr make_rough_conductor(float alpha, const Rgb& eta, const Rgb& k,
                             const Rgb& specular_reflectance = Rgb(1.0f));
// Diffuse base under a GGX dielectric coating (alpha == 0: smooth, delta coating lobe).
BsdfPtr make_rough_plastic(float alpha, const Rgb& diffuse_reflectance,
                           const Rgb& specular_reflectance = Rgb(1.0f), float int_ior = 1.49f,
                           float ext_ior = 1.000277f);
BsdfPtr make_two_sided(BsdfPtr inner);

}  // namespace emlt
