// Reading the files a user hands the toolkit (palettes, sidecars, detector
// configs, camera files, LUTs): only regular files, under a size cap, and
// JSON no deeper than a cap, so that /dev/zero, a FIFO, a folder or a
// 100,000-deep array is one clear error, not memory exhaustion, a hang or a
// stack overflow.
#ifndef CHROMATAG_BASE_INPUT_FILE_H_
#define CHROMATAG_BASE_INPUT_FILE_H_

#include <cstdint>
#include <optional>
#include <string>

namespace chromatag {

// The largest JSON file the toolkit reads (a 587-tag sheet's sidecar is
// about 0.3 MiB) and the deepest nesting any of its formats uses (4).
inline constexpr std::uintmax_t kMaxJsonFileBytes = 16u << 20;
inline constexpr int kMaxJsonDepth = 32;

// The whole file, or nullopt with *error "cannot read <kind> '<path>': why"
// (no such file, not a regular file, over `max_bytes`, a read error).
std::optional<std::string> ReadInputFile(const std::string& path, const std::string& kind,
                                         std::uintmax_t max_bytes, std::string* error);

// Whether `json_text` nests arrays and objects deeper than `max_depth`
// (brackets inside strings not counted). Run before parsing: the parser's
// callers (dumps, validators) recurse.
bool JsonDeeperThan(const std::string& json_text, int max_depth);

// The largest image decoded (16384 x 16384, 256 Mpx): beyond it the frame
// alone would take gigabytes.
inline constexpr int64_t kMaxImagePixels = int64_t{1} << 28;

// The size an image file's header claims, read before anything is decoded.
struct ImageSize {
  uint64_t width = 0;
  uint64_t height = 0;
};

// The formats whose size is read from the header: PNG, JPEG (any number of
// markers and fill bytes before the frame), TIFF and BigTIFF (the first
// page), BMP, WebP, and PNM/PAM/PFM. False for anything else and for a
// header that cannot be read: such a file is not decoded (its size, and so
// the memory it would take, is unknown).
bool ImageHeaderSize(const std::string& path, ImageSize* size);
// The same for a file already in memory.
bool ImageBytesSize(const std::string& bytes, ImageSize* size);
// The formats ImageHeaderSize reads, for messages.
inline constexpr const char* kSizedImageFormats = "PNG, JPEG, TIFF, BMP, WebP, PPM/PGM/PAM/PFM";

// Why an image of `size` is not decoded ("W x H pixels, over the limit of
// 256 Mpx", a size of 0), or "" when it may be.
std::string ImageSizeProblem(const ImageSize& size);

// A path's extension lower-cased, with its dot (".png"); "" when it has
// none. File kinds are told by it the same way everywhere.
std::string LowerExtension(const std::string& path);

// Whether `text` is well-formed UTF-8 (file names go into JSON sidecars,
// which must be UTF-8).
bool IsValidUtf8(const std::string& text);

}  // namespace chromatag

#endif  // CHROMATAG_BASE_INPUT_FILE_H_
