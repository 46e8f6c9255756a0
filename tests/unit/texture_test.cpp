// Textures (bitmap filtering, wrapping, uv transform, sRGB/raw decoding, checkerboard,
// scale) and the surface modifiers they drive in the scene: mask opacity in Embree's
// filter, bump mapping of the shading normal, and uvs for meshes that have none.
#include "emlt/scene/texture.h"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

// 2 x 2 image: red, green (top row); blue, white (bottom row).
Image quad_image() {
  Image image(2, 2);
  image.at(0, 0) = Rgb(1, 0, 0);
  image.at(1, 0) = Rgb(0, 1, 0);
  image.at(0, 1) = Rgb(0, 0, 1);
  image.at(1, 1) = Rgb(1, 1, 1);
  return image;
}

void expect_rgb_near(const Rgb& actual, const Rgb& expected, float tolerance, const std::string& what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], tolerance) << what << " channel " << c;
}

// A repeated texture is the same in every tile, left of, right of and far from the first:
// uv multiples of 1/64 on a 16 x 8 image keep every coordinate exact, so tiles k apart give
// the same bits. Both texel pairs of a lookup straddle a tile's edge somewhere in the grid.
TEST(BitmapTexture, RepeatedTilesAreIdenticalBitForBit) {
  Image image(16, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x)
      image.at(x, y) = Rgb(float(x) / 16.0f, float(y) / 8.0f, float((5 * x + 3 * y) % 7) / 7.0f);
  const TexturePtr t = make_bitmap_texture(image, {}, WrapMode::Repeat);
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; j += 3) {
      const Vec2 uv(float(i) / 64.0f, float(j) / 64.0f);
      const Rgb first = t->eval(uv);
      for (const Vec2 tile : {Vec2(1, 0), Vec2(-1, -1), Vec2(-3, 2), Vec2(37, -250), Vec2(-4096, 4096)})
        ASSERT_EQ(t->eval(uv + tile), first) << "uv " << uv.x << " " << uv.y << " tile " << tile.x << " " << tile.y;
    }
}

TEST(BitmapTexture, TexelCentresAreExactAndBilinearInBetween) {
  const TexturePtr t = make_bitmap_texture(quad_image());
  expect_rgb_near(t->eval(Vec2(0.25f, 0.25f)), Rgb(1, 0, 0), 1e-6f, "top left centre");
  expect_rgb_near(t->eval(Vec2(0.75f, 0.25f)), Rgb(0, 1, 0), 1e-6f, "top right centre");
  expect_rgb_near(t->eval(Vec2(0.25f, 0.75f)), Rgb(0, 0, 1), 1e-6f, "bottom left centre");
  // Midway between all four centres: their mean.
  expect_rgb_near(t->eval(Vec2(0.5f, 0.5f)), Rgb(0.5f, 0.5f, 0.5f), 1e-6f, "middle");
  // A quarter of the way from red to green along u.
  expect_rgb_near(t->eval(Vec2(0.375f, 0.25f)), Rgb(0.75f, 0.25f, 0.0f), 1e-6f, "between");
  EXPECT_FALSE(t->constant());
}

