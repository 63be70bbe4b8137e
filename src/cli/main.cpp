// cubecal — characterize, model, simulate and calibrate attitude sensors.
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <malloc.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "field_flags.hpp"
#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace {

constexpr int kExitBadInput = 2;
constexpr int kExitInternal = 1;

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

// A closed standard output (`cubecal dev a.csv >&-`) gets a placeholder
// that refuses writes, so that no file the command opens takes descriptor 1
// and a write to standard output fails as it would have.
void hold_closed_stdout() {
  if (::fcntl(STDOUT_FILENO, F_GETFD) == -1 && errno == EBADF) {
    const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    if (fd >= 0 && fd != STDOUT_FILENO) {
      ::dup2(fd, STDOUT_FILENO);
      ::close(fd);
    }
  }
}

// What the command printed must have reached standard output: a full disk
// (`> /dev/full`) or a closed one fails the run, exit 1, instead of exit 0
// with the output lost.
int check_stdout(int code) {
  std::cout.flush();
  const bool cout_failed = !std::cout.good();
  errno = 0;
  const bool stdio_failed = std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (!cout_failed && !stdio_failed) return code;
  const int err = errno;
  std::string why = err != 0 ? std::string(" (") + std::strerror(err) + ")" : std::string();
  const int rc = fail("cannot write to standard output" + why +
                          ": what the command printed there is incomplete (redirect it to a file, or to a pipe "
                          "that reads it all)",
                      kExitInternal);
  return code != 0 ? code : rc;
}

// `cubecal frobnicate`, `cubecal calibrate frob`: CLI11 says only "A
// subcommand is required"; name the word that is not a command and list them.
// Empty when the parse did not stop at an unknown command.
std::string unknown_command(const CLI::App& top) {
  const CLI::App* at = &top;
  while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
  std::vector<std::string> rest = at->remaining();
  if (rest.empty()) rest = top.remaining();
  const auto commands = at->get_subcommands([](const CLI::App*) { return true; });
  if (commands.empty() || rest.empty() || rest.front().empty() || rest.front().front() == '-') return {};
  std::string names;
  for (const CLI::App* c : commands) names += (names.empty() ? "" : ", ") + c->get_name();
  const std::string path = at == &top ? std::string("cubecal") : "cubecal " + at->get_name();
  return "unknown command '" + rest.front() + "' (" + path + " commands: " + names + "; see " + path + " --help)";
}

}  // namespace

int main(int argc, char** argv) {
  // Large arrays (a channel, a phase record: tens of MB each) are mapped and
  // unmapped on their own. glibc's default raises this threshold to the size
  // of the first large block freed, after which the channels analysed one at
  // a time by different threads are kept in per-thread arenas and the peak
  // memory holds several of them instead of one.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  hold_closed_stdout();
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
  // What the library writes into results and files names options as flags.
  cubecal::set_face_words(cubecal::cli::flag_of);
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
  cubecal::cli::add_plan_command(app, run);
  cubecal::cli::add_report_command(app, run);
  cubecal::cli::add_demo_command(app, run);
  cubecal::cli::add_status_command(app, run);

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
    if (const std::string unknown = unknown_command(app); !unknown.empty()) return fail(unknown, kExitBadInput);
    std::string where = app.get_subcommands().empty()
                            ? std::string("cubecal --help")
                            : "cubecal " + app.get_subcommands().front()->get_name() + " --help";
    return fail(std::string(e.what()) + " (see " + where + ")", kExitBadInput);
  }

  try {
    return check_stdout(run ? run() : 0);
  } catch (const cubecal::Error& e) {
    // Usage, input and calibration errors: what the user can fix.
    return fail(cubecal::cli::cli_message(e), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (analyse fewer columns at once or a shorter record)", kExitInternal);
  } catch (const std::exception& e) {
    return fail(std::string("internal error: ") + e.what() + " (please report it)", kExitInternal);
  }
}
