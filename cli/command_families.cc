#include <iostream>

#include "chromatag/families/decoder.h"
#include "chromatag/families/family.h"
#include "chromatag/families/listing_json.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

struct FamiliesOptions {
  std::string family;  // Empty: every family.
  bool json = false;
};

void PrintFamily(const TagFamily& family, const CodeDecoder& decoder) {
  const int d = family.payload_width();
  std::cout << "Family " << family.name() << "\n"
            << "  payload        " << d << "x" << d << " = " << family.num_bits()
            << " bits: " << family.num_red_cells() << " red cells (centre), "
            << family.num_green_cells() << " green cells (ring)\n"
            << "  black square   " << family.black_square_cells() << " cells (the tag size)\n"
            << "  kept IDs       " << family.kept_ids().size() << " of "
            << family.num_apriltag_ids() << ": " << FormatIdRanges(family.kept_ids()) << "\n";
  if (family.rejected_ids().empty()) {
    std::cout << "  rejected IDs   none\n";
  }
  for (size_t i = 0; i < family.rejected_ids().size(); ++i) {
    const auto& r = family.rejected_ids()[i];
    std::cout << (i == 0 ? "  rejected IDs   " : "                 ") << r.id << ": " << r.reason
              << "\n";
  }
  std::cout << "  min Hamming    " << family.min_hamming()
            << " over all rotations of the kept codes (AprilTag's nominal "
            << family.apriltag_min_hamming() << ")\n"
            << "  decoding       corrects up to " << decoder.radius() << " bits (safe up to "
            << family.max_safe_radius() << "); table of " << decoder.memory_bytes() / 1024
            << " KiB\n";
}

int RunFamilies(const FamiliesOptions& options) {
  const std::vector<std::string> names =
      options.family.empty() ? TagFamily::Names() : std::vector<std::string>{options.family};
  // Each family with its decoder, for --json.
  std::vector<std::shared_ptr<const TagFamily>> families;
  std::vector<std::unique_ptr<CodeDecoder>> decoders;
  for (size_t i = 0; i < names.size(); ++i) {
    std::string error;
    auto family = TagFamily::Load(names[i], &error);
    if (!family) return Fail("families", error);
    auto decoder = CodeDecoder::Create(family, CodeDecoder::DefaultRadius(*family), &error);
    if (!decoder) return Fail("families", error, kExitFailure);
    if (options.json) {
      families.push_back(std::move(family));
      decoders.push_back(std::move(decoder));
    } else {
      if (i) std::cout << "\n";
      PrintFamily(*family, *decoder);
    }
  }
  if (options.json) {
    std::vector<std::pair<const TagFamily*, const CodeDecoder*>> listed;
    for (size_t i = 0; i < families.size(); ++i)
      listed.push_back({families[i].get(), decoders[i].get()});
    std::cout << FamiliesJson(listed) << "\n";
  }
  return kExitOk;
}

}  // namespace

void RegisterFamilies(CLI::App& app, Action* action) {
  auto options = std::make_shared<FamiliesOptions>();
  CLI::App* command = app.add_subcommand(
      "families", "Show the tag families: kept and rejected IDs, cells, Hamming distances");
  command->add_option("--family", options->family, "Only this family")
      ->transform(FamilyPrefix())
      ->check(CLI::IsMember(TagFamily::Names()));
  command->add_flag("--json", options->json, "Print JSON instead of a table");
  command->callback([options, action] { *action = [options] { return RunFamilies(*options); }; });
}

}  // namespace chromatag::cli
