#include "chromatag/verify/family_check.h"

#include <cstdio>
#include <cstdlib>

#include "chromatag/generator/sheet.h"

namespace chromatag {

std::optional<FamilyVerdict> VerifyFamily(const std::string& family_name, const Palette& palette,
                                          const VerifyOptions& options, std::string* error) {
  SheetOptions sheet;
  sheet.family = TagFamily::Load(family_name, error);
  if (!sheet.family) return std::nullopt;
  sheet.ids = sheet.family->kept_ids();
  sheet.palette = palette;
  // Small enough for many per page, at least 6 px per cell at 200 dpi.
  sheet.tag_size_mm = sheet.family->black_square_cells() * 2.5;
  char folder[] = "/tmp/chromatag-verify-XXXXXX";
  if (mkdtemp(folder) == nullptr) {
    if (error) *error = "cannot create a temporary folder in /tmp";
    return std::nullopt;
  }
  const std::string path = std::string(folder) + "/" + family_name + ".pdf";
  std::vector<std::string> written;
  std::optional<SheetVerdict> sheet_verdict;
  if (WriteSheet(sheet, path, error, &written)) {
    sheet_verdict = VerifySheetFile(path, options, error);
  }
  for (const auto& file : written) std::remove(file.c_str());
  std::remove(folder);
  if (!sheet_verdict) return std::nullopt;

  auto decoder =
      CodeDecoder::Create(sheet.family, CodeDecoder::DefaultRadius(*sheet.family), error);
  if (!decoder) return std::nullopt;
  FamilyVerdict verdict;
  verdict.sheet = *sheet_verdict;
  verdict.audit = AuditFamily(*decoder);
  verdict.passed = verdict.sheet.passed && verdict.audit.DecodingIsSafe();
  return verdict;
}

}  // namespace chromatag
