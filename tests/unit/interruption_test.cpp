// The registry of temporaries that a second stop signal removes: an image and its preview
// are written at once by two threads, and both must go.
#include "emlt/core/interruption.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <latch>
#include <thread>

#include "support/test_support.h"

using namespace emlt;
namespace fs = std::filesystem;

namespace {

fs::path touch(const fs::path& path) {
  std::ofstream(path) << "partial";
  return path;
}

}  // namespace

TEST(Interruption, SecondSignalRemovesTheTemporariesOfEveryWritingThread) {
  const fs::path dir = test::scratch_dir("temporaries");
  const fs::path image = touch(dir / "out.exr.tmp-1"), preview = touch(dir / "out.png.tmp-1");
  const fs::path finished = touch(dir / "done.exr.tmp-1");
  // The main thread registers one file and then forgets it (written and renamed); a second
  // thread registers the preview and the main thread the image, both still being written.
  interruption::register_temporary(finished.string());
  interruption::register_temporary("");
  std::latch registered(1), removed(1);
  std::thread writer([&] {
    interruption::register_temporary(preview.string());
    registered.count_down();
    removed.wait();
    interruption::register_temporary("");  // as write_atomically does when it is done
  });
  registered.wait();
  interruption::register_temporary(image.string());
  interruption::remove_temporary();
  removed.count_down();
  writer.join();
  EXPECT_FALSE(fs::exists(image));
  EXPECT_FALSE(fs::exists(preview));
  EXPECT_TRUE(fs::exists(finished));  // forgotten: no longer the registry's to remove
  interruption::register_temporary("");
}

TEST(Interruption, AThreadsNewTemporaryReplacesItsOld) {
  const fs::path dir = test::scratch_dir("temporaries_replaced");
  const fs::path first = touch(dir / "a.tmp"), second = touch(dir / "b.tmp");
  // A thread registers the temporary it writes now; the one before is finished with.
  interruption::register_temporary(first.string());
  interruption::register_temporary(second.string());
  interruption::remove_temporary();
  EXPECT_TRUE(fs::exists(first));
  EXPECT_FALSE(fs::exists(second));
  interruption::register_temporary("");
}
