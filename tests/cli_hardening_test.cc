// Bad and hostile input, as a careless or hostile user gives it.
// Each case ends with exit 1 or 2 and one line on stderr naming what was
// wrong: never a signal, never a PASS on the wrong file, never a
// half-replaced output.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::CountLines;
using testing::ReadFile;
constexpr auto Chromatag = testing::RunChromatag;

class CliHardeningTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: ctest runs each test of this suite in its own.
    dir_ = ::testing::TempDir() + "/cli_hardening_" + std::to_string(getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ASSERT_EQ(Chromatag({"generate", "--ids", "0-1", "--size", "30mm", "-o", dir_ + "/sheet.pdf"})
                  .exit_code,
              0);
    ASSERT_EQ(Chromatag({"calib-sheet", "-o", dir_ + "/calib.pdf"}).exit_code, 0);
    ASSERT_EQ(
        Chromatag({"generate", "--ids", "3", "--dpi", "100", "-o", dir_ + "/page.png"}).exit_code,
        0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string dir_;
};
std::string CliHardeningTest::dir_;

void Write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A PNG that claims 40000 x 40000 pixels (no image data).
std::string HugePngHeader() {
  std::string png = "\x89PNG\r\n\x1a\n";
  auto chunk = [&](const std::string& type, const std::string& data) {
    for (int s = 24; s >= 0; s -= 8) png.push_back(static_cast<char>(data.size() >> s));
    const std::string body = type + data;
    png += body;
    const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size());
    for (int s = 24; s >= 0; s -= 8) png.push_back(static_cast<char>(crc >> s));
  };
  std::string ihdr;
  for (uint32_t side : {40000u, 40000u})
    for (int s = 24; s >= 0; s -= 8) ihdr.push_back(static_cast<char>(side >> s));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);
  chunk("IHDR", ihdr);
  chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8));  // An empty zlib stream.
  chunk("IEND", "");
  return png;
}

// `generate --color-lut` with a .cube of `size` points a side, `header`
// lines, and each entry the identity except red, which is `red` when given
// (for inputs of red above a half when it is "nan").
std::vector<std::string> LutArgs(const std::string& dir, const std::string& name, int size,
                                 const std::string& header, const std::string& red) {
  const std::string path = dir + "/" + name + ".cube";
  std::ofstream out(path);
  out << "LUT_3D_SIZE " << size << "\n" << header;
  for (int i = 0; i < size * size * size; ++i) {
    const double step = size > 1 ? 1.0 / (size - 1) : 0.0;
    const double r = (i % size) * step, g = (i / size % size) * step, b = (i / size / size) * step;
    const std::string red_text = red.empty() || (red == "nan" && r <= 0.5) ? std::to_string(r)
                                 : red == "nan"                            ? "nan"
                                                : std::to_string(r + std::stod(red));
    out << (size == 1 ? "0.5" : red_text) << " " << (size == 1 ? 0.5 : g) << " "
        << (size == 1 ? 0.5 : b) << "\n";
  }
  return {"generate", "--ids", "0", "--color-lut", path, "-o", dir + "/lut.pdf"};
}

struct Case {
  std::string name;
  std::function<std::vector<std::string>(const std::string& dir)> args;  // Sets up, returns args.
  int exit_code;
  std::string says;
};

