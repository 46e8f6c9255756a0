#include "emlt/path/path_type.h"

namespace emlt {

std::string PathType::to_string() const {
  std::string text;
  for (int i = 0; i < int(vertices); ++i) {
    if (i > 0) text += ' ';
    if (i == 0) text += 'L';
    else if (i + 1 == int(vertices)) text += 'E';
    else text += is_specular(i) ? 'S' : 'D';
  }
  return text;
}

}  // namespace emlt
