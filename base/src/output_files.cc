#include "chromatag/base/output_files.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>

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

// Writes `contents` to a new file `path` (O_EXCL and O_NOFOLLOW: never an
// existing file or a planted symlink), mode 0644, synced to disk; false with
// *why.
bool WriteNewFile(const std::string& path, const std::string& contents, std::string* why) {
  const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    *why = std::strerror(errno);
    return false;
  }
  bool ok = fchmod(fd, 0644) == 0;  // Past the umask: outputs are for sharing.
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

// One write on disk. Every file it makes is named from one unpredictable
// stem S (".chromatag-XXXXXX", made in the first target's folder):
//   S.journal              locked (flock) while its writer lives; its lines:
//                          "target PATH" for each target, synced before any
//                          new file exists; "new I DEV INO" for each new file
//                          and "old I DEV INO" for each target that had a
//                          file, then "commit" once every new file is whole;
//                          "rollback" if a rename failed after that
//   <target's folder>/S.I      the new contents of target I
//   <target's folder>/S.I.old  a hard link to target I's old file
// A writer killed (SIGKILL, power loss) leaves its journal, and the first
// write of a later process into that folder finishes it: before "commit"
// nothing was replaced, so the new files go; after it the renames are
// completed; after "rollback" the old files are put back. A target is only
// ever replaced or removed when it is still the very file the journal
// recorded (device and inode): a newer write since, or a journal that was
// planted, cannot make it touch anything else.
constexpr char kJournalHeader[] = "chromatag write journal 1\n";
constexpr char kJournalCommit[] = "commit\n";
constexpr char kJournalSuffix[] = ".journal";

// A path on one line: backslash and newline escaped.
std::string EscapeLine(const std::string& path) {
  std::string out;
  for (char c : path) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

std::string UnescapeLine(const std::string& line) {
  std::string out;
  for (size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size()) {
      out += line[i + 1] == 'n' ? '\n' : line[i + 1];
      ++i;
    } else {
      out += line[i];
    }
  }
  return out;
}

bool WriteAll(int fd, const std::string& text) {
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

// The new file and the backup of target `index` of the write named `stem`.
std::string NewName(const std::string& target, const std::string& stem, size_t index) {
  return Folder(target) + "/" + stem + "." + std::to_string(index);
}
std::string OldName(const std::string& target, const std::string& stem, size_t index) {
  return NewName(target, stem, index) + ".old";
}

struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  bool operator==(const FileId& other) const { return dev == other.dev && ino == other.ino; }
};