TEST(BitmapTexture, WrapModes) {
  const TexturePtr repeat = make_bitmap_texture(quad_image());
  // Repeat: u = 0 lies between the last and the first column.
  expect_rgb_near(repeat->eval(Vec2(0.0f, 0.25f)), Rgb(0.5f, 0.5f, 0.0f), 1e-6f, "repeat seam");
  expect_rgb_near(repeat->eval(Vec2(3.25f, -1.75f)), Rgb(1, 0, 0), 1e-5f, "repeat period");
  const TexturePtr clamp = make_bitmap_texture(quad_image(), {}, WrapMode::Clamp);
  expect_rgb_near(clamp->eval(Vec2(0.0f, 0.25f)), Rgb(1, 0, 0), 1e-6f, "clamp edge");
  expect_rgb_near(clamp->eval(Vec2(7.0f, 0.25f)), Rgb(0, 1, 0), 1e-6f, "clamp far");
  const TexturePtr mirror = make_bitmap_texture(quad_image(), {}, WrapMode::Mirror);
  expect_rgb_near(mirror->eval(Vec2(1.25f, 0.25f)), Rgb(0, 1, 0), 1e-5f, "mirror");
  // Zero and one: texels outside the image are 0 or 1, blended with the edge's.
  const TexturePtr zero = make_bitmap_texture(quad_image(), {}, WrapMode::Zero);
  expect_rgb_near(zero->eval(Vec2(0.0f, 0.25f)), Rgb(0.5f, 0, 0), 1e-6f, "zero seam");
  expect_rgb_near(zero->eval(Vec2(3.0f, 0.25f)), Rgb(0.0f), 1e-6f, "zero far");
  const TexturePtr one = make_bitmap_texture(quad_image(), {}, WrapMode::One);
  expect_rgb_near(one->eval(Vec2(0.0f, 0.25f)), Rgb(1, 0.5f, 0.5f), 1e-6f, "one seam");
  // One mode per axis (Mitsuba's wrapModeU, wrapModeV); u decides a corner outside both.
  const TexturePtr clamp_zero =
      make_bitmap_texture(quad_image(), {}, TextureWrap(WrapMode::Clamp, WrapMode::Zero));
  expect_rgb_near(clamp_zero->eval(Vec2(7.0f, 0.25f)), Rgb(0, 1, 0), 1e-6f, "u clamped");
  expect_rgb_near(clamp_zero->eval(Vec2(0.25f, 7.0f)), Rgb(0.0f), 1e-6f, "v zero");
  const TexturePtr one_zero =
      make_bitmap_texture(quad_image(), {}, TextureWrap(WrapMode::One, WrapMode::Zero));
  expect_rgb_near(one_zero->eval(Vec2(-3.0f, -3.0f)), Rgb(1.0f), 1e-6f, "u first");
}

TEST(BitmapTexture, UvTransformScalesThenOffsets) {
  UvTransform transform;
  transform.scale = Vec2(2.0f, 1.0f);
  transform.offset = Vec2(0.5f, 0.0f);
  const TexturePtr t = make_bitmap_texture(quad_image(), transform);
  // u' = 2 * 0.125 + 0.5 = 0.75: the green centre.
  expect_rgb_near(t->eval(Vec2(0.125f, 0.25f)), Rgb(0, 1, 0), 1e-6f, "transformed");
  EXPECT_NEAR(t->gradient_step().x, 0.25f, 1e-6f);  // one texel in the untransformed uv
}

