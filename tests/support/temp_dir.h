// Test support (not part of the library): a uniquely named scratch directory under the system
// temp directory, removed with its contents on destruction.
#pragma once

#include <filesystem>
#include <string_view>

namespace cmcsurf {

class TempDir {
 public:
  explicit TempDir(std::string_view prefix = "cmcsurf");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path operator/(std::string_view name) const { return dir_ / name; }

 private:
  std::filesystem::path dir_;
};

}  // namespace cmcsurf
