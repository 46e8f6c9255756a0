#pragma once
// Reading a scene's files ahead, in parallel. A scene file names its meshes and textures
// long before the loader, which reads elements one after another, reaches them; decoding
// them one at a time left the other cores idle for most of the loading (the public Veach
// door: 22 OBJ files and 7 images). A LoadPrefetch announced at the start reads the files
// in TBB tasks while the loader goes on; the loader then takes each result where it used
// to read the file. Whoever comes first reads it (the loader itself when no task has
// started it yet), so nothing waits on a queue, and the result is the very one the direct
// read gives: its errors are thrown where the loader takes it, in the file's order.
//
// The prefetch is active on the thread that created it until it is destroyed; a file
// that was not announced (or is taken a second way) is read directly as before.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emlt/image/image.h"
#include "emlt/scene/loaders/obj_loader.h"
#include "emlt/scene/loaders/ply_loader.h"

namespace emlt {

class LoadPrefetch {
 public:
  struct Obj {
    std::string path;
    bool smooth_normals = true, flip_v = true;
  };
  // One mesh of a PLY file (shape_index unused) or of a serialized file.
  struct MeshFile {
    enum class Format { Ply, Serialized } format = Format::Ply;
    std::string path;
    int shape_index = 0;
    bool operator==(const MeshFile&) const = default;
  };
  // Starts reading: 8-bit images (as read_stored_image reads them), OBJ, PLY and serialized
  // meshes (in the file's own space: read_obj_file, read_ply_file, read_serialized_mesh).
  LoadPrefetch(const std::vector<std::string>& images, const std::vector<Obj>& objs,
               const std::vector<MeshFile>& meshes = {});
  ~LoadPrefetch();  // skips the reads not begun, waits for those under way
  LoadPrefetch(const LoadPrefetch&) = delete;
  LoadPrefetch& operator=(const LoadPrefetch&) = delete;

  // The announced file's contents from the active prefetch of this thread: read now if no
  // task has begun it, waited for if one has. nullopt when nothing announced it.
  static std::optional<StoredImage> stored_image(const std::string& path);
  static std::optional<ObjInFileSpace> obj(const std::string& path, bool smooth_normals,
                                           bool flip_v);
  // A serialized mesh comes with no warnings.
  static std::optional<MeshInFileSpace> mesh(const MeshFile& file);

 private:
  struct Reads;
  std::unique_ptr<Reads> reads_;
  LoadPrefetch* outer_;  // the prefetch active before this one on this thread
};

}  // namespace emlt
