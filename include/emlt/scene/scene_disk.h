#pragma once
// Where light from infinity (the sky, a directional light) starts when traced: a disk of the
// scene's bounding radius facing the light, just outside the scene's bounding sphere, so
// every ray along the light's direction that can meet the scene crosses it once.
#include "emlt/core/frame.h"
#include "emlt/core/warp.h"

namespace emlt {

struct SceneDisk {
  Vec3 center{0.0f};
  float radius = 1.0f;

  // A point uniform on the disk facing `towards_light` (unit, from the scene to the light).
  Vec3 point(const Vec3& towards_light, const Vec2& u) const {
    const Frame frame(-towards_light);
    const Vec2 disk = square_to_uniform_disk_concentric(u);
    return center + radius * (towards_light + disk.x * frame.s + disk.y * frame.t);
  }
  // Its area density.
  float pdf() const { return 1.0f / (kPi * radius * radius); }
  // The disk's area: what a parallel beam through the scene crosses.
  float area() const { return kPi * radius * radius; }
};

}  // namespace emlt