TEST_F(CliHardeningTest, EveryBadInputIsOneLineAndAnExitCode) {
  const std::vector<Case> cases = {
      {"sidecar naming a file outside its folder",
       [](const std::string& d) {
         auto json = nlohmann::json::parse(ReadFile(d + "/sheet.pdf.json"));
         json["files"][0]["path"] = "../../../etc/passwd";
         fs::copy_file(d + "/sheet.pdf", d + "/evil.pdf", fs::copy_options::overwrite_existing);
         Write(d + "/evil.pdf.json", json.dump());
         return std::vector<std::string>{"verify", d + "/evil.pdf"};
       },
       2, "must be a file name beside the sidecar"},
      {"sidecar with a 100,000-deep array",
       [](const std::string& d) {
         auto text = ReadFile(d + "/sheet.pdf.json");
         text.insert(text.rfind('}'),
                     ", \"x\": " + std::string(100000, '[') + std::string(100000, ']'));
         fs::copy_file(d + "/sheet.pdf", d + "/deep.pdf", fs::copy_options::overwrite_existing);
         Write(d + "/deep.pdf.json", text);
         return std::vector<std::string>{"verify", d + "/deep.pdf"};
       },
       2, "nests deeper"},
      {"sidecar number 1e300 cast to int",
       [](const std::string& d) {
         auto json = nlohmann::json::parse(ReadFile(d + "/sheet.pdf.json"));
         json["quiet_zone_cells"] = 1e300;
         fs::copy_file(d + "/sheet.pdf", d + "/big.pdf", fs::copy_options::overwrite_existing);
         Write(d + "/big.pdf.json", json.dump());
         return std::vector<std::string>{"verify", d + "/big.pdf"};
       },
       2, "\"quiet_zone_cells\" must be an integer in [1, 20]"},
      {"calibration sidecar with a deep array",
       [](const std::string& d) {
         Write(d + "/deep-calib.json", std::string(100000, '[') + std::string(100000, ']'));
         return std::vector<std::string>{
             "calibrate", d + "/sheet.pdf", "--sheet", d + "/deep-calib.json", "-o", d + "/out"};
       },
       2, "nests deeper"},
      {"page of 1e12 mm",
       [](const std::string& d) {
         return std::vector<std::string>{"generate",   "--ids", "0",         "--page",
                                         "1e12x297mm", "-o",    d + "/x.pdf"};
       },
       2, "at most 10 m"},
      {"PNG past Cairo's 32767 px",
       [](const std::string& d) {
         return std::vector<std::string>{"generate", "--ids", "0",         "--dpi",
                                         "3000",     "-o",    d + "/x.png"};
       },
       2, "over the limit of 256 Mpx; at most 1666 dpi fits"},
      {"PNG sheet over the pixel budget verify reads back",
       [](const std::string& d) {
         return std::vector<std::string>{"generate", "--ids", "0",         "--dpi",
                                         "2000",     "-o",    d + "/x.png"};
       },
       2, "16535 x 23386 pixels (369 Mpx), over the limit of 256 Mpx"},
      {"a PNG cut in half (libpng would print its own line)",
       [](const std::string& d) {
         const std::string png = ReadFile(d + "/page.png");
         Write(d + "/cut.png", png.substr(0, png.size() / 2));
         return std::vector<std::string>{"detect", d + "/cut.png"};
       },
       1, "cannot read image '"},
      {"a PDF sheet cut short (poppler would print three lines)",
       [](const std::string& d) {
         const std::string pdf = ReadFile(d + "/sheet.pdf");
         Write(d + "/cut.pdf", pdf.substr(0, 3000));
         auto json = nlohmann::json::parse(ReadFile(d + "/sheet.pdf.json"));
         json["files"][0]["path"] = "cut.pdf";
         Write(d + "/cut.pdf.json", json.dump());
         return std::vector<std::string>{"verify", d + "/cut.pdf"};
       },
       2, "cannot read PDF '"},
      {"verify of a 10 m page at 200 dpi",
       [](const std::string& d) {
         EXPECT_EQ(
             Chromatag({"generate", "--ids", "0", "--page", "10000x10000mm", "-o", d + "/huge.pdf"})
                 .exit_code,
             0);
         return std::vector<std::string>{"verify", d + "/huge.pdf"};
       },
       2, "page 1: a page of 10000 x 10000 mm at 200 dpi is 78740 x 78740 pixels"},
      {"calibration sheet PNG past Cairo's limit",
       [](const std::string& d) {
         return std::vector<std::string>{"calib-sheet", "--page", "1000x1000mm", "--dpi",
                                         "1200",        "-o",     d + "/c.png"};
       },
       2, "lower --dpi"},
      {"truncated camera XML",
       [](const std::string& d) {
         Write(d + "/cut.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix type");
         return std::vector<std::string>{"detect",     "--camera", d + "/cut.xml",
                                         "--tag-size", "3cm",      d + "/sheet.pdf"};
       },
       2, "is not OpenCV XML"},
      {"config from /dev/zero",
       [](const std::string& d) {
         return std::vector<std::string>{"detect", "--config", "/dev/zero", d + "/sheet.pdf"};
       },
       2, "not a regular file"},
      {"palette file from /dev/zero",
       [](const std::string& d) {
         return std::vector<std::string>{"generate",  "--ids", "0",         "--palette-file",
                                         "/dev/zero", "-o",    d + "/x.pdf"};
       },
       2, "not a regular file"},
      {"colour LUT from /dev/zero",
       [](const std::string& d) {
         return std::vector<std::string>{"generate",  "--ids", "0",         "--color-lut",
                                         "/dev/zero", "-o",    d + "/x.pdf"};
       },
       2, "not a regular file"},
      {"a family named with terminal escapes",
       [](const std::string& d) {
         return std::vector<std::string>{"detect", "--family", "\x1b[31mX\a", d + "/page.png"};
       },
       2, "--family: \\x1b[31mX\\x07 not in"},
      {"an output name the file system cannot hold (its sidecar's)",
       [](const std::string& d) {
         return std::vector<std::string>{"generate", "--ids", "0", "-o",
                                         d + "/" + std::string(251, 'n') + ".pdf"};
       },
       2, ".pdf.json': its name is 260 bytes, over the file system's limit of 255"},
      // Broken LUTs that OpenColorIO reads without complaint and that would
      // print a sheet that does not decode.
      {"a LUT with nan entries",
       [](const std::string& d) { return LutArgs(d, "nan", 5, "", "nan"); }, 2,
       "does not raise red with red"},
      {"a LUT giving negative values",
       [](const std::string& d) { return LutArgs(d, "negative", 5, "", "-0.5"); }, 2,
       "gives -0.5 for RGB (0, 0, 0), outside 0-1"},
      {"a LUT of size 1", [](const std::string& d) { return LutArgs(d, "one", 1, "", ""); }, 2,
       "maps every colour to nearly the same one"},
      {"a LUT whose domain is upside down",
       [](const std::string& d) {
         return LutArgs(d, "domain", 5, "DOMAIN_MIN 1 1 1\nDOMAIN_MAX 0 0 0\n", "");
       },
       2, "does not raise red with red"},
      {"a FIFO named .png",
       [](const std::string& d) {
         mkfifo((d + "/fifo.png").c_str(), 0600);
         return std::vector<std::string>{"detect", d + "/fifo.png"};
       },
       2, "is not a regular file"},
      {"config step 4294967300",
       [](const std::string& d) {
         Write(d + "/step.json",
               R"({"schema": "chromatag-detector-config", "schema_version": 1,
                   "options": {"step": 4294967300}})");
         return std::vector<std::string>{"detect", "--config", d + "/step.json", d + "/sheet.pdf"};
       },
       2, "out of range"},
      {"config max_hamming 50",
       [](const std::string& d) {
         Write(d + "/hamming.json",
               R"({"schema": "chromatag-detector-config", "schema_version": 1,
                   "options": {"max_hamming": 50}})");
         return std::vector<std::string>{"detect", "--config", d + "/hamming.json",
                                         d + "/sheet.pdf"};
       },
       2, "unsafe"},
      {"an output name that is not UTF-8",
       [](const std::string& d) {
         return std::vector<std::string>{"generate", "--ids", "0", "-o", d + "/bad\xff.pdf"};
       },
       2, "must be UTF-8"},
      {"an image too large to decode",
       [](const std::string& d) {
         Write(d + "/huge.png", HugePngHeader());
         return std::vector<std::string>{"detect", d + "/huge.png"};
       },
       1, "40000 x 40000 pixels"},
      {"a LUT name with escape sequences",
       [](const std::string& d) {
         return std::vector<std::string>{
             "generate", "--ids", "0", "--color-lut", d + "/\x1b[31mred.cube", "-o", d + "/x.pdf"};
       },
       2, "\\x1b[31mred.cube"},
  };
  for (const Case& c : cases) {
    const auto result = Chromatag(c.args(dir_));
    EXPECT_EQ(result.exit_code, c.exit_code) << c.name << ": " << result.err;
    // The detect summary line follows a skipped input's message.
    const int lines = CountLines(result.err) - (c.exit_code == 1 ? 1 : 0);
    EXPECT_EQ(lines, 1) << c.name << ": " << result.err;
    EXPECT_NE(result.err.find(c.says), std::string::npos) << c.name << ": " << result.err;
    EXPECT_EQ(result.err.find('\x1b'), std::string::npos) << c.name;
  }
  EXPECT_FALSE(fs::exists(dir_ + "/x.pdf"));
  EXPECT_FALSE(fs::exists(dir_ + "/x.png"));
  // No refused write leaves a temporary behind.
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_NE(entry.path().filename().string().rfind(".chromatag-", 0), 0u) << entry.path();
}

