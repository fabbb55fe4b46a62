#include "chromatag/generator/file_util.h"

#include <glib.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace chromatag {
namespace {

bool WriteWhole(const std::string& path, const std::string& contents, std::string* error) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) {
    *error = "cannot write '" + path + "': " + std::strerror(errno);
    return false;
  }
  const bool ok = std::fwrite(contents.data(), 1, contents.size(), file) == contents.size();
  const int saved_errno = errno;
  if (std::fclose(file) != 0 || !ok) {
    *error = "cannot write '" + path + "': " + std::strerror(ok ? errno : saved_errno);
    return false;
  }
  return true;
}

}  // namespace

bool WriteFilesAtomically(const std::vector<OutputFile>& files, std::string* error) {
  std::string message;
  std::vector<std::string> temporaries;
  const std::string suffix = ".tmp-" + std::to_string(getpid());
  bool ok = true;
  for (const auto& file : files) {
    const std::string temporary = file.path + suffix;
    if (!WriteWhole(temporary, file.contents, &message)) {
      // Name the file the user asked for, not our temporary.
      message = "cannot write '" + file.path + "'" + message.substr(message.find("': ") + 1);
      std::remove(temporary.c_str());
      ok = false;
      break;
    }
    temporaries.push_back(temporary);
  }
  for (size_t i = 0; ok && i < temporaries.size(); ++i) {
    if (std::rename(temporaries[i].c_str(), files[i].path.c_str()) != 0) {
      message = "cannot write '" + files[i].path + "': " + std::strerror(errno);
      ok = false;
    }
  }
  if (!ok) {
    for (const auto& temporary : temporaries) std::remove(temporary.c_str());
    if (error) *error = message;
  }
  return ok;
}

std::string Sha256Hex(const std::string& data) {
  // GLib's checksum (GLib comes with Cairo): no hand-written hash to maintain.
  gchar* hex = g_compute_checksum_for_data(
      G_CHECKSUM_SHA256, reinterpret_cast<const guchar*>(data.data()), data.size());
  std::string out(hex);
  g_free(hex);
  return out;
}

}  // namespace chromatag
