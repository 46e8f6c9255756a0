#include "emlt/scene/load_prefetch.h"

#include <tbb/task_group.h>

#include <exception>
#include <functional>
#include <mutex>

namespace emlt {

namespace {

// One file: read once, by a task or by the loader, whichever calls first; the other
// waits in call_once. The error, if any, is kept and thrown to the loader.
template <typename Result>
struct Read {
  std::once_flag once;
  std::function<Result()> read;
  std::optional<Result> result;
  std::exception_ptr error;

  void run() {
    std::call_once(once, [this] {
      try {
        result = read();
      } catch (...) {
        error = std::current_exception();
      }
    });
  }
  // The contents, moved out: a file named twice (the door's checker.png) is announced
  // twice, or read directly the second time.
  Result take() {
    taken = true;
    run();
    if (error) std::rethrow_exception(error);
    return std::move(*result);
  }
  bool taken = false;  // only the loader's thread reads and writes it
};

thread_local LoadPrefetch* t_active = nullptr;

}  // namespace

struct LoadPrefetch::Reads {
  std::vector<std::pair<std::string, std::unique_ptr<Read<Image8>>>> images;
  std::vector<std::pair<Obj, std::unique_ptr<Read<ObjInFileSpace>>>> objs;
  tbb::task_group tasks;
};

LoadPrefetch::LoadPrefetch(const std::vector<std::string>& images, const std::vector<Obj>& objs)
    : reads_(std::make_unique<Reads>()), outer_(t_active) {
  for (const std::string& path : images) {
    auto read = std::make_unique<Read<Image8>>();
    read->read = [path] { return read_image8(path); };
    reads_->images.emplace_back(path, std::move(read));
  }
  for (const Obj& obj : objs) {
    auto read = std::make_unique<Read<ObjInFileSpace>>();
    read->read = [obj] { return read_obj_file(obj.path, obj.smooth_normals, obj.flip_v); };
    reads_->objs.emplace_back(obj, std::move(read));
  }
  // Images first: the loader reaches textures (declared at the top, or in the BSDFs) before
  // the shapes, and while a task decodes one the loader parses the meshes it needs first.
  for (auto& [path, read] : reads_->images) reads_->tasks.run([r = read.get()] { r->run(); });
  for (auto& [obj, read] : reads_->objs) reads_->tasks.run([r = read.get()] { r->run(); });
  t_active = this;
}

LoadPrefetch::~LoadPrefetch() {
  reads_->tasks.wait();
  t_active = outer_;
}

std::optional<Image8> LoadPrefetch::image8(const std::string& path) {
  if (!t_active) return std::nullopt;
  for (auto& [announced, read] : t_active->reads_->images)
    if (announced == path && !read->taken) return read->take();
  return std::nullopt;
}

std::optional<ObjInFileSpace> LoadPrefetch::obj(const std::string& path, bool smooth_normals,
                                                bool flip_v) {
  if (!t_active) return std::nullopt;
  for (auto& [announced, read] : t_active->reads_->objs)
    if (announced.path == path && announced.smooth_normals == smooth_normals &&
        announced.flip_v == flip_v && !read->taken)
      return read->take();
  return std::nullopt;
}

}  // namespace emlt
