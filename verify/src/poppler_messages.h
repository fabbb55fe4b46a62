// poppler's messages ("Couldn't find trailer dictionary") go to std::cerr
// unless told otherwise, and a library must not print: while a
// PopplerMessages lives, the thread's messages are collected instead, the
// first kept for an error message; outside one they are dropped.
#ifndef CHROMATAG_VERIFY_SRC_POPPLER_MESSAGES_H_
#define CHROMATAG_VERIFY_SRC_POPPLER_MESSAGES_H_

#include <poppler/cpp/poppler-global.h>

#include <mutex>
#include <string>

namespace chromatag {

class PopplerMessages {
 public:
  PopplerMessages() {
    static std::once_flag once;
    std::call_once(once, [] { poppler::set_debug_error_function(&Collect, nullptr); });
    Sink() = &first_;
  }
  ~PopplerMessages() { Sink() = nullptr; }
  PopplerMessages(const PopplerMessages&) = delete;
  PopplerMessages& operator=(const PopplerMessages&) = delete;

  // " (poppler: ...)" for an error message, or "".
  std::string Note() const { return first_.empty() ? "" : " (poppler: " + first_ + ")"; }

 private:
  static std::string*& Sink() {
    thread_local std::string* sink = nullptr;
    return sink;
  }
  static void Collect(const std::string& message, void*) {
    if (Sink() != nullptr && Sink()->empty()) *Sink() = message;
  }
  std::string first_;
};

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_SRC_POPPLER_MESSAGES_H_
