#include "support/test_scenes.h"

#include "emlt/scene/materials.h"

namespace emlt::test {

void add_quad(SceneDescription& d, Vec3 a, Vec3 b, Vec3 c, Vec3 e, int material, Rgb emission) {
  MeshDesc m;
  m.name = "quad";
  m.positions = {a, b, c, e};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  m.emission = emission;
  d.meshes.push_back(m);
}

int add_material(SceneDescription& d, BsdfPtr bsdf) {
  std::string name = "m";  // built in two steps: GCC 12 warns falsely (-Wrestrict) on "m" + string
  name += std::to_string(d.materials.size());
  d.materials.push_back({name, std::move(bsdf)});
  return int(d.materials.size()) - 1;
}

CameraDesc camera_at(Vec3 eye, Vec3 target, int size, Vec3 up) {
  CameraDesc c;
  c.to_world = look_at_matrix(eye, target, up);
  c.fov_degrees = 60.0f;
  c.width = c.height = size;
  return c;
}

std::unique_ptr<Scene> emissive_box(const Rgb& albedo, float le, int image_size) {
  return Scene::build(emissive_box_description(albedo, le, image_size));
}

SceneDescription emissive_box_description(const Rgb& albedo, float le, int image_size) {
  SceneDescription d;
  d.source = "emissive-box";
  const int m = add_material(d, make_lambertian(albedo));
  const Rgb e(le);
  const Vec3 p[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  // Counter-clockwise seen from inside, so normals point inwards.
  add_quad(d, p[0], p[1], p[2], p[3], m, e);  // z = -1
  add_quad(d, p[5], p[4], p[7], p[6], m, e);  // z = +1
  add_quad(d, p[4], p[0], p[3], p[7], m, e);  // x = -1
  add_quad(d, p[1], p[5], p[6], p[2], m, e);  // x = +1
  add_quad(d, p[4], p[5], p[1], p[0], m, e);  // y = -1
  add_quad(d, p[3], p[2], p[6], p[7], m, e);  // y = +1
  d.camera = camera_at(Vec3(0.1f, 0.2f, -0.5f), Vec3(0.3f, -0.2f, 1.0f), image_size);
  return d;
}

Rgb emissive_box_radiance(const Rgb& albedo, float le, int max_segments) {
  Rgb sum(0.0f), term(le);
  for (int k = 0; k < max_segments; ++k) {
    sum += term;
    term *= albedo;
  }
  return sum;
}

SceneDescription floor_mirror_description() {
  SceneDescription d;
  d.source = "floor-mirror";
  const int white = add_material(d, make_lambertian(Rgb(0.7f)));
  const int mirror = add_material(d, make_mirror(Rgb(0.9f)));
  add_quad(d, {-4, 0, -4}, {-4, 0, 8}, {4, 0, 8}, {4, 0, -4}, white, Rgb(0.0f));  // faces +y
  add_quad(d, {-1.5f, 1, 0.5f}, {1.5f, 1, 0.5f}, {1.5f, 1, 2.5f}, {-1.5f, 1, 2.5f}, mirror,
           Rgb(0.0f));  // faces -y
  const float h = 0.3f, s = 0.3f, zc = 3.2f;
  add_quad(d, {-s, h, zc - s}, {s, h, zc - s}, {s, h, zc + s}, {-s, h, zc + s}, white, Rgb(5.0f));
  d.camera = camera_at(Vec3(0.0f, 0.5f, -2.5f), Vec3(0.0f, 0.0f, -0.2f), 32);
  return d;
}

}  // namespace emlt::test
