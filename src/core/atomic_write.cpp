#include "emlt/core/atomic_write.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "emlt/core/error.h"
#include "emlt/core/interruption.h"

namespace emlt {

namespace {

std::string problem(std::string_view what, const char* verb, int error) {
  return std::string(verb) + " " + std::string(what) + ": " + std::strerror(error);
}

// Flushes an existing file (or directory) to the disk; errno on failure, 0 otherwise.
int sync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), (directory ? O_RDONLY | O_DIRECTORY : O_RDONLY) | O_CLOEXEC);
  if (fd < 0) return errno;
  const int result = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return result;
}

// The temporary registered with interruption.h for as long as it exists.
class Temporary {
 public:
  explicit Temporary(std::string path) : path_(std::move(path)) {
    interruption::register_temporary(path_);
  }
  ~Temporary() {
    if (!kept_) ::unlink(path_.c_str());
    interruption::register_temporary("");
  }
  Temporary(const Temporary&) = delete;
  Temporary& operator=(const Temporary&) = delete;
  const std::string& path() const { return path_; }
  void renamed() { kept_ = true; }

 private:
  std::string path_;
  bool kept_ = false;
};

void put_in_place(Temporary& temporary, const std::string& path, std::string_view what,
                  Durability durability) {
  if (durability == Durability::Synced)
    if (const int error = sync_path(temporary.path(), false))
      throw file_error(path, problem(what, "cannot flush", error) + " (to the disk)");
  if (std::rename(temporary.path().c_str(), path.c_str()) != 0)
    throw file_error(path, "cannot move the written " + std::string(what) +
                               " into place: " + std::strerror(errno));
  temporary.renamed();
  if (durability == Durability::Synced) {
    // The rename reaches the disk with its directory; a failure here leaves a whole file.
    const std::string directory = std::filesystem::path(path).parent_path().string();
    sync_path(directory.empty() ? "." : directory, true);
  }
}

}  // namespace

void write_file_atomically(const std::string& path, std::string_view what, std::string_view bytes,
                           Durability durability) {
  Temporary temporary(path + ".tmp-" + std::to_string(::getpid()));
  {
    const int fd = ::open(temporary.path().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw file_error(path, problem(what, "cannot write", errno));
    const char* data = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
      const ssize_t n = ::write(fd, data, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int error = n < 0 ? errno : EIO;
        ::close(fd);
        throw file_error(path, problem(what, "cannot write", error));
      }
      data += n;
      left -= size_t(n);
    }
    if (::close(fd) != 0) throw file_error(path, problem(what, "cannot write", errno));
  }
  put_in_place(temporary, path, what, durability);
}

void write_atomically(const std::string& path, std::string_view what,
                      const std::function<void(const std::string& temporary)>& write_to,
                      Durability durability) {
  Temporary temporary(path + ".tmp-" + std::to_string(::getpid()));
  try {
    write_to(temporary.path());
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // a library's own exceptions (OpenEXR's Iex), allocation
    throw file_error(path, "cannot write " + std::string(what) + ": " + e.what());
  }
  put_in_place(temporary, path, what, durability);
}

}  // namespace emlt
