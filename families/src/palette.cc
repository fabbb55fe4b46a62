#include "chromatag/families/palette.h"

#include "chromatag/base/input_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "builtin_palettes.h"

namespace chromatag {
namespace {

using json = nlohmann::json;

constexpr const char* kShadeNames[kNumShades] = {"red-1",   "red-0", "green-1",
                                                 "green-0", "black", "white"};
constexpr const char* kFormatName = "chromatag-palette";
constexpr int kFormatVersion = 1;

std::string Fixed(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f", value);
  return buffer;
}

std::string ValidShadeNames() {
  std::string names;
  for (const char* name : kShadeNames) names += std::string(names.empty() ? "" : ", ") + name;
  return names;
}

// Builds one check: `value` compared against `limit` (at least, or at most).
PaletteCheck Compare(std::string id, std::string description, PaletteCheck::Level level,
                     double value, double limit, bool at_least, std::string measured) {
  PaletteCheck check;
  check.id = std::move(id);
  check.description = std::move(description);
  check.level = level;
  check.passed = at_least ? value >= limit : value <= limit;
  check.detail = std::move(measured) + " = " + Fixed(value);
  return check;
}

}  // namespace

const char* ShadeName(Shade shade) { return kShadeNames[static_cast<int>(shade)]; }

std::optional<Shade> ShadeFromName(const std::string& name) {
  for (Shade shade : kAllShades) {
    if (name == ShadeName(shade)) return shade;
  }
  return std::nullopt;
}

namespace {

// What the palette's checks compare: the four colours and the gaps between them.
struct PaletteMeasures {
  Lab r1, r0, g1, g0;
  double a_gap;                       // min a*(reds) - max a*(greens).
  double red_b_gap;                   // b*(red-1) - b*(red-0).
  double green_b_gap;                 // b*(green-0) - b*(green-1).
  double chroma_l_min, chroma_l_max;  // L* of the four colours.
  double black_l, white_l;
};

PaletteMeasures Measure(const Palette& p) {
  PaletteMeasures m;
  m.r1 = p[Shade::kRed1];
  m.r0 = p[Shade::kRed0];
  m.g1 = p[Shade::kGreen1];
  m.g0 = p[Shade::kGreen0];
  m.a_gap = std::min(m.r1.a, m.r0.a) - std::max(m.g1.a, m.g0.a);
  m.red_b_gap = m.r1.b - m.r0.b;
  m.green_b_gap = m.g0.b - m.g1.b;
  m.chroma_l_min = std::min({m.r1.L, m.r0.L, m.g1.L, m.g0.L});
  m.chroma_l_max = std::max({m.r1.L, m.r0.L, m.g1.L, m.g0.L});
  m.black_l = p[Shade::kBlack].L;
  m.white_l = p[Shade::kWhite].L;
  return m;
}

PaletteCheck GamutCheck(const Palette& p, const PaletteLimits& limits) {
  PaletteCheck gamut;
  gamut.id = "in-srgb-gamut";
  gamut.description = "every colour can be written as sRGB";
  gamut.level = PaletteCheck::Level::kRequired;
  gamut.passed = true;
  for (Shade shade : kAllShades) {
    if (!InSrgbGamut(p[shade], limits.gamut_tolerance)) {
      gamut.passed = false;
      gamut.detail +=
          std::string(gamut.detail.empty() ? "" : ", ") + ShadeName(shade) + " is outside sRGB";
    }
  }
  if (gamut.passed) gamut.detail = "all six inside";
  return gamut;
}

// What detection needs: the reds and greens apart in a*, each pair's shades
// in order in b*, and the colours between black and white in L*.
void AddRequiredChecks(const PaletteMeasures& m, const PaletteLimits& limits,
                       std::vector<PaletteCheck>* checks) {
  const PaletteCheck::Level req = PaletteCheck::Level::kRequired;
  const Lab &r1 = m.r1, &r0 = m.r0, &g1 = m.g1, &g0 = m.g0;
  const double a_gap = m.a_gap, red_b_gap = m.red_b_gap, green_b_gap = m.green_b_gap;
  const double chroma_l_min = m.chroma_l_min, chroma_l_max = m.chroma_l_max;
  const double black_l = m.black_l, white_l = m.white_l;
  checks->push_back(
      Compare("red-green-a-gap",
              "min a*(reds) - max a*(greens) >= " + Fixed(limits.min_red_green_a_gap_required) +
                  " (detection by ADiffThresh)",
              req, a_gap, limits.min_red_green_a_gap_required, true, "gap"));
  checks->push_back(Compare("red-shades-b-order",
                            "b*(red-1) - b*(red-0) >= " + Fixed(limits.min_shade_b_gap_required) +
                                " (red-1 is the more orange red)",
                            req, red_b_gap, limits.min_shade_b_gap_required, true,
                            Fixed(r1.b) + " - " + Fixed(r0.b)));
  checks->push_back(Compare(
      "green-shades-b-order",
      "b*(green-0) - b*(green-1) >= " + Fixed(limits.min_shade_b_gap_required) +
          " (green-0 is the more yellow green)",
      req, green_b_gap, limits.min_shade_b_gap_required, true, Fixed(g0.b) + " - " + Fixed(g1.b)));
  checks->push_back(Compare("black-darker-than-colours",
                            "min L*(colours) - L*(black) >= " +
                                Fixed(limits.min_border_l_gap_required) + " (green-black border)",
                            req, chroma_l_min - black_l, limits.min_border_l_gap_required, true,
                            Fixed(chroma_l_min) + " - " + Fixed(black_l)));
  checks->push_back(Compare(
      "white-lighter-than-colours",
      "L*(white) - max L*(colours) >= " + Fixed(limits.min_border_l_gap_required) + " (quiet zone)",
      req, white_l - chroma_l_max, limits.min_border_l_gap_required, true,
      Fixed(white_l) + " - " + Fixed(chroma_l_max)));
}

// What the design recommends, for margins under real printing and light.
void AddRecommendedChecks(const PaletteMeasures& m, const PaletteLimits& limits,
                          std::vector<PaletteCheck>* checks) {
  const PaletteCheck::Level rec = PaletteCheck::Level::kRecommended;
  const Lab &r1 = m.r1, &r0 = m.r0, &g1 = m.g1, &g0 = m.g0;
  const double a_gap = m.a_gap, red_b_gap = m.red_b_gap, green_b_gap = m.green_b_gap;
  const double chroma_l_min = m.chroma_l_min, chroma_l_max = m.chroma_l_max;
  const double black_l = m.black_l, white_l = m.white_l;
  checks->push_back(Compare("red-a-equal",
                            "|a*(red-1) - a*(red-0)| <= " + Fixed(limits.max_a_spread_recommended),
                            rec, std::fabs(r1.a - r0.a), limits.max_a_spread_recommended, false,
                            "|" + Fixed(r1.a) + " - " + Fixed(r0.a) + "|"));
  checks->push_back(Compare(
      "green-a-equal", "|a*(green-1) - a*(green-0)| <= " + Fixed(limits.max_a_spread_recommended),
      rec, std::fabs(g1.a - g0.a), limits.max_a_spread_recommended, false,
      "|" + Fixed(g1.a) + " - " + Fixed(g0.a) + "|"));
  checks->push_back(
      Compare("red-green-a-gap-design",
              "min a*(reds) - max a*(greens) >= " + Fixed(limits.min_red_green_a_gap_recommended),
              rec, a_gap, limits.min_red_green_a_gap_recommended, true, "gap"));
  checks->push_back(Compare(
      "red-b-gap-design", "b*(red-1) - b*(red-0) >= " + Fixed(limits.min_shade_b_gap_recommended),
      rec, red_b_gap, limits.min_shade_b_gap_recommended, true, Fixed(r1.b) + " - " + Fixed(r0.b)));
  checks->push_back(Compare(
      "green-b-gap-design",
      "b*(green-0) - b*(green-1) >= " + Fixed(limits.min_shade_b_gap_recommended), rec, green_b_gap,
      limits.min_shade_b_gap_recommended, true, Fixed(g0.b) + " - " + Fixed(g1.b)));
  checks->push_back(
      Compare("colour-l-spread",
              "the four colours' L* within " + Fixed(limits.max_chromatic_l_spread_recommended) +
                  " (only black/white is a strong luminance edge)",
              rec, chroma_l_max - chroma_l_min, limits.max_chromatic_l_spread_recommended, false,
              Fixed(chroma_l_max) + " - " + Fixed(chroma_l_min)));
  checks->push_back(Compare("black-l", "L*(black) <= " + Fixed(limits.max_black_l_recommended), rec,
                            black_l, limits.max_black_l_recommended, false, "L*"));
  checks->push_back(Compare("white-l", "L*(white) >= " + Fixed(limits.min_white_l_recommended), rec,
                            white_l, limits.min_white_l_recommended, true, "L*"));
}

}  // namespace

std::vector<PaletteCheck> CheckPalette(const Palette& p, const PaletteLimits& limits) {
  const PaletteMeasures m = Measure(p);
  std::vector<PaletteCheck> checks;
  checks.push_back(GamutCheck(p, limits));
  AddRequiredChecks(m, limits, &checks);
  AddRecommendedChecks(m, limits, &checks);
  return checks;
}

bool MeetsRequiredChecks(const std::vector<PaletteCheck>& checks, std::string* error) {
  std::string failures;
  for (const auto& check : checks) {
    if (check.level == PaletteCheck::Level::kRequired && !check.passed) {
      failures += std::string(failures.empty() ? "" : "; ") + check.id + ": needs " +
                  check.description + ", got " + check.detail;
    }
  }
  if (error) *error = failures;
  return failures.empty();
}

std::vector<std::string> BuiltinPaletteNames() {
  std::vector<std::string> names;
  for (const auto& entry : internal::kBuiltinPalettes) names.emplace_back(entry.name);
  return names;
}

std::optional<Palette> BuiltinPalette(const std::string& name, std::string* error) {
  for (const auto& entry : internal::kBuiltinPalettes) {
    if (name == entry.name) return ParsePalette(entry.json, entry.name, error);
  }
  if (error) {
    std::string valid;
    for (const auto& known : BuiltinPaletteNames()) valid += (valid.empty() ? "" : ", ") + known;
    *error = "unknown palette '" + name + "' (valid: " + valid + ", or a palette file)";
  }
  return std::nullopt;
}

namespace {

// What is wrong with a palette's members, format and version; empty if nothing.
std::string HeaderProblem(const json& root) {
  for (const auto& item : root.items()) {
    // Not a structured binding: a lambda capturing one is C++20 (clang refuses it).
    const std::string& key = item.key();
    static const char* kKnown[] = {"format", "version", "name", "description", "lab"};
    if (std::find_if(std::begin(kKnown), std::end(kKnown),
                     [&](const char* k) { return key == k; }) == std::end(kKnown)) {
      return "palette has an unknown member \"" + key +
             "\" (allowed: format, version, name, description, lab)";
    }
  }
  if (root.contains("format") && root["format"] != kFormatName) {
    return std::string("palette \"format\" must be \"") + kFormatName + "\"";
  }
  if (root.contains("version") && root["version"] != kFormatVersion) {
    return "palette \"version\" must be " + std::to_string(kFormatVersion);
  }
  return std::string();
}

// The six shades from the "lab" object into *palette; what is wrong with
// them, or empty.
std::string ReadShades(const json& lab_object, Palette* palette) {
  bool seen[kNumShades] = {};
  for (const auto& [key, value] : lab_object.items()) {
    const auto shade = ShadeFromName(key);
    if (!shade) {
      return "palette has an unknown shade \"" + key + "\" (valid: " + ValidShadeNames() + ")";
    }
    if (!value.is_array() || value.size() != 3 ||
        !std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_number(); })) {
      return "palette shade \"" + key + "\" must be [L*, a*, b*], three numbers";
    }
    const Lab lab{value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
    if (!(lab.L >= 0.0 && lab.L <= 100.0) || !(std::fabs(lab.a) <= 128.0) ||
        !(std::fabs(lab.b) <= 128.0)) {
      return "palette shade \"" + key +
             "\" is out of range (L* in [0, 100], a* and b* in [-128, 128])";
    }
    (*palette)[*shade] = lab;
    seen[static_cast<int>(*shade)] = true;
  }
  for (Shade shade : kAllShades) {
    if (!seen[static_cast<int>(shade)]) {
      return std::string("palette is missing the shade \"") + ShadeName(shade) +
             "\" (needs all of " + ValidShadeNames() + ")";
    }
  }
  return std::string();
}

}  // namespace

