// Image reading and writing by file extension. Every format decodes to linear float RGB
// with row 0 at the top; every write goes through a temporary file that is renamed into
// place only once it is complete.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <stdexcept>

#include "emlt/core/atomic_write.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/image/image.h"
#include "src/image/image_file.h"
#include "src/image/jpeg_reader.h"
#include "src/image/png_reader.h"

namespace emlt {

namespace fs = std::filesystem;

namespace {

enum class Format { Exr, Hdr, Pfm, Png, Jpeg, Unknown };

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

Format format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr") return Format::Exr;
  if (ext == ".hdr") return Format::Hdr;
  if (ext == ".pfm") return Format::Pfm;
  if (ext == ".png") return Format::Png;
  if (ext == ".jpg" || ext == ".jpeg") return Format::Jpeg;
  return Format::Unknown;
}

Error unknown_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  return file_error(path, "unsupported image format '" + (ext.empty() ? "(none)" : ext) +
                              "' (expected .exr, .hdr, .pfm or .png)");
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// ---- OpenEXR ---------------------------------------------------------------------------

// Finds a channel by its base name, with or without a layer prefix ("R" or "diffuse.R"),
// preferring the unlayered one.
const char* find_channel(const Imf::ChannelList& channels, const char* name) {
  if (channels.findChannel(name)) return name;
  for (auto it = channels.begin(); it != channels.end(); ++it) {
    const std::string full = it.name();
    const size_t dot = full.rfind('.');
    if (dot != std::string::npos && full.compare(dot + 1, std::string::npos, name) == 0) {
      return it.name();
    }
  }
  return nullptr;
}

Image read_exr(const std::string& path) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i window = file.header().dataWindow();
  const int64_t width = int64_t(window.max.x) - window.min.x + 1;
  const int64_t height = int64_t(window.max.y) - window.min.y + 1;
  check_image_size(path, width, height);

  const Imf::ChannelList& channels = file.header().channels();
  const char* r = find_channel(channels, "R");
  const char* g = find_channel(channels, "G");
  const char* b = find_channel(channels, "B");
  const char* y = find_channel(channels, "Y");
  if (!r && !g && !b && !y) throw file_error(path, "has no R, G, B or Y channel");

  Image image{int(width), int(height)};
  std::vector<float> luminance_plane;
  Imf::FrameBuffer frame;
  auto* base = reinterpret_cast<char*>(image.pixels.data());
  if (r || g || b) {
    // Channels that are absent read as zero (the slice fill value).
    const char* names[3] = {r ? r : "R", g ? g : "G", b ? b : "B"};
    for (int c = 0; c < 3; ++c) {
      frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, base + c * sizeof(float), window,
                                              sizeof(Rgb), sizeof(Rgb) * size_t(width)));
    }
  } else {
    luminance_plane.resize(size_t(width * height));
    frame.insert(y, Imf::Slice::Make(Imf::FLOAT, luminance_plane.data(), window, sizeof(float),
                                     sizeof(float) * size_t(width)));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  if (!luminance_plane.empty()) {
    for (size_t i = 0; i < luminance_plane.size(); ++i) image.pixels[i] = Rgb(luminance_plane[i]);
  }
  return image;
}

void write_exr(const std::string& path, const Image& image) {
  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  Imf::OutputFile file(path.c_str(), header);
  Imf::FrameBuffer frame;
  // The library only reads through these pointers when writing.
  auto* base = reinterpret_cast<char*>(const_cast<Rgb*>(image.pixels.data()));
  const size_t row_stride = sizeof(Rgb) * size_t(image.width);
  frame.insert("R", Imf::Slice(Imf::FLOAT, base, sizeof(Rgb), row_stride));
  frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), sizeof(Rgb), row_stride));
  frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), sizeof(Rgb), row_stride));
  file.setFrameBuffer(frame);
  file.writePixels(image.height);
}

// ---- PFM (Portable Float Map) ------------------------------------------------------------
// Header "PF" (RGB) or "Pf" (grey), "width height", then a scale whose sign gives the byte
// order (negative = little-endian). Rows are stored bottom to top.

