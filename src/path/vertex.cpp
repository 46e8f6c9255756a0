#include "emlt/path/vertex.h"

#include "emlt/scene/scene.h"

namespace emlt {

PathVertex make_surface_vertex(const SurfaceHit& hit) {
  PathVertex v;
  v.kind = VertexKind::Surface;
  v.position = hit.position;
  v.normal = hit.geometric_normal;
  v.shading = hit.shading;
  v.uv = hit.uv;
  v.vertex_color = hit.vertex_color;
  v.bsdf = hit.bsdf;
  v.light = hit.light;
  return v;
}

PathVertex make_environment_vertex(const Scene& scene, const Vec3& direction) {
  PathVertex v;
  v.kind = VertexKind::Environment;
  v.sky_direction = direction;
  v.light = scene.environment();
  return v;
}

PathVertex make_camera_vertex(const Scene& scene, const Vec3& lens_point, const Vec2& raster) {
  PathVertex v;
  v.kind = scene.camera().is_orthographic() ? VertexKind::OrthographicCamera : VertexKind::Camera;
  v.position = lens_point;
  v.normal = scene.camera().forward();
  v.shading = scene.camera().forward_frame();
  v.raster = raster;
  return v;
}

}  // namespace emlt
