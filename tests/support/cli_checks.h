#pragma once
// What the end-to-end tests of the command line share: the binary's command, the Cornell box
// scene, and the check of a run that must fail as a user should see it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/test_support.h"

namespace emlt::test {

inline std::string emlt_cmd(const std::string& args) { return emlt_binary() + " " + args; }

inline std::string cornell(const std::string& file = "scene.json") {
  return source_path("scenes/cornell-box/" + file);
}

inline int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

// Runs a command that must fail: non-zero exit, one line naming `must_mention`, no file and
// no temporary left beside it.
inline void expect_clean_failure(const std::string& args, const std::string& must_mention,
                                 const std::filesystem::path& output) {
  namespace fs = std::filesystem;
  std::string text;
  const int status = run_command(emlt_cmd(args), &text);
  EXPECT_NE(status, 0) << args;
  EXPECT_EQ(count_lines(text), 1) << text;
  EXPECT_NE(text.find("error"), std::string::npos) << text;
  EXPECT_NE(text.find(must_mention), std::string::npos)
      << "expected '" << must_mention << "' in: " << text;
  EXPECT_FALSE(fs::exists(output)) << output;
  if (!fs::is_directory(output.parent_path())) return;
  for (const auto& entry : fs::directory_iterator(output.parent_path()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

}  // namespace emlt::test