TEST(BitmapTexture, PngIsDecodedFromSrgbUnlessRaw) {
  const auto dir = test::scratch_dir("texture-png");
  Image image(2, 1);
  // Linear values whose sRGB encodings are exactly 8-bit levels 128 and 64.
  const auto decode = [](float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
  };
  image.at(0, 0) = Rgb(decode(128.0f / 255.0f));
  image.at(1, 0) = Rgb(decode(64.0f / 255.0f));
  const std::string path = (dir / "levels.png").string();
  write_image(path, image);
  const TexturePtr srgb = load_bitmap_texture(path, std::nullopt, {}, WrapMode::Clamp);
  const TexturePtr raw = load_bitmap_texture(path, 1.0f, {}, WrapMode::Clamp);
  EXPECT_NEAR(srgb->eval(Vec2(0.25f, 0.5f)).x, decode(128.0f / 255.0f), 1e-5f);
  EXPECT_NEAR(raw->eval(Vec2(0.25f, 0.5f)).x, 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(raw->eval(Vec2(0.75f, 0.5f)).y, 64.0f / 255.0f, 1e-6f);
  EXPECT_THROW(load_bitmap_texture((dir / "absent.png").string()), Error);
}

// 8-bit files are kept as their bytes (a quarter of float RGB's memory); every texel must
// still read back exactly the float read_image decodes, sRGB or raw, at all 256 levels.
TEST(BitmapTexture, EightBitTexelsReadBackExactlyAsDecoded) {
  const auto dir = test::scratch_dir("texture-levels");
  const auto decode = [](float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
  };
  Image levels(256, 1);
  for (int i = 0; i < 256; ++i)
    levels.at(i, 0) = Rgb(decode(float(i) / 255.0f), decode(float(255 - i) / 255.0f),
                          decode(float((7 * i) % 256) / 255.0f));
  const std::string path = (dir / "levels.png").string();
  write_image(path, levels);
  const Image decoded = read_image(path);
  const TexturePtr srgb = load_bitmap_texture(path, std::nullopt, {}, WrapMode::Clamp);
  const TexturePtr raw = load_bitmap_texture(path, 1.0f, {}, WrapMode::Clamp);
  const std::vector<unsigned char> bytes = to_srgb8(decoded);
  for (int i = 0; i < 256; ++i) {
    const Vec2 centre((float(i) + 0.5f) / 256.0f, 0.5f);  // bilinear weight 1 on texel i
    EXPECT_EQ(srgb->eval(centre), decoded.at(i, 0)) << "level " << i;
    const Rgb stored(float(bytes[3 * size_t(i)]) / 255.0f, float(bytes[3 * size_t(i) + 1]) / 255.0f,
                     float(bytes[3 * size_t(i) + 2]) / 255.0f);
    EXPECT_EQ(raw->eval(centre), stored) << "level " << i;
  }
}

// The same between texels, in every wrap mode, under a uv transform and outside [0, 1):
// the byte-stored texture against a float texture of the decoded image (WrapModes checks
// the wrapping itself against expected texels).
TEST(BitmapTexture, EightBitStorageReadsTheDecodedFloatsExactly) {
  const auto dir = test::scratch_dir("texture-bytes");
  Image levels(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const float level = float(16 * y + x) / 255.0f;
      levels.at(x, y) =
          Rgb(level, float(255 - (16 * y + x)) / 255.0f, float((7 * x + y) % 16) / 15.0f);
    }
  const std::string path = (dir / "levels.png").string();
  write_image(path, levels);
  const Image decoded = read_image(path);
  Image raw_values = decoded;
  const std::vector<unsigned char> bytes = to_srgb8(decoded);
  for (size_t i = 0; i < raw_values.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) raw_values.pixels[i][c] = float(bytes[3 * i + size_t(c)]) / 255.0f;
  for (const WrapMode wrap : {WrapMode::Repeat, WrapMode::Mirror, WrapMode::Clamp}) {
    const UvTransform transform{Vec2(1.7f, 2.3f), Vec2(-0.4f, 0.15f)};
    const TexturePtr stored = load_bitmap_texture(path, std::nullopt, transform, wrap);
    const TexturePtr floats = make_bitmap_texture(decoded, transform, wrap);
    const TexturePtr stored_raw = load_bitmap_texture(path, 1.0f, transform, wrap);
    const TexturePtr floats_raw = make_bitmap_texture(raw_values, transform, wrap);
    for (int i = 0; i < 2000; ++i) {
      const Vec2 uv(float(i % 50) / 17.0f - 1.0f, float(i / 50) / 13.0f - 1.0f);
      ASSERT_EQ(stored->eval(uv), floats->eval(uv)) << "uv " << uv.x << " " << uv.y;
      ASSERT_EQ(stored_raw->eval(uv), floats_raw->eval(uv)) << "raw, uv " << uv.x << " " << uv.y;
    }
  }
}

// Bitmap lookups are remembered per thread (bitmap_texture.cpp: LookupCache). A value must
// come back only for its own texture and its own uv: two textures asked alternately at the
// same points, and a texture made where a freed one lay (same size, so the allocator hands
// out the same address) asked at the freed one's points, each give their own bilinear value.
TEST(BitmapTexture, RememberedLookupsAnswerOnlyTheirOwnTextureAndPoint) {
  Image other = quad_image();
  for (Rgb& texel : other.pixels) texel = Rgb(1.0f) - texel;
  // Reference values from textures that have never been asked anything.
  const auto fresh = [](const Image& image, const Vec2& uv) {
    return make_bitmap_texture(image)->eval(uv);
  };
  std::vector<Vec2> points;
  for (int i = 0; i < 300; ++i) points.emplace_back(float(i % 17) / 7.0f, float(i % 23) / 9.0f);

  const TexturePtr a = make_bitmap_texture(quad_image()), b = make_bitmap_texture(other);
  for (int round = 0; round < 3; ++round)
    for (const Vec2& uv : points) {
      ASSERT_EQ(a->eval(uv), fresh(quad_image(), uv)) << "a at " << uv.x << " " << uv.y;
      ASSERT_EQ(b->eval(uv), fresh(other, uv)) << "b at " << uv.x << " " << uv.y;
    }

  int reused = 0;
  for (int trial = 0; trial < 20; ++trial) {
    TexturePtr first = make_bitmap_texture(quad_image());
    const void* address = first.get();
    for (const Vec2& uv : points) (void)first->eval(uv);
    first.reset();
    const TexturePtr second = make_bitmap_texture(other);
    reused += second.get() == address;
    for (const Vec2& uv : points)
      ASSERT_EQ(second->eval(uv), fresh(other, uv))
          << "trial " << trial << " at " << uv.x << " " << uv.y;
  }
  // The case that matters, a new texture at a freed one's address, did happen (except
  // under AddressSanitizer, which keeps freed memory out of reach).
#if defined(__SANITIZE_ADDRESS__)
  (void)reused;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  (void)reused;
#else
  EXPECT_GT(reused, 0);
#endif
#else
  EXPECT_GT(reused, 0);
#endif
}

TEST(Checkerboard, MitsubaCellLayoutAndUvScale) {
  const Rgb c0(0.4f), c1(0.2f);
  const TexturePtr t = make_checkerboard_texture(c0, c1);
  EXPECT_EQ(t->eval(Vec2(0.1f, 0.1f)), c0);
  EXPECT_EQ(t->eval(Vec2(0.6f, 0.1f)), c1);
  EXPECT_EQ(t->eval(Vec2(0.1f, 0.6f)), c1);
  EXPECT_EQ(t->eval(Vec2(0.6f, 0.6f)), c0);
  // Mitsuba truncates the cell index towards zero: the cells beside u = 0 share a colour
  // (a flooring index would give c1 at u = -0.1), and the band past it is c1 again.
  EXPECT_EQ(t->eval(Vec2(-0.1f, 0.1f)), c0);
  EXPECT_EQ(t->eval(Vec2(-0.6f, 0.1f)), c1);
  EXPECT_EQ(t->eval(Vec2(-0.6f, -0.6f)), c0);
  UvTransform four;
  four.scale = Vec2(4.0f);
  const TexturePtr fine = make_checkerboard_texture(c0, c1, four);
  EXPECT_EQ(fine->eval(Vec2(0.05f, 0.05f)), c0);
  EXPECT_EQ(fine->eval(Vec2(0.15f, 0.05f)), c1);  // 8 cells per unit
}

TEST(ScaleTexture, MultipliesAndKeepsConstantsConstant) {
  const TexturePtr scaled = make_scale_texture(make_checkerboard_texture(Rgb(0.5f), Rgb(0.25f)),
                                               Rgb(2.0f, 1.0f, 0.5f));
  EXPECT_EQ(scaled->eval(Vec2(0.1f, 0.1f)), Rgb(1.0f, 0.5f, 0.25f));
  EXPECT_FALSE(scaled->constant());
  const TexturePtr constant = make_scale_texture(make_constant_texture(Rgb(0.5f)), Rgb(3.0f));
  ASSERT_TRUE(constant->constant());
  EXPECT_EQ(*constant->constant(), Rgb(1.5f));
  EXPECT_NEAR(constant->eval_average(Vec2(0.0f)), 1.5f, 1e-6f);
  EXPECT_NEAR(make_constant_texture(Rgb(1, 0, 0))->eval_luminance(Vec2(0.0f)), 0.2126f, 1e-6f);
}

// ---------------------------------------------------------------------------------------
// Scene-level: mask, bump, default uvs.

// A square [-1,1]^2 at height z facing +z (towards the camera/rays from above), with
// uv = ((x+1)/2, (y+1)/2).
MeshDesc square(float z, int material, float half = 1.0f) {
  MeshDesc m;
  m.name = "square z=" + std::to_string(z);
  m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  return m;
}

std::unique_ptr<Scene> masked_scene(float opacity) {
  SceneDescription d;
  d.source = "masked";
  d.materials.push_back({"floor", make_lambertian(Rgb(0.5f))});
  d.materials.push_back(
      MaterialDesc("masked", make_lambertian(Rgb(0.5f)), make_constant_texture(Rgb(opacity))));
  d.meshes.push_back(square(0.0f, 0, 10.0f));
  d.meshes.push_back(square(1.0f, 1));
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  return Scene::build(std::move(d));
}

// Fraction of vertical rays through the masked square that stop on it.
double blocked_fraction(const Scene& scene, int rays, bool use_occluded) {
  int blocked = 0;
  for (int i = 0; i < rays; ++i) {
    const float x = -0.9f + 1.8f * float(i % 97) / 97.0f, y = -0.9f + 1.8f * float(i / 97) / float(rays / 97 + 1);
    const Ray ray{Vec3(x, y, 3.0f), Vec3(0, 0, -1), 0.0f, 2.5f};  // ends above the floor
    if (use_occluded) {
      blocked += scene.occluded(ray) ? 1 : 0;
    } else {
      SurfaceHit hit;
      blocked += scene.intersect(ray, hit) ? 1 : 0;
    }
  }
  return double(blocked) / rays;
}

TEST(Mask, TransparentSurfaceNeitherOccludesNorIsHit) {
  const auto scene = masked_scene(0.0f);
  EXPECT_EQ(blocked_fraction(*scene, 2000, true), 0.0);
  EXPECT_EQ(blocked_fraction(*scene, 2000, false), 0.0);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.2f, 0.3f, 3.0f), Vec3(0, 0, -1), 0.0f, kInfinity}, hit));
  EXPECT_NEAR(hit.position.z, 0.0f, 1e-5f);  // went through to the floor
  const auto opaque = masked_scene(1.0f);
  EXPECT_EQ(blocked_fraction(*opaque, 2000, true), 1.0);
}