// The file at `path` (not followed through a symlink), if any.
std::optional<FileId> IdOf(const std::string& path) {
  struct stat st;
  if (lstat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

// Finishes the write whose journal is `journal`, unless its writer still
// holds it, it is not this user's, or it is not a journal.
void FinishInterruptedWrite(const std::string& journal) {
  const int fd = open(journal.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  struct stat st;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != geteuid() ||
      st.st_size > (64 << 20) || flock(fd, LOCK_EX | LOCK_NB) != 0) {
    close(fd);
    return;
  }
  // Finished (and unlinked) by another process while this one waited.
  if (fstat(fd, &st) != 0 || st.st_nlink == 0) {
    close(fd);
    return;
  }
  std::string text(static_cast<size_t>(st.st_size), '\0');
  const bool read_all = pread(fd, text.data(), text.size(), 0) == st.st_size;
  if (!read_all || text.rfind(kJournalHeader, 0) != 0) {
    // Killed before its first line was whole: nothing else of the write
    // exists yet. Its writer, were it alive, would hold the lock this process
    // has (a writer that locks after this unlink sees the journal gone and
    // makes another).
    const std::string header = kJournalHeader;
    if (read_all && header.compare(0, text.size(), text) == 0 && text.size() < header.size())
      unlink(journal.c_str());
    close(fd);
    return;
  }
  std::vector<std::string> targets;
  std::map<size_t, FileId> fresh_ids, old_ids;
  bool committed = false, rolled_back = false;
  for (size_t at = sizeof(kJournalHeader) - 1; at < text.size();) {
    const size_t end = text.find('\n', at);
    if (end == std::string::npos) break;  // A line cut short: not written whole.
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    unsigned long long index = 0, dev = 0, ino = 0;
    char kind[4] = {0};
    if (line.rfind("target ", 0) == 0) {
      if (!committed) targets.push_back(UnescapeLine(line.substr(7)));
    } else if (std::sscanf(line.c_str(), "%3s %llu %llu %llu", kind, &index, &dev, &ino) == 4 &&
               (std::strcmp(kind, "new") == 0 || std::strcmp(kind, "old") == 0)) {
      const FileId id{static_cast<dev_t>(dev), static_cast<ino_t>(ino)};
      (kind[0] == 'n' ? fresh_ids : old_ids)[index] = id;
    } else if (line == "commit") {
      committed = true;
    } else if (line == "rollback") {
      rolled_back = committed;
    }
  }
  std::string stem = fs::path(journal).filename().string();
  stem.resize(stem.size() - (sizeof(kJournalSuffix) - 1));
  const auto is = [](const std::optional<FileId>& id, const std::map<size_t, FileId>& ids,
                     size_t i) { return id && ids.count(i) && *id == ids.at(i); };
  std::vector<std::string> folders;
  for (size_t i = 0; i < targets.size(); ++i) {
    const std::string fresh = NewName(targets[i], stem, i), old = OldName(targets[i], stem, i);
    const auto target_id = IdOf(targets[i]), fresh_id = IdOf(fresh), old_id = IdOf(old);
    if (rolled_back) {
      // The new file leaves only where it is in place; the old comes back.
      if (is(target_id, fresh_ids, i)) {
        if (is(old_id, old_ids, i))
          rename(old.c_str(), targets[i].c_str());
        else if (!old_ids.count(i))
          unlink(targets[i].c_str());
      }
    } else if (committed && is(fresh_id, fresh_ids, i)) {
      // Completed only over the very file the write replaced (or none).
      const bool unchanged = old_ids.count(i) ? is(target_id, old_ids, i) : !target_id;
      if (unchanged) rename(fresh.c_str(), targets[i].c_str());
    }
    if (!committed || is(IdOf(fresh), fresh_ids, i)) unlink(fresh.c_str());
    if (!committed || is(IdOf(old), old_ids, i)) unlink(old.c_str());
    folders.push_back(Folder(targets[i]));
  }
  for (const std::string& folder : folders) SyncFolder(folder);
  unlink(journal.c_str());
  SyncFolder(Folder(journal));
  close(fd);
}

// Finishes the interrupted writes in `folder`, once per folder and process
// (an overlay folder is written thousands of times).
void FinishInterruptedWritesIn(const std::string& folder) {
  static std::mutex mutex;
  static std::set<std::string> done;
  std::error_code ec;
  const std::string key = fs::weakly_canonical(folder, ec).string();
  // Held through the recovery: another thread's write into the folder waits
  // until it is finished.
  std::lock_guard<std::mutex> lock(mutex);
  if (!done.insert(ec ? folder : key).second) return;
  std::vector<std::string> journals;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(".chromatag-", 0) == 0 && name.size() > sizeof(kJournalSuffix) &&
        name.compare(name.size() - (sizeof(kJournalSuffix) - 1), std::string::npos,
                     kJournalSuffix) == 0)
      journals.push_back(it->path().string());
  }
  for (const std::string& journal : journals) FinishInterruptedWrite(journal);
}

}  // namespace

bool CheckOutputTargets(const std::vector<std::string>& paths, std::string* error,
                        bool try_create) {
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
    if (try_create) {
      std::string probe = Folder(path) + "/.chromatag-probe-XXXXXX";
      const int fd = mkstemp(probe.data());
      if (fd < 0)
        return fail(path, "no file can be created in '" + Folder(path) + "' (" +
                              std::strerror(errno) + ")");
      close(fd);
      unlink(probe.c_str());
    }
  }
  return true;
}

