#include <fmt/core.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <future>

#include "cli/commands.h"
#include "cli/mlt_report.h"
#include "cli/readable_range.h"
#include "cli/render_job.h"
#include "cli/signals.h"
#include "emlt/core/cluster.h"
#include "emlt/core/error.h"
#include "emlt/core/interruption.h"
#include "emlt/image/image_metrics.h"
#include "emlt/integrators/mlt/mlt_integrator.h"
#include "emlt/integrators/registry.h"
#include "emlt/scene/loaders/loader.h"
#include "emlt/settings/render_option.h"

namespace emlt::cli {

std::map<std::string, std::string> parse_defines(const std::vector<std::string>& defines) {
  std::map<std::string, std::string> result;
  for (const auto& d : defines) {
    const auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error("-D " + d + ": expected name=value");
    result[d.substr(0, eq)] = d.substr(eq + 1);
  }
  return result;
}

// A validator that refuses what the option does not take, in its own words.
CLI::Validator validator_for(const OptionValues& values) {
  switch (values.kind) {
    case OptionValues::Kind::Whole: {
      const auto whole = [](double v) {
        return v >= 9.2e18 ? INT64_MAX : v <= -9.2e18 ? INT64_MIN : int64_t(v);
      };
      return whole_number(whole(values.low), whole(values.high), values.takes);
    }
    case OptionValues::Kind::Real:
      return real_number(values.low, values.low_open, values.high, values.takes);
    case OptionValues::Kind::Word:
      return CLI::IsMember(values.words);
    case OptionValues::Kind::Text:
      break;
  }
  return CLI::Validator();
}

void add_render_options(CLI::App& command, RenderOptions& o) {
  command.add_option("scene", o.scene, "Scene file (.json or Mitsuba .xml)")->required();
  command.add_option("-o,--output", o.output, "Output image (.exr, .pfm, .png, .hdr)");
  std::string integrators;
  for (const std::string& name : integrator_names())
    integrators += (integrators.empty() ? "" : " | ") + name;
  command.add_option("--integrator", o.integrator, integrators);
  command.add_option("--width", o.width, "Image width in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  command.add_option("--height", o.height, "Image height in pixels")
      ->check(whole_number(1, 16384, "a whole number of pixels from 1 to 16384"));
  // Every option an integrator or the run loop declares.
  for (const RenderOption& option : render_options()) {
    CLI::Option* added = command.add_option(option.flag, o.option_text[option.flag], option.help);
    if (option.values.kind != OptionValues::Kind::Text) added->check(validator_for(option.values));
  }
  command.add_option("--reference", o.reference, "Reference image for error metrics");
  command.add_option("--log", o.log,
                     "Convergence log (CSV) at power-of-two samples/mutations per pixel; needs --reference");
  command.add_option("--checkpoint", o.checkpoint,
                     "Save the render's whole state to this file every --checkpoint-interval "
                     "seconds, on Ctrl-C or SIGTERM, and when it finishes");
  command.add_option("--checkpoint-interval", o.checkpoint_interval,
                     "Seconds between checkpoints (default 600)")
      ->check(real_number(0.0, true, kMaxTimeSeconds,
                          "a positive number of seconds, at most 30 days"));
  command.add_option("--resume", o.resume,
                     "Continue the render saved in this checkpoint (same scene and settings; the "
                     "budget may grow); checkpoints go on into it unless --checkpoint says otherwise");
  command.add_option("-D", o.defines, "Scene parameter, name=value (repeatable)");
  command.add_flag("-q,--quiet", o.quiet, "No progress bar");
  command.add_flag("--strict", o.strict,
                   "Fail if the scene uses anything emlt approximates or cannot honour");
  command.add_flag("--bvh-only", o.bvh_only,
                   "Trace every ray through Embree's BVH, also on scenes of a few dozen triangles "
                   "that emlt otherwise tests one by one (for comparisons; the image differs "
                   "only by rounding)");
}

RenderRequest render_request(const CLI::App& command, const RenderOptions& o) {
  const auto given = [&](const std::string& flag) { return command.count(flag) > 0; };
  RenderRequest r;
  r.scene = o.scene;
  r.defines = o.defines;
  if (given("--integrator")) r.integrator = o.integrator;
  if (given("--width")) r.width = o.width;
  if (given("--height")) r.height = o.height;
  for (const RenderOption& option : render_options())
    if (given(option.flag)) r.options[option.flag] = o.option_text.at(option.flag);
  r.output = o.output;
  r.reference = o.reference;
  r.log = o.log;
  r.checkpoint = o.checkpoint;
  r.resume = o.resume;
  if (given("--checkpoint-interval")) r.checkpoint_interval = o.checkpoint_interval;
  r.progress = !o.quiet;
  r.strict = o.strict;
  r.bvh_only = o.bvh_only;
  return r;
}

std::string write_render_image(const std::string& output, const Image& image) {
  // The PNG preview is written beside the image, at once: each is one thread's compression.
  std::string outputs = output;
  std::future<void> preview_written;
  if (std::filesystem::path(output).extension().string() != ".png") {
    const std::string preview = preview_path_for(output);
    preview_written =
        std::async(std::launch::async, [&image, preview] { write_image(preview, image); });
    outputs += " + " + preview;
  }
  write_image(output, image);
  if (preview_written.valid()) preview_written.get();
  return outputs;
}

int run_render(const CLI::App& command, RenderOptions& o) {
  RenderRequest request = render_request(command, o);
  if (request.output.empty())
    request.output = std::filesystem::path(o.scene).stem().string() + ".exr";
  RenderJob job(std::move(request), [](const std::string& warning) {
    std::fprintf(stderr, "emlt: warning: %s\n", warning.c_str());
  });
  const RenderSettings& settings = job.settings();
  // Test hook: stop as if by Ctrl-C after this many samples or mutations (tests/e2e).
  if (const char* units = std::getenv("EMLT_STOP_AFTER"))
    interruption::stop_after(std::strtoull(units, nullptr, 10));
  handle_stop_signals();

  ProgressReporter progress(settings.progress);
  RenderResult result = job.run(progress);
  if (!cluster::is_root()) return result.interrupted ? exit_status_for_stop() : 0;

  const std::string outputs = write_render_image(job.request().output, result.image);
  if (const auto* chains = dynamic_cast<const ChainStatisticsSource*>(&job.integrator()))
    report_mlt_statistics(settings.integrator, chains->chain_statistics(), settings.stats_path);
  if (const std::optional<ImageMetrics> m = job.against_reference(result.image))
    std::fprintf(stderr, "against %s: mse %.6g, relmse %.6g, mse without visible emitters %.6g, mean ratio %.5f\n",
                 o.reference.c_str(), m->mse, m->rel_mse, m->mse_no_emitter, m->mean_ratio);
  if (result.invalid_samples > 0)
    std::fprintf(stderr, "emlt: warning: %llu NaN/Inf samples were dropped\n",
                 static_cast<unsigned long long>(result.invalid_samples));
  const std::string name = job.integrator().name();
  if (result.interrupted) {
    const char* unit = job.mcmc() ? "mutations" : "samples";
    std::string done = fmt::format("{:.4g} {} per pixel", result.per_pixel, unit);
    if (!result.stopped_in.empty()) done = "in " + result.stopped_in + ", before the chains began";
    std::string saved;
    if (job.checkpoints_written() > 0)
      saved = fmt::format("; state saved in {} (continue with --resume {})", job.checkpoint_path(),
                          job.checkpoint_path());
    fmt::print("{}: stopped by {} after {:.2f} s, {} -> {}{}\n", name, stop_signal_name(),
               result.seconds, done, outputs, saved);
    return exit_status_for_stop();
  }
  const double rate = result.seconds > 0.0 ? double(result.samples) / result.seconds : 0.0;
  // An MCMC render's work is counted in mutations (its samples_per_pixel is the mutations per
  // pixel, rounded), not in camera samples.
  if (job.mcmc())
    fmt::print("{}: {}x{}, {:.4g} mutations per pixel, {:.2f} s, {:.3f} M mutations/s -> {}\n",
               name, result.image.width, result.image.height,
               double(result.samples) / (double(result.image.width) * result.image.height),
               result.seconds, rate * 1e-6, outputs);
  else
    fmt::print("{}: {}x{}, {} spp, {:.2f} s, {:.3f} M samples/s -> {}\n", name,
               result.image.width, result.image.height, result.samples_per_pixel, result.seconds,
               rate * 1e-6, outputs);
  return 0;
}

}  // namespace emlt::cli