// A JPEG whose data is damaged still decodes (grey where it is lost), and
// libjpeg's "Corrupt JPEG data" line stays out of the tool's output.
TEST_F(CliHardeningTest, LibraryLinesStayOutOfTheToolsOutput) {
  const cv::Mat page = cv::imread(dir_ + "/page.png");
  std::vector<uchar> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", page, jpeg));
  std::fill(jpeg.begin() + static_cast<long>(jpeg.size() / 2),
            jpeg.begin() + static_cast<long>(jpeg.size() / 2) + 64, 0);
  Write(dir_ + "/damaged.jpg", std::string(jpeg.begin(), jpeg.end()));
  const auto result = Chromatag({"detect", dir_ + "/damaged.jpg"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(CountLines(result.err), 1) << result.err;  // The summary.
  EXPECT_EQ(result.err.rfind("detect: 1 frame", 0), 0u) << result.err;
  // Asked for, the libraries' lines come through.
  const auto through = testing::RunCommand(
      "/usr/bin/env",
      {"CHROMATAG_LIBRARY_OUTPUT=1", CHROMATAG_CLI_PATH, "detect", dir_ + "/damaged.jpg"});
  EXPECT_NE(through.err.find("Corrupt JPEG data"), std::string::npos) << through.err;
  EXPECT_EQ(through.exit_code, 0);
  // A crash shows what the libraries printed: the damaged JPEG is read,
  // then the tool waits on a stream that never answers (its socket is open)
  // and is aborted.
  const auto crash = testing::RunCommand(
      "/bin/sh", {"-c",
                  "\"$0\" detect \"$1\" udp://127.0.0.1:9 >/dev/null & pid=$!; i=0; "
                  "while [ $i -lt 600 ] && ! ls -l /proc/$pid/fd | grep -q socket; do "
                  "sleep 0.1; i=$((i+1)); done; sleep 0.5; kill -ABRT $pid; wait $pid",
                  CHROMATAG_CLI_PATH, dir_ + "/damaged.jpg"});
  EXPECT_EQ(crash.exit_code, 128 + SIGABRT) << crash.err;
  EXPECT_NE(
      crash.err.find("chromatag: what libraries printed before the crash:\nCorrupt JPEG data"),
      std::string::npos)
      << crash.err;
}

// OpenCV's own image budget is the tool's (a second line behind the header
// check), and one the user sets is kept: OpenCV then refuses to decode.
TEST_F(CliHardeningTest, OpenCvHoldsTheSameImageBudget) {
  const auto env = testing::RunCommand(
      "/bin/sh", {"-c",
                  "\"$0\" detect udp://127.0.0.1:9 >/dev/null 2>&1 & pid=$!; sleep 2; "
                  "tr '\\0' '\\n' < /proc/$pid/environ; kill $pid; wait $pid",
                  CHROMATAG_CLI_PATH});
  EXPECT_NE(env.out.find("OPENCV_IO_MAX_IMAGE_PIXELS=268435456\n"), std::string::npos) << env.out;
  const auto small = testing::RunCommand(
      "/usr/bin/env",
      {"OPENCV_IO_MAX_IMAGE_PIXELS=1000", CHROMATAG_CLI_PATH, "detect", dir_ + "/page.png"});
  EXPECT_EQ(small.exit_code, 1) << small.err;
  EXPECT_NE(small.err.find("cannot read image"), std::string::npos) << small.err;
  EXPECT_EQ(Chromatag({"detect", dir_ + "/page.png"}).exit_code, 0);
}

// A file named to set the terminal's title: the table shows the escapes as
// text, the JSON as JSON escapes; no raw control byte reaches the terminal.
TEST_F(CliHardeningTest, NamesWithTerminalEscapesAreShownEscaped) {
  const std::string odd = dir_ + "/\x1b]0;pwned\a.png";
  fs::copy_file(dir_ + "/page.png", odd, fs::copy_options::overwrite_existing);
  const auto table = Chromatag({"detect", odd});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("\\x1b]0;pwned\\x07.png"), std::string::npos) << table.out;
  const auto json = Chromatag({"detect", "--json", odd, dir_ + "/missing-\a.png"});
  EXPECT_EQ(json.exit_code, 2);
  EXPECT_NE(json.err.find("missing-\\x07.png"), std::string::npos) << json.err;
  const auto ok = Chromatag({"detect", "--json", odd});
  EXPECT_NE(ok.out.find("\\u001b]0;pwned\\u0007.png"), std::string::npos) << ok.out;
  for (const auto& r : {table, json, ok}) {
    for (const std::string* text : {&r.out, &r.err})
      for (char c : *text) EXPECT_FALSE(c == '\x1b' || c == '\a') << *text;
  }
  fs::remove(odd);
}

// An input whose name is too long for an overlay name of its own still gets
// its overlay: the name is cut and told apart by a hash.
TEST_F(CliHardeningTest, OverlaysOfInputsWithLongNames) {
  const std::string long_name = dir_ + "/" + std::string(251, 'p') + ".png";
  const std::string other = dir_ + "/" + std::string(251, 'p') + ".jpg";
  fs::copy_file(dir_ + "/page.png", long_name, fs::copy_options::overwrite_existing);
  fs::copy_file(dir_ + "/page.png", other, fs::copy_options::overwrite_existing);
  const std::string overlays = dir_ + "/long-overlays";
  const auto result = Chromatag({"detect", "--json", "--overlay", overlays, long_name, other});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(CountLines(result.out), 2);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(overlays))
    names.push_back(entry.path().filename().string());
  ASSERT_EQ(names.size(), 2u);
  EXPECT_NE(names[0], names[1]);
  for (const std::string& name : names) EXPECT_LE(name.size(), 255u) << name;
  fs::remove(long_name);
  fs::remove(other);
}

