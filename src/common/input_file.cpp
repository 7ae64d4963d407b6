#include "common/input_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include <fmt/core.h>

namespace cmcsurf {

namespace fs = std::filesystem;

namespace {

const char* kind_name(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory: return "a directory";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::block: return "a block device";
    case fs::file_type::character: return "a character device";
    default: return "not a plain file";
  }
}

}  // namespace

void require_regular_file(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);  // follows links, opens nothing
  if (s.type() == fs::file_type::not_found || s.type() == fs::file_type::regular) return;
  if (ec)
    throw std::runtime_error(
        fmt::format("cannot read {} '{}': {}", what, path.string(), ec.message()));
  throw std::runtime_error(fmt::format("{} '{}' is not a regular file ({}); cmcsurf reads only "
                                       "regular files there",
                                       what, path.string(), kind_name(s.type())));
}

std::string read_input_file(const fs::path& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("cannot read '{}'", path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw std::runtime_error(fmt::format("cannot read '{}'", path.string()));
  return s.str();
}

}  // namespace cmcsurf
