#pragma once
// Basic vector types and constants. Geometry is single precision (Embree's), colour is
// linear RGB. Anything that accumulates over many samples uses double.
#include <glm/glm.hpp>

#include <cmath>
#include <limits>

namespace emlt {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;
using DVec3 = glm::dvec3;
using DMat3 = glm::dmat3;
using Rgb = glm::vec3;  // linear RGB (radiance, reflectance or throughput)

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kTwoPi = 2.0f * kPi;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInvTwoPi = 1.0f / kTwoPi;
inline constexpr float kInvFourPi = 1.0f / (4.0f * kPi);
inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// Rec. 709 luminance: the scalar target function of every Metropolis chain.
inline float luminance(const Rgb& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

inline bool is_finite(const Rgb& c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}
inline bool is_black(const Rgb& c) { return c.x == 0.0f && c.y == 0.0f && c.z == 0.0f; }
inline float max_component(const Rgb& c) { return glm::max(c.x, glm::max(c.y, c.z)); }

inline float safe_sqrt(float x) { return std::sqrt(glm::max(x, 0.0f)); }
inline float safe_acos(float x) { return std::acos(glm::clamp(x, -1.0f, 1.0f)); }
inline float square(float x) { return x * x; }

// Reflection of w about n (both pointing away from the surface).
inline Vec3 reflect_about(const Vec3& w, const Vec3& n) { return 2.0f * glm::dot(w, n) * n - w; }

}  // namespace emlt
