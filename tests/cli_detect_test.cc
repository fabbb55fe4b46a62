// `chromatag detect` as a user runs it, on sheets made by `chromatag generate`.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "test_util.h"

namespace chromatag {
namespace {

using testing::CountLines;
using testing::ReadFile;
constexpr auto Chromatag = testing::RunChromatag;

// A folder with one PNG sheet of 16h5 IDs 0 and 3 at 150 dpi.
std::string MakeSheet(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/cli_detect_" + name;
  std::system(("rm -rf '" + dir + "'").c_str());
  mkdir(dir.c_str(), 0755);
  const auto result = Chromatag(
      {"generate", "--ids", "0,3", "--size", "25.4mm", "--dpi", "150", "-o", dir + "/sheet.png"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return dir;
}

TEST(CliDetectTest, JsonLinesMatchTheSidecar) {
  const std::string dir = MakeSheet("json");
  const auto result = Chromatag({"detect", "--json", dir + "/sheet.png"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  ASSERT_EQ(CountLines(result.out), 1) << result.out;
  const auto frame = nlohmann::json::parse(result.out);
  EXPECT_EQ(frame["file"], dir + "/sheet.png");
  EXPECT_EQ(frame["frame"], 0);
  EXPECT_EQ(frame["width"], 1240);  // A4 at 150 dpi.
  EXPECT_EQ(frame["height"], 1754);
  EXPECT_GE(frame["time_us"].get<double>(), 0.0);
  const auto sidecar = nlohmann::json::parse(ReadFile(dir + "/sheet.png.json"));
  ASSERT_EQ(frame["detections"].size(), 2u);
  const double px_per_mm = 150.0 / 25.4;
  for (const auto& detection : frame["detections"]) {
    EXPECT_EQ(detection["family"], "16h5");
    EXPECT_EQ(detection["hamming"], 0);
    const auto& expected = sidecar["tags"][detection["id"] == 0 ? 0 : 1];
    ASSERT_EQ(expected["id"], detection["id"]);
    for (int i = 0; i < 4; ++i) {
      // Sidecar mm (pixel edges) to pixel centres.
      const double x = expected["corners_mm"][i][0].get<double>() * px_per_mm - 0.5;
      const double y = expected["corners_mm"][i][1].get<double>() * px_per_mm - 0.5;
      EXPECT_NEAR(detection["corners"][i][0].get<double>(), x, 0.5) << "corner " << i;
      EXPECT_NEAR(detection["corners"][i][1].get<double>(), y, 0.5) << "corner " << i;
    }
  }
}

TEST(CliDetectTest, FoldersOverlaysAndATable) {
  const std::string dir = MakeSheet("folder");
  const std::string overlays = dir + "/overlays";
  mkdir(overlays.c_str(), 0755);
  const auto result = Chromatag({"detect", "--overlay", overlays, dir});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("16h5"), std::string::npos) << result.out;
  EXPECT_EQ(CountLines(result.out), 3) << result.out;  // Header and two tags.
  const auto listing = testing::RunCommand("/bin/ls", {overlays});
  EXPECT_EQ(CountLines(listing.out), 1) << listing.out;  // One overlay for the one frame.
  EXPECT_NE(listing.out.find("sheet"), std::string::npos) << listing.out;
}

TEST(CliDetectTest, UnreadableInputsAreReportedSkippedAndFailTheRun) {
  const std::string dir = MakeSheet("bad");
  std::system(("echo 'not an image' > '" + dir + "/broken.png'").c_str());
  const auto result = Chromatag({"detect", "--json", dir + "/broken.png", dir + "/sheet.png"});
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(CountLines(result.out), 1) << result.out;  // The readable sheet still ran.
  EXPECT_NE(result.err.find("cannot read image '" + dir + "/broken.png'"), std::string::npos)
      << result.err;
  // A missing input is bad usage, found before anything runs (exit 2, as verify and calibrate).
  const auto missing = Chromatag({"detect", "--json", dir + "/sheet.png", dir + "/missing.png"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(missing.out.empty()) << missing.out;
  EXPECT_NE(missing.err.find("missing.png"), std::string::npos) << missing.err;
}

// A folder holding a symbolic link loop and a dangling link beside a good
// image: each bad entry is named and skipped, the image is read, exit 1.
TEST(CliDetectTest, AFoldersUnreadableEntriesAreSkipped) {
  const std::string dir = MakeSheet("links");
  ASSERT_EQ(symlink("loop-b.png", (dir + "/loop-a.png").c_str()), 0);
  ASSERT_EQ(symlink("loop-a.png", (dir + "/loop-b.png").c_str()), 0);
  // Not an image by its name: passed over like any other such file.
  ASSERT_EQ(symlink("loop-d", (dir + "/loop-c").c_str()), 0);
  ASSERT_EQ(symlink("loop-c", (dir + "/loop-d").c_str()), 0);
  ASSERT_EQ(symlink("nothing.png", (dir + "/gone.png").c_str()), 0);
  // Entries that are not files: reading them would block or never end.
  ASSERT_EQ(mkfifo((dir + "/fifo.png").c_str(), 0644), 0);
  ASSERT_EQ(symlink("/dev/zero", (dir + "/zero.png").c_str()), 0);
  const int sock = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(sock, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string sock_path = dir + "/sock.png";
  ASSERT_LT(sock_path.size(), sizeof(address.sun_path));
  std::copy(sock_path.begin(), sock_path.end(), address.sun_path);
  ASSERT_EQ(bind(sock, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  const auto result = Chromatag({"detect", "--json", dir});
  close(sock);
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_EQ(CountLines(result.out), 1) << result.out;  // sheet.png
  for (const std::string& says :
       {"'" + dir + "/loop-a.png': Too many levels of symbolic links, skipped",
        "'" + dir + "/loop-b.png': Too many levels of symbolic links, skipped",
        "'" + dir + "/gone.png': a link to nothing, skipped",
        "'" + dir + "/fifo.png': a FIFO, skipped", "'" + dir + "/zero.png': a device, skipped",
        "'" + dir + "/sock.png': a socket, skipped"})
    EXPECT_NE(result.err.find(says), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("loop-c"), std::string::npos) << result.err;
}

// detect looks for both families by default: a 36h11 sheet is found.
TEST(CliDetectTest, BothFamiliesByDefault) {
  const std::string dir = MakeSheet("families");
  ASSERT_EQ(Chromatag({"generate", "--family", "36h11", "--ids", "5", "--size", "25.4mm", "--dpi",
                       "150", "-o", dir + "/big.png"})
                .exit_code,
            0);
  const auto result = Chromatag({"detect", "--json", dir + "/big.png"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto frame = nlohmann::json::parse(result.out);
  ASSERT_EQ(frame["detections"].size(), 1u);
  EXPECT_EQ(frame["detections"][0]["family"], "36h11");
  EXPECT_EQ(frame["detections"][0]["id"], 5);
}

// The same intrinsics from OpenCV YAML and JSON, ROS camera_info and Kalibr
// give the same pose; a broken file is one line and exit 2.
TEST(CliDetectTest, CameraFilesInTheLayoutsPeopleHave) {
  const std::string dir = MakeSheet("camera");
  const std::map<std::string, std::string> files = {
      {"opencv.yaml",
       "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
       "   data: [ 1500., 0., 620., 0., 1500., 877., 0., 0., 1. ]\n"
       "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
       "   data: [ 0., 0., 0., 0., 0. ]\n"},
      {"ros.yaml",
       "image_width: 1240\nimage_height: 1754\ncamera_name: test\ncamera_matrix:\n  rows: 3\n"
       "  cols: 3\n  data: [1500, 0, 620, 0, 1500, 877, 0, 0, 1]\ndistortion_model: plumb_bob\n"
       "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n"
       "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"},
      {"kalibr.yaml",
       "cam0:\n  camera_model: pinhole\n  intrinsics: [1500, 1500, 620, 877]\n"
       "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [1240, "
       "1754]\n"},
      {"opencv.json",
       "{\"camera_matrix\": {\"type_id\": \"opencv-matrix\", \"rows\": 3, \"cols\": 3, "
       "\"dt\": \"d\", \"data\": [1500, 0, 620, 0, 1500, 877, 0, 0, 1]}}"}};
  std::vector<double> depths;
  for (const auto& [name, text] : files) {
    std::ofstream(dir + "/" + name) << text;
    const auto result = Chromatag({"detect", "--json", "--camera", dir + "/" + name, "--tag-size",
                                   "25.4mm", dir + "/sheet.png"});
    ASSERT_EQ(result.exit_code, 0) << name << ": " << result.err;
    const auto frame = nlohmann::json::parse(result.out);
    ASSERT_EQ(frame["detections"].size(), 2u) << name;
    depths.push_back(frame["detections"][0]["pose"]["tvec"][2].get<double>());
  }
  // A 25.4 mm tag of 150 px at f = 1500 px is 0.254 m away.
  for (double z : depths) EXPECT_NEAR(z, 0.254, 0.003);
  for (const auto& [name, text] :
       std::vector<std::pair<std::string, std::string>>{{"broken.yaml", "a:\n b: 1\n : 2\n"},
                                                        {"empty.yaml", ""},
                                                        {"fisheye.yaml",
                                                         "intrinsics: [1, 1, 1, 1]\n"
                                                         "distortion_model: equidistant\n"},
                                                        {"nan.json", "{\"camera_matrix\": [1]}"},
                                                        // OpenCV logged its own line first.
                                                        {"broken.xml",
                                                         "<?xml version=\"1.0\"?>\n"
                                                         "<opencv_storage><camera_m"},
                                                        {"notes.txt", "fx 1500"}}) {
    std::ofstream(dir + "/" + name) << text;
    const auto result = Chromatag(
        {"detect", "--camera", dir + "/" + name, "--tag-size", "25.4mm", dir + "/sheet.png"});
    EXPECT_EQ(result.exit_code, 2) << name;
    EXPECT_EQ(CountLines(result.err), 1) << name << ": " << result.err;
    EXPECT_NE(result.err.find("camera file '" + dir + "/" + name + "'"), std::string::npos)
        << result.err;
  }
}

// --rejected lists the candidates the detector abandoned (JSON) and draws them
// on the overlay; without it neither appears. Smarties are red next to green.
TEST(CliDetectTest, RejectedCandidatesInJsonAndOverlays) {
  const std::string photo = "/usr/share/doc/opencv-doc/examples/data/smarties.png";
  const std::string dir = ::testing::TempDir() + "/cli_detect_rejected";
  std::system(("rm -rf '" + dir + "'").c_str());
  const auto plain = Chromatag({"detect", "--json", "--overlay", dir + "/plain", photo});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_FALSE(nlohmann::json::parse(plain.out).contains("rejected"));
  const auto with =
      Chromatag({"detect", "--json", "--rejected", "--overlay", dir + "/with", photo});
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const auto frame = nlohmann::json::parse(with.out);
  EXPECT_TRUE(frame["detections"].empty());
  ASSERT_GT(frame["rejected"].size(), 5u);
  const std::set<std::string> stages = {"InitialScan", "BuildPolygon", "PolyToQuad", "Decode"};
  for (const auto& r : frame["rejected"]) {
    EXPECT_EQ(stages.count(r["stage"].get<std::string>()), 1u) << r.dump();
    EXPECT_FALSE(r["reason"].get<std::string>().empty());
    EXPECT_GE(r["seed"][0].get<int>(), 0);
    EXPECT_LT(r["seed"][0].get<int>(), frame["width"].get<int>());
  }
  EXPECT_NE(ReadFile(dir + "/plain/smarties_png.png"), ReadFile(dir + "/with/smarties_png.png"));
}

// detect --board: a board written by generate --board, seen face-on in its
// own PNG (150 dpi: at f = 1500 px the page is 0.254 m away), reports the
// board's pose per frame in the JSON and the table; a frame without it
// reports it not seen.
TEST(CliDetectTest, BoardPoseInJsonAndTable) {
  const std::string dir = ::testing::TempDir() + "/cli_detect_board";
  std::system(("rm -rf '" + dir + "'").c_str());
  mkdir(dir.c_str(), 0755);
  const auto generated =
      Chromatag({"generate", "--board", "3x2", "--dpi", "150", "-o", dir + "/board.png"});
  ASSERT_EQ(generated.exit_code, 0) << generated.err;
  EXPECT_NE(generated.out.find("Wrote a 3 x 2 board of 16h5 tags"), std::string::npos)
      << generated.out;
  const auto sidecar = nlohmann::json::parse(ReadFile(dir + "/board.png.json"));
  const double width_mm = sidecar["page"]["width_mm"], height_mm = sidecar["page"]["height_mm"];
  const double px_per_mm = 150 / 25.4;
  const double cx = (width_mm * px_per_mm - 1) / 2, cy = (height_mm * px_per_mm - 1) / 2;
  std::ofstream(dir + "/camera.yaml")
      << "camera_matrix: [1500, 0, " << cx << ", 0, 1500, " << cy << ", 0, 0, 1]\n";
  cv::imwrite(dir + "/blank.png", cv::Mat(200, 300, CV_8UC3, cv::Scalar(200, 200, 200)));
  const auto result = Chromatag({"detect", "--json", "--camera", dir + "/camera.yaml", "--board",
                                 dir + "/board.png.json", dir + "/board.png", dir + "/blank.png"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::istringstream lines(result.out);
  std::string line;
  std::getline(lines, line);
  const auto frame = nlohmann::json::parse(line);
  const auto& board = frame["board"];
  EXPECT_EQ(board["name"], "board.png");
  EXPECT_EQ(board["tags_used"], nlohmann::json({0, 1, 2, 3, 4, 6}));
  EXPECT_TRUE(board["tags_rejected"].empty());
  EXPECT_LT(board["rms_error_px"].get<double>(), 0.5);
  // Its covariance as ROS writes one: 36 numbers, row-major, symmetric, a
  // positive variance on each axis (and under a millimetre on a sharp page).
  const nlohmann::json& covariance = board["covariance"];
  ASSERT_EQ(covariance.size(), 36u) << board;
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(covariance[7 * i].get<double>(), 0.0) << board;
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(covariance[6 * i + j].get<double>(), covariance[6 * j + i].get<double>(), 1e-12)
          << board;
  }
  EXPECT_LT(std::sqrt(covariance[14].get<double>()), 0.001) << board;
  // The origin, the bottom-left black square's bottom-left corner, where the
  // page puts it in front of the camera.
  const double ox = sidecar["board"]["origin_mm"][0], oy = sidecar["board"]["origin_mm"][1];
  const double z = 1500 / (px_per_mm * 1000);
  EXPECT_NEAR(board["tvec"][0].get<double>(), (ox * px_per_mm - 0.5 - cx) / 1500 * z, 0.001);
  EXPECT_NEAR(board["tvec"][1].get<double>(), (oy * px_per_mm - 0.5 - cy) / 1500 * z, 0.001);
  EXPECT_NEAR(board["tvec"][2].get<double>(), z, 0.002);
  // Face-on: 180 degrees about x (board y up, z towards the camera), +x or -x.
  EXPECT_NEAR(std::fabs(board["rvec"][0].get<double>()), 3.14159, 0.01);
  EXPECT_NEAR(board["rvec"][1].get<double>(), 0.0, 0.01);
  EXPECT_NEAR(board["rvec"][2].get<double>(), 0.0, 0.01);
  std::getline(lines, line);
  EXPECT_TRUE(nlohmann::json::parse(line)["board"].is_null()) << line;

  const auto table = Chromatag({"detect", "--camera", dir + "/camera.yaml", "--board",
                                dir + "/board.png.json", dir + "/board.png", dir + "/blank.png"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("board board.png: t = ("), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("6 of 6 tags"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find(" m  ± "), std::string::npos) << table.out;  // Its 1-sigma.
  EXPECT_NE(table.out.find("board board.png: not seen"), std::string::npos) << table.out;

  // The board's tags twice in one frame (a frame spliced from two, or two
  // boards): the frame is named, its board pose not reported, exit 1.
  cv::Mat page = cv::imread(dir + "/board.png"), twice;
  cv::hconcat(page, page, twice);
  cv::imwrite(dir + "/twice.png", twice);
  const auto doubled = Chromatag({"detect", "--json", "--camera", dir + "/camera.yaml", "--board",
                                  dir + "/board.png.json", dir + "/twice.png"});
  EXPECT_EQ(doubled.exit_code, 1) << doubled.err;
  EXPECT_NE(doubled.err.find("'" + dir +
                             "/twice.png' frame 0: board tag(s) 0, 1, 2, 3, 4, 6 "
                             "seen twice (a damaged or spliced frame, or two boards in view)"),
            std::string::npos)
      << doubled.err;
  EXPECT_TRUE(nlohmann::json::parse(doubled.out)["board"].is_null()) << doubled.out;

  for (const auto& [args, message] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--board", dir + "/board.png.json"}, "--board needs --camera FILE"},
           {{"--camera", dir + "/camera.yaml", "--board", dir + "/none.json"},
            "cannot read board file '" + dir + "/none.json'"},
           {{"--camera", dir + "/camera.yaml", "--board", dir + "/camera.yaml"},
            "has no tag_bundles"},
           {{"--camera", dir + "/camera.yaml"}, "or --board FILE"},
           {{"--camera", dir + "/camera.yaml", "--board", dir + "/board.png.json", "--family",
             "36h11"},
            "--family 36h11 leaves out every tag of the board (16h5)"},
           {{"--smooth"}, "--smooth smooths poses: it needs --camera FILE with --tag-size"},
           {{"--camera", dir + "/camera.yaml", "--board", dir + "/board.png.json", "--smooth"},
            "'" + dir + "/board.png' is an image"}}) {
    std::vector<std::string> command = {"detect"};
    command.insert(command.end(), args.begin(), args.end());
    command.push_back(dir + "/board.png");
    const auto refused = Chromatag(command);
    EXPECT_EQ(refused.exit_code, 2) << message;
    EXPECT_EQ(CountLines(refused.err), 1) << refused.err;
    EXPECT_NE(refused.err.find(message), std::string::npos) << refused.err;
  }
}

// --smooth on a video of a still board through sensor noise: the board's
// pose moves less from frame to frame than each frame's own.
TEST(CliDetectTest, SmoothFiltersABoardsPoseOverAVideo) {
  const std::string dir = ::testing::TempDir() + "/cli_detect_smooth";
  std::system(("rm -rf '" + dir + "'").c_str());
  mkdir(dir.c_str(), 0755);
  const auto generated = Chromatag({"generate", "--board", "3x2", "--page", "120x90mm", "--dpi",
                                    "150", "-o", dir + "/board.png"});
  ASSERT_EQ(generated.exit_code, 0) << generated.err;
  const cv::Mat page = cv::imread(dir + "/board.png");
  ASSERT_FALSE(page.empty());
  const double cx = (page.cols - 1) / 2.0, cy = (page.rows - 1) / 2.0;
  std::ofstream(dir + "/camera.yaml")
      << "camera_matrix: [2000, 0, " << cx << ", 0, 2000, " << cy << ", 0, 0, 1]\n";
  cv::VideoWriter video(dir + "/still.avi", cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30,
                        page.size());
  ASSERT_TRUE(video.isOpened());
  cv::RNG rng(7);
  for (int f = 0; f < 24; ++f) {
    cv::Mat noise(page.size(), CV_16SC3), frame;
    rng.fill(noise, cv::RNG::NORMAL, 0, 12);
    cv::add(page, noise, frame, cv::noArray(), CV_8UC3);
    video.write(frame);
  }
  video.release();
  // The board's distance per frame, each frame's own and smoothed.
  const auto distances = [&](bool smooth) {
    std::vector<std::string> command = {"detect",          "--json",
                                        "--camera",        dir + "/camera.yaml",
                                        "--board",         dir + "/board.png.json",
                                        dir + "/still.avi"};
    if (smooth) command.push_back("--smooth");
    const auto run = Chromatag(command);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    std::vector<double> out;
    std::istringstream lines(run.out);
    for (std::string line; std::getline(lines, line);) {
      const auto frame = nlohmann::json::parse(line);
      if (!frame["board"].is_null()) out.push_back(frame["board"]["tvec"][2].get<double>());
    }
    return out;
  };
  const auto spread = [](std::vector<double> v) {
    v.erase(v.begin(), v.begin() + 8);  // The filter settling.
    double mean = 0, sum = 0;
    for (double x : v) mean += x / v.size();
    for (double x : v) sum += (x - mean) * (x - mean);
    return std::sqrt(sum / v.size());
  };
  const std::vector<double> raw = distances(false), smooth = distances(true);
  ASSERT_EQ(raw.size(), 24u);
  ASSERT_EQ(smooth.size(), 24u);
  // The still board's distance varies by about 0.05 mm from frame to frame:
  // as little as the filter's motion model (PoseFilterOptions' defaults)
  // lets the board move between frames, so it keeps about 0.7 of it.
  EXPECT_LT(spread(smooth), 0.8 * spread(raw)) << spread(smooth) << " against " << spread(raw);
}

TEST(CliDetectTest, BadUsageIsExitTwo) {
  const std::string dir = MakeSheet("usage");
  EXPECT_EQ(Chromatag({"detect", "--family", "25h9", dir + "/sheet.png"}).exit_code, 2);
  EXPECT_EQ(Chromatag({"detect"}).exit_code, 2);
  const auto size = Chromatag({"detect", "--tag-size", "40ft", dir + "/sheet.png"});
  EXPECT_EQ(size.exit_code, 2);
  EXPECT_EQ(CountLines(size.err), 1) << size.err;
}

}  // namespace
}  // namespace chromatag