std::optional<Palette> ParsePalette(const std::string& json_text, const std::string& default_name,
                                    std::string* error) {
  auto fail = [&](const std::string& message) -> std::optional<Palette> {
    if (error) *error = message;
    return std::nullopt;
  };
  if (JsonDeeperThan(json_text, kMaxJsonDepth))
    return fail("palette nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
  const json root = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) return fail("palette is not valid JSON");
  if (!root.is_object()) return fail("palette must be a JSON object with a \"lab\" member");
  const std::string header_problem = HeaderProblem(root);
  if (!header_problem.empty()) return fail(header_problem);
  Palette palette;
  palette.name = default_name;
  if (root.contains("name")) {
    if (!root["name"].is_string() || root["name"].get<std::string>().empty()) {
      return fail("palette \"name\" must be a non-empty string");
    }
    palette.name = root["name"].get<std::string>();
  }
  if (root.contains("description")) {
    if (!root["description"].is_string()) return fail("palette \"description\" must be a string");
    palette.description = root["description"].get<std::string>();
  }
  if (!root.contains("lab") || !root["lab"].is_object()) {
    return fail("palette needs a \"lab\" object with the six shades " + ValidShadeNames());
  }
  const std::string shade_problem = ReadShades(root["lab"], &palette);
  if (!shade_problem.empty()) return fail(shade_problem);
  std::string failures;
  if (!MeetsRequiredChecks(CheckPalette(palette), &failures)) {
    return fail("palette '" + palette.name + "' cannot be used: " + failures);
  }
  return palette;
}

std::optional<Palette> LoadPaletteFile(const std::string& path, std::string* error) {
  const auto text = ReadInputFile(path, "palette file", kMaxJsonFileBytes, error);
  if (!text) return std::nullopt;
  std::string stem = path.substr(path.find_last_of('/') + 1);
  stem = stem.substr(0, stem.rfind('.'));
  std::string parse_error;
  auto palette = ParsePalette(*text, stem, &parse_error);
  if (!palette && error) *error = path + ": " + parse_error;
  return palette;
}

std::string PaletteToJson(const Palette& palette) {
  // Ordered: the file reads in the order of the spec's tables.
  nlohmann::ordered_json lab = nlohmann::ordered_json::object();
  for (Shade shade : kAllShades) {
    const Lab& v = palette[shade];
    // Two decimals: far below any printer's or camera's repeatability.
    auto round2 = [](double x) { return std::round(x * 100.0) / 100.0; };
    lab[ShadeName(shade)] = {round2(v.L), round2(v.a), round2(v.b)};
  }
  nlohmann::ordered_json root = {{"format", kFormatName},
                                 {"version", kFormatVersion},
                                 {"name", palette.name},
                                 {"description", palette.description},
                                 {"lab", lab}};
  return root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace chromatag
