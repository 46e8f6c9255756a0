// Mitsuba 0.6's sensors, films, crop windows and reconstruction filters mapped onto the
// scene's camera, with Mitsuba's defaults (a 768x576 film, an mfilm of one pixel, a
// Gaussian filter, a 50 mm focal length).
#include "src/scene/loaders/mitsuba_sensor.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "src/scene/parameter_ranges.h"

namespace emlt::mitsuba {

namespace {

class SensorReader {
 public:
  SensorReader(const Document& doc, SceneDescription& desc) : doc_(doc), desc_(desc) {}

  void read(pugi::xml_node node) {
    const std::string type = doc_.attribute(node, "type");
    if (type != "perspective" && type != "thinlens" && type != "orthographic")
      doc_.fail(node, "sensor type '" + type +
                          "' is not supported (perspective, thinlens, orthographic)");
    Properties props(doc_, node);
    CameraDesc& camera = desc_.camera;
    camera.to_world = props.get_transform("toWorld");
    const bool orthographic = type == "orthographic";
    if (orthographic) camera.projection = CameraDesc::Projection::Orthographic;
    // Mitsuba's pinhole reads no focus distance (scene exporters write one anyway).
    if (type == "perspective" || orthographic) props.ignore({"focusDistance"});
    if (props.has("nearClip") || props.has("farClip")) {
      const float near_clip = props.get_float("nearClip", 1e-2f);
      const float far_clip = props.get_float("farClip", 1e4f);
      doc_.warn(node,
                fmt::format("nearClip {:g} and farClip {:g}", near_clip, far_clip) +
                    " are not applied: only geometry nearer the camera than nearClip, or "
                    "farther than farClip, would look different",
                Document::Warning::Note);
    }
    for (pugi::xml_node child : props.objects()) {
      const std::string kind = child.name();
      if (kind == "film")
        read_film(child);
      else if (kind == "sampler")
        read_sampler(doc_, child, desc_.render);
      else
        doc_.warn(child, "unsupported element <" + kind + "> inside <sensor> ignored");
    }

    if (orthographic) {  // no field of view: to_world's scale sizes the film
      props.ignore({"shutterOpen", "shutterClose"});
      props.warn_unused();
      return;
    }
    const std::string axis = props.get_string("fovAxis", "x");
    bool diagonal = false;
    if (const auto parsed = parse_fov_axis(axis))
      camera.fov_axis = *parsed;
    else if (axis == "diagonal")
      diagonal = true;
    else
      doc_.fail(node, "unknown fovAxis '" + axis + "'");

    if (props.has("fov")) {
      camera.fov_degrees = props.get_float("fov", 45.0f, loader::kFovRange);
      if (props.has("focalLength"))
        doc_.warn(node, "focalLength ignored because fov is given", Document::Warning::Note);
      props.ignore({"focalLength"});
    } else {
      // Mitsuba's focal length is in 35 mm film units (36 mm wide); 50 mm by default.
      std::string focal = props.get_string("focalLength", "50mm");
      if (focal.size() > 2 && focal.substr(focal.size() - 2) == "mm")
        focal.resize(focal.size() - 2);
      const pugi::xml_node given = props.node_of("focalLength");
      const float millimetres = doc_.to_float(given, focal);
      if (!(millimetres > 0.0f))
        doc_.fail(given, "'focalLength' " +
                             loader::refusal("a positive length in millimetres, such as 50mm",
                                             props.get_string("focalLength", "")));
      camera.fov_degrees = glm::degrees(2.0f * std::atan(18.0f / millimetres));
      camera.fov_axis = CameraDesc::FovAxis::X;
      diagonal = false;
      // Mitsuba 3 changed this: its focal length spans the 36 x 24 mm frame's diagonal.
      if (doc_.mitsuba3()) {
        camera.fov_degrees =
            glm::degrees(2.0f * std::atan(std::hypot(36.0f, 24.0f) / (2.0f * millimetres)));
        diagonal = true;
      }
    }
    if (diagonal) {
      // Convert the diagonal field of view to the horizontal one for this image aspect.
      const float w = float(camera.width), h = float(camera.height);
      const float tan_half =
          std::tan(glm::radians(camera.fov_degrees) * 0.5f) * w / std::sqrt(w * w + h * h);
      camera.fov_degrees = glm::degrees(2.0f * std::atan(tan_half));
      camera.fov_axis = CameraDesc::FovAxis::X;
    }
    if (type == "thinlens") {
      camera.aperture_radius =
          props.get_float("apertureRadius", camera.aperture_radius, loader::kNonNegativeRange);
      camera.focus_distance =
          props.get_float("focusDistance", camera.focus_distance, loader::kPositiveRange);
    }
    props.ignore({"shutterOpen", "shutterClose"});
    props.warn_unused();
  }

