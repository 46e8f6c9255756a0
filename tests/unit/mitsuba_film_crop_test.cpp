// Mitsuba 0.6's crop window (cropOffsetX/Y, cropWidth/Height, read by every film): only the
// window is rendered and written, as an image of its size, and the whole film still frames
// the view. The loader reads it (verdict exact), refuses a window off the film as Mitsuba
// does, and the camera's rays, raster positions and importance of the cropped image are the
// whole film's, restricted to the window.
#include <gtest/gtest.h>

#include <string>

#include "emlt/scene/camera.h"
#include "emlt/scene/description.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

std::string scene_with_film(const std::string& film) {
  return R"(<?xml version="1.0"?>
<scene version="0.6.0">
  <sensor type="perspective">
    <float name="fov" value="40"/><string name="fovAxis" value="smaller"/>
    <transform name="toWorld"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
    )" + film +
         R"(
  </sensor>
  <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
  <shape type="sphere"/>
</scene>
)";
}

SceneDescription load_film(const std::string& name, const std::string& film) {
  return load_scene_description(
      test::write_file(test::scratch_dir("film-crop"), name, scene_with_film(film)));
}

std::string film_error(const std::string& name, const std::string& film) {
  const std::string path =
      test::write_file(test::scratch_dir("film-crop"), name, scene_with_film(film));
  return test::error_of([&] { load_scene_description(path); });
}

const char* kCropped = R"(<film type="hdrfilm">
      <integer name="width" value="40"/><integer name="height" value="30"/>
      <integer name="cropOffsetX" value="8"/><integer name="cropOffsetY" value="5"/>
      <integer name="cropWidth" value="20"/><integer name="cropHeight" value="12"/>
      <string name="channelNames" value="beauty"/><rfilter type="box"/></film>)";

}  // namespace

TEST(MitsubaFilmCrop, LoaderReadsTheWindowOfEveryFilm) {
  const SceneDescription cropped = load_film("cropped.xml", kCropped);
  EXPECT_EQ(cropped.verdict(), "exact");
  const CameraDesc& camera = cropped.camera;
  EXPECT_EQ(camera.width, 40);  // the film that frames the view
  EXPECT_EQ(camera.height, 30);
  EXPECT_TRUE(camera.cropped());
  EXPECT_EQ(camera.crop_x, 8);
  EXPECT_EQ(camera.crop_y, 5);
  EXPECT_EQ(camera.crop_width, 20);
  EXPECT_EQ(camera.crop_height, 12);
  const Camera built(camera);
  EXPECT_EQ(built.width(), 20);  // the image rendered and written
  EXPECT_EQ(built.height(), 12);

  // An offset alone keeps the film's size as the window's size: Mitsuba refuses it.
  const std::string off = film_error("off.xml", R"(<film type="ldrfilm">
      <integer name="width" value="40"/><integer name="height" value="30"/>
      <integer name="cropOffsetX" value="2"/></film>)");
  EXPECT_NE(off.find("off.xml: line"), std::string::npos) << off;
  EXPECT_NE(off.find("invalid crop window: 40x30 at (2, 0)"), std::string::npos) << off;

  // The window alone is cropped from the film's top-left corner.
  const SceneDescription corner = load_film("corner.xml", R"(<film type="tiledhdrfilm">
      <integer name="width" value="40"/><integer name="height" value="30"/>
      <integer name="cropWidth" value="10"/><integer name="cropHeight" value="30"/></film>)");
  EXPECT_EQ(corner.verdict(), "exact");
  EXPECT_EQ(corner.camera.crop_x, 0);
  EXPECT_EQ(corner.camera.crop_width, 10);
  EXPECT_EQ(corner.camera.crop_height, 30);

  // Mitsuba's mfilm is one pixel unless told otherwise; its number format and variable name
  // change only the file it writes.
  const SceneDescription mfilm = load_film("mfilm.xml", R"(<film type="mfilm">
      <integer name="digits" value="6"/><string name="variable" value="radiance"/></film>)");
  EXPECT_EQ(mfilm.verdict(), "exact");
  EXPECT_EQ(mfilm.camera.width, 1);
  EXPECT_EQ(mfilm.camera.height, 1);
  EXPECT_FALSE(mfilm.camera.cropped());
}

TEST(MitsubaFilmCrop, CroppedCameraIsTheWholeFilmsCameraInTheWindow) {
  CameraDesc whole = load_film("whole.xml", R"(<film type="hdrfilm">
      <integer name="width" value="40"/><integer name="height" value="30"/>
      <rfilter type="box"/></film>)")
                         .camera;
  const CameraDesc cropped_desc = load_film("cropped2.xml", kCropped).camera;
  const Camera full(whole), cropped(cropped_desc);
  const Vec2 offset(8.0f, 5.0f);
  for (const Vec2 raster : {Vec2(0.5f, 0.5f), Vec2(19.9f, 11.9f), Vec2(3.25f, 7.75f)}) {
    const Ray a = cropped.generate_ray(raster, Vec2(0.5f));
    const Ray b = full.generate_ray(raster + offset, Vec2(0.5f));
    EXPECT_NEAR(glm::length(a.direction - b.direction), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(a.origin - b.origin), 0.0f, 1e-6f);
    // Back to the same raster position of the window.
    const auto back = cropped.raster_position(a.origin, a.direction);
    ASSERT_TRUE(back.has_value());
    EXPECT_NEAR(back->x, raster.x, 1e-3f);
    EXPECT_NEAR(back->y, raster.y, 1e-3f);
    // W_e integrates to one over the window's part of the plane: the whole film's
    // importance times the film's pixels over the window's.
    EXPECT_NEAR(cropped.importance(a.origin, a.direction),
                full.importance(b.origin, b.direction) * (40.0f * 30.0f) / (20.0f * 12.0f),
                1e-4f * full.importance(b.origin, b.direction) * 5.0f);
  }
  // A direction the whole film sees outside the window misses the cropped image.
  const Ray outside = full.generate_ray(Vec2(2.0f, 2.0f), Vec2(0.5f));
  EXPECT_FALSE(cropped.raster_position(outside.origin, outside.direction).has_value());
  EXPECT_EQ(cropped.importance(outside.origin, outside.direction), 0.0f);
}
