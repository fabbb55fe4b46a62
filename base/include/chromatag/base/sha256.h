// SHA-256, which the sidecars record for every file of a sheet.
#ifndef CHROMATAG_BASE_SHA256_H_
#define CHROMATAG_BASE_SHA256_H_

#include <string>

namespace chromatag {

// SHA-256 of `data`, as 64 lower-case hex digits (FIPS 180-4).
std::string Sha256Hex(const std::string& data);

}  // namespace chromatag

#endif  // CHROMATAG_BASE_SHA256_H_
