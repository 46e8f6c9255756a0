#include "emlt/scene/loaders/ply_loader.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string_view>

#include "emlt/core/error.h"
#include "emlt/scene/shape_builders.h"
#include "src/scene/loaders/gzip_bytes.h"

namespace emlt {

namespace {

[[noreturn]] void fail_at(const std::string& path, const std::string& problem) {
  throw file_error(path, problem);
}

// File text quoted in a message: printable ASCII only, and short, so that a binary or
// corrupt file still gives one readable line.
std::string printable(std::string_view text) {
  std::string out = "'";
  for (const char c : text.substr(0, 40)) out += c >= 32 && c < 127 ? c : '?';
  return out + (text.size() > 40 ? "...'" : "'");
}

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<Type> parse_type(const std::string& name) {
  static const std::pair<const char*, Type> kNames[] = {
      {"char", Type::Int8},      {"int8", Type::Int8},       {"uchar", Type::UInt8},
      {"uint8", Type::UInt8},    {"short", Type::Int16},     {"int16", Type::Int16},
      {"ushort", Type::UInt16},  {"uint16", Type::UInt16},   {"int", Type::Int32},
      {"int32", Type::Int32},    {"uint", Type::UInt32},     {"uint32", Type::UInt32},
      {"float", Type::Float32},  {"float32", Type::Float32}, {"double", Type::Float64},
      {"float64", Type::Float64}};
  for (const auto& [text, type] : kNames)
    if (name == text) return type;
  return std::nullopt;
}

int size_of(Type type) {
  switch (type) {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
  }
  return 1;
}

bool is_integer(Type type) {
  return type != Type::Float32 && type != Type::Float64;
}

struct Property {
  std::string name;
  Type type = Type::Float32;  // of the items, for a list
  bool is_list = false;
  Type count_type = Type::UInt8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

// Names the item being read in error messages ("vertex 17"). Formatted only when a message
// is made: built for every item, the string took a quarter of a million-triangle load.
struct ItemName {
  const std::string& element;
  uint64_t index;
  std::string str() const { return element + " " + std::to_string(index); }
};

// The data after the header, read value by value with every read bounds-checked.
class DataReader {
 public:
  DataReader(const std::string& path, std::string_view data, Format format)
      : path_(path), data_(data), format_(format) {}

  size_t remaining() const { return data_.size() - pos_; }

  // Any scalar, as a double; `what` names the value for the truncation message.
  double number(Type type, const ItemName& what) {
    if (format_ == Format::Ascii) {
      const std::string_view text = token(what);
      double value = 0.0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec != std::errc() || end != text.data() + text.size())
        fail("cannot parse " + printable(text) + " as a number (" + what.str() + ")");
      return value;
    }
    const unsigned char* bytes = take(size_of(type), what);
    switch (type) {
      case Type::Int8:
        return double(load<int8_t>(bytes));
      case Type::UInt8:
        return double(load<uint8_t>(bytes));
      case Type::Int16:
        return double(load<int16_t>(bytes));
      case Type::UInt16:
        return double(load<uint16_t>(bytes));
      case Type::Int32:
        return double(load<int32_t>(bytes));
      case Type::UInt32:
        return double(load<uint32_t>(bytes));
      case Type::Float32:
        return double(load<float>(bytes));
      case Type::Float64:
        return load<double>(bytes);
    }
    return 0.0;
  }

  // A value of an integer type (list counts, indices): exact, and whole in ASCII.
  int64_t integer(Type type, const ItemName& what) {
    if (format_ == Format::Ascii) {
      const std::string_view text = token(what);
      int64_t value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec != std::errc() || end != text.data() + text.size())
        fail("cannot parse " + printable(text) + " as an integer (" + what.str() + ")");
      return value;
    }
    return int64_t(number(type, what));  // every integer type fits a double exactly
  }

  void skip(const Property& property, const ItemName& what) {
    if (!property.is_list) {
      skip_value(property.type, what);
      return;
    }
    const int64_t count = integer(property.count_type, what);
    if (count < 0) fail("negative list length " + std::to_string(count) + " (" + what.str() + ")");
    for (int64_t i = 0; i < count; ++i) skip_value(property.type, what);
  }

  [[noreturn]] void fail(const std::string& problem) const { throw file_error(path_, problem); }

 private:
  void skip_value(Type type, const ItemName& what) {
    if (format_ == Format::Ascii)
      token(what);
    else
      take(size_of(type), what);
  }

