// The built-in palettes, compiled in from families/palettes/*.json by CMake
// (see families/CMakeLists.txt); the JSON files are the source of truth.
#ifndef CHROMATAG_FAMILIES_SRC_BUILTIN_PALETTES_H_
#define CHROMATAG_FAMILIES_SRC_BUILTIN_PALETTES_H_

namespace chromatag::internal {

struct BuiltinPaletteEntry {
  const char* name;
  const char* json;
};

extern const BuiltinPaletteEntry kBuiltinPalettes[2];

}  // namespace chromatag::internal

#endif  // CHROMATAG_FAMILIES_SRC_BUILTIN_PALETTES_H_
