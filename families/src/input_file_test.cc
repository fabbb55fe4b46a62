#include "chromatag/families/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

namespace chromatag {
namespace {

TEST(InputFileTest, OnlyRegularFilesUnderTheCap) {
  std::string error;
  EXPECT_FALSE(ReadInputFile("/dev/zero", "palette file", 100, &error));
  EXPECT_EQ(error, "cannot read palette file '/dev/zero': not a regular file");
  EXPECT_FALSE(ReadInputFile("/tmp", "sidecar", 100, &error));
  EXPECT_EQ(error, "cannot read sidecar '/tmp': not a regular file");
  EXPECT_FALSE(ReadInputFile("/nonexistent/x", "sidecar", 100, &error));
  EXPECT_EQ(error, "cannot read sidecar '/nonexistent/x': no such file");
  const std::string fifo = ::testing::TempDir() + "/input_file_fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(ReadInputFile(fifo, "detector config", 100, &error));  // Would block if opened.
  EXPECT_NE(error.find("not a regular file"), std::string::npos);
  std::remove(fifo.c_str());
  const std::string path = ::testing::TempDir() + "/input_file.txt";
  std::ofstream(path) << "0123456789";
  EXPECT_EQ(ReadInputFile(path, "x", 10, &error).value_or(""), "0123456789");
  EXPECT_FALSE(ReadInputFile(path, "x", 9, &error));
  EXPECT_NE(error.find("10 bytes, over the limit of 9"), std::string::npos) << error;
}

TEST(InputFileTest, JsonDepthIgnoresBracketsInStrings) {
  EXPECT_FALSE(JsonDeeperThan(R"({"a": [[1, 2], {"b": "[[[[[[["}]})", 3));
  EXPECT_TRUE(JsonDeeperThan(R"({"a": [[[1]]]})", 3));
  EXPECT_FALSE(JsonDeeperThan(R"({"a": "\"[[[[[["})", 1));
  EXPECT_TRUE(JsonDeeperThan(std::string(100000, '[') + std::string(100000, ']'), kMaxJsonDepth));
}

TEST(InputFileTest, Utf8) {
  EXPECT_TRUE(IsValidUtf8("tags.pdf"));
  EXPECT_TRUE(IsValidUtf8("\xc3\xa9t\xc3\xa9.pdf"));  // été
  EXPECT_TRUE(IsValidUtf8("\xf0\x9f\x98\x80"));       // U+1F600
  EXPECT_FALSE(IsValidUtf8("bad\xff.pdf"));
  EXPECT_FALSE(IsValidUtf8("\xc3"));          // Cut short.
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));      // Overlong '/'.
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));  // A surrogate.
}

}  // namespace
}  // namespace chromatag
