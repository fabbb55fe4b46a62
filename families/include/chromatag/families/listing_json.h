// The JSON of the `chromatag families` and `chromatag palettes` listings:
// one writer each.
#ifndef CHROMATAG_FAMILIES_LISTING_JSON_H_
#define CHROMATAG_FAMILIES_LISTING_JSON_H_

#include <string>
#include <utility>
#include <vector>

#include "chromatag/families/decoder.h"
#include "chromatag/families/palette.h"

namespace chromatag {

// `chromatag families --json`'s document (indented by 2): "families", per
// family its geometry, kept and rejected IDs, Hamming distances and its
// decoder's radius and table size. Each family with its decoder.
std::string FamiliesJson(
    const std::vector<std::pair<const TagFamily*, const CodeDecoder*>>& families);

// `chromatag palettes --json`'s document (indented by 2): "palettes", per
// palette its name, description, shades (lab, srgb, hex) and checks
// (CheckPalette with the default limits).
std::string PalettesJson(const std::vector<Palette>& palettes);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_LISTING_JSON_H_
