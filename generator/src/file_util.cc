#include "chromatag/generator/file_util.h"

#include <fcntl.h>
#include <glib.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace chromatag {
namespace {

namespace fs = std::filesystem;

std::string Folder(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

// Blocks the signals that end a process from the terminal (Ctrl-C, hang-up,
// kill) in this thread while it lives: a write is then never cut between two
// renames; a pending signal arrives once the files are whole.
class SignalGuard {
 public:
  SignalGuard() {
    sigset_t block;
    sigemptyset(&block);
    for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&block, signal);
    pthread_sigmask(SIG_BLOCK, &block, &saved_);
  }
  ~SignalGuard() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  sigset_t saved_;
};

// A new file with a short unpredictable name in `folder` (mkostemp: O_EXCL,
// so never an existing file or a planted symlink), holding `contents`,
// synced to disk. Its path in *temporary; false with *why.
bool WriteTemporary(const std::string& folder, const std::string& contents, std::string* temporary,
                    std::string* why) {
  std::string name = folder + "/.chromatag-XXXXXX";
  const int fd = mkostemp(name.data(), O_CLOEXEC);
  if (fd < 0) {
    *why = std::strerror(errno);
    return false;
  }
  *temporary = name;
  bool ok = fchmod(fd, 0644) == 0;  // mkostemp makes 0600; outputs are for sharing.
  for (size_t done = 0; ok && done < contents.size();) {
    const ssize_t n = write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    ok = n > 0;
    if (ok) done += static_cast<size_t>(n);
  }
  ok = ok && fsync(fd) == 0;
  const int saved = errno;
  ok = close(fd) == 0 && ok;
  if (!ok) *why = std::strerror(saved ? saved : errno);
  return ok;
}

void SyncFolder(const std::string& folder) {
  const int fd = open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  fsync(fd);
  close(fd);
}

}  // namespace

bool CheckOutputTargets(const std::vector<std::string>& paths, std::string* error) {
  auto fail = [&](const std::string& path, const std::string& why) {
    if (error) *error = "cannot write '" + path + "': " + why;
    return false;
  };
  for (size_t i = 0; i < paths.size(); ++i) {
    const std::string& path = paths[i];
    std::error_code ec;
    const fs::file_status folder = fs::status(Folder(path), ec);
    if (!fs::exists(folder)) return fail(path, "no such folder");
    if (!fs::is_directory(folder)) return fail(path, "'" + Folder(path) + "' is not a folder");
    if (access(Folder(path).c_str(), W_OK | X_OK) != 0) return fail(path, std::strerror(errno));
    // A name the file system cannot hold would fail after the temporaries
    // are written.
    const long name_max = pathconf(Folder(path).c_str(), _PC_NAME_MAX);
    const std::string name = fs::path(path).filename().string();
    if (name_max > 0 && name.size() > static_cast<size_t>(name_max)) {
      return fail(path, "its name is " + std::to_string(name.size()) +
                            " bytes, over the file system's limit of " + std::to_string(name_max));
    }
    const fs::file_status target = fs::symlink_status(path, ec);
    if (ec && ec != std::errc::no_such_file_or_directory) return fail(path, ec.message());
    if (fs::is_directory(target)) return fail(path, "it is a folder");
    if (fs::exists(target) && !fs::is_regular_file(target) && !fs::is_symlink(target))
      return fail(path, "it is not a regular file");
    for (size_t j = 0; j < i; ++j) {
      if (paths[j] == path) return fail(path, "named twice in one write");
    }
  }
  return true;
}

bool WriteFilesAtomically(const std::vector<OutputFile>& files, std::string* error) {
  // Every target checked before anything is written.
  std::vector<std::string> paths;
  for (const OutputFile& file : files) paths.push_back(file.path);
  if (!CheckOutputTargets(paths, error)) return false;
  auto fail = [&](const std::string& path, const std::string& why) {
    if (error) *error = "cannot write '" + path + "': " + why;
    return false;
  };
  SignalGuard guard;
  std::vector<std::string> temporaries;
  auto remove_all = [&](const std::vector<std::string>& paths) {
    for (const std::string& p : paths) unlink(p.c_str());
  };
  for (const OutputFile& file : files) {
    std::string temporary, why;
    if (!WriteTemporary(Folder(file.path), file.contents, &temporary, &why)) {
      if (!temporary.empty()) unlink(temporary.c_str());
      remove_all(temporaries);
      return fail(file.path, why);
    }
    temporaries.push_back(temporary);
  }
  // Backups of the targets that exist (hard links, no copy), so that a
  // rename failing half way can put the earlier ones back.
  std::vector<std::string> backups(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(files[i].path, ec))) continue;
    std::string name = Folder(files[i].path) + "/.chromatag-old-XXXXXX";
    const int fd = mkostemp(name.data(), O_CLOEXEC);
    if (fd >= 0) close(fd);
    if (fd < 0 || rename(files[i].path.c_str(), name.c_str()) != 0 ||
        link(name.c_str(), files[i].path.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      if (fd >= 0 && fs::exists(fs::symlink_status(name, ec)) &&
          !fs::exists(fs::symlink_status(files[i].path, ec)))
        rename(name.c_str(), files[i].path.c_str());
      else if (fd >= 0)
        unlink(name.c_str());
      for (size_t j = 0; j < i; ++j) {
        if (!backups[j].empty()) unlink(backups[j].c_str());
      }
      remove_all(temporaries);
      return fail(files[i].path, why);
    }
    backups[i] = name;
  }
  for (size_t i = 0; i < files.size(); ++i) {
    if (rename(temporaries[i].c_str(), files[i].path.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      for (size_t j = 0; j < i; ++j) {  // Undo: the old files back, new ones gone.
        if (!backups[j].empty())
          rename(backups[j].c_str(), files[j].path.c_str());
        else
          unlink(files[j].path.c_str());
      }
      for (size_t j = i; j < files.size(); ++j) {
        if (!backups[j].empty()) unlink(backups[j].c_str());
      }
      remove_all(
          std::vector<std::string>(temporaries.begin() + static_cast<long>(i), temporaries.end()));
      return fail(files[i].path, why);
    }
  }
  for (const std::string& backup : backups) {
    if (!backup.empty()) unlink(backup.c_str());
  }
  std::vector<std::string> folders;
  for (const OutputFile& file : files) {
    if (std::find(folders.begin(), folders.end(), Folder(file.path)) == folders.end())
      folders.push_back(Folder(file.path));
  }
  for (const std::string& folder : folders) SyncFolder(folder);
  return true;
}

std::string Sha256Hex(const std::string& data) {
  // GLib's checksum (GLib comes with Cairo): no hand-written hash to maintain.
  gchar* hex = g_compute_checksum_for_data(
      G_CHECKSUM_SHA256, reinterpret_cast<const guchar*>(data.data()), data.size());
  std::string out(hex);
  g_free(hex);
  return out;
}

}  // namespace chromatag
