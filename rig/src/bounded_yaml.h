// One way to read the YAML files calib reads (camera files, board and bundle
// files), bounded by the file's own size.
#ifndef CHROMATAG_CALIB_SRC_BOUNDED_YAML_H_
#define CHROMATAG_CALIB_SRC_BOUNDED_YAML_H_

#include <yaml-cpp/yaml.h>

#include <string>

namespace chromatag::internal {

// Most nodes a file may hold. A bundle of a thousand tags is under 10,000.
inline constexpr int kMaxYamlNodes = 200000;

// Parses the first document of `text` as YAML::Load does, refusing anchors'
// aliases (`*name`): a few kilobytes of anchors and aliases can stand for
// billions of nodes, which every later walk over the tree would visit. No
// camera or board format read here uses them. Also refuses more than
// kMaxYamlNodes nodes. Throws YAML::Exception (YAML::ParserException for
// these refusals), whose mark names the line.
YAML::Node LoadBoundedYaml(const std::string& text);

// "line N: what" for a YAML::Exception, for messages.
std::string YamlErrorAt(const YAML::Exception& e);

}  // namespace chromatag::internal

#endif  // CHROMATAG_CALIB_SRC_BOUNDED_YAML_H_