 private:
  void read_film(pugi::xml_node node) {
    Properties props(doc_, node);
    // Mitsuba's mfilm is one pixel by default (a measurement), its other films 768x576.
    const bool mfilm = doc_.attribute(node, "type") == "mfilm";
    CameraDesc& camera = desc_.camera;
    camera.width = props.get_integer("width", mfilm ? 1 : 768, loader::kFilmSideRange);
    camera.height = props.get_integer("height", mfilm ? 1 : 576, loader::kFilmSideRange);
    read_crop(node, props);
    // Output encoding only; the renderer chooses its own from the output file name (an
    // ldrfilm's tone mapping included: emlt writes linear radiance and a PNG preview; the
    // EXR channels' names and an mfilm's number format and variable name likewise).
    props.ignore({"banner", "pixelFormat", "componentFormat", "fileFormat", "attachLog",
                  "tonemapMethod", "gamma", "exposure", "key", "burn", "channelNames", "digits",
                  "variable"});
    const bool high_quality_edges = props.get_boolean("highQualityEdges", false);
    if (props.has("filename")) {  // not a Mitsuba film parameter; the output is named by -o
      props.ignore({"filename"});
      doc_.warn(node, "film parameter 'filename' ignored, as Mitsuba does (the output is -o)",
                Document::Warning::Note);
    }
    desc_.camera.filter = {PixelFilterDesc::Kind::Gaussian};  // Mitsuba's default
    for (pugi::xml_node child : props.objects()) {
      if (std::string(child.name()) == "rfilter")
        read_filter(child);
      else
        doc_.warn(child, "unsupported element " + doc_.describe(child) + " inside <film> ignored");
    }
    // Mitsuba then also samples just outside the image, so that a border pixel gets its
    // filter's whole footprint; emlt normalises the footprint over the part inside the image,
    // as Mitsuba does without it. A box filter lies within its pixel: nothing changes.
    if (high_quality_edges) {
      const bool box = desc_.camera.filter.kind == PixelFilterDesc::Kind::Box &&
                       desc_.camera.filter.box_radius <= 0.5f;
      doc_.warn(node,
                box ? "'highQualityEdges' changes nothing with a box filter"
                    : "'highQualityEdges' is not supported: the border pixels are filtered over "
                      "the part of their footprint inside the image, as Mitsuba does without it",
                box ? Document::Warning::Note : Document::Warning::Approximated);
    }
    props.warn_unused();
  }

  // Mitsuba's crop window (every film): only the window's pixels are rendered and written,
  // as an image of its size, while the whole film frames the view; Mitsuba refuses a window
  // that does not lie within the film.
  void read_crop(pugi::xml_node node, Properties& props) {
    CameraDesc& camera = desc_.camera;
    if (!props.has("cropOffsetX") && !props.has("cropOffsetY") && !props.has("cropWidth") &&
        !props.has("cropHeight"))
      return;
    const int x = props.get_integer("cropOffsetX", 0), y = props.get_integer("cropOffsetY", 0);
    const int width = props.get_integer("cropWidth", camera.width);
    const int height = props.get_integer("cropHeight", camera.height);
    if (x < 0 || y < 0 || width <= 0 || height <= 0 || int64_t(x) + width > camera.width ||
        int64_t(y) + height > camera.height)
      doc_.fail(node, fmt::format("invalid crop window: {}x{} at ({}, {}) does not lie within "
                                  "the {}x{} film (Mitsuba refuses it too)",
                                  width, height, x, y, camera.width, camera.height));
    camera.crop_x = x, camera.crop_y = y, camera.crop_width = width, camera.crop_height = height;
  }

  void read_filter(pugi::xml_node node) {
    const std::string type = doc_.attribute(node, "type");
    Properties props(doc_, node);
    PixelFilterDesc& filter = desc_.camera.filter;
    if (type == "box") {
      filter.kind = PixelFilterDesc::Kind::Box;
      // Mitsuba 0.6's box counts a sample fully for every pixel whose centre lies within
      // `radius` of it on each axis (0.5: its own pixel only).
      if (!doc_.mitsuba3())
        filter.box_radius = props.get_float("radius", 0.5f, loader::kFilterRadiusRange);
    } else if (type == "tent") {
      filter.kind = PixelFilterDesc::Kind::Tent;
      // Mitsuba 0.6's tent is one pixel wide whatever the file says (it reads no
      // parameter and warns of an unqueried 'radius'); Mitsuba 3's reads its radius.
      if (doc_.mitsuba3()) {
        filter.radius = props.get_float("radius", 1.0f, loader::kFilterRadiusRange);
      } else {
        filter.radius = 1.0f;
        if (props.has("radius")) {
          props.ignore({"radius"});
          doc_.warn(node,
                    "Mitsuba 0.6's tent filter reads no 'radius' (it is one pixel wide); "
                    "ignored as Mitsuba does",
                    Document::Warning::Note);
        }
      }
    } else if (type == "gaussian") {
      filter.stddev = props.get_float("stddev", 0.5f, loader::kFilterStddevRange);
    } else if (type == "mitchell") {
      filter.kind = PixelFilterDesc::Kind::Mitchell;
      filter.b = props.get_float("B", 1.0f / 3.0f);
      filter.c = props.get_float("C", 1.0f / 3.0f);
    } else if (type == "catmullrom") {
      filter.kind = PixelFilterDesc::Kind::CatmullRom;
    } else if (type == "lanczos") {
      filter.kind = PixelFilterDesc::Kind::Lanczos;
      filter.lobes = props.get_integer("lobes", 3, loader::kFilterLobesRange);
    } else {
      doc_.warn(node,
                "unknown reconstruction filter " + doc_.describe(node) +
                    " approximated by Mitsuba's default gaussian (stddev 0.5)",
                Document::Warning::Approximated);
      props.ignore({"B", "C", "lobes", "radius", "stddev"});
    }
    props.warn_unused();
  }

  const Document& doc_;
  SceneDescription& desc_;  // its camera and render request are what the sensor says
};

}  // namespace

void read_sensor(const Document& doc, pugi::xml_node node, SceneDescription& desc) {
  SensorReader(doc, desc).read(node);
}

}  // namespace emlt::mitsuba
