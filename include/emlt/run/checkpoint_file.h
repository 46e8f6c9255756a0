#pragma once
// The checkpoint file: "EMLTCKPT", the format version, the payload's length, the payload and
// its checksum. The payload holds two sections: the header (what the render was made of,
// written and checked by the command line: the scene's fingerprint, every argument that
// affects the image, the log rows) and the integrator's state (render_control.h). Written to
// a temporary name beside the target, flushed to disk with fsync and renamed over it, so a
// crash or a signal while writing leaves the previous checkpoint whole.
#include <cstdint>
#include <string>
#include <string_view>

namespace emlt::checkpoint_file {

// Raised whenever the layout of any integrator's state or of the header changes.
// 2: PSSMLT's per-length counters. 3: MLT/EMLT's counters in up to 256 blocks (were 64).
// 5: the path-space chains' normalisation drawn beside them (normalisation_pass.h).
// 6: pssmlt's and mmlt's two parts of the image in layers of their films, and the sums of
// their converging b (pss_chains.h, pss_normalisation.h). 7: mmlt's BDPT samples of b_k split
// by length, at the end of its chains' section.
inline constexpr uint32_t kVersion = 7;
// The oldest version still read: 4 lacks only the sums of the normalisation at the end of the
// path-space chains' section, which a resumed render then starts from the bootstrap's figures.
// pssmlt's and mmlt's chains' sections of formats 4 and 5 hold one film of the two parts
// summed, which cannot be parted again: their renders resume only from before the chains.
inline constexpr uint32_t kOldestReadable = 4;

struct Contents {
  std::string header;
  std::string state;
  uint32_t version = kVersion;  // the format it was written in
};

// Throws emlt::Error naming the path on any I/O failure; never leaves a partial file.
void write(const std::string& path, std::string_view header, std::string_view state);

// Throws emlt::Error "<path>: <problem>" for a missing, truncated, corrupted (checksum) or
// foreign file, or one of another format version.
Contents read(const std::string& path);

}  // namespace emlt::checkpoint_file
