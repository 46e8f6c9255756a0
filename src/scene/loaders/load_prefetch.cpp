#include "emlt/scene/loaders/load_prefetch.h"

#include <tbb/task_group.h>

#include <atomic>
#include <exception>
#include <functional>
#include <mutex>

#include "emlt/scene/loaders/serialized_loader.h"

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
  std::atomic<bool> started{false}, done{false};

  void run() {
    std::call_once(once, [this] {
      started = true;
      try {
        result = read();
      } catch (...) {
        error = std::current_exception();
      }
      done = true;
    });
  }
  // The contents, moved out: a file named twice (the door's checker.png) is announced
  // twice, or read directly the second time. `help` reads another file nobody has begun
  // (false when there is none): called while a task is still reading this one, so that the
  // loader's thread works instead of waiting (with two threads, the task's worker and the
  // loader would otherwise read a scene's files one after the other).
  template <typename Help>
  Result take(const Help& help) {
    taken = true;
    while (started && !done && help()) {
    }
    run();
    if (error) std::rethrow_exception(error);
    return std::move(*result);
  }
  bool taken = false;  // only the loader's thread reads and writes it
};

thread_local LoadPrefetch* t_active = nullptr;

}  // namespace

struct LoadPrefetch::Reads {
  std::vector<std::pair<std::string, std::unique_ptr<Read<StoredImage>>>> images;
  std::vector<std::pair<Obj, std::unique_ptr<Read<ObjInFileSpace>>>> objs;
  std::vector<std::pair<MeshFile, std::unique_ptr<Read<MeshInFileSpace>>>> meshes;
  tbb::task_group tasks;

  // Reads one announced file that no one has begun; false if there is none.
  bool read_one_not_begun() {
    const auto first_of = [](auto& list) -> bool {
      for (auto& entry : list)
        if (!entry.second->started) {
          entry.second->run();
          return true;
        }
      return false;
    };
    return first_of(images) || first_of(objs) || first_of(meshes);
  }
  auto helper() {
    return [this] { return read_one_not_begun(); };
  }
};

LoadPrefetch::LoadPrefetch(const std::vector<std::string>& images, const std::vector<Obj>& objs,
                           const std::vector<MeshFile>& meshes)
    : reads_(std::make_unique<Reads>()), outer_(t_active) {
  for (const std::string& path : images) {
    auto read = std::make_unique<Read<StoredImage>>();
    read->read = [path] { return read_stored_image(path); };
    reads_->images.emplace_back(path, std::move(read));
  }
  for (const Obj& obj : objs) {
    auto read = std::make_unique<Read<ObjInFileSpace>>();
    read->read = [obj] { return read_obj_file(obj.path, obj.smooth_normals, obj.flip_v); };
    reads_->objs.emplace_back(obj, std::move(read));
  }
  for (const MeshFile& file : meshes) {
    auto read = std::make_unique<Read<MeshInFileSpace>>();
    read->read = [file] {
      if (file.format == MeshFile::Format::Ply) return read_ply_file(file.path);
      return MeshInFileSpace{read_serialized_mesh(file.path, file.shape_index), {}};
    };
    reads_->meshes.emplace_back(file, std::move(read));
  }
  // Images first: the loader reaches textures (declared at the top, or in the BSDFs) before
  // the shapes, and while a task decodes one the loader parses the meshes it needs first.
  for (auto& [path, read] : reads_->images) reads_->tasks.run([r = read.get()] { r->run(); });
  for (auto& [obj, read] : reads_->objs) reads_->tasks.run([r = read.get()] { r->run(); });
  for (auto& [file, read] : reads_->meshes) reads_->tasks.run([r = read.get()] { r->run(); });
  t_active = this;
}

LoadPrefetch::~LoadPrefetch() {
  // Whatever no task has begun is not read: the loader is done with the prefetch, and when it
  // ended on an error, that error should not wait for every announced mesh (a scene's first
  // shape naming a missing file waited 0.2 s for eight 20 MB PLY files). Reads under way
  // finish.
  reads_->tasks.cancel();
  reads_->tasks.wait();
  t_active = outer_;
}

std::optional<StoredImage> LoadPrefetch::stored_image(const std::string& path) {
  if (!t_active) return std::nullopt;
  for (auto& [announced, read] : t_active->reads_->images)
    if (announced == path && !read->taken) return read->take(t_active->reads_->helper());
  return std::nullopt;
}

std::optional<ObjInFileSpace> LoadPrefetch::obj(const std::string& path, bool smooth_normals,
                                                bool flip_v) {
  if (!t_active) return std::nullopt;
  for (auto& [announced, read] : t_active->reads_->objs)
    if (announced.path == path && announced.smooth_normals == smooth_normals &&
        announced.flip_v == flip_v && !read->taken)
      return read->take(t_active->reads_->helper());
  return std::nullopt;
}

std::optional<MeshInFileSpace> LoadPrefetch::mesh(const MeshFile& file) {
  if (!t_active) return std::nullopt;
  for (auto& [announced, read] : t_active->reads_->meshes)
    if (announced == file && !read->taken) return read->take(t_active->reads_->helper());
  return std::nullopt;
}

}  // namespace emlt
