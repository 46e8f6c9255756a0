#pragma once
// What emlt.Scene holds: the file and defines a render reads again, and what loading said.
#include <string>
#include <utility>
#include <vector>

namespace emlt::python {

struct SceneHandle {
  std::string path;
  std::vector<std::string> defines;  // "name=value"
  std::string integrator;
  int width = 0, height = 0;
  std::string verdict;
  std::vector<std::pair<std::string, std::string>> warnings;  // kind, message
};

}  // namespace emlt::python
