// Writing outputs without ever leaving a half-written file: everything goes to
// a temporary file beside the target and is renamed into place at the end.
#ifndef CHROMATAG_BASE_OUTPUT_FILES_H_
#define CHROMATAG_BASE_OUTPUT_FILES_H_

#include <string>
#include <vector>

namespace chromatag {

struct OutputFile {
  std::string path;
  std::string contents;
};

// Writes all the files of one command, all or nothing:
// - every target is checked first (its folder exists and is writable, the
//   target is not a folder or a device, no path twice);
// - a journal naming the targets is written and synced (a file with a short
//   unpredictable name, mkostemps, in the first target's folder);
// - each file goes to a new temporary file beside its target (O_EXCL, never
//   through a symlink), mode 0644, synced to disk;
// - the existing targets are kept as hard-linked backups, the journal
//   marked committed, the temporaries renamed into place, the backups and
//   the journal dropped and the folders synced;
// - Ctrl-C, SIGTERM, SIGHUP and SIGQUIT are held back in this thread until
//   it is over.
// On any failure the old files are left as they were, no temporary remains,
// and *error names the target and why. A write cut short by SIGKILL or a
// power loss is finished by the first write of a later process into the
// same folder: undone before its commit, completed after it, so the targets
// are one whole set, old or new, and its temporaries are removed.
bool WriteFilesAtomically(const std::vector<OutputFile>& files, std::string* error = nullptr);

// The checks WriteFilesAtomically makes of its targets before writing, for
// a command to make before long work: false with *error naming the first
// target that cannot be written and why. With `try_create`, a file is also
// created and removed in each target's folder (a folder such as /proc
// passes the permission checks and takes no file).
bool CheckOutputTargets(const std::vector<std::string>& paths, std::string* error = nullptr,
                        bool try_create = false);

// False (and *error) if an output names the same file as one of the
// inputs (`inputs`: what each is, e.g. "--board", then its path), or the
// same path; an output that does not exist yet is compared by path.
bool CheckOutputsAreNotInputs(const std::vector<std::string>& outputs,
                              const std::vector<std::pair<std::string, std::string>>& inputs,
                              std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_BASE_OUTPUT_FILES_H_