uint32_t byte_swap(uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

Image read_pfm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open file");
  std::string magic;
  long long width = 0, height = 0;
  double scale = 0.0;
  in >> magic >> width >> height >> scale;
  if (!in || (magic != "PF" && magic != "Pf")) throw file_error(path, "not a PFM file");
  check_image_size(path, width, height);
  if (scale == 0.0 || !std::isfinite(scale)) throw file_error(path, "malformed PFM scale");
  in.get();  // the single whitespace byte that ends the header

  const int channels = magic == "PF" ? 3 : 1;
  // Check the size before allocating, so a corrupt header cannot ask for gigabytes.
  const std::streamoff data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff data_bytes = in.tellg() - data_start;
  in.seekg(data_start);
  if (data_bytes < std::streamoff(width * height * channels * 4)) {
    throw file_error(path, "truncated PFM data");
  }
  std::vector<uint32_t> raw(size_t(width * height * channels));
  in.read(reinterpret_cast<char*>(raw.data()), std::streamsize(raw.size() * sizeof(uint32_t)));
  if (in.gcount() != std::streamsize(raw.size() * sizeof(uint32_t))) {
    throw file_error(path, "truncated PFM data");
  }
  const bool file_little_endian = scale < 0.0;
  const bool host_little_endian = std::endian::native == std::endian::little;
  if (file_little_endian != host_little_endian) {
    for (uint32_t& v : raw) v = byte_swap(v);
  }

  Image image{int(width), int(height)};
  for (int y = 0; y < image.height; ++y) {
    const size_t file_row = size_t(image.height - 1 - y);
    for (int x = 0; x < image.width; ++x) {
      const size_t at = (file_row * size_t(width) + size_t(x)) * channels;
      Rgb value;
      for (int c = 0; c < 3; ++c) {
        value[c] = std::bit_cast<float>(raw[at + (channels == 3 ? c : 0)]);
      }
      image.at(x, y) = value;
    }
  }
  return image;
}

// Writers below throw WriteFailure with the problem only; write_atomically names the
// target path (not the temporary) in the emlt::Error it raises.
struct WriteFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void write_pfm(const std::string& path, const Image& image) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw WriteFailure("cannot create the file (does the directory exist?)");
  const bool little = std::endian::native == std::endian::little;
  out << "PF\n" << image.width << ' ' << image.height << '\n' << (little ? "-1.0" : "1.0") << '\n';
  for (int y = image.height - 1; y >= 0; --y) {
    out.write(reinterpret_cast<const char*>(&image.at(0, y)),
              std::streamsize(sizeof(Rgb) * size_t(image.width)));
  }
  out.flush();
  if (!out) throw WriteFailure("write failed");
}

// ---- Radiance .hdr (stb) ----------------------------------------------------------------

// stb's reason for a failed decode; Debian's build may leave it empty.
std::string stb_failure() {
  const char* why = stbi_failure_reason();
  return why && *why ? std::string(why) : std::string("corrupt or truncated data");
}

// The size from the header alone (stbi_info decodes no pixels); a header stb cannot read
// is left to the decoder, which says why.
void check_stb_image_size(const std::string& path) {
  int width = 0, height = 0, components = 0;
  if (stbi_info(path.c_str(), &width, &height, &components)) check_image_size(path, width, height);
}

// stb's Radiance decoder (Debian's 2.27) loops forever on a run-length scanline holding
// a zero count, and reads past the end of the data as zeros. So the pixel data is walked
// here first, exactly as stb will walk it: a zero count or data that ends early is an
// error before stb sees the file; whatever stb itself refuses is left to it.
void check_hdr_data(const std::string& path, int64_t width, int64_t height) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto byte = [&](size_t at) { return unsigned(static_cast<unsigned char>(bytes[at])); };
  // The header as stb reads it (stbi__hdr_gettoken): the magic line, lines up to one that
  // is empty or starts with a NUL, then the resolution line; lines are cut at 1023 bytes.
  size_t pos = 0;
  const auto read_line = [&]() -> unsigned {  // the line's first byte, 0 when empty
    const auto get8 = [&]() -> unsigned { return pos < bytes.size() ? byte(pos++) : 0u; };
    size_t length = 0;
    unsigned first = 0, c = get8();
    while (pos < bytes.size() && c != '\n') {
      if (length++ == 0) first = c;
      if (length == 1023) {
        while (pos < bytes.size() && get8() != '\n') {
        }
        break;
      }
      c = get8();
    }
    return first;
  };
  read_line();
  while (read_line() != 0) {
  }
  read_line();
  const Error truncated = file_error(path, "truncated or corrupt Radiance HDR pixel data");
  // Flat (uncompressed) RGBE from `pos` on, `texels` of them.
  const auto check_flat = [&](int64_t texels) {
    if (int64_t(bytes.size() - pos) < 4 * texels) throw truncated;
  };
  if (width < 8 || width >= 32768) return check_flat(width * height);
  for (int64_t y = 0; y < height; ++y) {
    if (pos + 4 > bytes.size()) throw truncated;
    if (byte(pos) != 2 || byte(pos + 1) != 2 || (byte(pos + 2) & 0x80)) {
      return check_flat(width * height);  // stb decodes the whole image flat from here
    }
    if (int64_t(byte(pos + 2) << 8 | byte(pos + 3)) != width) return;  // stb refuses it
    pos += 4;
    for (int channel = 0; channel < 4; ++channel) {
      for (int64_t x = 0; x < width;) {
        if (pos >= bytes.size()) throw truncated;
        unsigned count = byte(pos++);
        if (count > 128) {  // a run: one value
          count -= 128;
          if (pos >= bytes.size()) throw truncated;
          ++pos;
        } else {  // literal values
          if (count == 0) throw file_error(path, "corrupt Radiance HDR run-length data");
          if (count <= width - x && pos + count > bytes.size()) throw truncated;
          pos += count;
        }
        if (count > width - x) return;  // stb refuses it
        x += count;
      }
    }
  }
}

