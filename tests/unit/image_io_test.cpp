// Image reading/writing: round trips per format, error messages that name the file,
// atomic writes, and the sRGB preview encoding.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "emlt/core/error.h"
#include "emlt/image/image.h"
#include "support/test_support.h"

using namespace emlt;
namespace fs = std::filesystem;

namespace {

// Odd sizes catch stride mistakes; distinct values per channel catch channel swaps; the
// top-left and bottom-right corners differ, so a vertical flip is visible.
Image gradient(float peak) {
  Image image(7, 5);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      image.at(x, y) = peak * Rgb(float(x) / 6.0f, float(y) / 4.0f, 0.1f + 0.05f * float(x + y));
    }
  }
  return image;
}

// Expects `action` to throw emlt::Error whose message names `path` and contains `words`.
template <typename Action>
void expect_file_error(Action action, const std::string& path, const std::string& words) {
  try {
    action();
    ADD_FAILURE() << "no error for " << path;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(words), std::string::npos) << message;
  }
}

std::vector<std::string> directory_listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// A binary PPM (P6) or PGM (P5) as 3 bytes per texel, a grey file's value repeated.
StoredImage read_pnm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int max_value = 0;
  StoredImage image;
  in >> magic >> image.width >> image.height >> max_value;
  in.get();  // the single whitespace byte before the texels
  const int channels = magic == "P6" ? 3 : 1;
  std::vector<unsigned char> data(size_t(image.width) * size_t(image.height) * size_t(channels));
  in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size()));
  EXPECT_TRUE((magic == "P5" || magic == "P6") && max_value == 255 && in) << path;
  for (size_t i = 0; i < data.size(); i += size_t(channels)) {
    for (int c = 0; c < 3; ++c) image.bytes.push_back(data[i + size_t(channels == 3 ? c : 0)]);
  }
  return image;
}

// A PNG file built chunk by chunk: IHDR from the arguments, then `chunks` (type and
// data), the scanlines' bytes (filter bytes included) compressed into one IDAT, and IEND.
std::string png_file(uint32_t width, uint32_t height, int bits, int colour, int interlace,
                     const std::string& scanlines,
                     const std::vector<std::pair<std::string, std::string>>& chunks = {}) {
  const auto be32 = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  const auto chunk = [&](const std::string& type, const std::string& data) {
    const std::string body = type + data;
    const auto crc =
        uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size())));
    return be32(uint32_t(data.size())) + body + be32(crc);
  };
  std::string packed(compressBound(uLong(scanlines.size())), '\0');
  uLongf packed_size = uLongf(packed.size());
  compress(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
           reinterpret_cast<const Bytef*>(scanlines.data()), uLong(scanlines.size()));
  packed.resize(packed_size);
  std::string file = "\x89PNG\r\n\x1a\n";
  file += chunk("IHDR", be32(width) + be32(height) +
                            std::string{char(bits), char(colour), 0, 0, char(interlace)});
  for (const auto& [type, data] : chunks) file += chunk(type, data);
  return file + chunk("IDAT", packed) + chunk("IEND", "");
}

StoredImage stored_from(const fs::path& dir, const std::string& name, const std::string& bytes) {
  const std::string path = (dir / name).string();
  { std::ofstream(path, std::ios::binary) << bytes; }
  return read_stored_image(path);
}

}  // namespace

TEST(ImageIo, FloatFormatsRoundTripExactly) {
  const fs::path dir = test::scratch_dir("float");
  const Image image = gradient(40.0f);
  for (const char* name : {"g.exr", "g.pfm"}) {
    const std::string path = (dir / name).string();
    write_image(path, image);
    const Image back = read_image(path);
    ASSERT_EQ(back.width, image.width) << name;
    ASSERT_EQ(back.height, image.height) << name;
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      ASSERT_EQ(back.pixels[i], image.pixels[i]) << name << " texel " << i;
    }
  }
}

TEST(ImageIo, RadianceHdrRoundTripsWithinRgbePrecision) {
  const fs::path dir = test::scratch_dir("hdr");
  const Image image = gradient(40.0f);
  const std::string path = (dir / "g.hdr").string();
  write_image(path, image);
  const Image back = read_image(path);
  ASSERT_EQ(back.width, image.width);
  ASSERT_EQ(back.height, image.height);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    // RGBE shares one exponent: each channel is exact to about 2^-8 of the largest.
    const float tolerance = 0.01f * max_component(image.pixels[i]) + 1e-6f;
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(back.pixels[i][c], image.pixels[i][c], tolerance) << "texel " << i;
    }
  }
}

