#include "emlt/scene/loaders/serialized_loader.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "emlt/core/error.h"
#include "emlt/scene/shape_builders.h"

namespace emlt {

namespace {

constexpr uint16_t kMagic = 0x041C;
constexpr uint32_t kHasNormals = 0x0001, kHasTexcoords = 0x0002, kHasColors = 0x0008,
                   kDoublePrecision = 0x2000;
// zlib cannot expand data by more than about 1032:1, which bounds what counts a mesh may
// claim before anything is allocated for them.
constexpr uint64_t kMaxInflateRatio = 1032;

// The format is little endian whatever the host; values are assembled byte by byte.
uint64_t little_endian(const unsigned char* bytes, int size) {
  uint64_t value = 0;
  for (int i = 0; i < size; ++i) value |= uint64_t(bytes[i]) << (8 * i);
  return value;
}

float decode_real(const unsigned char* bytes, int size) {
  if (size == 8) return float(std::bit_cast<double>(little_endian(bytes, 8)));
  return std::bit_cast<float>(uint32_t(little_endian(bytes, 4)));
}

class SerializedFile {
 public:
  explicit SerializedFile(const std::string& path) : path_(path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw file_error(path, "serialized mesh file not found");
    size_ = std::filesystem::file_size(path, ec);
    if (ec) throw file_error(path, "cannot read file");
    in_.open(path, std::ios::binary);
    if (!in_) throw file_error(path, "cannot read file");
  }

  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }
  std::ifstream& stream() { return in_; }

  [[noreturn]] void fail(const std::string& problem) const { throw file_error(path_, problem); }

  void read(uint64_t offset, unsigned char* out, size_t n, const std::string& what) {
    if (offset > size_ || n > size_ - offset) fail("truncated file (" + what + " missing)");
    in_.clear();
    in_.seekg(std::streamoff(offset));
    in_.read(reinterpret_cast<char*>(out), std::streamsize(n));
    if (in_.gcount() != std::streamsize(n)) fail("read error (" + what + ")");
  }

  // The 4-byte header: magic and format version (3 or 4).
  int read_header(uint64_t offset, const std::string& where) {
    unsigned char bytes[4];
    read(offset, bytes, 4, where + "header");
    const auto magic = uint16_t(little_endian(bytes, 2));
    const auto version = uint16_t(little_endian(bytes + 2, 2));
    if (magic == 0x1C04)
      fail(where + "byte-swapped header: written by an old Mitsuba version; re-export it");
    if (magic != kMagic) {
      char text[8];
      std::snprintf(text, sizeof text, "%04X", magic);
      fail(where + "not a Mitsuba serialized mesh (header 0x" + text + ", expected 0x041C)");
    }
    if (version != 3 && version != 4)
      fail(where + "unsupported serialized format version " + std::to_string(version) +
           " (3 and 4 are known)");
    return version;
  }

 private:
  std::string path_;
  uint64_t size_ = 0;
  std::ifstream in_;
};

// Reads the zlib stream stored in [begin, end) of the file, through a buffer.
class InflateReader {
 public:
  InflateReader(SerializedFile& file, uint64_t begin, uint64_t end, std::string where)
      : file_(file),
        next_(begin),
        end_(end),
        where_(std::move(where)),
        input_(1 << 16),
        output_(1 << 18) {
    if (inflateInit(&stream_) != Z_OK) file_.fail(where_ + "cannot initialise zlib");
  }
  ~InflateReader() { inflateEnd(&stream_); }
  InflateReader(const InflateReader&) = delete;
  InflateReader& operator=(const InflateReader&) = delete;

  // Inflates the rest of the stream, which checks its Adler-32 checksum (trailing data
  // after the mesh is allowed and ignored).
  void finish() {
    while (!finished_) refill("end of the compressed stream");
  }

  void read(unsigned char* out, size_t n, const char* what) {
    while (n > 0) {
      if (out_pos_ == out_end_) refill(what);
      const size_t take = std::min(n, out_end_ - out_pos_);
      std::copy_n(output_.data() + out_pos_, take, out);
      out_pos_ += take;
      out += take;
      n -= take;
    }
  }

