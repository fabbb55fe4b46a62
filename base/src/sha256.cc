#include "chromatag/base/sha256.h"

#include <glib.h>

namespace chromatag {

std::string Sha256Hex(const std::string& data) {
  // GLib's checksum (GLib comes with Cairo): no hand-written hash to maintain.
  gchar* hex = g_compute_checksum_for_data(
      G_CHECKSUM_SHA256, reinterpret_cast<const guchar*>(data.data()), data.size());
  std::string out(hex);
  g_free(hex);
  return out;
}

}  // namespace chromatag