TEST(ImageIo, PngRoundTripsAtEightBitSrgbPrecision) {
  const fs::path dir = test::scratch_dir("png");
  const Image image = gradient(0.9f);
  const std::string path = (dir / "g.png").string();
  write_image(path, image);
  const Image back = read_image(path);
  ASSERT_EQ(back.width, image.width);
  ASSERT_EQ(back.height, image.height);
  // Decoding to linear then re-encoding reproduces the stored bytes exactly.
  EXPECT_EQ(to_srgb8(back), to_srgb8(image));
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      // One 8-bit sRGB step is at most ~0.9% of linear full scale (near white).
      ASSERT_NEAR(back.pixels[i][c], image.pixels[i][c], 0.01f) << "texel " << i;
    }
  }
  // Overflow clamps to white in the preview.
  Image bright(1, 1, Rgb(5.0f, 0.0f, -1.0f));
  write_image(path, bright);
  EXPECT_EQ(read_image(path).at(0, 0), Rgb(1.0f, 0.0f, 0.0f));
}

TEST(ImageIo, GreyscalePfmAndBigEndianPfmAreRead) {
  const fs::path dir = test::scratch_dir("pfm");
  const std::string grey = (dir / "grey.pfm").string();
  {
    std::ofstream out(grey, std::ios::binary);
    out << "Pf\n2 1\n-1.0\n";
    const float values[2] = {0.25f, 3.0f};
    out.write(reinterpret_cast<const char*>(values), sizeof(values));
  }
  const Image g = read_image(grey);
  ASSERT_EQ(g.width, 2);
  EXPECT_EQ(g.at(0, 0), Rgb(0.25f));
  EXPECT_EQ(g.at(1, 0), Rgb(3.0f));

  // Big-endian RGB, two rows stored bottom first: (1,2,3) ends up at the bottom.
  const std::string big = (dir / "big.pfm").string();
  {
    std::ofstream out(big, std::ios::binary);
    out << "PF\n1 2\n1.0\n";
    for (float v : {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f}) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      const unsigned char bytes[4] = {static_cast<unsigned char>(bits >> 24),
                                      static_cast<unsigned char>(bits >> 16),
                                      static_cast<unsigned char>(bits >> 8),
                                      static_cast<unsigned char>(bits)};
      out.write(reinterpret_cast<const char*>(bytes), 4);
    }
  }
  const Image b = read_image(big);
  ASSERT_EQ(b.height, 2);
  EXPECT_EQ(b.at(0, 0), Rgb(4.0f, 5.0f, 6.0f));
  EXPECT_EQ(b.at(0, 1), Rgb(1.0f, 2.0f, 3.0f));
}

TEST(ImageIo, NonFiniteTexelsAreRejectedOnRead) {
  const fs::path dir = test::scratch_dir("nan");
  for (const char* name : {"nan.pfm", "nan.exr"}) {
    Image image = gradient(1.0f);
    image.at(3, 2).y = std::numeric_limits<float>::quiet_NaN();
    const std::string path = (dir / name).string();
    write_image(path, image);  // writing keeps the evidence; reading refuses it
    expect_file_error([&] { read_image(path); }, path, "NaN or infinite");
  }
  Image image = gradient(1.0f);
  image.at(0, 0).x = std::numeric_limits<float>::infinity();
  const std::string path = (dir / "inf.pfm").string();
  write_image(path, image);
  expect_file_error([&] { read_image(path); }, path, "NaN or infinite");
}

