// chromatag: print, detect and calibrate ChromaTag fiducial markers.
#include <CLI/CLI.hpp>
#include <iostream>

#include "chromatag/families/version.h"
#include "commands.h"

int main(int argc, char** argv) {
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version.
    std::cerr << "chromatag: error: " << e.what() << " (see chromatag --help)\n";
    return chromatag::cli::kExitUsage;
  }
  return action ? action() : chromatag::cli::kExitUsage;
}
