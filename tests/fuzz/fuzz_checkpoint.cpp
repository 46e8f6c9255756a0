// libFuzzer target: checkpoints (--checkpoint / --resume). A file's checksum turns away
// nearly every mutated file before any loader behind it sees a byte, so the first input
// byte (modulo 9) says what the rest is:
//   0      a whole checkpoint file, read as --resume reads it: checkpoint_file::read, the
//          command line's header section (CheckpointHeader::decode, then check_matches
//          against this target's render) and, when it matches, the state resumed by the
//          integrator the header names;
//   1 .. 8 the integrator state of a resume of pt, bdpt, mlt, gamlt, emlt, pssmlt (over the
//          path tracer), pssmlt over BDPT or mmlt, with no checksum in the way: the loaders
//          behind it (PixelRenderState, the pass schedule, BDPT's film and splat lists,
//          MLT's chains with their paths, films and sweep, the primary-sample chains with
//          their coordinates and splats) and whatever they let through to the render itself.
// The render is a tiny one (checkpoint_resume.h). emlt::Error and emlt::StateError are the
// loaders' refusals, and a render that finishes is as good an outcome; anything else (a
// crash, a sanitizer report, a hang, a huge allocation) is a finding.
#include <string>

#include "checkpoint_resume.h"
#include "cli/checkpoint_header.h"
#include "emlt/core/error.h"
#include "emlt/core/state_io.h"
#include "emlt/run/checkpoint_file.h"
#include "fuzz_input.h"

namespace {

using emlt::fuzz::CheckpointFixture;

void resume(const std::string& integrator, std::string state) {
  try {
    CheckpointFixture::get().resume(integrator, std::move(state));
  } catch (const emlt::StateError&) {
    // the state refused: what `emlt render --resume` reports as "cannot resume: ..."
  } catch (const emlt::Error&) {
    // a refusal the render itself makes (an overflowing film, for one)
  }
}

void read_file(const std::string& path) {
  const emlt::checkpoint_file::Contents contents = emlt::checkpoint_file::read(path);
  const emlt::cli::CheckpointHeader header =
      emlt::cli::CheckpointHeader::decode(contents.header, path);
  const CheckpointFixture& fixture = CheckpointFixture::get();
  for (const auto& [flag, value] : header.settings) {
    if (flag != "--integrator") continue;
    for (const char* name : emlt::fuzz::kCheckpointIntegrators) {
      if (value != name) continue;
      const emlt::cli::CheckpointHeader now = emlt::cli::CheckpointHeader::describe(
          fixture.scene().description(), fixture.settings(name), {});
      header.check_matches(now, path);
      resume(name, contents.state);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0] % (emlt::fuzz::kCheckpointIntegrators.size() + 1);
  if (mode == 0) return emlt::fuzz::run(data + 1, size - 1, ".ck", read_file);
  resume(emlt::fuzz::kCheckpointIntegrators[mode - 1],
         std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  return 0;
}