 private:
  void refill(const char* what) {
    out_pos_ = out_end_ = 0;
    if (finished_)
      file_.fail(where_ + "truncated mesh data (" + what +
                 " missing after the end of the compressed stream)");
    while (out_end_ == 0 && !finished_) {
      if (stream_.avail_in == 0) {
        if (next_ >= end_) file_.fail(where_ + "truncated compressed data (" + what + " missing)");
        const auto n = size_t(std::min<uint64_t>(input_.size(), end_ - next_));
        file_.read(next_, input_.data(), n, "compressed data");
        next_ += n;
        stream_.next_in = input_.data();
        stream_.avail_in = uInt(n);
      }
      stream_.next_out = output_.data();
      stream_.avail_out = uInt(output_.size());
      const int rc = inflate(&stream_, Z_NO_FLUSH);
      out_end_ = output_.size() - stream_.avail_out;
      if (rc == Z_STREAM_END) {
        finished_ = true;
      } else if (rc == Z_NEED_DICT) {
        file_.fail(where_ + "corrupt compressed data (zlib wants a preset dictionary)");
      } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
        file_.fail(where_ + "corrupt compressed data (zlib: " +
                   (stream_.msg ? stream_.msg : "error " + std::to_string(rc)) + ")");
      }
    }
  }

  SerializedFile& file_;
  uint64_t next_, end_;
  std::string where_;
  z_stream stream_{};
  std::vector<unsigned char> input_, output_;
  size_t out_pos_ = 0, out_end_ = 0;
  bool finished_ = false;
};

// `count` reals of `size` bytes; the vector grows as data actually arrives, so a lying
// count fails on truncated data before it can allocate much.
std::vector<float> read_reals(InflateReader& in, uint64_t count, int size, const char* what) {
  std::vector<float> values;
  values.reserve(size_t(std::min<uint64_t>(count, 1 << 20)));
  unsigned char chunk[1 << 15];
  const uint64_t per_chunk = sizeof chunk / size_t(size);
  for (uint64_t done = 0; done < count;) {
    const uint64_t n = std::min(per_chunk, count - done);
    in.read(chunk, size_t(n) * size_t(size), what);
    for (uint64_t i = 0; i < n; ++i) values.push_back(decode_real(chunk + i * size_t(size), size));
    done += n;
  }
  return values;
}

}  // namespace

MeshDesc load_serialized_mesh(const std::string& path, int shape_index, const Mat4& to_world) {
  return place_serialized_mesh(read_serialized_mesh(path, shape_index), to_world);
}

MeshDesc place_serialized_mesh(MeshDesc mesh, const Mat4& to_world) {
  transform_mesh(mesh, to_world, true);  // a mirroring transform keeps the facing
  return mesh;
}

