#pragma once
// Every file emlt writes (images, checkpoints, statistics, convergence logs) is written whole
// or not at all: the bytes go to a temporary beside the target ("<path>.tmp-<pid>", in the
// same directory so that the rename is atomic), which is renamed over the target once it is
// complete. A reader, or a render resumed after a crash, never sees half a file, and an
// existing file is kept until its replacement is whole. On any failure the temporary is
// removed and file_error(path, "cannot write <what>: ...") is thrown; a second Ctrl-C while
// the file is written removes the temporary too (interruption.h).
#include <functional>
#include <string>
#include <string_view>

namespace emlt {

enum class Durability {
  Renamed,  // atomic for readers; the operating system writes it back in its own time
  Synced,   // the bytes and the rename are on the disk before the call returns (checkpoints:
            // a power cut must leave the last one whole)
};

// Writes `bytes` to `path`. `what` names the file in errors ("the checkpoint", "statistics").
void write_file_atomically(const std::string& path, std::string_view what, std::string_view bytes,
                           Durability durability = Durability::Renamed);

// For writers that need a file name (OpenEXR, libpng): `write_to` writes the file it is given,
// throwing on failure; emlt::Error passes through as it is, any other exception becomes
// file_error(path, "cannot write <what>: " + its message).
void write_atomically(const std::string& path, std::string_view what,
                      const std::function<void(const std::string& temporary)>& write_to,
                      Durability durability = Durability::Renamed);

}  // namespace emlt