// A non-UTF-8 file name is written into JSON with U+FFFD, not thrown on.
TEST_F(CliHardeningTest, JsonOfANameThatIsNotUtf8) {
  const std::string odd = dir_ + "/odd\xff.png";
  fs::copy_file(dir_ + "/page.png", odd, fs::copy_options::overwrite_existing);
  const auto result = Chromatag({"detect", "--json", "--family", "16h5", odd});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(nlohmann::json::parse(result.out)["file"].get<std::string>().find("\xef\xbf\xbd"),
            std::string::npos);
}

// A palette file whose name (its default palette name) is not UTF-8: the
// JSON report writes U+FFFD instead of throwing.
TEST_F(CliHardeningTest, PaletteNamedByANameThatIsNotUtf8) {
  const std::string path = dir_ + "/p\xff.json";
  Write(path, R"({"lab": {"red-1": [52, 79, 18.25], "red-0": [50, 71, -52.8],
                  "green-1": [50, -36, 3.5], "green-0": [54, -36, 55],
                  "black": [5, 0, 0], "white": [98, 0, 0]}})");
  const auto result = Chromatag({"palettes", "--json", "--palette-file", path});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(nlohmann::json::parse(result.out)["palettes"][0]["name"].get<std::string>().find(
                "\xef\xbf\xbd"),
            std::string::npos);
}

