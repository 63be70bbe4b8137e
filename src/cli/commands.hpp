// Subcommands of the cubecal tool. Each registers its options on the parent
// app and returns the function to run once parsing succeeded.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace cubecal::cli {

using Command = std::function<int()>;

CLI::App* add_dev_command(CLI::App& app, Command& run);
CLI::App* add_demo_command(CLI::App& app, Command& run);

}  // namespace cubecal::cli
