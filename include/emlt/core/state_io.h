#pragma once
// Binary encoding of a render's state for checkpoints (run/checkpoint_file.h). Values are
// written in the machine's byte order, floating point bit for bit, so that a state read
// back continues the render to the very same bits; a checkpoint is only ever read by the
// build that wrote it (its format version and a checksum guard that). A reader never reads
// past its data: a truncated or inconsistent state raises StateError, which the checkpoint
// reader turns into a one-line error naming the file.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace emlt {

class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StateWriter {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const char*>(&value);
    data_.append(bytes, sizeof(T));
  }
  void put_string(std::string_view s) {
    put<uint64_t>(s.size());
    data_.append(s.data(), s.size());
  }
  // A vector of plain values: its length, then its elements as they lie in memory.
  template <typename T, typename Allocator>
  void put_vector(const std::vector<T, Allocator>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<uint64_t>(values.size());
    data_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  // A section whose length is written first, so a reader can hand it on whole.
  void put_block(const std::string& block) { put_string(block); }

  // Empties the writer but keeps its memory (a writer reused for every exchange).
  void clear() { data_.clear(); }
  const std::string& data() const { return data_; }
  std::string take() { return std::move(data_); }

 private:
  std::string data_;
};

class StateReader {
 public:
  explicit StateReader(std::string_view data) : data_(data) {}

  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  std::string get_string() {
    const uint64_t size = get<uint64_t>();
    if (size > remaining()) throw StateError("a string runs past the end of the data");
    return std::string(take(size), size);
  }
  // `expected`: the length the caller knows the vector must have (the film's pixels, the
  // chains ...); a state that disagrees is refused rather than trusted.
  template <typename T>
  std::vector<T> get_vector(uint64_t expected) {
    static_assert(std::is_trivially_copyable_v<T>);
    const uint64_t size = get<uint64_t>();
    if (size != expected)
      throw StateError("an array holds " + std::to_string(size) + " entries where " +
                       std::to_string(expected) + " were expected");
    return get_vector_data<T>(size);
  }
  // A vector of any length up to `limit` entries.
  template <typename T>
  std::vector<T> get_vector_up_to(uint64_t limit) {
    const uint64_t size = get<uint64_t>();
    if (size > limit) throw StateError("an array is longer than possible");
    return get_vector_data<T>(size);
  }
  // The same into `values`, reusing its storage.
  template <typename T, typename Allocator>
  void get_vector_into(std::vector<T, Allocator>& values, uint64_t limit) {
    static_assert(std::is_trivially_copyable_v<T>);
    const uint64_t size = get<uint64_t>();
    if (size > limit || size > remaining() / sizeof(T))
      throw StateError("an array is longer than possible");
    values.resize(size);
    if (size > 0) std::memcpy(values.data(), take(size * sizeof(T)), size * sizeof(T));
  }
  std::string_view get_block() {
    const uint64_t size = get<uint64_t>();
    if (size > remaining()) throw StateError("a section runs past the end of the data");
    return std::string_view(take(size), size);
  }

  uint64_t remaining() const { return data_.size() - offset_; }
  // Throws unless every byte was read (a state longer than its reader expects is not ours).
  void expect_end() const {
    if (remaining() != 0) throw StateError("unexpected data after the end of the state");
  }

 private:
  template <typename T>
  std::vector<T> get_vector_data(uint64_t size) {
    if (size > remaining() / sizeof(T)) throw StateError("an array runs past the end of the data");
    std::vector<T> values(size);
    // An empty vector's data() may be null, which memcpy must not be given even for no
    // bytes (BDPT's strategy sums are empty without --bdpt-strategies).
    if (size > 0) std::memcpy(values.data(), take(size * sizeof(T)), size * sizeof(T));
    return values;
  }
  const char* take(uint64_t bytes) {
    if (bytes > remaining()) throw StateError("the data ends early");
    const char* p = data_.data() + offset_;
    offset_ += bytes;
    return p;
  }

  std::string_view data_;
  uint64_t offset_ = 0;
};

// FNV-1a, 64 bits: the checksum of a checkpoint's payload and the fingerprint of the scene
// files (not a cryptographic hash: it guards against accidents, not against an adversary).
inline uint64_t fnv1a64(std::string_view data, uint64_t hash = 0xcbf29ce484222325ull) {
  for (const unsigned char c : data) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

}  // namespace emlt
