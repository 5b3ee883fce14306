// The options of the hil and qemu-command subcommands (main.cpp declares the others): hil has the most.
#pragma once

#include <CLI/CLI.hpp>

#include "commands.hpp"

namespace lashid::app {

CLI::App* add_hil(CLI::App& app, HilArgs& args);
CLI::App* add_qemu_command(CLI::App& app, QemuCommandArgs& args);

}  // namespace lashid::app