MeshDesc read_serialized_mesh(const std::string& path, int shape_index) {
  SerializedFile file(path);
  if (file.size() < 4) file.fail("not a Mitsuba serialized mesh (file too short)");
  const int version = file.read_header(0, "");
  if (shape_index < 0) file.fail("shapeIndex must be >= 0");

  // The offset dictionary: one offset per mesh (uint64 in v4, uint32 in v3), then the
  // mesh count as uint32 at the very end. A file without one (its last bytes are then the
  // zlib checksum) holds a single mesh at offset 0. Mitsuba takes the dictionary as valid
  // when the file is long enough for `count` meshes of one triangle, measured
  // uncompressed; tiny files fail that, so a dictionary that fits and starts with offset 0
  // (as every exporter writes it) is accepted too.
  const uint64_t entry = version == 4 ? 8 : 4;
  unsigned char bytes[8];
  file.read(file.size() - 4, bytes, 4, "mesh count");
  const uint64_t count = little_endian(bytes, 4);
  const uint64_t min_mesh = 4 + 4 + 1 + 16 + 12 + 12;
  bool has_dictionary = count > 0 && 4 + count * min_mesh <= file.size();
  if (!has_dictionary && count > 0 && 8 + count * entry <= file.size()) {
    file.read(file.size() - 4 - count * entry, bytes, size_t(entry), "offset dictionary");
    has_dictionary = little_endian(bytes, int(entry)) == 0;
  }
  std::vector<uint64_t> offsets{0};
  uint64_t data_end = file.size();
  if (has_dictionary) {
    data_end = file.size() - 4 - count * entry;
    offsets.resize(size_t(count));
    std::vector<unsigned char> table(size_t(count * entry));
    file.read(data_end, table.data(), table.size(), "offset dictionary");
    for (size_t i = 0; i < offsets.size(); ++i)
      offsets[i] = little_endian(table.data() + i * entry, int(entry));
  }
  if (uint64_t(shape_index) >= offsets.size())
    file.fail("shapeIndex " + std::to_string(shape_index) + " out of range (the file holds " +
              std::to_string(offsets.size()) + (offsets.size() == 1 ? " mesh)" : " meshes)"));

  const std::string where =
      offsets.size() > 1 ? "mesh " + std::to_string(shape_index) + ": " : std::string();
  const uint64_t offset = offsets[size_t(shape_index)];
  if (offset >= data_end || data_end - offset < 4)
    file.fail(where + "offset " + std::to_string(offset) + " in the dictionary lies outside the " +
              "mesh data");
  file.read_header(offset, where);
  // The mesh's compressed bytes end where the next mesh (or the dictionary) begins.
  uint64_t end = data_end;
  for (const uint64_t other : offsets)
    if (other > offset && other < end) end = other;
  const uint64_t compressed = end - (offset + 4);
  InflateReader in(file, offset + 4, end, where);

  in.read(bytes, 4, "flags");
  const auto flags = uint32_t(little_endian(bytes, 4));
  std::string name;
  if (version == 4) {
    // Zero-terminated; bounded so a corrupt stream cannot grow it without end.
    for (unsigned char c = 0;;) {
      in.read(&c, 1, "mesh name");
      if (c == 0) break;
      if (name.size() >= 4096) file.fail(where + "mesh name is not terminated");
      name += c >= 32 && c < 127 ? char(c) : '?';  // it appears in messages
    }
  }
  in.read(bytes, 8, "vertex count");
  const uint64_t vertex_count = little_endian(bytes, 8);
  in.read(bytes, 8, "triangle count");
  const uint64_t triangle_count = little_endian(bytes, 8);

  const int real = flags & kDoublePrecision ? 8 : 4;
  const uint64_t reals_per_vertex = 3 + (flags & kHasNormals ? 3 : 0) +
                                    (flags & kHasTexcoords ? 2 : 0) + (flags & kHasColors ? 3 : 0);
  const std::string counts = std::to_string(vertex_count) + " vertices and " +
                             std::to_string(triangle_count) + " triangles";
  if (vertex_count > UINT32_MAX || triangle_count > (uint64_t(1) << 40) ||
      vertex_count * reals_per_vertex * uint64_t(real) + triangle_count * 12 >
          compressed * kMaxInflateRatio + 1024)
    file.fail(where + "header claims " + counts + ", more than the file's " +
              std::to_string(compressed) + " compressed bytes can hold");

  const std::vector<float> positions = read_reals(in, vertex_count * 3, real, "positions");
  std::vector<float> normals, uvs, colors;
  if (flags & kHasNormals) normals = read_reals(in, vertex_count * 3, real, "normals");
  if (flags & kHasTexcoords) uvs = read_reals(in, vertex_count * 2, real, "texture coordinates");
  // Linear RGB as stored (no sRGB curve: Mitsuba reads them as they are).
  if (flags & kHasColors) colors = read_reals(in, vertex_count * 3, real, "vertex colours");

  MeshDesc mesh;
  mesh.name = std::filesystem::path(path).filename().string() + "@" + std::to_string(shape_index);
  if (!name.empty()) mesh.name += " '" + name + "'";
  mesh.positions.reserve(size_t(vertex_count));
  for (size_t v = 0; v < size_t(vertex_count); ++v) {
    mesh.positions.push_back(Vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
    if (!normals.empty())
      mesh.normals.push_back(Vec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]));
    if (!uvs.empty()) mesh.uvs.push_back(Vec2(uvs[2 * v], uvs[2 * v + 1]));
    if (!colors.empty())
      mesh.colors.push_back(Rgb(colors[3 * v], colors[3 * v + 1], colors[3 * v + 2]));
  }

  mesh.indices.reserve(size_t(std::min<uint64_t>(triangle_count * 3, 3 << 20)));
  unsigned char chunk[3 * 4 * 1024];
  for (uint64_t done = 0; done < triangle_count;) {
    const uint64_t n = std::min<uint64_t>(1024, triangle_count - done);
    in.read(chunk, size_t(n) * 12, "triangles");
    for (size_t i = 0; i < size_t(n) * 3; ++i) {
      const auto index = uint32_t(little_endian(chunk + 4 * i, 4));
      if (index >= vertex_count)
        file.fail(where + "triangle " + std::to_string(done + i / 3) + " uses vertex " +
                  std::to_string(index) + ", out of range (" + std::to_string(vertex_count) +
                  " vertices)");
      mesh.indices.push_back(index);
    }
    done += n;
  }

  in.finish();
  return mesh;
}

}  // namespace emlt
