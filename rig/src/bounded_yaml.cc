#include "bounded_yaml.h"

#include <yaml-cpp/eventhandler.h>

#include <sstream>

namespace chromatag::internal {
namespace {

// Counts the nodes of a parse and refuses aliases, before any tree is built.
class BoundedEvents : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { Count(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    throw YAML::ParserException(mark, "an alias (*name), which these files may not use");
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                const std::string&) override {
    Count(mark);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    Count(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    Count(mark);
  }
  void OnMapEnd() override {}

 private:
  void Count(const YAML::Mark& mark) {
    if (++nodes_ > kMaxYamlNodes)
      throw YAML::ParserException(mark, "more than " + std::to_string(kMaxYamlNodes) +
                                            " values, more than these files hold");
  }
  int nodes_ = 0;
};

}  // namespace

YAML::Node LoadBoundedYaml(const std::string& text) {
  {
    std::istringstream in(text);
    YAML::Parser parser(in);
    BoundedEvents events;
    while (parser.HandleNextDocument(events)) {
    }
  }
  return YAML::Load(text);
}

std::string YamlErrorAt(const YAML::Exception& e) {
  return "line " + std::to_string(e.mark.line + 1) + (e.msg.empty() ? "" : ": " + e.msg);
}

}  // namespace chromatag::internal