TEST(Mask, PartialOpacityStopsThatFractionOfRaysReproducibly) {
  const auto scene = masked_scene(0.3f);
  const int rays = 20000;
  const double occluded = blocked_fraction(*scene, rays, true);
  const double hit = blocked_fraction(*scene, rays, false);
  const double sigma = std::sqrt(0.3 * 0.7 / rays);
  EXPECT_NEAR(occluded, 0.3, 4.0 * sigma);
  EXPECT_EQ(occluded, hit);  // both queries make the same decision for the same ray
  EXPECT_EQ(blocked_fraction(*scene, rays, true), occluded);  // and again next time
}

TEST(Bump, LinearRampTiltsTheShadingNormalByItsSlope) {
  // Height h(u, v) = 0.5 u over a square of side 2: dh/dx = 0.5 * du/dx = 0.25, so the
  // normal tilts by atan(0.25) towards -x. A ramp image sampled at texel centres is linear
  // in between, so finite differences are exact there.
  Image ramp(64, 1);
  for (int x = 0; x < 64; ++x) ramp.at(x, 0) = Rgb(0.5f * (float(x) + 0.5f) / 64.0f);
  SceneDescription d;
  d.source = "bump";
  d.materials.push_back(MaterialDesc("bumped", make_lambertian(Rgb(0.5f)), nullptr,
                                     make_bitmap_texture(ramp, {}, WrapMode::Clamp), true));
  d.meshes.push_back(square(0.0f, 0));
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  const auto scene = Scene::build(std::move(d));
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(0.1f, 0.2f, 2.0f), Vec3(0, 0, -1), 0.0f, kInfinity}, hit));
  EXPECT_EQ(hit.geometric_normal, Vec3(0, 0, 1));
  const float expected = std::atan(0.25f);
  EXPECT_NEAR(std::acos(hit.shading_normal.z), expected, 1e-3f);
  EXPECT_LT(hit.shading_normal.x, 0.0f);
  EXPECT_NEAR(hit.shading_normal.y, 0.0f, 1e-4f);
  EXPECT_NEAR(glm::dot(hit.shading.n, hit.shading_normal), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(hit.dpdu - Vec3(2, 0, 0)), 0.0f, 1e-5f);
}

