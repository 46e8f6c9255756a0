#include "emlt/scene/description.h"

namespace emlt {

std::optional<CameraDesc::FovAxis> parse_fov_axis(const std::string& name) {
  if (name == "x") return CameraDesc::FovAxis::X;
  if (name == "y") return CameraDesc::FovAxis::Y;
  if (name == "smaller") return CameraDesc::FovAxis::Smaller;
  if (name == "larger") return CameraDesc::FovAxis::Larger;
  return std::nullopt;
}

Mat4 look_at_matrix(const Vec3& origin, const Vec3& target, const Vec3& up) {
  // Mitsuba's lookat: camera +z towards the target, +x to the image's left. A degenerate
  // triple produces NaNs on purpose, so Scene::build rejects it with a clear message.
  const Vec3 dir = glm::normalize(target - origin);
  const Vec3 left = glm::normalize(glm::cross(up, dir));
  const Vec3 new_up = glm::cross(dir, left);
  Mat4 m(1.0f);
  m[0] = Vec4(left, 0.0f);
  m[1] = Vec4(new_up, 0.0f);
  m[2] = Vec4(dir, 0.0f);
  m[3] = Vec4(origin, 1.0f);
  return m;
}

}  // namespace emlt

namespace emlt {

std::optional<std::string> SceneRenderRequest::said(std::string_view flag) const {
  for (const auto& [f, text] : options)
    if (f == flag) return text;
  for (const auto& [f, text] : integrator_options)
    if (f == flag) return text;
  return std::nullopt;
}

namespace {
// Records `text` for `flag` in `list`, replacing what was said before.
void record(std::vector<std::pair<std::string, std::string>>& list, const std::string& flag,
            std::string text) {
  for (auto& [f, t] : list)
    if (f == flag) {
      t = std::move(text);
      return;
    }
  list.emplace_back(flag, std::move(text));
}
}  // namespace

void SceneRenderRequest::set(const std::string& flag, std::string text) {
  record(options, flag, std::move(text));
}

void SceneRenderRequest::set_integrator_option(const std::string& flag, std::string text) {
  record(integrator_options, flag, std::move(text));
}

std::string SceneDescription::verdict() const {
  size_t approximated = 0, unsupported = 0;
  for (const Divergence& d : divergences)
    ++(d.kind == Divergence::Kind::Approximated ? approximated : unsupported);
  if (approximated + unsupported == 0) return "exact";
  auto items = [](size_t n) { return std::to_string(n) + (n == 1 ? " item" : " items"); };
  std::string text;
  if (approximated) text = "approximated: " + items(approximated);
  if (unsupported)
    text += (text.empty() ? "" : ", ") + std::string("unsupported: ") + items(unsupported);
  return text;
}

}  // namespace emlt