bool CheckOutputsAreNotInputs(const std::vector<std::string>& outputs,
                              const std::vector<std::pair<std::string, std::string>>& inputs,
                              std::string* error) {
  for (const std::string& output : outputs) {
    for (const auto& [what, input] : inputs) {
      std::error_code ec;
      const bool same = fs::exists(output, ec) && fs::exists(input, ec)
                            ? fs::equivalent(output, input, ec)
                            : fs::weakly_canonical(output, ec) == fs::weakly_canonical(input, ec);
      if (same && !ec) {
        if (error)
          *error = "'" + output + "' is also an input (" + what +
                   "): an output may not overwrite an input; choose another name";
        return false;
      }
    }
  }
  return true;
}

namespace {

// One WriteFilesAtomically: the journal, the new files beside their targets,
// the backups of the targets that exist, then the commit and the renames.
// Each step returns false with *error set, having undone what it and the
// steps before it made (the targets untouched).
class AtomicWrite {
 public:
  AtomicWrite(const std::vector<OutputFile>& files, std::string* error)
      : files_(files), error_(error), had_old_(files.size(), false) {}

  bool Run() {
    for (const OutputFile& file : files_) {
      std::error_code ec;
      const fs::path absolute = fs::absolute(file.path, ec);
      targets_.push_back(ec ? file.path : absolute.string());
      if (std::find(folders_.begin(), folders_.end(), Folder(file.path)) == folders_.end())
        folders_.push_back(Folder(file.path));
    }
    for (const std::string& folder : folders_) FinishInterruptedWritesIn(folder);
    return OpenJournal() && ListTargets() && WriteNewFiles() && LinkOldFiles() && Commit() &&
           RenameIntoPlace();
  }

 private:
  bool Fail(const std::string& path, const std::string& why) {
    if (error_) *error_ = "cannot write '" + path + "': " + why;
    return false;
  }

  // The journal, locked before anything is written to it; another process
  // may find it empty and unlocked in between and remove it, so it is made
  // again then.
  bool OpenJournal() {
    const std::string& first = files_[0].path;
    for (int attempt = 0; journal_fd_ < 0; ++attempt) {
      journal_ = Folder(first) + "/.chromatag-XXXXXX" + kJournalSuffix;
      journal_fd_ =
          mkostemps(journal_.data(), static_cast<int>(sizeof(kJournalSuffix) - 1), O_CLOEXEC);
      if (journal_fd_ < 0) return Fail(first, std::strerror(errno));
      struct stat st;
      if (flock(journal_fd_, LOCK_EX) != 0 || fstat(journal_fd_, &st) != 0) {
        const std::string why = std::strerror(errno);
        unlink(journal_.c_str());
        close(journal_fd_);
        return Fail(first, why);
      }
      if (st.st_nlink == 0) {
        close(journal_fd_);
        journal_fd_ = -1;
        if (attempt == 100) return Fail(first, "its folder's journal kept being removed");
      }
    }
    stem_ = fs::path(journal_).filename().string();
    stem_.resize(stem_.size() - (sizeof(kJournalSuffix) - 1));
    return true;
  }

  // Removes what this write made and its journal: the targets untouched.
  bool Abandon(const std::string& path, const std::string& why) {
    for (size_t i = 0; i < made_; ++i) unlink(NewName(files_[i].path, stem_, i).c_str());
    for (size_t i = 0; i < linked_; ++i)
      if (had_old_[i]) unlink(OldName(files_[i].path, stem_, i).c_str());
    unlink(journal_.c_str());
    close(journal_fd_);
    return Fail(path, why);
  }

  // The journal names the targets and is synced before any new file exists.
  bool ListTargets() {
    std::string listing = kJournalHeader;
    for (const std::string& target : targets_) listing += "target " + EscapeLine(target) + "\n";
    if (!WriteAll(journal_fd_, listing) || fsync(journal_fd_) != 0)
      return Abandon(files_[0].path, std::strerror(errno));
    SyncFolder(Folder(files_[0].path));
    return true;
  }

