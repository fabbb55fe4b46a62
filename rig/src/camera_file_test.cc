#include "chromatag/rig/camera_file.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace chromatag {
namespace {

CameraIntrinsics Camera(LensModel model) {
  CameraIntrinsics camera;
  camera.fx = 601.25;
  camera.fy = 603.5;
  camera.cx = 371.125;
  camera.cy = 244.75;
  camera.model = model;
  camera.distortion = model == LensModel::kFisheye
                          ? std::vector<double>{-0.02, 0.01, -0.004, 0.001}
                          : std::vector<double>{-0.25, 0.08, 0.001, -0.0005, 0.0};
  return camera;
}

// Every format, written and read back by the reader `detect --camera` uses:
// the same camera, model and coefficients.
TEST(CameraFileTest, WritesWhatItReadsBack) {
  CameraFileInfo info;
  info.image_size = {752, 480};
  info.rms_px = 0.07;
  for (LensModel model : {LensModel::kPinhole, LensModel::kFisheye}) {
    for (CameraFileFormat format :
         {CameraFileFormat::kOpenCv, CameraFileFormat::kRos, CameraFileFormat::kKalibr}) {
      SCOPED_TRACE(std::string(CameraFileFormatName(format)) + " " + LensModelName(model));
      const CameraIntrinsics camera = Camera(model);
      std::string error;
      const std::string text = CameraFileText(camera, info, format, &error);
      ASSERT_FALSE(text.empty()) << error;
      CameraIntrinsics back;
      CameraFileInfo recorded;
      ASSERT_TRUE(ParseCameraFile(text, ".yaml", &back, &error, &recorded)) << error << "\n"
                                                                            << text;
      EXPECT_EQ(recorded.image_size, cv::Size(752, 480));
      EXPECT_EQ(back.fx, camera.fx);
      EXPECT_EQ(back.fy, camera.fy);
      EXPECT_EQ(back.cx, camera.cx);
      EXPECT_EQ(back.cy, camera.cy);
      EXPECT_EQ(back.model, model);
      // Kalibr's radtan drops k3, which is 0 here.
      ASSERT_GE(back.distortion.size(), 4u);
      for (size_t i = 0; i < camera.distortion.size(); ++i) {
        EXPECT_EQ(i < back.distortion.size() ? back.distortion[i] : 0.0, camera.distortion[i]);
      }
      EXPECT_NE(text.find("752"), std::string::npos) << text;
    }
  }
}

// The OpenCV file is what OpenCV's calibration samples write: FileStorage
// reads its matrices.
TEST(CameraFileTest, OpenCvReadsItsLayout) {
  CameraFileInfo info;
  info.image_size = {752, 480};
  std::string error;
  const std::string text =
      CameraFileText(Camera(LensModel::kPinhole), info, CameraFileFormat::kOpenCv, &error);
  cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  cv::Mat k, d;
  fs["camera_matrix"] >> k;
  fs["distortion_coefficients"] >> d;
  ASSERT_EQ(k.rows, 3);
  EXPECT_EQ(k.at<double>(0, 0), 601.25);
  EXPECT_EQ(k.at<double>(1, 2), 244.75);
  ASSERT_EQ(d.total(), 5u);
  EXPECT_EQ(d.at<double>(0), -0.25);
  EXPECT_EQ(static_cast<int>(fs["image_width"]), 752);
}

// Kalibr's radtan has no k3: a camera that needs it is refused, not cut.
TEST(CameraFileTest, KalibrRefusesK3) {
  CameraIntrinsics camera = Camera(LensModel::kPinhole);
  camera.distortion[4] = 0.01;
  std::string error;
  EXPECT_TRUE(CameraFileText(camera, {}, CameraFileFormat::kKalibr, &error).empty());
  EXPECT_NE(error.find("no k3"), std::string::npos) << error;
  camera.distortion[4] = 0.0;
  EXPECT_FALSE(CameraFileText(camera, {}, CameraFileFormat::kKalibr, &error).empty());
}

// OpenCV's XML names the model too; a file without one is a pinhole camera,
// whatever the struct held before.
TEST(CameraFileTest, XmlNamesItsModel) {
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<opencv_storage>\n"
      "<camera_matrix type_id=\"opencv-matrix\"><rows>3</rows><cols>3</cols><dt>d</dt>"
      "<data>300 0 320 0 300 240 0 0 1</data></camera_matrix>\n"
      "<distortion_coefficients type_id=\"opencv-matrix\"><rows>1</rows><cols>4</cols>"
      "<dt>d</dt><data>0.1 0.01 0 0</data></distortion_coefficients>\n"
      "<distortion_model>\"fisheye\"</distortion_model>\n</opencv_storage>\n";
  CameraIntrinsics camera;
  std::string error;
  ASSERT_TRUE(ParseCameraFile(xml, ".xml", &camera, &error)) << error;
  EXPECT_EQ(camera.model, LensModel::kFisheye);
  std::string pinhole = xml;
  pinhole.erase(pinhole.find("<distortion_model>"),
                pinhole.find("</opencv_storage>") - pinhole.find("<distortion_model>"));
  ASSERT_TRUE(ParseCameraFile(pinhole, ".xml", &camera, &error)) << error;
  EXPECT_EQ(camera.model, LensModel::kPinhole);
}

// The recorded image size from JSON and XML too; a size that is not two
// positive integers is no size.
TEST(CameraFileTest, ReadsTheRecordedImageSize) {
  CameraIntrinsics camera;
  CameraFileInfo info;
  std::string error;
  ASSERT_TRUE(ParseCameraFile(
      R"({"image_width": 640, "image_height": 480, "camera_matrix": [500, 0, 320, 0, 500, 240, 0, 0, 1]})",
      ".json", &camera, &error, &info))
      << error;
  EXPECT_EQ(info.image_size, cv::Size(640, 480));
  ASSERT_TRUE(ParseCameraFile(
      "<?xml version=\"1.0\"?><opencv_storage><image_width>1920</image_width>"
      "<image_height>1080</image_height><camera_matrix><data>900 0 960 0 900 540 0 0 1</data>"
      "</camera_matrix></opencv_storage>",
      ".xml", &camera, &error, &info))
      << error;
  EXPECT_EQ(info.image_size, cv::Size(1920, 1080));
  ASSERT_TRUE(ParseCameraFile(
      "image_width: -3\nimage_height: 2.5\ncamera_matrix: [1, 0, 1, 0, 1, 1, 0, 0, 1]\n", ".yaml",
      &camera, &error, &info))
      << error;
  EXPECT_TRUE(info.image_size.empty());
}

TEST(CameraFileTest, RefusesAnUnknownLensModel) {
  CameraIntrinsics camera;
  std::string error;
  EXPECT_FALSE(ParseCameraFile(
      "cam0:\n  camera_model: omni\n  intrinsics: [1, 1, 1, 1]\n  distortion_model: none\n",
      ".yaml", &camera, &error));
  EXPECT_NE(error.find("camera_model 'omni'"), std::string::npos) << error;
  EXPECT_FALSE(
      ParseCameraFile("camera_matrix: [1, 0, 1, 0, 1, 1, 0, 0, 1]\ndistortion_model: fisheye\n"
                      "distortion_coefficients: [0.1, 0.2, 0.3, 0.4, 0.5]\n",
                      ".yaml", &camera, &error));
  EXPECT_NE(error.find("fisheye model needs 4"), std::string::npos) << error;
}

// Anchors' aliases let a few kilobytes stand for billions of values (a
// camera_matrix whose data is 3,000 aliases of a list of 3,000 aliases):
// refused at the first alias, naming its line, before any tree is walked;
// so is a file of more values than any camera file holds.
TEST(CameraFileTest, RefusesAliasesAndHugeFiles) {
  CameraIntrinsics camera;
  std::string error;
  std::string bomb = "r: &r [600, 0, 320]\nm: &m [";
  for (int i = 0; i < 3000; ++i) bomb += i ? ",*r" : "*r";
  bomb += "]\ncamera_matrix: {rows: 3, cols: 3, data: [";
  for (int i = 0; i < 3000; ++i) bomb += i ? ",*m" : "*m";
  bomb += "]}\n";
  EXPECT_FALSE(ParseCameraFile(bomb, ".yaml", &camera, &error));
  EXPECT_NE(error.find("line 2: an alias (*name)"), std::string::npos) << error;
  // One harmless alias is refused as well: no camera format uses them.
  EXPECT_FALSE(ParseCameraFile("k: &k [600, 0, 320, 0, 600, 240, 0, 0, 1]\ncamera_matrix: *k\n",
                               ".yaml", &camera, &error));
  EXPECT_NE(error.find("line 2: an alias"), std::string::npos) << error;
  std::string many = "camera_matrix: [1, 0, 1, 0, 1, 1, 0, 0, 1]\nextra: [";
  for (int i = 0; i < 250000; ++i) many += i ? ",0" : "0";
  many += "]\n";
  EXPECT_FALSE(ParseCameraFile(many, ".yaml", &camera, &error));
  EXPECT_NE(error.find("more than 200000 values"), std::string::npos) << error;
}

// A camera matrix must be [fx 0 cx; 0 fy cy; 0 0 1]: a transposed one (as
// MATLAB writes it) was read as cx = cy = 0, a skew and a corner of 0
// were ignored. Each is refused, naming the entry.
TEST(CameraFileTest, RefusesAMatrixOfAnotherShape) {
  CameraIntrinsics camera;
  std::string error;
  for (const auto& [data, says] : std::vector<std::pair<std::string, std::string>>{
           {"600, 0, 0, 0, 600, 0, 320, 240, 1",
            "entry [2][0] is 320, not 0: is the matrix transposed"},
           {"600, 0.5, 320, 0, 600, 240, 0, 0, 1", "entry [0][1] is 0.5, a skew"},
           {"600, 0, 320, 0, 600, 240, 0, 0, 0", "entry [2][2] is 0, not 1"},
           {"600, 0, 320, 3, 600, 240, 0, 0, 1", "entry [1][0] is 3, not 0"}}) {
    EXPECT_FALSE(ParseCameraFile("camera_matrix: {rows: 3, cols: 3, data: [" + data + "]}\n",
                                 ".yaml", &camera, &error))
        << data;
    EXPECT_NE(error.find(says), std::string::npos) << error;
  }
  ASSERT_TRUE(ParseCameraFile(
      "camera_matrix: {rows: 3, cols: 3, data: [600, 0, 320, 0, 601, 240, 0, 0, 1]}\n", ".yaml",
      &camera, &error))
      << error;
  EXPECT_EQ(camera.fy, 601);
  EXPECT_EQ(camera.cy, 240);
}

// OpenCV's XML is read by an XML parser: a camera_matrix inside a comment
// is a comment (it was read, and used), a second one is refused, and a
// truncated file is not XML.
TEST(CameraFileTest, XmlIsReadAsXml) {
  const std::string matrix =
      "<camera_matrix type_id=\"opencv-matrix\"><rows>3</rows><cols>3</cols><dt>d</dt>"
      "<data>300 0 320 0 300 240 0 0 1</data></camera_matrix>\n";
  const std::string commented =
      "<?xml version=\"1.0\"?>\n<opencv_storage>\n<!-- " + matrix + " -->\n</opencv_storage>\n";
  CameraIntrinsics camera;
  std::string error;
  EXPECT_FALSE(ParseCameraFile(commented, ".xml", &camera, &error));
  EXPECT_NE(error.find("needs a camera_matrix"), std::string::npos) << error;
  const std::string twice =
      "<?xml version=\"1.0\"?>\n<opencv_storage>\n" + matrix + matrix + "</opencv_storage>\n";
  EXPECT_FALSE(ParseCameraFile(twice, ".xml", &camera, &error));
  EXPECT_NE(error.find("has two <camera_matrix> elements"), std::string::npos) << error;
  const std::string cdata =
      "<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix><data><![CDATA["
      "301 0 320 0 300 240 0 0 1]]></data></camera_matrix></opencv_storage>\n";
  ASSERT_TRUE(ParseCameraFile(cdata, ".xml", &camera, &error)) << error;
  EXPECT_EQ(camera.fx, 301);
  EXPECT_FALSE(ParseCameraFile("<?xml version=\"1.0\"?>\n<opencv_storage>\n<camera_matrix type",
                               ".xml", &camera, &error));
  EXPECT_NE(error.find("is not OpenCV XML (invalid XML at line 3)"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag
