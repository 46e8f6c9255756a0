#include "emlt/run/checkpoint_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "emlt/core/atomic_write.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/core/state_io.h"

namespace emlt::checkpoint_file {

namespace {

constexpr char kMagic[8] = {'E', 'M', 'L', 'T', 'C', 'K', 'P', 'T'};
// Written after the version: a file from a machine of the other byte order reads it
// reversed and is refused by name rather than misread.
constexpr uint32_t kByteOrder = 0x01020304u;
constexpr size_t kPrefix = sizeof(kMagic) + 2 * sizeof(uint32_t) + sizeof(uint64_t);

}  // namespace

void write(const std::string& path, std::string_view header, std::string_view state) {
  StateWriter payload;
  payload.put_block(std::string(header));
  payload.put_block(std::string(state));
  const std::string& body = payload.data();
  StateWriter prefix;
  for (const char c : kMagic) prefix.put(c);
  prefix.put<uint32_t>(kVersion);
  prefix.put<uint32_t>(kByteOrder);
  prefix.put<uint64_t>(body.size());
  StateWriter suffix;
  suffix.put<uint64_t>(fnv1a64(body));

  std::string bytes = prefix.data();
  bytes += body;
  bytes += suffix.data();
  write_file_atomically(path, "the checkpoint", bytes, Durability::Synced);
}

Contents read(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw file_error(path, "checkpoint not found");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(path, "cannot open the checkpoint");
  std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw file_error(path, "cannot read the checkpoint");
  if (file.size() < sizeof(kMagic) || std::memcmp(file.data(), kMagic, sizeof(kMagic)) != 0)
    throw file_error(path, "not an emlt checkpoint");
  if (file.size() < kPrefix)
    throw file_error(path, "checkpoint is truncated (" + std::to_string(file.size()) + " bytes)");
  StateReader prefix(std::string_view(file).substr(sizeof(kMagic), kPrefix - sizeof(kMagic)));
  const uint32_t version = prefix.get<uint32_t>();
  const uint32_t byte_order = prefix.get<uint32_t>();
  const uint64_t size = prefix.get<uint64_t>();
  if (byte_order != kByteOrder)
    throw file_error(path, "checkpoint was written on a machine of another byte order");
  if (version < kOldestReadable || version > kVersion)
    throw file_error(path, "checkpoint has format version " + std::to_string(version) +
                               ", this emlt reads versions " + std::to_string(kOldestReadable) +
                               " to " + std::to_string(kVersion));
  const uint64_t expected = kPrefix + size + sizeof(uint64_t);
  if (size > file.size() || file.size() < expected)
    throw file_error(path, "checkpoint is truncated (" + std::to_string(file.size()) + " of " +
                               std::to_string(expected) + " bytes)");
  if (file.size() > expected)
    throw file_error(
        path, "checkpoint has " + std::to_string(file.size() - expected) + " bytes after its end");
  const std::string_view body = std::string_view(file).substr(kPrefix, size);
  uint64_t checksum;
  std::memcpy(&checksum, file.data() + kPrefix + size, sizeof(checksum));
  if (checksum != fnv1a64(body))
    throw file_error(path, "checkpoint is corrupted (its checksum does not match its contents)");
  try {
    StateReader reader(body);
    Contents contents;
    contents.version = version;
    contents.header = std::string(reader.get_block());
    contents.state = std::string(reader.get_block());
    reader.expect_end();
    return contents;
  } catch (const StateError& e) {
    throw file_error(path, std::string("checkpoint is malformed: ") + e.what());
  }
}

}  // namespace emlt::checkpoint_file
