#include "chromatag/base/output_files.h"
#include "chromatag/base/sha256.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

namespace chromatag {
namespace {

std::string Read(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

TEST(Sha256Test, MatchesFips180Vectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(OutputFilesTest, WritesAllFilesOrLeavesEverythingAsItWas) {
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

// Cases: a target that is a folder, a name of 250 characters, a
// symlink at the target, the mode, and never a temporary left behind.
TEST(OutputFilesTest, TargetsAreCheckedFirstAndNothingIsLeftBehind) {
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
namespace fs = std::filesystem;

// Names in `dir` left by a write (its journal, new files, backups).
std::vector<std::string> Leftovers(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(".chromatag-", 0) == 0) out.push_back(name);
  }
  return out;
}

// A write killed by SIGKILL at any moment leaves the targets as one whole set,
// old or new, once the next process writing into the folder has run: the child rewrites
// ten files over and over, each round with its own number in every file, and
// is killed after a random delay.
TEST(OutputFilesTest, AWriteKilledAnywhereIsFinishedByTheNextOne) {
  const std::string root = ::testing::TempDir() + "/atomic_kill_" + std::to_string(getpid());
  fs::remove_all(root);
  std::mt19937 random(7);
  int killed_with_leftovers = 0;
  for (int trial = 0; trial < 40; ++trial) {
    // A folder per trial: a process finishes a folder's writes once.
    const std::string dir = root + "/" + std::to_string(trial);
    fs::create_directories(dir);
    const auto round_files = [&](int round) {
      std::vector<OutputFile> files;
      for (int i = 0; i < 10; ++i) {
        files.push_back({dir + "/f" + std::to_string(i),
                         "round " + std::to_string(round) + "\n" + std::string(32 << 10, 'x')});
      }
      return files;
    };
    // Round 0 in a process of its own: this one must come to the folder
    // fresh, as the next run would.
    const pid_t writer = fork();
    ASSERT_GE(writer, 0);
    if (writer == 0) _exit(WriteFilesAtomically(round_files(0)) ? 0 : 1);
    int status = 1;
    waitpid(writer, &status, 0);
    ASSERT_EQ(status, 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      for (int round = 1;; ++round) WriteFilesAtomically(round_files(round));
    }
    std::this_thread::sleep_for(std::chrono::microseconds(random() % 20000));
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    killed_with_leftovers += Leftovers(dir).empty() ? 0 : 1;
    ASSERT_TRUE(WriteFilesAtomically({{dir + "/other", "x"}}));
    EXPECT_TRUE(Leftovers(dir).empty()) << "trial " << trial << ": " << Leftovers(dir)[0];
    std::string first;
    for (int i = 0; i < 10; ++i) {
      const std::string text = Read(dir + "/f" + std::to_string(i));
      const std::string round = text.substr(0, text.find('\n'));
      if (i == 0) first = round;
      EXPECT_EQ(round, first) << "trial " << trial << ", file " << i;
      EXPECT_EQ(text.size(), round.size() + 1 + (32 << 10));
    }
  }
  // The kills landed inside writes (else the test shows nothing).
  EXPECT_GT(killed_with_leftovers, 10);
  fs::remove_all(root);
}

// The three states a killed write can leave, made by hand from the journal's
// layout (output_files.cc): before its commit, after it, and during an undo.
TEST(OutputFilesTest, InterruptedWritesAreUndoneCompletedOrRolledBack) {
  const std::string root = ::testing::TempDir() + "/atomic_states_" + std::to_string(getpid());
  fs::remove_all(root);
  // "new I DEV INO" / "old I DEV INO" for a file, as the writer records it.
  const auto id_line = [](const char* kind, int index, const std::string& path) {
    struct stat st;
    EXPECT_EQ(lstat(path.c_str(), &st), 0) << path;
    return std::string(kind) + " " + std::to_string(index) + " " + std::to_string(st.st_dev) + " " +
           std::to_string(st.st_ino) + "\n";
  };
  // `tail` follows the ID lines: "", "commit\n" or "commit\nrollback\n".
  const auto setup = [&](const std::string& name, const std::string& tail) {
    const std::string dir = root + "/" + name;
    fs::create_directories(dir);
    std::ofstream(dir + "/a") << "old a";  // b did not exist.
    std::ofstream(dir + "/.chromatag-AbC123.0") << "new a";
    std::ofstream(dir + "/.chromatag-AbC123.1") << "new b";
    fs::create_hard_link(dir + "/a", dir + "/.chromatag-AbC123.0.old");
    std::ofstream(dir + "/.chromatag-AbC123.journal")
        << "chromatag write journal 1\ntarget " << dir << "/a\ntarget " << dir << "/b\n"
        << id_line("new", 0, dir + "/.chromatag-AbC123.0")
        << id_line("new", 1, dir + "/.chromatag-AbC123.1")
        << id_line("old", 0, dir + "/.chromatag-AbC123.0.old") << tail;
    return dir;
  };
  // Killed before the commit: nothing was replaced; the new files go.
  std::string dir = setup("before", "");
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/other", "x"}}));
  EXPECT_EQ(Read(dir + "/a"), "old a");
  EXPECT_FALSE(fs::exists(dir + "/b"));
  EXPECT_TRUE(Leftovers(dir).empty());
  // Killed after the commit, a renamed: the write is completed.
  dir = setup("after", "commit\n");
  fs::rename(dir + "/.chromatag-AbC123.0", dir + "/a");
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/other", "x"}}));
  EXPECT_EQ(Read(dir + "/a"), "new a");
  EXPECT_EQ(Read(dir + "/b"), "new b");
  EXPECT_TRUE(Leftovers(dir).empty());
  // Killed while undoing a failed rename (b renamed in, a not): old files back.
  dir = setup("undo", "commit\nrollback\n");
  fs::rename(dir + "/.chromatag-AbC123.1", dir + "/b");
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/other", "x"}}));
  EXPECT_EQ(Read(dir + "/a"), "old a");
  EXPECT_FALSE(fs::exists(dir + "/b"));
  EXPECT_TRUE(Leftovers(dir).empty());
  // A journal its writer still holds is left alone.
  dir = setup("live", "");
  const int fd = open((dir + "/.chromatag-AbC123.journal").c_str(), O_RDONLY);
  ASSERT_EQ(flock(fd, LOCK_EX), 0);
  const pid_t child = fork();
  if (child == 0) _exit(WriteFilesAtomically({{dir + "/other", "x"}}) ? 0 : 1);
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(Leftovers(dir).size(), 4u);
  close(fd);
  // Committed, but a newer write has replaced b since: the stale new file
  // does not overwrite it.
  dir = setup("newer", "commit\n");
  fs::rename(dir + "/.chromatag-AbC123.0", dir + "/a");
  std::ofstream(dir + "/b") << "newer b";
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/other", "x"}}));
  EXPECT_EQ(Read(dir + "/b"), "newer b");
  EXPECT_TRUE(Leftovers(dir).empty());
  // A planted journal (unpacked from an archive, so owned by the user)
  // naming a file elsewhere to roll back: the file is not the journal's, so
  // it is left alone.
  const std::string victim = root + "/victim.txt";
  std::ofstream(victim) << "precious";
  dir = root + "/planted";
  fs::create_directories(dir);
  std::ofstream(dir + "/.chromatag-aaaaaa.journal")
      << "chromatag write journal 1\ntarget " << victim << "\ncommit\nrollback\n";
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/s.pdf", "x"}}));
  EXPECT_EQ(Read(victim), "precious");
  EXPECT_TRUE(Leftovers(dir).empty());
  // Killed before its first line was whole (empty, or half a header): gone
  // at once. A file of that name that is not a journal is not ours to remove.
  dir = root + "/unwritten";
  fs::create_directories(dir);
  std::ofstream(dir + "/.chromatag-empty00.journal") << "";
  std::ofstream(dir + "/.chromatag-half00.journal") << "chromatag write jo";
  std::ofstream(dir + "/.chromatag-other0.journal") << "someone else's notes";
  ASSERT_TRUE(WriteFilesAtomically({{dir + "/s.pdf", "x"}}));
  EXPECT_EQ(Leftovers(dir), std::vector<std::string>{".chromatag-other0.journal"});
  fs::remove_all(root);
}

}  // namespace chromatag
