// Detector settings as a JSON file, written by `chromatag calibrate` and read
// by `chromatag detect --config` (docs/calibration.md, "Detector config").
//
//   {
//     "schema": "chromatag-detector-config", "schema_version": 1,
//     "options": {"adiff_thresh": 18.5, "border_thresh": 6.0,
//                 "min_decision_margin": 2.0, ...},
//     "calibration": {...free-form provenance, ignored when read...}
//   }
//
// "options" may name any subset of the DetectorOptions fields below; the rest
// keep their defaults (or the caller's values). Unknown members are refused,
// so a typo does not pass silently.
#ifndef CHROMATAG_DETECTOR_CONFIG_H_
#define CHROMATAG_DETECTOR_CONFIG_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/detector/options.h"

namespace chromatag {

inline constexpr const char* kDetectorConfigSchema = "chromatag-detector-config";

// The names "options" may hold, as in the file: every DetectorOptions field
// but report_rejected and time_stages (a run's choices), camera and tag_size (a rig's, not a
// print's). Python's Detector takes the same names as keyword arguments.
std::vector<std::string> DetectorConfigFieldNames();

// Writes `fields` of `options` (names as in DetectorConfigFieldNames; empty:
// all of them) with `provenance` (a JSON object's text, or empty) as
// "calibration".
std::string DetectorConfigToJson(const DetectorOptions& options,
                                 const std::vector<std::string>& fields = {},
                                 const std::string& provenance_json = "");

// Applies the file's options on top of `*options` and validates the result
// (DetectorOptions::IsValid). Refuses (false, *error) malformed JSON, another
// schema or version, unknown or mistyped fields, and values out of range;
// *options is untouched then.
bool ParseDetectorConfig(const std::string& text, DetectorOptions* options,
                         std::string* error = nullptr);

// Reads and parses `path`; errors name the path.
bool LoadDetectorConfig(const std::string& path, DetectorOptions* options,
                        std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_CONFIG_H_
