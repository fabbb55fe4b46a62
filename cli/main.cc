// chromatag: print, detect and calibrate ChromaTag fiducial markers.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>

#include "chromatag/families/version.h"
#include "commands.h"

namespace chromatag::cli {

int Fail(const char* command, const std::string& message, int code) {
  std::string line = "chromatag " + std::string(command) + ": " + message;
  for (char& c : line) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) c = '?';
  }
  std::cerr << line << "\n";
  return code;
}

}  // namespace chromatag::cli

int main(int argc, char** argv) {
  // OpenCV's and FFmpeg's own log lines ("[ERROR:0@0.006] global ...") would
  // come before the tool's one message; the tool says what went wrong itself.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET, unless the user asks for more.
  CLI::App app{"ChromaTag toolkit: coloured fiducial markers (DeGol, Bretl and Hoiem, ICCV 2017)",
               "chromatag"};
  app.set_version_flag("--version", std::string("chromatag ") + chromatag::kVersion);
  app.require_subcommand(1);

  chromatag::cli::Action action;
  chromatag::cli::RegisterFamilies(app, &action);
  chromatag::cli::RegisterPalettes(app, &action);
  chromatag::cli::RegisterGenerate(app, &action);
  chromatag::cli::RegisterVerify(app, &action);
  chromatag::cli::RegisterDetect(app, &action);
  chromatag::cli::RegisterCalib(app, &action);
  chromatag::cli::RegisterCalibrateCamera(app, &action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version.
    std::cerr << "chromatag: error: " << e.what() << " (see chromatag --help)\n";
    return chromatag::cli::kExitUsage;
  }
  if (!action) return chromatag::cli::kExitUsage;
  try {
    return action();
  } catch (const std::exception& e) {
    // A library threw where it should have returned an error: still one
    // line and a failed exit, never an abort.
    return chromatag::cli::Fail(
        app.get_subcommands().empty() ? "error" : app.get_subcommands().front()->get_name().c_str(),
        std::string("unexpected error: ") + e.what(), chromatag::cli::kExitFailure);
  }
}