TEST(DefaultUvs, TexturedMeshWithoutUvsGetsAPlanarProjectionAndAWarning) {
  SceneDescription d;
  d.source = "no-uv";
  d.materials.push_back(MaterialDesc(
      "checker", make_lambertian(make_checkerboard_texture(Rgb(0.8f), Rgb(0.2f))), nullptr,
      nullptr, true));
  MeshDesc mesh = square(0.0f, 0, 2.0f);
  mesh.uvs.clear();
  d.meshes.push_back(mesh);
  d.environment.kind = EnvironmentDesc::Kind::Constant;
  d.environment.radiance = Rgb(1.0f);
  const auto scene = Scene::build(std::move(d));
  ASSERT_EQ(scene->warnings().size(), 1u);
  EXPECT_NE(scene->warnings()[0].find("no texture coordinates"), std::string::npos);
  SurfaceHit hit;
  ASSERT_TRUE(scene->intersect(Ray{Vec3(1.0f, -1.0f, 1.0f), Vec3(0, 0, -1), 0.0f, kInfinity}, hit));
  EXPECT_NEAR(hit.uv.x, 0.75f, 1e-5f);
  EXPECT_NEAR(hit.uv.y, 0.25f, 1e-5f);
}

}  // namespace

TEST(GridTexture, MitsubaLinesAlongWholeUv) {
  const Rgb c0(0.2f), c1(0.4f);
  const TexturePtr t = make_grid_texture(c0, c1, 0.01f);
  EXPECT_EQ(t->eval(Vec2(0.5f, 0.5f)), c0);
  EXPECT_EQ(t->eval(Vec2(0.005f, 0.5f)), c1);   // beside u = 0
  EXPECT_EQ(t->eval(Vec2(0.5f, 0.995f)), c1);   // beside v = 1, from below
  EXPECT_EQ(t->eval(Vec2(-2.004f, 0.3f)), c1);  // any whole u, negative too
  EXPECT_EQ(t->eval(Vec2(0.02f, 0.98f)), c0);
  // The line's half-width is in uv units after the transform (Mitsuba's uvscale/uoffset).
  UvTransform transform;
  transform.scale = Vec2(4.0f);
  transform.offset = Vec2(0.1f, 0.0f);
  const TexturePtr wide = make_grid_texture(c0, c1, 0.1f, transform);
  EXPECT_EQ(wide->eval(Vec2(0.22f, 0.1f)), c1);  // 4 * 0.22 + 0.1 = 0.98: beside u = 1
  EXPECT_EQ(wide->eval(Vec2(0.1f, 0.1f)), c0);   // 0.5, 0.4
  EXPECT_EQ(wide->eval(Vec2(0.1f, 0.26f)), c1);  // v: 1.04
}
