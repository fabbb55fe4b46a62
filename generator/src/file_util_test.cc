#include "chromatag/generator/file_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace chromatag {
namespace {

std::string Read(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

TEST(FileUtilTest, Sha256MatchesFips180Vectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(FileUtilTest, WritesAllFilesOrLeavesEverythingAsItWas) {
  const std::string dir = ::testing::TempDir();
  const std::string a = dir + "/atomic_a.txt";
  const std::string b = dir + "/atomic_b.txt";
  std::string error;
  ASSERT_TRUE(WriteFilesAtomically({{a, "one"}, {b, "two"}}, &error)) << error;
  EXPECT_EQ(Read(a), "one");
  EXPECT_EQ(Read(b), "two");
  // The second file cannot be written: the first keeps its old contents.
  EXPECT_FALSE(WriteFilesAtomically({{a, "changed"}, {"/nonexistent/dir/b.txt", "x"}}, &error));
  EXPECT_NE(error.find("cannot write '/nonexistent/dir/b.txt'"), std::string::npos) << error;
  EXPECT_EQ(Read(a), "one");
  std::remove(a.c_str());
  std::remove(b.c_str());
}

}  // namespace
}  // namespace chromatag
