#pragma once
// gzip-compressed files as pbrt-v4 reads them: its scene texts (`.pbrt.gz`, the public hair
// and fur scenes' curves) and PLY meshes (`.ply.gz`, the ganesha and sssdragon scenes).
// Recognised by the gzip magic bytes, so that a name and its content cannot disagree.
#include <string>
#include <string_view>

namespace emlt::loader {

bool is_gzip(std::string_view bytes);

// The decompressed content of the gzip data `bytes` read from `path` (concatenated members
// are joined, as gzip does); corrupt or truncated data, or content beyond `limit` bytes, is
// "<path>: ..." in one line.
std::string gunzip(const std::string& path, std::string_view bytes, size_t limit = size_t(1) << 32);

// `bytes` decompressed when they are gzip data, otherwise unchanged.
std::string maybe_gunzip(const std::string& path, std::string bytes);

}  // namespace emlt::loader
