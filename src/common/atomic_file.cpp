#include "common/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>

namespace cmcsurf {

namespace {

std::filesystem::path temp_name_for(const std::filesystem::path& target) {
  static std::atomic<unsigned long> seq{0};
  std::filesystem::path temp = target;
  temp += fmt::format(".cmcsurf-tmp.{}.{}", static_cast<long>(::getpid()), seq++);
  return temp;
}

// fsync of a file or directory by path; returns 0 or the errno.
int sync_path(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (directory ? O_DIRECTORY : 0));
  if (fd < 0) return errno;
  int err = 0;
  while (::fsync(fd) != 0) {
    if (errno == EINTR) continue;
    err = errno;
    break;
  }
  ::close(fd);
  return err;
}

}  // namespace

AtomicWriter::AtomicWriter(std::filesystem::path target)
    : target_(std::move(target)), temp_(temp_name_for(target_)) {
  errno = 0;
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    const int err = errno;
    throw std::runtime_error(fmt::format("cannot open '{}' for writing (temporary '{}'): {}",
                                         target_.string(), temp_.string(),
                                         err ? std::strerror(err) : "unknown error"));
  }
}

AtomicWriter::~AtomicWriter() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(temp_, ec);  // best effort; destructors do not throw
}

std::filesystem::path temporary_name(const std::filesystem::path& target) {
  return temp_name_for(target);
}

void AtomicWriter::finish_writing() {
  if (finished_) return;
  // A stream that failed while the caller wrote to it still holds that write's errno (ENOSPC
  // on a full disk), unless something else ran since; keep it before flushing.
  const int earlier_err = errno;
  const bool failed_earlier = !out_;
  errno = 0;
  out_.flush();
  const bool write_ok = static_cast<bool>(out_);
  const int write_err = errno;
  out_.close();
  if (!write_ok || !out_) {
    const int err = failed_earlier ? earlier_err : (write_err ? write_err : errno);
    std::string why = err ? std::strerror(err) : "stream error";
    std::error_code ec;
    const auto parent =
        target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
    const std::filesystem::space_info space = std::filesystem::space(parent, ec);
    if (!ec && space.available < (std::uintmax_t(1) << 20))
      why += fmt::format(" ({} bytes free on that device)", space.available);
    throw std::runtime_error(fmt::format("error writing '{}' (temporary '{}'): {}",
                                         target_.string(), temp_.string(), why));
  }
  // The data reaches the disk before the name does: after a power cut the target is either
  // the old file or the whole new one. (A full disk or an I/O error can surface only here.)
  if (const int err = sync_path(temp_, false); err != 0)
    throw std::runtime_error(fmt::format("error writing '{}' (temporary '{}'): fsync: {}",
                                         target_.string(), temp_.string(), std::strerror(err)));
  finished_ = true;
}

void AtomicWriter::commit() {
  if (committed_)
    throw std::logic_error("AtomicWriter::commit called twice for " + target_.string());
  finish_writing();
  if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int err = errno;
    throw std::runtime_error(fmt::format("cannot rename '{}' to '{}': {}", temp_.string(),
                                         target_.string(), std::strerror(err)));
  }
  committed_ = true;
  const auto parent =
      target_.has_parent_path() ? target_.parent_path() : std::filesystem::path(".");
  // EINVAL: a file system that cannot sync directories; the rename is done either way.
  if (const int err = sync_path(parent, true); err != 0 && err != EINVAL)
    throw std::runtime_error(fmt::format("'{}' is in place, but its directory could not be "
                                         "synced to the disk: {}",
                                         target_.string(), std::strerror(err)));
}

void write_file_atomic(const std::filesystem::path& path, std::string_view contents) {
  AtomicWriter writer(path);
  writer.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  writer.commit();
}

int remove_stale_temporaries(const std::filesystem::path& dir) {
  static const std::regex temporary(R"(.+\.cmcsurf-tmp\.(\d+)\.\d+)");
  std::error_code ec;
  int removed = 0;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, temporary) || !it->is_regular_file(ec)) continue;
    const long long pid = std::stoll(m[1].str().substr(0, 18));
    const bool mine = pid == static_cast<long long>(::getpid());
    const bool gone = pid <= 0 || pid > 0x7fffffffLL ||
                      (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH);
    std::error_code rm;
    if ((mine || gone) && std::filesystem::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

void ensure_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  const auto status = std::filesystem::status(dir, ec);
  if (std::filesystem::is_directory(status)) return;
  if (std::filesystem::exists(status))
    throw std::runtime_error(fmt::format(
        "cannot create directory '{}': it exists and is not a directory", dir.string()));
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error(
        fmt::format("cannot create directory '{}': {}", dir.string(), ec.message()));
}

}  // namespace cmcsurf
