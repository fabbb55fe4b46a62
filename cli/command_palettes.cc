#include <cstdio>
#include <iostream>

#include "chromatag/families/listing_json.h"
#include "chromatag/families/palette.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

struct PalettesOptions {
  std::string palette;       // Only this built-in palette.
  std::string palette_file;  // Or check this file.
  bool json = false;
};

const char* LevelName(PaletteCheck::Level level) {
  return level == PaletteCheck::Level::kRequired ? "required" : "recommended";
}

void PrintPalette(const Palette& palette) {
  std::cout << "Palette " << palette.name << "\n";
  if (!palette.description.empty()) std::cout << "  " << palette.description << "\n";
  std::cout << "  shade        L*      a*      b*     sRGB\n";
  for (Shade shade : kAllShades) {
    const Lab& lab = palette[shade];
    const Rgb8 rgb = palette.Srgb8(shade);
    char line[128];
    std::snprintf(line, sizeof(line), "  %-8s %6.1f  %6.1f  %6.1f   %s (%3d, %3d, %3d)\n",
                  ShadeName(shade), lab.L, lab.a, lab.b, ToHex(rgb).c_str(), rgb.r, rgb.g, rgb.b);
    std::cout << line;
  }
  std::cout << "  checks\n";
  for (const auto& check : CheckPalette(palette)) {
    std::cout << "    "
              << (check.passed ? "ok  "
                               : (check.level == PaletteCheck::Level::kRequired ? "FAIL" : "warn"))
              << "  " << check.description << ": " << check.detail << " [" << LevelName(check.level)
              << "]\n";
  }
}

int RunPalettes(const PalettesOptions& options) {
  std::vector<Palette> palettes;
  std::string error;
  if (!options.palette_file.empty()) {
    auto palette = LoadPaletteFile(options.palette_file, &error);
    if (!palette) return Fail("palettes", error);
    palettes.push_back(*palette);
  } else {
    const auto names =
        options.palette.empty() ? BuiltinPaletteNames() : std::vector<std::string>{options.palette};
    for (const auto& name : names) {
      auto palette = BuiltinPalette(name, &error);
      if (!palette) return Fail("palettes", error);
      palettes.push_back(*palette);
    }
  }
  if (options.json) {
    std::cout << PalettesJson(palettes) << "\n";
  } else {
    for (size_t i = 0; i < palettes.size(); ++i) {
      if (i) std::cout << "\n";
      PrintPalette(palettes[i]);
    }
  }
  return kExitOk;
}

}  // namespace

void RegisterPalettes(CLI::App& app, Action* action) {
  auto options = std::make_shared<PalettesOptions>();
  CLI::App* command = app.add_subcommand(
      "palettes", "Show the colour palettes: CIELAB and sRGB values and constraint checks");
  auto* name = command->add_option("--palette", options->palette, "Only this built-in palette");
  command->add_option("--palette-file", options->palette_file, "Check a palette JSON file instead")
      ->excludes(name);
  command->add_flag("--json", options->json, "Print JSON instead of a table");
  command->callback([options, action] { *action = [options] { return RunPalettes(*options); }; });
}

}  // namespace chromatag::cli