  // A line of the journal's commit: a file this write made, by its identity.
  bool Record(const char* kind, size_t index, const std::string& path) {
    const auto id = IdOf(path);
    if (!id) return false;
    commit_ += std::string(kind) + " " + std::to_string(index) + " " +
               std::to_string(static_cast<unsigned long long>(id->dev)) + " " +
               std::to_string(static_cast<unsigned long long>(id->ino)) + "\n";
    return true;
  }

  bool WriteNewFiles() {
    for (; made_ < files_.size(); ++made_) {
      std::string why;
      const std::string fresh = NewName(files_[made_].path, stem_, made_);
      if (!WriteNewFile(fresh, files_[made_].contents, &why) || !Record("new", made_, fresh)) {
        unlink(fresh.c_str());  // A part written, if any.
        return Abandon(files_[made_].path, why.empty() ? std::strerror(errno) : why);
      }
    }
    return true;
  }

  // Hard links to the targets that exist, so that a rename failing half way
  // can put the earlier ones back.
  bool LinkOldFiles() {
    for (; linked_ < files_.size(); ++linked_) {
      if (!IdOf(files_[linked_].path)) continue;
      const std::string old = OldName(files_[linked_].path, stem_, linked_);
      if (link(files_[linked_].path.c_str(), old.c_str()) != 0 || !Record("old", linked_, old)) {
        const std::string why = std::strerror(errno);
        if (IdOf(old)) unlink(old.c_str());
        return Abandon(files_[linked_].path, why);
      }
      had_old_[linked_] = true;
    }
    return true;
  }

  // The commit point: from here an interrupted write is completed, not
  // undone. The new names are made durable first.
  bool Commit() {
    for (const std::string& folder : folders_) SyncFolder(folder);
    commit_ += kJournalCommit;
    if (!WriteAll(journal_fd_, commit_) || fsync(journal_fd_) != 0)
      return Abandon(files_[0].path, std::strerror(errno));
    return true;
  }

  // Undoes the renames before the i-th, marked first so that an undo cut
  // short is finished the same way.
  bool RollBack(size_t i, const std::string& why) {
    const bool marked = WriteAll(journal_fd_, "rollback\n") && fsync(journal_fd_) == 0;
    for (size_t j = 0; j < files_.size(); ++j) {
      if (j < i && !had_old_[j]) unlink(files_[j].path.c_str());
      if (j < i && had_old_[j])
        rename(OldName(files_[j].path, stem_, j).c_str(), files_[j].path.c_str());
      unlink(NewName(files_[j].path, stem_, j).c_str());
      unlink(OldName(files_[j].path, stem_, j).c_str());
    }
    if (marked) unlink(journal_.c_str());  // Else the next write finishes the undo.
    close(journal_fd_);
    return Fail(files_[i].path, why);
  }

  bool RenameIntoPlace() {
    for (size_t i = 0; i < files_.size(); ++i) {
      if (rename(NewName(files_[i].path, stem_, i).c_str(), files_[i].path.c_str()) != 0)
        return RollBack(i, std::strerror(errno));
    }
    for (size_t i = 0; i < files_.size(); ++i)
      if (had_old_[i]) unlink(OldName(files_[i].path, stem_, i).c_str());
    for (const std::string& folder : folders_) SyncFolder(folder);
    unlink(journal_.c_str());
    SyncFolder(Folder(files_[0].path));
    close(journal_fd_);
    return true;
  }

  const std::vector<OutputFile>& files_;
  std::string* error_;
  std::vector<std::string> targets_, folders_;
  std::string journal_, stem_;
  int journal_fd_ = -1;
  size_t made_ = 0, linked_ = 0;  // New files written, targets looked at for backups.
  std::vector<bool> had_old_;
  std::string commit_;  // The lines that follow the targets, "commit" last.
};

}  // namespace

bool WriteFilesAtomically(const std::vector<OutputFile>& files, std::string* error) {
  // Every target checked before anything is written.
  std::vector<std::string> paths;
  for (const OutputFile& file : files) paths.push_back(file.path);
  if (!CheckOutputTargets(paths, error)) return false;
  if (files.empty()) return true;
  SignalGuard guard;
  return AtomicWrite(files, error).Run();
}

}  // namespace chromatag
