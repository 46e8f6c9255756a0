// core/atomic_write.h: a file is written whole or not at all. A failed write leaves the
// previous file untouched and no temporary behind, and its error names the file.
#include "emlt/core/atomic_write.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "support/test_support.h"

using namespace emlt;

namespace {

std::string contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every entry of the folder but `keep`: a stray temporary shows here.
int others(const std::filesystem::path& dir, const std::string& keep) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().filename() != keep) ++n;
  return n;
}

}  // namespace

TEST(AtomicWrite, ReplacesTheFileWholeInBothDurabilities) {
  const auto dir = test::scratch_dir("atomic-write");
  const std::string path = (dir / "out.txt").string();
  write_file_atomically(path, "the test file", "first");
  EXPECT_EQ(contents(path), "first");
  write_file_atomically(path, "the test file", std::string(1 << 20, 'x'), Durability::Synced);
  EXPECT_EQ(contents(path), std::string(1 << 20, 'x'));
  write_atomically(path, "the test file",
                   [](const std::string& temporary) { std::ofstream(temporary) << "third"; });
  EXPECT_EQ(contents(path), "third");
  EXPECT_EQ(others(dir, "out.txt"), 0);
}

TEST(AtomicWrite, AFailedWriteKeepsThePreviousFileAndLeavesNoTemporary) {
  const auto dir = test::scratch_dir("atomic-write-fail");
  const std::string path = (dir / "image.exr").string();
  write_file_atomically(path, "image", "previous");
  // A library's own exception becomes an error naming the file and what was written.
  const std::string message = test::error_of([&] {
    write_atomically(path, "image", [](const std::string& temporary) {
      std::ofstream(temporary) << "half";
      throw std::runtime_error("disk full");
    });
  });
  EXPECT_EQ(message, path + ": cannot write image: disk full");
  EXPECT_EQ(contents(path), "previous");
  EXPECT_EQ(others(dir, "image.exr"), 0);
}

TEST(AtomicWrite, AMissingFolderIsOneLineNamingTheFile) {
  const auto dir = test::scratch_dir("atomic-write-missing");
  const std::string path = (dir / "no-such-folder" / "stats.json").string();
  const std::string message =
      test::error_of([&] { write_file_atomically(path, "statistics", "{}"); });
  EXPECT_EQ(message.rfind(path + ": cannot write statistics: ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(path));
}
