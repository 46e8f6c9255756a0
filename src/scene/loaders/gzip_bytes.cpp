#include "src/scene/loaders/gzip_bytes.h"

#include <zlib.h>

#include <algorithm>

#include "emlt/core/error.h"

namespace emlt::loader {

bool is_gzip(std::string_view bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

std::string gunzip(const std::string& path, std::string_view bytes, size_t limit) {
  z_stream stream{};
  // 16 + MAX_WBITS: a gzip header and trailer (CRC-32 and length checked by zlib).
  if (inflateInit2(&stream, 16 + MAX_WBITS) != Z_OK)
    throw file_error(path, "cannot initialise zlib to read the gzip data");
  std::string out;
  size_t in_pos = 0;
  int rc = Z_OK;
  std::string problem;
  while (problem.empty()) {
    if (stream.avail_in == 0) {
      const size_t n = std::min<size_t>(bytes.size() - in_pos, size_t(1) << 30);
      stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + in_pos));
      stream.avail_in = uInt(n);
      in_pos += n;
    }
    const size_t chunk = size_t(1) << 20;
    const size_t start = out.size();
    if (start >= limit) {
      problem = "gzip data expands beyond " + std::to_string(limit >> 20) + " MiB";
      break;
    }
    out.resize(start + chunk);
    stream.next_out = reinterpret_cast<Bytef*>(out.data() + start);
    stream.avail_out = uInt(chunk);
    rc = inflate(&stream, Z_NO_FLUSH);
    out.resize(start + (chunk - stream.avail_out));
    if (rc == Z_STREAM_END) {
      // Another member may follow (gzip concatenates them); anything else is not gzip.
      const size_t rest = stream.avail_in + (bytes.size() - in_pos);
      if (rest == 0) break;
      const std::string_view tail = bytes.substr(bytes.size() - rest);
      if (!is_gzip(tail)) {
        problem = "data after the end of the gzip stream";
        break;
      }
      inflateReset(&stream);
    } else if (rc == Z_BUF_ERROR && stream.avail_in == 0 && in_pos == bytes.size()) {
      problem = "truncated gzip data";
    } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
      problem = std::string("corrupt gzip data (") + (stream.msg ? stream.msg : "zlib error") + ")";
    }
  }
  inflateEnd(&stream);
  if (!problem.empty()) throw file_error(path, problem);
  return out;
}

std::string maybe_gunzip(const std::string& path, std::string bytes) {
  return is_gzip(bytes) ? gunzip(path, bytes) : std::move(bytes);
}

}  // namespace emlt::loader
