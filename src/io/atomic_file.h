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

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;  // "<target>.tmp.<pid>.<seq>", same directory
  std::ofstream out_;
  bool committed_ = false;
};

void write_file_atomic(const std::filesystem::path& path, std::string_view contents);

// Removes the temporaries (`<name>.tmp.<pid>.<seq>`) that a writer killed before its commit
// (kill -9, a second signal) left directly in dir: those of this process and of processes that
// no longer exist. Returns how many; errors are ignored (best effort).
int remove_stale_temporaries(const std::filesystem::path& dir);

// Creates `dir` and its parents; fine if it already is a directory. Throws
// std::runtime_error if it exists as something else or cannot be created.
void ensure_directory(const std::filesystem::path& dir);

}  // namespace cmcsurf
