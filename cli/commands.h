// The `chromatag` subcommands. Each Register<Command> adds its subcommand and
// binds flags straight to an options struct; the Run<Command> functions hold
// no algorithm, only input checking, library calls and output.
#ifndef CHROMATAG_CLI_COMMANDS_H_
#define CHROMATAG_CLI_COMMANDS_H_

#include <CLI/CLI.hpp>
#include <cctype>
#include <functional>
#include <string>

#include "chromatag/base/input_file.h"

namespace chromatag::cli {

// Exit codes: 0 success, 1 the job failed, 2 bad usage or input.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// The one error line of a command: "chromatag <command>: <message>" on
// stderr, control characters replaced (a message may quote the bytes of a
// broken file, escape sequences included). Returns `code`.
int Fail(const char* command, const std::string& message, int code = kExitUsage);

// printf to std::cout, so that it goes through the same escaping as every
// other output (main.cc).
void Print(const char* format, ...) __attribute__((format(printf, 1, 2)));

// A --family value as AprilTag names it ("tag16h5", "tag36h11") becomes this
// toolkit's name ("16h5", "36h11"); put before the option's check.
inline CLI::Validator FamilyPrefix() {
  return CLI::Validator(
      [](std::string& name) {
        if (name.rfind("tag", 0) == 0) name = name.substr(3);
        return std::string();
      },
      "");
}

// A subcommand's action, run after parsing; returns an exit code.
using Action = std::function<int()>;

void RegisterFamilies(CLI::App& app, Action* action);
void RegisterPalettes(CLI::App& app, Action* action);
void RegisterGenerate(CLI::App& app, Action* action);
void RegisterVerify(CLI::App& app, Action* action);
void RegisterDetect(CLI::App& app, Action* action);
void RegisterCalib(CLI::App& app, Action* action);  // calib-sheet and calibrate.
void RegisterCalibrateCamera(CLI::App& app, Action* action);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_COMMANDS_H_
