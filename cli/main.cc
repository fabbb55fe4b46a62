// chromatag: print, detect and calibrate ChromaTag fiducial markers.
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <opencv2/core/utils/logger.hpp>
#include <streambuf>
#include <string>

#include "chromatag/base/input_file.h"
#include "chromatag/families/version.h"
#include "commands.h"
#include "flag_terms.h"
#include "library_output.h"

namespace chromatag::cli {

int Fail(const char* command, const std::string& message, int code) {
  // One line, whatever a library put in its message (OpenCV's end in "\n").
  std::string line = InFlagTerms(message);
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
  for (size_t at; (at = line.find('\n')) != std::string::npos;) line.replace(at, 1, "; ");
  std::cerr << "chromatag " << command << ": " << line << "\n";
  return code;
}

void Print(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    std::string text(static_cast<size_t>(n) + 1, '\0');
    std::vsnprintf(text.data(), text.size(), format, again);
    text.pop_back();
    std::cout << text;
  }
  va_end(again);
}

namespace {

// A stream buffer over a C stream, unbuffered (as std::cerr's own).
class FileBuffer : public std::streambuf {
 public:
  explicit FileBuffer(std::FILE* file) : file_(file) {}

 protected:
  int_type overflow(int_type ch) override {
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    return std::fputc(ch, file_) == EOF ? traits_type::eof() : ch;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return static_cast<std::streamsize>(std::fwrite(s, 1, static_cast<size_t>(n), file_));
  }
  int sync() override { return std::fflush(file_) == 0 ? 0 : -1; }

 private:
  std::FILE* file_;
};

// Writes through to another stream buffer with control characters (all but
// newline and tab) shown as \xNN: a file name, an argument or a file's
// contents quoted in a message cannot move the cursor, set the terminal's
// title or ring its bell. Installed on std::cout and std::cerr for the
// whole run, so that every message and table goes through it.
class EscapingBuffer : public std::streambuf {
 public:
  explicit EscapingBuffer(std::streambuf* out) : out_(out) {}

 protected:
  int_type overflow(int_type ch) override {
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    const char c = traits_type::to_char_type(ch);
    return xsputn(&c, 1) == 1 ? ch : traits_type::eof();
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    std::streamsize done = 0;
    while (done < n) {
      std::streamsize run = 0;  // Characters that go through as they are.
      while (done + run < n && !Control(s[done + run])) ++run;
      if (run > 0 && out_->sputn(s + done, run) != run) return done;
      done += run;
      if (done == n) break;
      char text[8];
      std::snprintf(text, sizeof text, "\\x%02x", static_cast<unsigned char>(s[done]));
      if (out_->sputn(text, 4) != 4) return done;
      ++done;
    }
    return done;
  }
  int sync() override { return out_->pubsync(); }

 private:
  static bool Control(char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 0x20 && c != '\n' && c != '\t') || u == 0x7f;
  }
  std::streambuf* out_;
};

}  // namespace
}  // namespace chromatag::cli

int main(int argc, char** argv) {
  // OpenCV's own image budget, a second line behind DecodeImage's: OpenCV
  // reads OPENCV_IO_MAX_IMAGE_PIXELS once, as its library loads, before
  // main. So the commands that decode images set it to kMaxImagePixels and
  // run the tool again (one exec); a value the user set is kept.
  const std::string command = argc > 1 ? argv[1] : "";
  if ((command == "detect" || command == "verify" || command == "calibrate" ||
       command == "calibrate-camera") &&
      std::getenv("OPENCV_IO_MAX_IMAGE_PIXELS") == nullptr &&
      setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(chromatag::kMaxImagePixels).c_str(), 0) ==
          0) {
    execv("/proc/self/exe", argv);  // Returns only if it failed: go on as is.
  }
  // Libraries' own lines kept apart from the tool's (library_output.h).
  chromatag::cli::CaptureLibraryOutput();
  // Never freed: the standard streams flush through them at exit.
  std::cout.rdbuf(new chromatag::cli::EscapingBuffer(std::cout.rdbuf()));
  std::cerr.rdbuf(new chromatag::cli::EscapingBuffer(
      new chromatag::cli::FileBuffer(chromatag::cli::ToolErr())));
  // OpenCV's and FFmpeg's own log lines ("[ERROR:0@0.006] global ...") would
  // come before the tool's one message; the tool says what went wrong itself.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET, unless the user asks for more.
  CLI::App app{"ChromaTag toolkit: coloured fiducial markers (DeGol, Bretl and Hoiem, ICCV 2017)",
               "chromatag"};
  app.set_version_flag("--version", std::string("chromatag ") + chromatag::kVersion);
  app.require_subcommand(1);

  chromatag::cli::Action action;
  chromatag::cli::RegisterFamilies(app, &action);
  chromatag::cli::RegisterPalettes(app, &action);
  chromatag::cli::RegisterGenerate(app, &action);
  chromatag::cli::RegisterVerify(app, &action);
  chromatag::cli::RegisterDetect(app, &action);
  chromatag::cli::RegisterCalib(app, &action);
  chromatag::cli::RegisterCalibrateCamera(app, &action);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version.
    std::cerr << "chromatag: error: " << e.what() << " (see chromatag --help)\n";
    return chromatag::cli::kExitUsage;
  }
  if (!action) return chromatag::cli::kExitUsage;
  try {
    return action();
  } catch (const std::exception& e) {
    // A library threw where it should have returned an error: still one
    // line and a failed exit, never an abort.
    return chromatag::cli::Fail(
        app.get_subcommands().empty() ? "error" : app.get_subcommands().front()->get_name().c_str(),
        std::string("unexpected error: ") + e.what(), chromatag::cli::kExitFailure);
  }
}