  // A value of the file's byte order: a plain load where it is the machine's.
  template <class T>
  T load(const unsigned char* bytes) const {
    std::array<unsigned char, sizeof(T)> raw;
    std::memcpy(raw.data(), bytes, sizeof(T));
    if ((format_ == Format::BinaryBig) != (std::endian::native == std::endian::big))
      std::reverse(raw.begin(), raw.end());
    return std::bit_cast<T>(raw);
  }

  const unsigned char* take(int n, const ItemName& what) {
    if (remaining() < size_t(n)) fail("truncated data (" + what.str() + ")");
    const auto* bytes = reinterpret_cast<const unsigned char*>(data_.data() + pos_);
    pos_ += size_t(n);
    return bytes;
  }

  // The next whitespace-separated word (line breaks are not significant).
  std::string_view token(const ItemName& what) {
    auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while (pos_ < data_.size() && space(data_[pos_])) ++pos_;
    if (pos_ == data_.size()) fail("truncated data (" + what.str() + ")");
    const size_t begin = pos_;
    while (pos_ < data_.size() && !space(data_[pos_])) ++pos_;
    return data_.substr(begin, pos_ - begin);
  }

  const std::string& path_;
  std::string_view data_;
  Format format_;
  size_t pos_ = 0;
};

// Fewest bytes one item of `element` can take, for checking counts against the file.
uint64_t min_item_bytes(const Element& element, Format format) {
  uint64_t bytes = 0;
  for (const Property& p : element.properties)
    bytes += format == Format::Ascii ? 2 : uint64_t(size_of(p.is_list ? p.count_type : p.type));
  return std::max<uint64_t>(bytes, 1);
}

int find_property(const Element& element, std::initializer_list<const char*> names) {
  for (const char* name : names)
    for (size_t i = 0; i < element.properties.size(); ++i)
      if (!element.properties[i].is_list && element.properties[i].name == name) return int(i);
  return -1;
}

// Mitsuba's PLY reader takes a vertex colour channel from a property named `red` or
// `diffuse_red` (and likewise green and blue) of type uchar (divided by 255) or float (as
// it is); a property of another type it never sees. Colours exist when a red channel does;
// a missing green or blue reads 0. Of two properties for one channel, the later in the
// vertex wins (Mitsuba's reader sets the channel once for each).
struct ColorProperties {
  std::array<int, 3> index{-1, -1, -1};  // red, green, blue; -1: none
  bool present() const { return index[0] >= 0; }
  Rgb read(const Element& vertex, const std::vector<double>& values) const {
    Rgb color(0.0f);
    for (int c = 0; c < 3; ++c) {
      if (index[size_t(c)] < 0) continue;
      const auto i = size_t(index[size_t(c)]);
      const auto value = float(values[i]);
      color[c] = vertex.properties[i].type == Type::UInt8 ? value / 255.0f : value;
    }
    return color;
  }
};

ColorProperties color_properties(const Element& vertex, const std::string& path,
                                 std::vector<std::string>& warnings) {
  static const char* const kNames[3][2] = {
      {"red", "diffuse_red"}, {"green", "diffuse_green"}, {"blue", "diffuse_blue"}};
  ColorProperties colors;
  for (size_t i = 0; i < vertex.properties.size(); ++i) {
    const Property& p = vertex.properties[i];
    for (int c = 0; c < 3; ++c) {
      if (p.is_list || (p.name != kNames[c][0] && p.name != kNames[c][1])) continue;
      if (p.type == Type::UInt8 || p.type == Type::Float32)
        colors.index[size_t(c)] = int(i);
      else
        warnings.push_back(path + ": vertex colour property '" + p.name +
                           "' ignored: Mitsuba reads colours of type uchar or float only");
    }
  }
  return colors;
}

}  // namespace

MeshDesc load_ply_mesh(const std::string& path, const Mat4& to_world,
                       std::vector<std::string>* warnings) {
  return place_ply_mesh(read_ply_file(path), to_world, warnings);
}

MeshDesc place_ply_mesh(MeshInFileSpace ply, const Mat4& to_world,
                        std::vector<std::string>* warnings) {
  if (warnings) warnings->insert(warnings->end(), ply.warnings.begin(), ply.warnings.end());
  // Mitsuba's PLY loader transforms normals by the inverse transpose but, unlike its
  // serialized loader, leaves the winding alone under a mirroring transform.
  transform_mesh(ply.mesh, to_world, false);
  return std::move(ply.mesh);
}

