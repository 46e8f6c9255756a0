// pbrt-v4's Camera, Film, Sampler, Integrator and PixelFilter mapped onto the scene's camera
// and render request.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

#include "src/scene/loaders/pbrt_reader.h"

namespace emlt::pbrt {

namespace {

// Parameters that only steer how pbrt samples or stores, never the converged image.
void note_sampling_only(Reader& reader, const Where& at, const Params& params,
                        std::initializer_list<const char*> names, const std::string& what) {
  std::string listed;
  for (const char* name : names)
    if (params.has(name)) {
      params.ignore(name);
      listed += (listed.empty() ? "'" : ", '") + std::string(name) + "'";
    }
  if (!listed.empty()) reader.note(at, what + ": " + listed + " ignored (the image is the same)");
}

}  // namespace

void Reader::camera(const Where& at, const std::string& type, const Params& params) {
  if (camera_seen_) fail(at, "a second Camera");
  camera_seen_ = true;
  CameraDesc& cam = desc_.camera;
  // The matrix at Camera is world to camera. pbrt's camera space has +x at the image's
  // right; emlt's (Mitsuba's) has +x at its left: the x axis is mirrored.
  cam.to_world = glm::inverse(state_.ctm) * glm::scale(Mat4(1.0f), Vec3(-1.0f, 1.0f, 1.0f));
  if (!is_finite(Vec3(cam.to_world[3])) || !std::isfinite(glm::determinant(cam.to_world)) ||
      glm::determinant(cam.to_world) == 0.0f)
    fail(at, "the camera's transformation is singular");
  note_sampling_only(*this, at, params, {"shutteropen", "shutterclose"}, "Camera");
  if (type == "perspective") {
    cam.projection = CameraDesc::Projection::Perspective;
    const float fov = params.get_float("fov", 90.0f);
    if (!(fov > 0.0f && fov < 180.0f)) Params::fail(*params.get("fov"), "must be in (0, 180)");
    cam.fov_degrees = fov;
    // pbrt's field of view spans the image's shorter side.
    cam.fov_axis = CameraDesc::FovAxis::Smaller;
    cam.aperture_radius = params.get_float("lensradius", 0.0f);
    if (cam.aperture_radius < 0.0f) Params::fail(*params.get("lensradius"), "must not be negative");
    cam.focus_distance = params.get_float("focaldistance", 1e6f);
    if (!(cam.focus_distance > 0.0f))
      Params::fail(*params.get("focaldistance"), "must be positive");
    if (cam.aperture_radius == 0.0f && params.has("focaldistance"))
      params.ignore("focaldistance");  // a pinhole has no focus
  } else if (type == "orthographic") {
    cam.projection = CameraDesc::Projection::Orthographic;
    if (params.get_float("lensradius", 0.0f) > 0.0f)
      warn(at, "an orthographic camera's lens (lensradius) is not supported; rendered as pinhole");
    params.ignore("focaldistance");
    ortho_ = true;
  } else if (type == "realistic" || type == "spherical") {
    fail(at, "Camera \"" + type + "\" is not supported (perspective, orthographic)");
  } else {
    fail(at, "unknown camera type '" + type + "'");
  }
  for (const char* name : {"screenwindow", "frameaspectratio"})
    if (const Param* p = params.get(name))
      warn({p->file, p->line},
           "Camera " + p->quoted() + " is not supported; the window of pbrt's default is used");
  report_unused(params, "Camera \"" + type + "\"");
}

void Reader::film(const Where& at, const std::string& type, const Params& params) {
  if (type != "rgb" && type != "gbuffer" && type != "spectral")
    fail(at, "unknown film type '" + type + "'");
  if (type == "spectral")
    warn(at, "Film \"spectral\": emlt writes RGB only; the image is the RGB film's",
         Divergence::Kind::Approximated);
  if (type == "gbuffer") note(at, "Film \"gbuffer\": only the colour image is written");
  CameraDesc& cam = desc_.camera;
  cam.width = params.get_int("xresolution", 1280);
  cam.height = params.get_int("yresolution", 720);
  if (cam.width < 1 || cam.height < 1 || cam.width > 65536 || cam.height > 65536)
    fail(at, fmt::format("film resolution {}x{} out of range (1 to 65536)", cam.width, cam.height));
  if (params.has("filename"))
    note(at, "Film 'filename' \"" + params.get_string("filename", "") +
                 "\" not used (the command line's -o names the image)");
  if (const Param* p = params.get("cropwindow")) {
    const std::vector<float> w = params.get_floats("cropwindow");
    if (w.size() != 4 ||
        !(w[0] >= 0 && w[0] < w[1] && w[1] <= 1 && w[2] >= 0 && w[2] < w[3] && w[3] <= 1))
      Params::fail(*p, "expected x0 x1 y0 y1 with 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1");
    // pbrt rounds the window's edges up to whole pixels.
    cam.crop_x = int(std::ceil(cam.width * w[0]));
    cam.crop_y = int(std::ceil(cam.height * w[2]));
    cam.crop_width = std::max(1, int(std::ceil(cam.width * w[1])) - cam.crop_x);
    cam.crop_height = std::max(1, int(std::ceil(cam.height * w[3])) - cam.crop_y);
  }
  if (const Param* p = params.get("pixelbounds")) {
    const std::vector<int> b = params.get_ints("pixelbounds");
    if (b.size() != 4 || !(b[0] >= 0 && b[0] < b[1] && b[1] <= cam.width && b[2] >= 0 &&
                           b[2] < b[3] && b[3] <= cam.height))
      Params::fail(*p, "expected x0 x1 y0 y1 inside the film");
    cam.crop_x = b[0];
    cam.crop_y = b[2];
    cam.crop_width = b[1] - b[0];
    cam.crop_height = b[3] - b[2];
  }
  // The sensor's response: pbrt scales by exposure time times ISO / 100 (1 by default) and
  // integrates spectra against the CIE curves; an RGB renderer has neither.
  const float iso = params.get_float("iso", 100.0f),
              exposure = params.get_float("exposuretime", 1.0f);
  if (iso * exposure != 100.0f)
    warn(at, fmt::format("Film iso {:g} and exposuretime {:g} (an image scale of {:g}) are not "
                         "supported; the scale 1 is used",
                         iso, exposure, iso * exposure / 100.0f));
  const std::string sensor = params.get_string("sensor", "cie1931");
  if (sensor != "cie1931") warn(at, "Film sensor \"" + sensor + "\" is not supported; ignored");
  if (params.has("whitebalance") && params.get_float("whitebalance", 0.0f) != 0.0f)
    warn(at, "Film 'whitebalance' is not supported; ignored");
  if (params.has("maxcomponentvalue") &&
      std::isfinite(params.get_float("maxcomponentvalue", INFINITY)))
    warn(at, "Film 'maxcomponentvalue' (clamping samples) is not supported; nothing is clamped");
  note_sampling_only(*this, at, params, {"savefp16", "diagonal", "writefp16"}, "Film");
  report_unused(params, "Film \"" + type + "\"");
}

void Reader::sampler(const Where& at, const std::string& type, const Params& params) {
  static const char* kTypes[] = {"halton", "independent", "paddedsobol", "pmj02bn",
                                 "sobol",  "stratified",  "zsobol"};
  if (std::find_if(std::begin(kTypes), std::end(kTypes),
                   [&](const char* t) { return type == t; }) == std::end(kTypes))
    fail(at, "unknown sampler type '" + type + "'");
  if (type == "stratified") {
    // The stratified sampler's count is xsamples times ysamples.
    const int x = params.get_int("xsamples", 4), y = params.get_int("ysamples", 4);
    if (x < 1 || y < 1) fail(at, "xsamples and ysamples must be positive");
    desc_.render.set("--spp", std::to_string(int64_t(x) * y));
    params.ignore("jitter");
  } else if (params.has("pixelsamples")) {
    const int spp = params.get_int("pixelsamples", 16);
    if (spp < 1) Params::fail(*params.get("pixelsamples"), "must be positive");
    desc_.render.set("--spp", std::to_string(spp));
  }
  note_sampling_only(*this, at, params, {"seed", "randomization", "jitter"}, "Sampler");
  report_unused(params, "Sampler \"" + type + "\"");
}

void Reader::integrator(const Where& at, const std::string& type, const Params& params) {
  SceneRenderRequest& request = desc_.render;
  if (type == "path" || type == "volpath" || type == "simplepath" || type == "simplevolpath" ||
      type == "randomwalk") {
    // The same expectation: they differ in how they sample lights and media.
    request.integrator = "pt";
  } else if (type == "bdpt") {
    request.integrator = "bdpt";
  } else if (type == "lightpath") {
    request.integrator = "ptracer";
  } else if (type == "mlt") {
    // pbrt's MLT is multiplexed MLT (Hachisuka et al. 2014) over its BDPT.
    request.integrator = "mmlt";
    if (params.has("mutationsperpixel"))
      request.set("--mpp", std::to_string(params.get_int("mutationsperpixel", 100)));
    note_sampling_only(*this, at, params,
                       {"bootstrapsamples", "chains", "largestepprobability", "sigma"},
                       "Integrator \"mlt\"");
  } else if (type == "sppm") {
    // Progressive photon mapping converges to the same image as a path tracer.
    request.integrator = "bdpt";
    note(at, "Integrator \"sppm\" rendered by bdpt (the same converged image)");
    note_sampling_only(*this, at, params, {"photonsperiteration", "radius", "iterations", "seed"},
                       "Integrator \"sppm\"");
  } else if (type == "ambientocclusion" || type == "aov" || type == "function") {
    warn(at, "Integrator \"" + type +
                 "\" is not supported; emlt's default integrator renders "
                 "the scene's light transport instead");
    for (const Param* p : params.unused()) p->used = true;
    return;
  } else {
    fail(at, "unknown integrator type '" + type + "'");
  }
  if (params.has("maxdepth")) {
    const int depth = params.get_int("maxdepth", 5);
    if (depth < 0) Params::fail(*params.get("maxdepth"), "must not be negative");
    // pbrt counts bounces (0: emitters seen directly); emlt counts path edges.
    request.set("--max-depth", std::to_string(int64_t(depth) + 1));
  }
  if (params.get_bool("regularize", false))
    warn(at,
         "Integrator 'regularize' (roughening near-specular surfaces, biased) is not supported");
  for (const char* name : {"visualizestrategies", "visualizeweights"})
    if (params.get_bool(name, false))
      warn(at, std::string("Integrator '") + name + "' is not supported (one image is written)");
  note_sampling_only(*this, at, params, {"lightsampler"}, "Integrator");
  report_unused(params, "Integrator \"" + type + "\"");
}

void Reader::pixel_filter(const Where& at, const std::string& type, const Params& params) {
  filter_seen_ = true;
  PixelFilterDesc& f = desc_.camera.filter;
  if (type == "box") {
    // pbrt's box of radius r counts every sample within r of the pixel centre, weight 1.
    f.kind = PixelFilterDesc::Kind::Box;
    const std::vector<float> r = params.get_floats("radius");
    f.box_radius = 0.5f;
    if (!r.empty()) {
      if (r.size() != 2 || !(r[0] > 0.0f) || r[0] != r[1])
        Params::fail(*params.get("radius"), "a box's radius must be two equal positive values");
      f.box_radius = r[0];
    }
  } else if (type == "gaussian") {
    f.kind = PixelFilterDesc::Kind::Gaussian;
    f.stddev = params.get_float("sigma", 0.5f);
    if (!(f.stddev > 0.0f)) Params::fail(*params.get("sigma"), "must be positive");
    params.ignore("radius");
    warn(at,
         "PixelFilter \"gaussian\": approximated by emlt's Gaussian of the same sigma, which "
         "reaches 4 sigma and is not lowered to 0 at pbrt's radius (the image is slightly "
         "blurrier; its mean is the same)",
         Divergence::Kind::Approximated);
  } else if (type == "triangle") {
    f.kind = PixelFilterDesc::Kind::Tent;
    const std::vector<float> r = params.get_floats("radius");
    f.radius = 2.0f;
    if (!r.empty()) {
      if (r.size() != 2 || !(r[0] > 0.0f) || r[0] != r[1])
        Params::fail(*params.get("radius"),
                     "a triangle's radius must be two equal positive values");
      f.radius = r[0];
    }
  } else if (type == "mitchell") {
    f.kind = PixelFilterDesc::Kind::Mitchell;
    f.b = params.get_float("B", 1.0f / 3.0f);
    f.c = params.get_float("C", 1.0f / 3.0f);
    const std::vector<float> r = params.get_floats("radius");
    if (!r.empty() && (r.size() != 2 || r[0] != 2.0f || r[1] != 2.0f))
      warn(at, "PixelFilter \"mitchell\" radius other than 2 is not supported; 2 is used",
           Divergence::Kind::Approximated);
  } else if (type == "sinc") {
    f.kind = PixelFilterDesc::Kind::Lanczos;
    f.lobes = 3;
    params.ignore("radius");
    params.ignore("tau");
    warn(at, "PixelFilter \"sinc\": approximated by a Lanczos sinc of 3 lobes",
         Divergence::Kind::Approximated);
  } else {
    fail(at, "unknown pixel filter type '" + type + "'");
  }
  report_unused(params, "PixelFilter \"" + type + "\"");
}

}  // namespace emlt::pbrt
