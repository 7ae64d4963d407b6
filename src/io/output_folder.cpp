#include "io/output_folder.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

namespace cmcsurf {

namespace fs = std::filesystem;

namespace {

// A regular file's JSON object, or null (missing, not regular, not JSON, too large).
nlohmann::json small_json_object(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > (64u << 20) || ec) return {};
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() ? j : nlohmann::json();
}

bool starts_with_bytes(const fs::path& path, std::string_view magic) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::string head(magic.size(), '\0');
  in.read(head.data(), std::streamsize(head.size()));
  return in && head == magic;
}

std::vector<std::string> some_entries(const fs::path& dir, std::size_t limit, std::size_t& total) {
  std::vector<std::string> names;
  total = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    ++total;
    if (names.size() < limit) names.push_back(it->path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string errno_text(int err) { return err ? std::strerror(err) : "unknown error"; }

}  // namespace

FolderClaim::FolderClaim(FolderClaim&& other) noexcept
    : dir_(std::move(other.dir_)), fd_(other.fd_) {
  other.fd_ = -1;
}

FolderClaim& FolderClaim::operator=(FolderClaim&& other) noexcept {
  if (this != &other) {
    release();
    dir_ = std::move(other.dir_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

FolderClaim::~FolderClaim() { release(); }

void FolderClaim::release() {
  if (fd_ >= 0) ::close(fd_);  // closing the descriptor drops the flock
  fd_ = -1;
}

bool is_cmcsurf_folder(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir / kFolderMarker, ec)) return true;
  // Folders written before markers existed.
  const nlohmann::json report = small_json_object(dir / "report.json");
  if (report.contains("version") && report.contains("build") && report.contains("parameters"))
    return true;
  const nlohmann::json sweep = small_json_object(dir / "sweep.json");
  if (sweep.contains("version") && sweep.contains("members") && sweep.contains("parameters"))
    return true;
  return starts_with_bytes(dir / "checkpoint.bin", "CMCSCKPT");
}

FolderClaim claim_output_folder(const fs::path& dir, const ClaimOptions& options) {
  const std::string name = dir.string();
  const std::string_view option = options.option;
  if (name.empty()) throw FolderRefused(fmt::format("{}: an empty folder name", option), true);
  std::error_code ec;
  const fs::file_status status = fs::status(dir, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw FolderRefused(
        fmt::format("{} '{}': exists and is not a folder", option, name), true);
  if (!fs::exists(status)) {
    fs::create_directories(dir, ec);
    if (ec)
      throw FolderRefused(
          fmt::format("{} '{}': cannot create the folder: {}", option, name, ec.message()), false);
  }
  const fs::path canonical = fs::weakly_canonical(dir, ec);
  if (!ec && canonical == canonical.root_path())
    throw FolderRefused(
        fmt::format("{} '{}': the root of the file system is never an output folder", option,
                    name),
        true);
  if (!is_cmcsurf_folder(dir)) {
    std::size_t total = 0;
    const std::vector<std::string> names = some_entries(dir, 5, total);
    if (total > 0 && !options.force)
      throw FolderRefused(
          fmt::format("{} '{}': the folder is not empty and was not written by cmcsurf (it holds "
                      "{}{}); cmcsurf replaces only its own files, so choose a new or empty "
                      "folder, or pass --force to write its outputs into this one",
                      option, name, fmt::join(names, ", "),
                      total > names.size() ? fmt::format(" and {} more", total - names.size())
                                           : std::string()),
          true);
  }
  const fs::path marker = dir / kFolderMarker;
  const int fd = ::open(marker.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0) {
    const int err = errno;
    throw FolderRefused(fmt::format("{} '{}': cannot write into the folder ({}: {})", option, name,
                                    marker.string(), errno_text(err)),
                        false);
  }
  FolderClaim claim;
  claim.dir_ = dir;
  claim.fd_ = fd;
  int locked;
  while ((locked = ::flock(fd, LOCK_EX | (options.wait ? 0 : LOCK_NB))) != 0 && errno == EINTR) {
  }
  if (locked != 0) {
    const int err = errno;
    if (err == EWOULDBLOCK) {
      std::array<char, 512> buffer{};
      const ssize_t got = ::pread(fd, buffer.data(), buffer.size() - 1, 0);
      const nlohmann::json holder =
          nlohmann::json::parse(std::string(buffer.data(), got > 0 ? std::size_t(got) : 0),
                                nullptr, false);
      const bool named = holder.is_object() && holder.contains("pid") &&
                         holder["pid"].is_number_integer();
      const long holder_pid = named ? holder["pid"].get<long>() : 0;
      // The marker names the last claimant; say so only when that process still runs.
      const std::string pid = holder_pid > 0 && ::kill(pid_t(holder_pid), 0) == 0
                                  ? fmt::format(" (pid {})", holder_pid)
                                  : std::string();
      throw FolderRefused(
          fmt::format("{} '{}': another cmcsurf process{} is writing this folder; wait for it "
                      "to finish or choose another folder",
                      option, name, pid),
          false);
    }
    throw FolderRefused(
        fmt::format("{} '{}': cannot lock {}: {}", option, name, marker.string(), errno_text(err)),
        false);
  }
  // Who holds it, for the message a second writer gets (and what kind of folder this is).
  const std::string about = nlohmann::json{{"cmcsurf", std::string(options.kind)},
                                           {"pid", long(::getpid())}}
                                .dump() +
                            "\n";
  if (::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, about.data(), about.size(), 0) != static_cast<ssize_t>(about.size())) {
    const int err = errno;
    throw FolderRefused(fmt::format("{} '{}': cannot write {}: {}", option, name,
                                    marker.string(), errno_text(err)),
                        false);
  }
  // The outputs are new files beside the marker: make sure one can be created now, not after
  // the solve.
  const fs::path probe = dir / fmt::format(".cmcsurf-probe.{}", long(::getpid()));
  const int pfd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (pfd < 0) {
    const int err = errno;
    throw FolderRefused(fmt::format("{} '{}': cannot create files in the folder: {}", option,
                                    name, errno_text(err)),
                        false);
  }
  ::close(pfd);
  ::unlink(probe.c_str());
  return claim;
}

bool remove_folder_if_only_ours(const fs::path& dir) {
  std::error_code ec;
  fs::remove(dir / kFolderMarker, ec);
  return fs::remove(dir, ec) && !ec;  // removes an empty folder only
}

}  // namespace cmcsurf