// stb decodes whatever format it recognises in the bytes, whatever the extension (a .png
// that was a headerless TGA claiming 18505 x 21060 texels in 24 bytes, when stb read PNG),
// so the file must start with the Radiance signature.
void check_hdr_signature(const std::string& path) {
  char head[2] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(head, sizeof(head));
  if (in.gcount() != 2 || head[0] != '#' || head[1] != '?')
    throw file_error(path, "not a Radiance HDR file");
}

Image read_hdr(const std::string& path) {
  check_hdr_signature(path);
  check_stb_image_size(path);
  {
    int width = 0, height = 0, components = 0;
    if (stbi_info(path.c_str(), &width, &height, &components)) {
      check_hdr_data(path, width, height);
    }
  }
  int width = 0, height = 0, components = 0;
  float* data = stbi_loadf(path.c_str(), &width, &height, &components, 3);
  if (!data) {
    throw file_error(path, "cannot decode Radiance HDR (" + stb_failure() + ")");
  }
  Image image(width, height);
  std::memcpy(image.pixels.data(), data, sizeof(float) * 3 * size_t(width) * size_t(height));
  stbi_image_free(data);
  return image;
}

// ---- PNG and JPEG (libpng, libjpeg: png_reader.cpp, jpeg_reader.cpp) --------------------

StoredImage read_stored_bytes(const std::string& path) {
  return format_of(path) == Format::Jpeg ? read_jpeg(path) : read_png(path);
}

void write_hdr(const std::string& path, const Image& image) {
  if (!stbi_write_hdr(path.c_str(), image.width, image.height, 3,
                      reinterpret_cast<const float*>(image.pixels.data()))) {
    throw WriteFailure("cannot write Radiance HDR (does the directory exist?)");
  }
}

void write_png(const std::string& path, const Image& image) {
  const std::vector<unsigned char> bytes = to_srgb8(image);
  if (!stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(), image.width * 3)) {
    throw WriteFailure("cannot write PNG (does the directory exist?)");
  }
}

}  // namespace

namespace {

// What every read checks first: a known extension and a file (not a folder) there.
Format check_readable(const std::string& path) {
  const Format format = format_of(path);
  if (format == Format::Unknown) throw unknown_format(path);
  std::error_code error;
  if (!fs::exists(path, error)) throw file_error(path, "file not found");
  if (fs::is_directory(path, error)) throw file_error(path, "is a directory, not an image");
  return format;
}

}  // namespace

float decode_gamma(float value, float gamma) {
  if (gamma == kSrgbGamma) return srgb_to_linear(value);
  if (gamma == 1.0f) return value;
  return value > 0.0f ? std::pow(value, gamma) : 0.0f;
}

std::array<float, 256> levels8(float gamma) {
  std::array<float, 256> table{};
  for (int i = 0; i < 256; ++i) table[size_t(i)] = decode_gamma(float(i) / 255.0f, gamma);
  return table;
}

const std::array<float, 256>& srgb8_levels() {
  static const std::array<float, 256> levels = levels8(kSrgbGamma);
  return levels;
}

StoredImage select_channel(StoredImage image, const std::string& channel, const std::string& path) {
  std::string wanted = channel;
  for (char& c : wanted) c = char(std::tolower(static_cast<unsigned char>(c)));
  const size_t index = wanted.size() == 1 ? image.channels.find(wanted[0]) : std::string::npos;
  if (index == std::string::npos) {
    std::string names;
    for (char c : image.channels) names += (names.empty() ? "" : ", ") + std::string(1, c);
    throw file_error(path, "has no channel '" + channel + "' (its channels: " + names + ")");
  }
  const bool alpha = image.channels[index] == 'a';
  // Grey files ("l", "ya") hold their value in every colour sample.
  const size_t colour = image.channels.size() <= 2 ? 0 : index;
  const auto pick = [&](auto& samples, const auto& alpha_samples) {
    for (size_t i = 0; i < samples.size(); i += 3) {
      const auto value = alpha ? alpha_samples[i / 3] : samples[i + colour];
      samples[i] = samples[i + 1] = samples[i + 2] = value;
    }
  };
  if (image.words.empty())
    pick(image.bytes, image.alpha_bytes);
  else
    pick(image.words, image.alpha_words);
  if (alpha) image.gamma = 1.0f;  // Mitsuba: an alpha channel is linear
  image.channels = std::string(1, image.channels[index]);
  image.alpha_bytes.clear(), image.alpha_words.clear();
  return image;
}