TEST(ImageIo, MissingMalformedAndUnknownFilesNameThePath) {
  const fs::path dir = test::scratch_dir("errors");
  const std::string missing = (dir / "missing.exr").string();
  expect_file_error([&] { read_image(missing); }, missing, "not found");

  const std::string unknown = (dir / "image.tiff").string();
  { std::ofstream(unknown) << "whatever"; }
  expect_file_error([&] { read_image(unknown); }, unknown, "unsupported");
  const std::string unknown_out = (dir / "image.bmp").string();
  expect_file_error([&] { write_image(unknown_out, gradient(1.0f)); }, unknown_out,
                    "unsupported");
  EXPECT_FALSE(fs::exists(unknown_out));

  const std::string garbage_exr = (dir / "garbage.exr").string();
  { std::ofstream(garbage_exr) << "this is not an OpenEXR file"; }
  expect_file_error([&] { read_image(garbage_exr); }, garbage_exr, "");

  const std::string garbage_hdr = (dir / "garbage.hdr").string();
  { std::ofstream(garbage_hdr) << "#?NOPE\n"; }
  expect_file_error([&] { read_image(garbage_hdr); }, garbage_hdr, "");

  const std::string truncated = (dir / "truncated.pfm").string();
  { std::ofstream(truncated, std::ios::binary) << "PF\n4 4\n-1.0\n" << std::string(20, 'x'); }
  expect_file_error([&] { read_image(truncated); }, truncated, "truncated");

  const std::string empty = (dir / "empty.pfm").string();
  { std::ofstream(empty, std::ios::binary) << "PF\n0 0\n-1.0\n"; }
  expect_file_error([&] { read_image(empty); }, empty, "zero size");

  // A PNG cut anywhere after its signature: libpng's reason, never an empty one.
  const std::string whole_png = (dir / "whole.png").string();
  write_image(whole_png, gradient(1.0f));
  std::string bytes;
  {
    std::ifstream in(whole_png, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  for (size_t length = 40; length <= 200 && length < bytes.size(); length += 20) {
    const std::string cut_png = (dir / ("cut" + std::to_string(length) + ".png")).string();
    { std::ofstream(cut_png, std::ios::binary) << bytes.substr(0, length); }
    expect_file_error([&] { read_image(cut_png); }, cut_png, "file ends early");
    try {
      read_stored_image(cut_png);
      ADD_FAILURE() << "no error for " << cut_png;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find("()"), std::string::npos) << "an empty reason";
    }
  }

  const std::string zero_out = (dir / "zero.exr").string();
  expect_file_error([&] { write_image(zero_out, Image()); }, zero_out, "empty");
  EXPECT_FALSE(fs::exists(zero_out));
}

// The readers' texel limit is 2^28 (16384 x 16384, the largest film): a header one row
// beyond it is refused from the header, before 3 GiB are allocated for it. Under the old
// limit (2^29) these headers got through to the allocation.
TEST(ImageIo, HeaderJustAboveTheTexelLimitIsRefusedBeforeAllocation) {
  const fs::path dir = test::scratch_dir("texel-limit");
  const std::string refusal =
      "header claims 16384 x 16385 texels; images may have at most 65536 texels a side and "
      "2^28 (about 268 million) in all";
  // At the limit the header passes, and the reader finds the data missing (it checks the
  // file's length before it allocates).
  const std::string at_limit = test::write_file(dir, "at_limit.pfm", "PF\n16384 16384\n-1.0\n");
  expect_file_error([&] { read_image(at_limit); }, at_limit, "truncated PFM data");
  const std::string pfm = test::write_file(dir, "above.pfm", "PF\n16384 16385\n-1.0\n");
  expect_file_error([&] { read_image(pfm); }, pfm, refusal);

  // An EXR whose data window is patched to 16384 x 16385 after a 1 x 1 image was written:
  // OpenEXR reads the header and the offset table only, then emlt refuses.
  const std::string exr = (dir / "above.exr").string();
  write_image(exr, Image(1, 1, Rgb(1.0f)));
  std::string bytes;
  {
    std::ifstream in(exr, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // The attribute: name, type, size (16), then min.x, min.y, max.x, max.y, each a
  // little-endian int32.
  const std::string attribute("dataWindow\0box2i\0", 17);
  const size_t at = bytes.find(attribute);
  ASSERT_NE(at, std::string::npos);
  const uint32_t max_corner[2] = {16383, 16384};
  for (size_t i = 0; i < 2; ++i)
    for (size_t b = 0; b < 4; ++b)
      bytes[at + attribute.size() + 12 + 4 * i + b] = char((max_corner[i] >> (8 * b)) & 0xffu);
  // Room for the offset table such a header implies (one 8-byte offset per 16 rows, as
  // ZIP compresses), which OpenEXR reads with the header; the offsets themselves are junk.
  bytes += std::string(16385 / 16 * 8 + 8, '\0');
  test::write_file(dir, "above.exr", bytes);
  expect_file_error([&] { read_image(exr); }, exr, refusal);
}

TEST(ImageIo, WritesAreAtomic) {
  const fs::path dir = test::scratch_dir("atomic");
  const Image first = gradient(1.0f), second = gradient(2.0f);
  for (const char* name : {"a.exr", "a.pfm", "a.hdr", "a.png"}) {
    write_image((dir / name).string(), first);
    write_image((dir / name).string(), second);  // replaces the existing file
  }
  EXPECT_EQ(directory_listing(dir), (std::vector<std::string>{"a.exr", "a.hdr", "a.pfm", "a.png"}));
  EXPECT_EQ(read_image((dir / "a.pfm").string()).at(6, 4), second.at(6, 4));

  // A missing directory: an error naming the target, and nothing created anywhere.
  for (const char* name : {"a.exr", "a.pfm", "a.hdr", "a.png"}) {
    const std::string path = (dir / "no-such-dir" / name).string();
    expect_file_error([&] { write_image(path, first); }, path, "");
  }
  EXPECT_FALSE(fs::exists(dir / "no-such-dir"));
  EXPECT_EQ(directory_listing(dir).size(), 4u);
}

TEST(ImageIo, PreviewPathAndSrgbEncoding) {
  EXPECT_EQ(preview_path_for("a/b.exr"), "a/b.png");
  EXPECT_EQ(preview_path_for("cornell.pfm"), "cornell.png");
  EXPECT_EQ(preview_path_for("out/render.v2.hdr"), "out/render.v2.png");

  Image image(6, 1);
  image.at(0, 0) = Rgb(0.0f, 1.0f, 0.5f);
  image.at(1, 0) = Rgb(-1.0f, 7.0f, std::numeric_limits<float>::quiet_NaN());
  image.at(2, 0) = Rgb(0.002f, 0.0031308f, 0.18f);
  image.at(3, 0) = Rgb(0.25f);
  const std::vector<unsigned char> bytes = to_srgb8(image);
  ASSERT_EQ(bytes.size(), 18u);
  EXPECT_EQ(bytes[0], 0);
  EXPECT_EQ(bytes[1], 255);
  EXPECT_EQ(bytes[2], 188);  // linear 0.5 -> sRGB 0.7354
  EXPECT_EQ(bytes[3], 0);    // negative
  EXPECT_EQ(bytes[4], 255);  // overflow
  EXPECT_EQ(bytes[5], 0);    // NaN
  EXPECT_EQ(bytes[6], 7);    // linear segment: 12.92 * 0.002 * 255 = 6.59
  EXPECT_EQ(bytes[7], 10);   // the knee: 0.04045 * 255 = 10.3
  EXPECT_EQ(bytes[8], 118);  // 18% grey -> 0.4614
  // Exposure multiplies before the curve: 0.25 at exposure 2 encodes like 0.5.
  EXPECT_EQ(to_srgb8(image, 2.0f)[9], 188);
}

// to_srgb8 keeps the bytes of the values it has met (a memo by the float's bits): a value
// whose slot another value took must still get its own byte. Every value of the image,
// encoded alone (a fresh memo), against the same value inside a 120 000-value image, where
// values share slots.
TEST(ImageIo, SrgbEncodingOfManyValuesMatchesEachValueAlone) {
  Image image(40000, 1);
  uint32_t state = 12345u;
  for (Rgb& pixel : image.pixels)
    for (int c = 0; c < 3; ++c) {
      state = state * 1664525u + 1013904223u;
      pixel[c] = float(state >> 8) * 0x1p-24f;
    }
  const std::vector<unsigned char> bytes = to_srgb8(image);
  int mismatches = 0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    Image one(1, 1);
    one.pixels[0] = image.pixels[i];
    const std::vector<unsigned char> alone = to_srgb8(one);
    for (size_t c = 0; c < 3; ++c) mismatches += alone[c] != bytes[3 * i + c];
  }
  EXPECT_EQ(mismatches, 0);
}

// JPEG texels are libjpeg's default decode, which is what Mitsuba 0.6 reads JPEG textures
// with: bit for bit the texels djpeg wrote beside the files (tools/conformance/
// make_scenes.py). stb_image's decoder, used before, differs from it by 1 or 2 levels in
// 259 of grid.jpg's 3072 bytes and 12 of grid-grey.jpg's (its own IDCT and upsampling).
TEST(ImageIo, JpegTexelsAreLibjpegsDefaultDecode) {
  const fs::path assets = fs::path(EMLT_SOURCE_DIR) / "tests/conformance/scenes/assets";
  for (const char* name : {"grid.jpg", "grid-grey.jpg"}) {
    SCOPED_TRACE(name);
    const std::string path = (assets / name).string();
    const StoredImage expected = read_pnm(path + ".ppm");
    const StoredImage decoded = read_stored_image(path);
    ASSERT_EQ(decoded.width, expected.width);
    ASSERT_EQ(decoded.height, expected.height);
    EXPECT_TRUE(decoded.bytes == expected.bytes);
    const Image linear = read_image(path);  // the same bytes through the sRGB curve
    EXPECT_EQ(linear.at(31, 31).y, srgb8_levels()[expected.bytes[3 * (31 * 32 + 31) + 1]]);
  }
}

// A JPEG cut short, or with damaged entropy-coded data, is an error naming the file, not a
// texture with grey blocks where the data was missing (libjpeg only warns of either).
TEST(ImageIo, DamagedJpegIsAFileError) {
  const fs::path dir = test::scratch_dir("jpeg");
  std::string bytes;
  {
    std::ifstream in(fs::path(EMLT_SOURCE_DIR) / "tests/conformance/scenes/assets/grid.jpg",
                     std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 1000u);
  for (size_t length : {size_t(2), size_t(40), size_t(300), bytes.size() - 400, bytes.size() - 2}) {
    const std::string cut = (dir / ("cut" + std::to_string(length) + ".jpg")).string();
    { std::ofstream(cut, std::ios::binary) << bytes.substr(0, length); }
    expect_file_error([&] { read_image(cut); }, cut, "JPEG");
  }
  // Ones written over the last 200 bytes of scan data: codes no Huffman table holds.
  std::string damaged = bytes;
  std::fill(damaged.end() - 202, damaged.end() - 2, '\xff');
  const std::string path = (dir / "damaged.jpg").string();
  { std::ofstream(path, std::ios::binary) << damaged; }
  expect_file_error([&] { read_stored_image(path); }, path, "corrupt JPEG");
}

// PNG files read as Mitsuba 0.6 reads them with libpng (Bitmap::readPNG): every colour
// type to three samples, 16-bit samples kept, Adam7 interlacing undone.
TEST(ImageIo, PngColourTypesExpandAsMitsubasReader) {
  const fs::path dir = test::scratch_dir("png-types");
  using Bytes = std::vector<unsigned char>;
  // Palette of two entries; tRNS makes entry 0 transparent (alpha, kept beside the colour).
  const StoredImage palette = stored_from(
      dir, "palette.png",
      png_file(2, 1, 8, 3, 0, std::string("\0\x01\x00", 3),
               {{"PLTE", "\x10\x20\x30\xc0\xd0\xe0"}, {"tRNS", std::string("\x00\xff", 2)}}));
  EXPECT_EQ(palette.bytes, (Bytes{0xc0, 0xd0, 0xe0, 0x10, 0x20, 0x30}));
  EXPECT_EQ(palette.channels, "rgba");
  EXPECT_EQ(palette.alpha_bytes, (Bytes{0xff, 0x00}));
  // Grey with alpha: the grey value three times.
  const StoredImage grey_alpha =
      stored_from(dir, "grey-alpha.png", png_file(1, 1, 8, 4, 0, std::string("\0\x40\x80", 3)));
  EXPECT_EQ(grey_alpha.bytes, (Bytes{0x40, 0x40, 0x40}));
  EXPECT_EQ(grey_alpha.channels, "ya");
  EXPECT_EQ(grey_alpha.alpha_bytes, (Bytes{0x80}));
  // 2-bit grey scaled to 8 bits (level 1 of 3 -> 85), four texels in one byte.
  const StoredImage two_bit =
      stored_from(dir, "grey2.png", png_file(4, 1, 2, 0, 0, std::string("\0\x1b", 2)));
  EXPECT_EQ(two_bit.bytes, (Bytes{0, 0, 0, 85, 85, 85, 170, 170, 170, 255, 255, 255}));
  EXPECT_EQ(two_bit.channels, "l");
  EXPECT_TRUE(two_bit.alpha_bytes.empty());
  // 16-bit grey: the samples as stored, in `words`.
  const StoredImage sixteen =
      stored_from(dir, "grey16.png", png_file(1, 1, 16, 0, 0, std::string("\0\x12\x34", 3)));
  EXPECT_TRUE(sixteen.bytes.empty());
  EXPECT_EQ(sixteen.words, (std::vector<uint16_t>{0x1234, 0x1234, 0x1234}));
  // Adam7 interlaced 2 x 2 grey: pass 1 holds (0, 0), pass 6 (1, 0), pass 7 the second row.
  const StoredImage interlaced = stored_from(
      dir, "adam7.png", png_file(2, 2, 8, 0, 1, std::string("\0\x0a\0\x0b\0\x0c\x0d", 7)));
  EXPECT_EQ(interlaced.bytes, (Bytes{10, 10, 10, 11, 11, 11, 12, 12, 12, 13, 13, 13}));
  // A bad CRC on a critical chunk, and data that decompresses short of the image.
  std::string bad_crc = png_file(1, 1, 8, 0, 0, std::string("\0\x01", 2));
  bad_crc[29] ^= 1;  // IHDR's CRC (8 signature + 8 length/type + 13 data = byte 29)
  expect_file_error([&] { stored_from(dir, "crc.png", bad_crc); }, (dir / "crc.png").string(),
                    "PNG");
  expect_file_error(
      [&] { stored_from(dir, "short.png", png_file(4, 4, 8, 2, 0, std::string("\0\x01", 2))); },
      (dir / "short.png").string(), "PNG");
}

// The file's curve: Mitsuba reads a PNG's sRGB chunk first, then its gAMA chunk (the
// exponent 1 / gAMA), else sRGB; the conformance scenes tex-png-* show it in renders.
TEST(ImageIo, PngCurveComesFromItsSrgbOrGamaChunk) {
  const fs::path assets = fs::path(EMLT_SOURCE_DIR) / "tests/conformance/scenes/assets";
  const auto gamma_of = [&](const char* name) {
    return read_stored_image((assets / name).string()).gamma;
  };
  EXPECT_EQ(gamma_of("grid.png"), kSrgbGamma);
  EXPECT_EQ(gamma_of("grid-gama1.png"), 1.0f);
  EXPECT_NEAR(gamma_of("grid-gama15.png"), 1.5f, 1e-4f);  // gAMA 66667 / 100000
  EXPECT_EQ(gamma_of("grid-srgb-gama15.png"), kSrgbGamma);
  // read_image decodes by that curve.
  const std::string linear_path = (assets / "grid-gama1.png").string();
  const StoredImage linear = read_stored_image(linear_path);
  EXPECT_EQ(read_image(linear_path).at(0, 0).x, float(linear.bytes[0]) / 255.0f);
  const std::string power_path = (assets / "grid-gama15.png").string();
  const StoredImage power = read_stored_image(power_path);
  EXPECT_EQ(read_image(power_path).at(5, 9).y,
            std::pow(float(power.bytes[3 * (9 * 32 + 5) + 1]) / 255.0f, power.gamma));
  // A 16-bit file's samples, decoded without rounding to 8 bits.
  const std::string wide_path = (assets / "grid16.png").string();
  const StoredImage wide = read_stored_image(wide_path);
  ASSERT_EQ(wide.words.size(), 32u * 32u * 3u);
  EXPECT_EQ(wide.words[0], 62258);  // the top-left marker's 0.95
  EXPECT_EQ(read_image(wide_path).at(0, 0).x, decode_gamma(62258.0f / 65535.0f, kSrgbGamma));
}

// Mitsuba's bitmap `channel`: one channel of the file in all three samples; alpha linear.
TEST(ImageIo, ChannelOfAStoredImage) {
  const fs::path assets = fs::path(EMLT_SOURCE_DIR) / "tests/conformance/scenes/assets";
  const std::string path = (assets / "grid-alpha.png").string();
  const StoredImage rgba = read_stored_image(path);
  ASSERT_EQ(rgba.channels, "rgba");
  const StoredImage green = select_channel(rgba, "G", path);
  EXPECT_EQ(green.gamma, kSrgbGamma);
  const StoredImage alpha = select_channel(rgba, "a", path);
  EXPECT_EQ(alpha.gamma, 1.0f);
  for (size_t i : {size_t(0), size_t(8), size_t(8 * 32 + 8), size_t(1023)}) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(green.bytes[3 * i + size_t(c)], rgba.bytes[3 * i + 1]) << i;
      EXPECT_EQ(alpha.bytes[3 * i + size_t(c)], rgba.alpha_bytes[i]) << i;
    }
  }
  EXPECT_EQ(alpha.bytes[0], 255);    // the holes pattern: opaque top-left block,
  EXPECT_EQ(alpha.bytes[3 * 8], 0);  // a hole right of it
  expect_file_error([&] { select_channel(rgba, "y", path); }, path, "its channels: r, g, b, a");
  const std::string grey = (assets / "grid-grey.jpg").string();
  EXPECT_EQ(read_stored_image(grey).channels, "l");
  expect_file_error([&] { select_channel(read_stored_image(grey), "r", path); }, path,
                    "its channels: l");
}
