#include "emlt/integrators/mlt/mcmc_phase_state.h"

#include "emlt/core/error.h"

namespace emlt {

namespace {
constexpr uint8_t kPhaseDirect = 0, kPhaseChains = 1;
}  // namespace

void McmcPhaseState::load(std::string_view saved, bool direct_separate, int width, int height) {
  StateReader in(saved);
  const uint8_t phase = in.get<uint8_t>();
  if (phase != kPhaseDirect && phase != kPhaseChains)
    throw StateError("the saved render is in no known phase");
  earlier_seconds = in.get<double>();
  if (direct_separate) direct.load(in, width, height);
  if (phase == kPhaseChains) chain_section = std::string(in.get_block());
  in.expect_end();
}

void McmcPhaseState::save(StateWriter& out, double seconds, bool direct_separate,
                          const std::function<void(StateWriter&)>& chains) const {
  out.put<uint8_t>(chains || !chain_section.empty() ? kPhaseChains : kPhaseDirect);
  out.put<double>(seconds);
  if (direct_separate) direct.save(out);
  if (chains) {
    StateWriter section;
    chains(section);
    out.put_block(section.data());
  } else if (!chain_section.empty()) {
    out.put_block(chain_section);
  }
}

}  // namespace emlt
