#pragma once
// Orthonormal frame whose z axis is a given unit normal. BSDFs work in this local frame:
// cos(theta) of a direction is simply its z component.
#include "emlt/core/math.h"

namespace emlt {

struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  Frame() = default;
  // Builds a continuous tangent basis without branches on the normal's sign
  // (Duff et al. 2017, "Building an orthonormal basis, revisited").
  explicit Frame(const Vec3& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t = Vec3(b, sign + n.y * n.y * a, -n.y);
  }

  // Mitsuba's shading frame: s is the tangent made orthogonal to the normal (Gram-Schmidt),
  // t = n x s. Anisotropic BSDFs depend on s, so a surface's frame follows its dp/du; a
  // tangent (nearly) parallel to the normal, or not finite, gives the frame of the normal
  // alone.
  Frame(const Vec3& normal, const Vec3& tangent) : Frame(normal) {
    const Vec3 s_raw = tangent - n * glm::dot(n, tangent);
    const float length2 = glm::dot(s_raw, s_raw);
    if (!(length2 > 1e-12f * glm::dot(tangent, tangent)) || !std::isfinite(length2)) return;
    s = s_raw / std::sqrt(length2);
    t = glm::cross(n, s);
  }

  Vec3 to_local(const Vec3& w) const { return {glm::dot(w, s), glm::dot(w, t), glm::dot(w, n)}; }
  Vec3 to_world(const Vec3& w) const { return w.x * s + w.y * t + w.z * n; }
};

// Helpers for directions expressed in a local frame.
inline float cos_theta(const Vec3& w) { return w.z; }
inline float abs_cos_theta(const Vec3& w) { return std::abs(w.z); }
inline bool same_hemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0.0f; }

}  // namespace emlt
