// The folders cmcsurf writes (a run, a sweep, a sweep's members, the scaffold cache): marked as
// ours by a `.cmcsurf` file, so that we only ever clear or replace what we wrote, and locked by
// one writer at a time (docs/reliability.md, "Whose folder").
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cmcsurf {

// The marker of a cmcsurf folder; it is also the file the writer locks (flock).
inline constexpr const char* kFolderMarker = ".cmcsurf";

// Why a folder cannot be claimed. `usage`: the user's choice of folder is wrong (a foreign
// folder, a file, the file system's root): the CLI exits 2; otherwise (another writer holds
// it, it cannot be written) exit 1.
class FolderRefused : public std::runtime_error {
 public:
  FolderRefused(const std::string& what, bool usage) : std::runtime_error(what), usage_(usage) {}
  bool usage() const { return usage_; }

 private:
  bool usage_;
};

// An exclusive claim on an output folder for the lifetime of the object (move-only). The lock
// is an advisory flock on the marker: a second cmcsurf process claiming the folder is refused
// at once, and a crashed writer's lock goes with its process.
struct ClaimOptions;

class FolderClaim {
 public:
  FolderClaim() = default;
  FolderClaim(FolderClaim&& other) noexcept;
  FolderClaim& operator=(FolderClaim&& other) noexcept;
  FolderClaim(const FolderClaim&) = delete;
  FolderClaim& operator=(const FolderClaim&) = delete;
  ~FolderClaim();

  bool held() const { return fd_ >= 0; }
  const std::filesystem::path& dir() const { return dir_; }
  // Lets the lock go (the marker stays: the folder remains ours).
  void release();

 private:
  friend FolderClaim claim_output_folder(const std::filesystem::path&, const ClaimOptions&);
  std::filesystem::path dir_;
  int fd_ = -1;
};

// Whether dir is a cmcsurf folder: it holds the marker, or (a folder written before markers
// existed) a report.json, sweep.json or checkpoint.bin that cmcsurf wrote.
bool is_cmcsurf_folder(const std::filesystem::path& dir);

struct ClaimOptions {
  std::string_view kind = "run";     // written into a new marker: "run", "sweep", "cache"
  std::string_view option = "--out";  // what the user typed, for the messages
  bool force = false;                 // write into a non-empty folder that is not ours
  bool wait = false;                  // wait for another writer instead of refusing
};

// Claims dir for writing, before any work: creates it (and its parents) when missing, marks it
// as ours when it is new or empty (or holds only cmcsurf files from before markers), refuses a
// non-empty folder that is not ours unless `force` (naming `option`, the folder and what it
// holds), refuses the file system's root even so, locks it (or waits for the lock), and checks
// that a file can be created in it. Throws FolderRefused.
FolderClaim claim_output_folder(const std::filesystem::path& dir, const ClaimOptions& options);

// Removes dir's marker and dir itself if nothing else is left in it (a member folder of an
// earlier sweep whose outputs were cleared); returns whether dir is gone.
bool remove_folder_if_only_ours(const std::filesystem::path& dir);

}  // namespace cmcsurf
