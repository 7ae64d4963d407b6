#include "support/temp_dir.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>

namespace cmcsurf {

TempDir::TempDir(std::string_view prefix) {
  static std::atomic<unsigned long> seq{0};
  const auto base = std::filesystem::temp_directory_path();
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto candidate =
        base / fmt::format("{}-{}-{:x}-{}", prefix, static_cast<long>(::getpid()), stamp, seq++);
    std::error_code ec;
    if (std::filesystem::create_directory(candidate, ec)) {
      dir_ = std::move(candidate);
      return;
    }
    if (ec && ec != std::errc::file_exists)
      throw std::runtime_error(fmt::format("cannot create temporary directory '{}': {}",
                                           candidate.string(), ec.message()));
  }
  throw std::runtime_error("cannot create a unique temporary directory under " + base.string());
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

}  // namespace cmcsurf
