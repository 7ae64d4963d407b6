// Crash-safe file output: write to a temporary name beside the target, sync it to the disk,
// rename it into place and sync the directory, so that neither a crashed process nor a power
// cut leaves a half-written file under the target name (docs/reliability.md).
#pragma once

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string_view>

namespace cmcsurf {

// Usage: AtomicWriter w(path); w.stream() << ...; w.commit();
// Destroying the writer without commit() removes the temporary and leaves any
// existing target untouched. Errors throw std::runtime_error naming the path.
class AtomicWriter {
 public:
  explicit AtomicWriter(std::filesystem::path target);
  ~AtomicWriter();
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;

  std::ostream& stream() { return out_; }
  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temp_path() const { return temp_; }

  // Flushes, closes, syncs (fsync) and renames the temporary onto the target, then syncs the
  // directory so that the new name survives a power cut too.
  void commit();
  // The first half of commit(): the whole file is on the disk under its temporary name (a full
  // disk fails here). For two files that must appear together: finish both, then commit both.
  void finish_writing();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;  // "<target>.cmcsurf-tmp.<pid>.<seq>", same directory
  std::ofstream out_;
  bool committed_ = false;
  bool finished_ = false;
};

// A fresh temporary name beside target (`<target>.cmcsurf-tmp.<pid>.<seq>`), for a writer that
// must write the file itself (a library given a path); remove_stale_temporaries knows it.
std::filesystem::path temporary_name(const std::filesystem::path& target);

void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// Removes the temporaries (`<name>.cmcsurf-tmp.<pid>.<seq>`: ours by name, never a user's
// `x.tmp.1.2`) that a writer killed before its commit (kill -9, a second signal) left directly
// in dir: those of this process and of processes that no longer exist. Call it only on a
// folder cmcsurf owns (io/output_folder.h). Returns how many; errors are ignored.
int remove_stale_temporaries(const std::filesystem::path& dir);

// Creates `dir` and its parents; fine if it already is a directory. Throws
// std::runtime_error if it exists as something else or cannot be created.
void ensure_directory(const std::filesystem::path& dir);

}  // namespace cmcsurf
