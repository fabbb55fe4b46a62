// The sheet the print check's tests print, scan and photograph: every kept
// 16h5 ID at 30 mm on A4 (three pages), written into a temporary folder of
// its own, its pages rasterised at kPrintedSheetDpi, and the SWOP press.
#ifndef CHROMATAG_TESTS_PRINTED_SHEET_H_
#define CHROMATAG_TESTS_PRINTED_SHEET_H_

#include <memory>
#include <string>

#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"

namespace chromatag::testing {

inline constexpr double kPrintedSheetDpi = 300.0;

struct PrintedSheet {
  std::string dir;  // Holds tags.pdf and its sidecar; removed with the sheet.
  SheetRecord record;
  SheetImages images;
  std::unique_ptr<IccPress> press;

  static double PxPerMm() { return kPrintedSheetDpi / 25.4; }
  ~PrintedSheet();
};

// Nullptr with *error when a step fails. `name` makes the folder's name
// (with the process ID), so that test programs running at once do not meet.
std::unique_ptr<PrintedSheet> MakePrintedSheet(const std::string& name, std::string* error);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_PRINTED_SHEET_H_