// A sidecar that is a folder: the old sheet stays, nothing else appears.
TEST_F(CliHardeningTest, AFailedWriteLeavesTheOldFiles) {
  const std::string d = dir_ + "/keep";
  fs::create_directories(d + "/x.pdf.json");
  Write(d + "/x.pdf", "old sheet");
  const auto result = Chromatag({"generate", "--ids", "0", "-o", d + "/x.pdf"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(CountLines(result.err), 1) << result.err;
  EXPECT_EQ(ReadFile(d + "/x.pdf"), "old sheet");
  size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(d)) entries += entry.exists() ? 1 : 0;
  EXPECT_EQ(entries, 2u);
}

// verify holds one page in memory at a time: a 587-page sheet at 100 dpi is
// 1.7 GB of pages, and passes under a 1 GB address-space limit.
TEST_F(CliHardeningTest, VerifyOfALongSheetHoldsOnePageAtATime) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizers reserve terabytes of address space";
#elif defined(__has_feature)  // clang's way of saying it.
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
  GTEST_SKIP() << "sanitizers reserve terabytes of address space";
#endif
#endif
  const std::string sheet = dir_ + "/all36h11.pdf";
  ASSERT_EQ(Chromatag({"generate", "--family", "36h11", "--all", "--one-per-page", "-o", sheet})
                .exit_code,
            0);
  const auto result =
      testing::RunCommand("/bin/sh", {"-c", "ulimit -v 1000000 && exec \"$@\"", "sh",
                                      CHROMATAG_CLI_PATH, "verify", sheet, "--dpi", "100"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("587 of 587 tags pass, nothing else found. PASS"), std::string::npos)
      << result.out.substr(result.out.size() > 400 ? result.out.size() - 400 : 0);
}

}  // namespace
}  // namespace chromatag
