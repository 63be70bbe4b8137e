// cubecal — characterize, model, simulate and calibrate attitude sensors.
#include <CLI/CLI.hpp>
#include <malloc.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <utility>

#include "commands.hpp"
#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace {

constexpr int kExitBadInput = 2;
constexpr int kExitInternal = 1;

// The flag of each request field a library UsageError may name.
std::string usage_message(const cubecal::UsageError& e) {
  static constexpr std::pair<const char*, const char*> kFlags[] = {
      {"units", "--unit"},
      {"lsb", "--model-lsb"},
      {"temp_index", "--temp-col"},
      {"temp_order", "--temp-order"},
      {"bias", "--bias"},
      {"columns", "--columns"},
      {"unit", "--unit"},
      {"reference_columns", "--ref-columns"},
      {"schedule", "--schedule"},
      {"plateaus", "--margin/--min-plateau/--ref-tolerance/--window"},
      {"mag_columns", "--columns"},
      {"counts_per_unit", "--lsb"},
      {"field_norm", "--field-norm"},
      {"field_column", "--field-col"},
      {"noise", "--noise"},
      {"reject_sigma", "--reject"},
      {"sampling", "--time-col/--rate"},
      {"polynomial_order", "--order"},
      {"rate", "--rate"},
      {"time_col", "--time-col"},
      {"out", "--out"},
      {"report", "--report"},
      {"estimators", "--for"},
      {"inflate", "--inflate"},
      {"gnuplot", "--gnuplot"},
      {"duration", "--duration"},
      {"binary", "--binary"},
      {"dataset", "--dataset"},
      {"stat", "--stat"},
      {"type", "--type"},
      {"taus", "--taus"},
      {"gaps", "--gaps"},
      {"topics", "--topic"},
      {"memory", "--memory"},
      {"window", "--window"},
      {"segment_length", "--segment"},
      {"min_frequency", "--fmin"},
      {"overlap", "--overlap"},
      {"bins_per_decade", "--bins-per-decade"},
      {"fit_range", "--fit-min/--fit-max"},
      {"step", "--step"},
      {"psd", "--psd"},
      {"model", "--model"},
      {"bootstrap", "--bootstrap"},
      {"wic_replicates", "--wic-replicates"},
      {"efficiency", "--efficiency"},
      {"ci", "--ci"},
  };
  for (const auto& [option, flag] : kFlags)
    if (e.option() == option) return std::string(flag) + ": " + e.what();
  return e.what();
}

// CLI11's "INI was not able to parse analyze.bogus" as a hint on the file.
std::string config_message(const CLI::ConfigError& e, const std::string& file) {
  const std::string what = e.what();
  const std::string prefix = "INI was not able to parse ";
  if (what.rfind(prefix, 0) != 0) return file + ": " + what;
  return file + ": unknown key '" + what.substr(prefix.size()) +
         "' (keys are a command's long option names in its section, e.g. [analyze] inflate = 2; see "
         "cubecal analyze --help)";
}

// One line on the terminal whatever the message quotes (a column name, a
// library's message): never raw bytes, never cut at a NUL.
int fail(const std::string& msg, int code) {
  std::fflush(stdout);
  const std::string line = cubecal::printable_text(msg);
  std::fprintf(stderr, "cubecal: error: %s\n", line.c_str());
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // Large arrays (a channel, a phase record: tens of MB each) are mapped and
  // unmapped on their own. glibc's default raises this threshold to the size
  // of the first large block freed, after which the channels analysed one at
  // a time by different threads are kept in per-thread arenas and the peak
  // memory holds several of them instead of one.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  CLI::App app{
      "cubecal: stability statistics, noise models and calibration for gyroscopes, "
      "magnetometers, accelerometers and clocks"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cubecal " CUBECAL_VERSION);
  // Repeatable runs: options from a TOML/INI file, one section per command
  // ([analyze] inflate = 2); flags on the command line override it, a key no
  // command knows is an error. Fallthrough lets `cubecal analyze --config F`
  // reach this top-level option.
  CLI::Option* config = app.set_config("--config", "",
                                       "Read options from a TOML/INI file, a section per command ([analyze] "
                                       "for = [\"kalibr\"]); command-line flags override it");
  app.allow_config_extras(CLI::config_extras_mode::error);
  app.fallthrough();
  cubecal::cli::Command run;
  cubecal::cli::set_invocation(argc, argv);
  cubecal::cli::add_dev_command(app, run);
  cubecal::cli::add_analyze_command(app, run);
  cubecal::cli::add_simulate_command(app, run);
  cubecal::cli::add_calibrate_command(app, run);
  cubecal::cli::add_turnon_command(app, run);
  cubecal::cli::add_compare_command(app, run);
  cubecal::cli::add_psd_command(app, run);
  cubecal::cli::add_davar_command(app, run);
  cubecal::cli::add_model_command(app, run);
  cubecal::cli::add_record_command(app, run);
  cubecal::cli::add_report_command(app, run);
  cubecal::cli::add_demo_command(app, run);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ConfigError& e) {
    return fail(config_message(e, config->count() ? config->as<std::string>() : std::string("--config")),
                kExitBadInput);
  } catch (const CLI::ParseError& e) {
    std::string where = app.get_subcommands().empty()
                            ? std::string("cubecal --help")
                            : "cubecal " + app.get_subcommands().front()->get_name() + " --help";
    return fail(std::string(e.what()) + " (see " + where + ")", kExitBadInput);
  }

  try {
    return run ? run() : 0;
  } catch (const cubecal::InputError& e) {
    return fail(e.what(), kExitBadInput);
  } catch (const cubecal::UsageError& e) {
    return fail(usage_message(e), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (analyse fewer columns at once or a shorter record)", kExitInternal);
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what() + " (please report it)", kExitInternal);
  }
}