Image decode_stored_image(const StoredImage& stored, float gamma) {
  Image image(stored.width, stored.height);
  float* out = reinterpret_cast<float*>(image.pixels.data());
  if (stored.words.empty()) {
    const std::array<float, 256> to_linear = levels8(gamma);
    for (size_t i = 0; i < stored.bytes.size(); ++i) out[i] = to_linear[stored.bytes[i]];
  } else {
    for (size_t i = 0; i < stored.words.size(); ++i)
      out[i] = decode_gamma(float(stored.words[i]) / 65535.0f, gamma);
  }
  return image;
}

bool is_stored_image(const std::string& path) {
  const Format format = format_of(path);
  return format == Format::Png || format == Format::Jpeg;
}

StoredImage read_stored_image(const std::string& path) {
  if (!is_stored_image(path)) throw file_error(path, "not a PNG or JPEG file (.png, .jpg)");
  check_readable(path);
  StoredImage image;
  try {
    image = read_stored_bytes(path);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // allocation failures
    throw file_error(path, std::string("cannot read image: ") + e.what());
  }
  if (image.width <= 0 || image.height <= 0 || (image.bytes.empty() && image.words.empty()))
    throw file_error(path, "image has zero size");
  return image;
}

Image read_image(const std::string& path) {
  const Format format = check_readable(path);

  Image image;
  try {
    switch (format) {
      case Format::Exr:
        image = read_exr(path);
        break;
      case Format::Hdr:
        image = read_hdr(path);
        break;
      case Format::Pfm:
        image = read_pfm(path);
        break;
      case Format::Png:
      case Format::Jpeg: {
        const StoredImage stored = read_stored_bytes(path);
        image = decode_stored_image(stored, stored.gamma);
        break;
      }
      case Format::Unknown:
        break;
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // OpenEXR (Iex) and allocation failures
    throw file_error(path, std::string("cannot read image: ") + e.what());
  }
  if (image.width <= 0 || image.height <= 0 || image.pixels.empty()) {
    throw file_error(path, "image has zero size");
  }
  for (const Rgb& texel : image.pixels) {
    if (!is_finite(texel)) throw file_error(path, "contains NaN or infinite texels");
  }
  return image;
}

void write_image(const std::string& path, const Image& image) {
  const Format format = format_of(path);
  if (format == Format::Unknown || format == Format::Jpeg) throw unknown_format(path);
  if (image.width <= 0 || image.height <= 0) throw file_error(path, "cannot write an empty image");
  if (image.pixels.size() != size_t(image.width) * size_t(image.height)) {
    throw file_error(path, "image size does not match its pixel count");
  }
  write_atomically(path, "image", [&](const std::string& target) {
    switch (format) {
      case Format::Exr:
        write_exr(target, image);
        break;
      case Format::Hdr:
        write_hdr(target, image);
        break;
      case Format::Pfm:
        write_pfm(target, image);
        break;
      case Format::Png:
        write_png(target, image);
        break;
      case Format::Jpeg:
      case Format::Unknown:
        break;
    }
  });
}

std::string preview_path_for(const std::string& path) {
  return fs::path(path).replace_extension(".png").string();
}

std::vector<unsigned char> to_srgb8(const Image& image, float exposure) {
  // The bytes of the values met so far, by their bits (direct-mapped): an image decoded from
  // an 8-bit file has at most 256 values per channel, and a render's black background and
  // clipped highlights repeat too; one pow per channel is the cost otherwise. A memo of the
  // function itself, so every byte is the one the conversion gives.
  constexpr uint32_t kMemoBits = 12;
  struct Memo {
    uint32_t key;
    bool valid;
    unsigned char byte;
  };
  std::vector<Memo> memo(size_t(1) << kMemoBits, Memo{0, false, 0});
  std::vector<unsigned char> bytes(image.pixels.size() * 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float linear = image.pixels[i][c] * exposure;
      // NaN and negatives map to black, overflow to white.
      const float clamped = linear > 0.0f ? std::min(linear, 1.0f) : 0.0f;
      const uint32_t key = std::bit_cast<uint32_t>(clamped);
      Memo& m = memo[(key * 2654435761u) >> (32 - kMemoBits)];
      if (!m.valid || m.key != key)
        m = {key, true, static_cast<unsigned char>(linear_to_srgb(clamped) * 255.0f + 0.5f)};
      bytes[3 * i + c] = m.byte;
    }
  }
  return bytes;
}

}  // namespace emlt
