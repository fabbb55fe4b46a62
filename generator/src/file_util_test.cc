#include "chromatag/generator/file_util.h"

#include <gtest/gtest.h>

#include <filesystem>
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

// Issue 12's cases: a target that is a folder, a name of 250 characters, a
// symlink at the target, the mode, and never a temporary left behind.
TEST(FileUtilTest, TargetsAreCheckedFirstAndNothingIsLeftBehind) {
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/atomic_cases";
  fs::remove_all(dir);
  fs::create_directories(dir + "/x.pdf.json");  // A folder where the sidecar goes.
  std::ofstream(dir + "/x.pdf") << "old sheet";
  std::string error;
  EXPECT_FALSE(
      WriteFilesAtomically({{dir + "/x.pdf", "new"}, {dir + "/x.pdf.json", "{}"}}, &error));
  EXPECT_EQ(error, "cannot write '" + dir + "/x.pdf.json': it is a folder");
  EXPECT_EQ(Read(dir + "/x.pdf"), "old sheet");
  fs::remove_all(dir + "/x.pdf.json");

  const std::string long_name = dir + "/" + std::string(250, 'n');
  ASSERT_TRUE(WriteFilesAtomically({{long_name, "long"}}, &error)) << error;
  EXPECT_EQ(Read(long_name), "long");

  // A symlink at the target is replaced, and what it pointed to is untouched.
  std::ofstream(dir + "/victim") << "keep me";
  fs::create_symlink(dir + "/victim", dir + "/link.pdf");
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/link.pdf", "sheet"}}, &error)) << error;
  EXPECT_EQ(Read(dir + "/victim"), "keep me");
  EXPECT_FALSE(fs::is_symlink(dir + "/link.pdf"));
  EXPECT_EQ(Read(dir + "/link.pdf"), "sheet");
  EXPECT_EQ(fs::status(dir + "/link.pdf").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                fs::perms::others_read);

  EXPECT_FALSE(WriteFilesAtomically({{dir + "/a", "1"}, {dir + "/a", "2"}}, &error));
  EXPECT_NE(error.find("named twice"), std::string::npos) << error;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().rfind(".chromatag-", 0), std::string::npos)
        << entry.path();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace chromatag