void decode_srgb_vertex_colors(MeshDesc& mesh) {
  const auto decode = [](float value) {
    if (value <= 0.04045f) return value / 12.92f;
    return std::pow((value + 0.055f) / 1.055f, 2.4f);
  };
  for (Rgb& color : mesh.colors) color = Rgb(decode(color.x), decode(color.y), decode(color.z));
}

MeshInFileSpace read_ply_file(const std::string& path) {
  MeshInFileSpace ply;
  MeshDesc& mesh = ply.mesh;
  std::vector<std::string>* warnings = &ply.warnings;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "PLY file not found");
  std::string bytes;
  {
    // Read whole into a string of the file's size (a stream buffer grew and copied it).
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw file_error(path, "cannot read file");
    const std::streamoff size = in.tellg();
    if (size < 0) throw file_error(path, "cannot read file");
    bytes.resize(size_t(size));
    in.seekg(0);
    if (!in.read(bytes.data(), size)) throw file_error(path, "cannot read file");
  }
  // pbrt-v4 reads gzip-compressed PLY meshes (`.ply.gz`), as several public scenes ship.
  bytes = loader::maybe_gunzip(path, std::move(bytes));

  // --- Header: lines up to "end_header" ---
  size_t pos = 0;
  auto next_line = [&](std::string& line) {
    if (pos >= bytes.size()) return false;
    const size_t end = bytes.find('\n', pos);
    line = bytes.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? bytes.size() : end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  std::string line;
  if (!next_line(line) || line != "ply")
    fail_at(path, "not a PLY file (it does not start with 'ply')");
  std::optional<Format> format;
  std::vector<Element> elements;
  bool header_done = false;
  int line_number = 1;
  while (!header_done && next_line(line)) {
    ++line_number;
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const std::string where = "header line " + std::to_string(line_number) + ": ";
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      header_done = true;
    } else if (keyword == "format") {
      std::string name, version;
      words >> name >> version;
      if (name == "ascii")
        format = Format::Ascii;
      else if (name == "binary_little_endian")
        format = Format::BinaryLittle;
      else if (name == "binary_big_endian")
        format = Format::BinaryBig;
      else
        fail_at(path, where + "unknown format " + printable(name));
      if (version != "1.0") fail_at(path, where + "unsupported PLY version " + printable(version));
    } else if (keyword == "element") {
      Element element;
      std::string count;
      words >> element.name >> count;
      const auto [end, err] =
          std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (element.name.empty() || err != std::errc() || end != count.data() + count.size())
        fail_at(path, where + "malformed element declaration " + printable(line));
      elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (elements.empty()) fail_at(path, where + "property declared before any element");
      Property property;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type;
        words >> count_type >> type;
        const auto parsed = parse_type(count_type);
        if (!parsed || !is_integer(*parsed))
          fail_at(path,
                  where + "list length type " + printable(count_type) + " is not an integer type");
        property.is_list = true;
        property.count_type = *parsed;
      }
      const auto parsed = parse_type(type);
      if (!parsed) fail_at(path, where + "unknown property type " + printable(type));
      property.type = *parsed;
      words >> property.name;
      if (property.name.empty()) fail_at(path, where + "property without a name");
      elements.back().properties.push_back(property);
    } else {
      fail_at(path, where + "unknown header keyword " + printable(keyword));
    }
  }
  if (!header_done) fail_at(path, "truncated header (no 'end_header')");
  if (!format) fail_at(path, "header has no 'format' line");

  // Counts the remaining bytes cannot hold are refused before anything is allocated.
  const uint64_t data_bytes = bytes.size() - pos;
  uint64_t needed = 0;
  for (const Element& element : elements) {
    const uint64_t item = min_item_bytes(element, *format);
    if (element.count > data_bytes / item || needed + element.count * item > data_bytes + 1)
      fail_at(path, "header claims " + std::to_string(element.count) + " " + element.name +
                        " elements, more than the file's " + std::to_string(data_bytes) +
                        " data bytes can hold");
    needed += element.count * item;
  }

  const Element* vertex = nullptr;
  for (const Element& element : elements)
    if (element.name == "vertex" && !vertex) vertex = &element;
  if (!vertex) fail_at(path, "no vertex element");
  const int x = find_property(*vertex, {"x"}), y = find_property(*vertex, {"y"}),
            z = find_property(*vertex, {"z"});
  if (x < 0 || y < 0 || z < 0) fail_at(path, "vertex element lacks x, y or z");
  const int nx = find_property(*vertex, {"nx"}), ny = find_property(*vertex, {"ny"}),
            nz = find_property(*vertex, {"nz"});
  const int u = find_property(*vertex, {"u", "s", "texture_u"}),
            v = find_property(*vertex, {"v", "t", "texture_v"});
  const bool has_normals = nx >= 0 && ny >= 0 && nz >= 0, has_uvs = u >= 0 && v >= 0;
  const ColorProperties colors = color_properties(*vertex, path, *warnings);
  if (vertex->count > UINT32_MAX) fail_at(path, "more vertices than 32-bit indices can address");

  mesh.name = std::filesystem::path(path).filename().string();
  DataReader data(path, std::string_view(bytes).substr(pos), *format);
  size_t short_faces = 0;
  bool has_face_list = false;
  for (const Element& element : elements) {
    const bool is_vertex = &element == vertex;
    int face_list = -1;
    if (element.name == "face")
      for (size_t i = 0; i < element.properties.size(); ++i)
        if (element.properties[i].is_list && (element.properties[i].name == "vertex_indices" ||
                                              element.properties[i].name == "vertex_index")) {
          face_list = int(i);
          break;
        }
    if (face_list >= 0) {
      if (!is_integer(element.properties[size_t(face_list)].type))
        fail_at(path, "face indices are not of an integer type");
      has_face_list = true;
      mesh.indices.reserve(size_t(std::min<uint64_t>(element.count * 3, 3 << 20)));
    }
    if (is_vertex) {
      mesh.positions.reserve(size_t(vertex->count));
      if (has_normals) mesh.normals.reserve(size_t(vertex->count));
      if (has_uvs) mesh.uvs.reserve(size_t(vertex->count));
      if (colors.present()) mesh.colors.reserve(size_t(vertex->count));
    }
    std::vector<double> values(element.properties.size(), 0.0);
    for (uint64_t item = 0; item < element.count; ++item) {
      const ItemName what{element.name, item};
      if (is_vertex) {
        for (size_t i = 0; i < element.properties.size(); ++i) {
          const Property& p = element.properties[i];
          if (p.is_list)
            data.skip(p, what);
          else
            values[i] = data.number(p.type, what);
        }
        mesh.positions.push_back(
            Vec3(float(values[size_t(x)]), float(values[size_t(y)]), float(values[size_t(z)])));
        if (has_normals)
          mesh.normals.push_back(Vec3(float(values[size_t(nx)]), float(values[size_t(ny)]),
                                      float(values[size_t(nz)])));
        if (has_uvs) mesh.uvs.push_back(Vec2(float(values[size_t(u)]), float(values[size_t(v)])));
        if (colors.present()) mesh.colors.push_back(colors.read(*vertex, values));
        continue;
      }
      for (size_t i = 0; i < element.properties.size(); ++i) {
        const Property& p = element.properties[i];
        if (int(i) != face_list) {
          data.skip(p, what);
          continue;
        }
        const int64_t n = data.integer(p.count_type, what);
        if (n < 0)
          fail_at(path, "negative list length " + std::to_string(n) + " (" + what.str() + ")");
        // Fan triangulation needs only the first and the previous corner.
        uint32_t first = 0, previous = 0;
        for (int64_t k = 0; k < n; ++k) {
          const int64_t index = data.integer(p.type, what);
          if (index < 0 || uint64_t(index) >= vertex->count)
            fail_at(path, what.str() + " uses vertex " + std::to_string(index) +
                              ", out of range (" + std::to_string(vertex->count) + " vertices)");
          const auto corner = uint32_t(index);
          if (k == 0)
            first = corner;
          else if (k >= 2)
            mesh.indices.insert(mesh.indices.end(), {first, previous, corner});
          previous = corner;
        }
        if (n < 3) ++short_faces;
      }
    }
  }
  if (!has_face_list) fail_at(path, "no face element with a vertex_indices list");
  if (mesh.indices.empty()) fail_at(path, "no faces with three or more vertices");
  if (short_faces > 0)
    warnings->push_back(path + ": " + std::to_string(short_faces) +
                        " faces with fewer than three vertices skipped");
  return ply;
}

}  // namespace emlt
