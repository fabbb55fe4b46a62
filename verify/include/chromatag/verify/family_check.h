// `chromatag verify --family F --all`: every kept ID rendered, printed to a
// sheet and detected again, plus the family audit (families/audit.h).
#ifndef CHROMATAG_VERIFY_FAMILY_CHECK_H_
#define CHROMATAG_VERIFY_FAMILY_CHECK_H_

#include <optional>
#include <string>

#include "chromatag/families/audit.h"
#include "chromatag/verify/sheet_check.h"

namespace chromatag {

struct FamilyVerdict {
  SheetVerdict sheet;  // The round trip of every kept ID.
  FamilyAudit audit;
  bool passed = false;  // Every tag passed and decoding within the radius is safe.
};

// Renders every kept ID of `family_name` as a PDF sheet in a temporary folder
// (removed afterwards), verifies it, and audits the family's codes.
std::optional<FamilyVerdict> VerifyFamily(const std::string& family_name, const Palette& palette,
                                          const VerifyOptions& options,
                                          std::string* error = nullptr);

// `chromatag verify --family F --all --json`'s document, on one line: the
// round trip's verdict as SheetVerdictJson writes it, "family", "audit"
// (FamilyAuditJson), "passed" for the whole check, and "stress" (StressJson)
// when `stress` is not null.
std::string FamilyVerdictJson(const std::string& family, const FamilyVerdict& verdict,
                              const std::vector<TagStress>* stress = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_FAMILY_CHECK_H_
