#include "sources.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include "commands.h"

namespace chromatag::cli {
namespace {

namespace fs = std::filesystem;

Source MakeSource(SourceKind kind, std::string name) {
  Source source;
  source.kind = kind;
  source.name = std::move(name);
  return source;
}

}  // namespace

bool IsVideo(const fs::path& path) {
  const std::string ext = LowerExtension(path.string());
  for (const char* v : {".avi", ".mp4", ".mkv", ".mov", ".webm", ".mpg", ".mpeg", ".m4v"})
    if (ext == v) return true;
  return false;
}

bool IsImage(const fs::path& path) {
  const std::string ext = LowerExtension(path.string());
  for (const char* v : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".pgm", ".webp"})
    if (ext == v) return true;
  return false;
}

bool OpenSource(const Source& source, double open_timeout_s, cv::VideoCapture* capture) {
  if (source.camera_index >= 0) return capture->open(source.camera_index);
  if (source.kind != SourceKind::kStream) return capture->open(source.name);
  const int ms = static_cast<int>(std::lround(open_timeout_s * 1000.0));
  return capture->open(source.name, cv::CAP_FFMPEG, {cv::CAP_PROP_OPEN_TIMEOUT_MSEC, ms});
}

namespace {

// A folder's images and videos, sorted; its subfolders named in *notes
// (not read), entries that cannot be read in *skipped.
void ReadFolder(const std::string& input, std::vector<Source>* sources,
                std::vector<std::string>* notes, std::vector<std::string>* skipped) {
  std::error_code ec;
  std::vector<fs::path> files;
  std::vector<std::string> bad;
  for (const auto& entry : fs::directory_iterator(fs::path(input), ec)) {
    // An entry whose type cannot be read (a symbolic link loop, a
    // dangling link) is named and passed over; the rest are read.
    std::error_code entry_ec;
    const fs::file_status status = entry.status(entry_ec);
    const bool wanted = IsImage(entry.path()) || IsVideo(entry.path());
    if (entry_ec && entry_ec != std::errc::no_such_file_or_directory && wanted) {
      bad.push_back("'" + entry.path().string() + "': " + entry_ec.message() + ", skipped");
    } else if (fs::is_directory(status) && notes) {
      notes->push_back("'" + entry.path().string() + "' is a folder inside '" + input +
                       "', not read: give it as an input to read it");
    } else if (fs::is_regular_file(status) && wanted) {
      files.push_back(entry.path());
    } else if (!fs::exists(status) && wanted) {
      bad.push_back("'" + entry.path().string() + "': a link to nothing, skipped");
    } else if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status)) {
      // Reading a FIFO blocks, a device never ends: named, never read.
      const char* kind = fs::is_fifo(status)     ? "a FIFO"
                         : fs::is_socket(status) ? "a socket"
                         : fs::is_character_file(status) || fs::is_block_file(status)
                             ? "a device"
                             : "not a regular file";
      bad.push_back("'" + entry.path().string() + "': " + kind + ", skipped");
    }
  }
  if (notes) std::sort(notes->begin(), notes->end());
  std::sort(bad.begin(), bad.end());
  if (skipped) skipped->insert(skipped->end(), bad.begin(), bad.end());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files)
    sources->push_back(
        MakeSource(IsVideo(file) ? SourceKind::kVideo : SourceKind::kImage, file.string()));
}

// Overlay names: the file name with its extension (scene.jpg and scene.mp4
// differ), and a counter for names met before (a/x.png, b/x.png).
void NameOverlays(std::vector<Source>* sources) {
  std::map<std::string, int> used;
  for (Source& s : *sources) {
    std::string stem =
        s.kind == SourceKind::kStream ? "stream" : fs::path(s.name).filename().string();
    if (s.camera_index >= 0) stem = "camera" + std::to_string(s.camera_index);
    std::replace(stem.begin(), stem.end(), '.', '_');
    // Room for a counter, a frame number and ".png" within a file name's
    // 255 bytes: a longer name is cut (on a UTF-8 character boundary) and
    // told apart by a hash of the whole.
    constexpr size_t kMaxStem = 200;
    if (stem.size() > kMaxStem) {
      char hash[16];
      std::snprintf(hash, sizeof hash, "~%08zx", std::hash<std::string>()(stem) & 0xffffffffu);
      size_t cut = kMaxStem - 9;
      while (cut > 0 && (static_cast<unsigned char>(stem[cut]) & 0xc0) == 0x80) --cut;
      stem = stem.substr(0, cut) + hash;
    }
    const int n = ++used[stem];
    s.overlay_stem = n == 1 ? stem : stem + "-" + std::to_string(n);
  }
}

}  // namespace

bool GatherSources(const std::vector<std::string>& inputs, const std::vector<int>& camera_indices,
                   std::vector<Source>* sources, std::string* error,
                   std::vector<std::string>* notes, std::vector<std::string>* skipped) {
  std::vector<std::string> missing;
  for (const std::string& input : inputs) {
    std::error_code ec;
    const fs::path path(input);
    const bool file_url = input.rfind("file:", 0) == 0;
    if (file_url && !fs::exists(fs::path(input.substr(5)), ec)) {
      // A local file named as a URL (read as a stream, as FFmpeg reads it:
      // the path after "file:") must exist, as every input must.
      missing.push_back(input);
    } else if (file_url && !fs::is_regular_file(input.substr(5), ec)) {
      *error = "'" + input + "' is not a regular file (a FIFO or a device would block the run)";
      return false;
    } else if (input.find("://") != std::string::npos) {
      sources->push_back(MakeSource(SourceKind::kStream, input));
    } else if (input.rfind("/dev/video", 0) == 0) {
      if (!fs::exists(path, ec)) {
        missing.push_back(input);
      } else {
        sources->push_back(MakeSource(SourceKind::kCamera, input));
      }
    } else if (fs::is_directory(path, ec)) {
      ReadFolder(input, sources, notes, skipped);
    } else if (!fs::exists(path, ec)) {
      missing.push_back(input);
    } else if (!fs::is_regular_file(path, ec)) {
      // A FIFO named .png would block the run forever; a device is not an image.
      *error = "'" + input + "' is not a regular file, a folder, /dev/videoN or a URL";
      return false;
    } else {
      sources->push_back(
          MakeSource(IsVideo(path) ? SourceKind::kVideo : SourceKind::kImage, input));
    }
  }
  for (int index : camera_indices) {
    if (index < 0) {
      *error = "--camera-index " + std::to_string(index) + ": a camera index is 0 or more";
      return false;
    }
    Source camera = MakeSource(SourceKind::kCamera, "camera " + std::to_string(index));
    camera.camera_index = index;
    sources->push_back(camera);
  }
  if (!missing.empty()) {
    *error = "no such file or folder: '" + missing[0] + "'" +
             (missing.size() > 1 ? " (and " + std::to_string(missing.size() - 1) + " more)" : "");
    return false;
  }
  if (sources->empty()) {
    *error =
        "no input: give images, folders, videos, /dev/videoN, a stream URL or "
        "--camera-index N";
    return false;
  }
  NameOverlays(sources);
  return true;
}

}  // namespace chromatag::cli
